//! Oblique impacts with friction (docs/physics.md §9): Walton's impulse model against its closed
//! form, for walls and for pairs, and no impact that adds energy.

use crate::common;
use glam::DVec3;
use proptest::prelude::*;
use wetbounce::contact::{Friction, Spinning, tangential_impulse};
use wetbounce::correlations::{sphere_moment_of_inertia, sphere_volume};

/// A solid sphere of density `rho` and diameter `d` in vacuum (no added mass), at `v`, `omega`.
fn sphere(rho: f64, d: f64, v: DVec3, omega: DVec3) -> Spinning {
    Spinning {
        inv_mass: 1.0 / (rho * sphere_volume(d)),
        inv_moment: 1.0 / sphere_moment_of_inertia(rho, d),
        radius: 0.5 * d,
        v,
        omega,
    }
}

/// The closed form of docs/physics.md §9 with the factor `k` (7/2 for solid spheres in vacuum).
fn psi2_closed_form(psi1: f64, mu: f64, beta0: f64, e: f64, k: f64) -> (f64, bool) {
    if (1.0 + beta0) * psi1 <= k * mu * (1.0 + e) {
        (-beta0 * psi1, true)
    } else {
        (psi1 - k * mu * (1.0 + e), false)
    }
}

/// Ψ2 of an impact of `a` on `b` (normal `n` from a to b), normal speed `vn`, restitution `e`:
/// the contact point's relative tangential velocity after, along the one before, over `vn`.
fn psi2_of(a: &Spinning, b: &Spinning, n: DVec3, vn: f64, e: f64, f: &Friction) -> (f64, f64, bool) {
    let t = tangential_impulse(a, b, n, vn, e, f);
    let [(va, oa), (vb, ob)] = t.apply(a, b, n);
    let after = Spinning { v: va, omega: oa, ..*a };
    let other = Spinning { v: vb, omega: ob, ..*b };
    let u = wetbounce::contact::rules::friction::contact_velocity(&after, &other, n);
    let ut = u - u.dot(n) * n;
    let dir = t.slip.normalize_or_zero();
    (t.slip.length() / vn, ut.dot(dir) / vn, t.sticking)
}

fn check_curve(a_of: impl Fn(f64) -> (Spinning, Spinning), label: &str) {
    let f = Friction { mu: 0.15, beta0: 0.4, rolling: 0.0 };
    let (e, vn) = (0.8, 0.3);
    let (mut stuck, mut slid) = (0, 0);
    for i in 0..=60 {
        let psi1 = 0.1 * i as f64;
        let (a, b) = a_of(psi1 * vn);
        let (p1, p2, sticking) = psi2_of(&a, &b, DVec3::NEG_Z, vn, e, &f);
        assert!((p1 - psi1).abs() < 1e-12, "{label}: Ψ1 {p1} vs {psi1}");
        let (expected, sticks) = psi2_closed_form(psi1, f.mu, f.beta0, e, 3.5);
        assert_eq!(sticking, sticks, "{label}: regime at Ψ1 = {psi1}");
        assert!((p2 - expected).abs() < 1e-12, "{label}: Ψ1 = {psi1}: Ψ2 = {p2}, closed form {expected}");
        if sticks { stuck += 1 } else { slid += 1 }
    }
    assert!(stuck > 5 && slid > 5, "{label}: both regimes seen ({stuck} sticking, {slid} sliding)");
}

#[test]
fn wall_rebound_angle_matches_the_closed_form_in_both_regimes() {
    // A bead moving down (−z) onto a floor below it: the normal from it to the wall is −z.
    check_curve(|ut| (sphere(2500.0, 2e-3, DVec3::new(ut, 0.0, -0.3), DVec3::ZERO), Spinning::WALL), "wall");
}

#[test]
fn equal_mass_pair_rebound_angle_matches_the_closed_form_in_both_regimes() {
    // Two equal beads, spinning: Ψ1 counts the spin's part of the contact point's slip.
    let omega = DVec3::new(0.0, 20.0, 0.0);
    check_curve(
        |ut| {
            let a = sphere(2500.0, 2e-3, DVec3::new(0.0, 0.0, -0.15), omega);
            let mut b = sphere(2500.0, 2e-3, DVec3::new(0.0, 0.0, 0.15), -omega);
            // The spins' slip at the contact: ω_a × (a n) − ω_b × (−a n) = 2 a ω × n along x.
            let spin_slip = (omega.cross(1e-3 * DVec3::NEG_Z) - (-omega).cross(1e-3 * DVec3::Z)).x;
            b.v.x = spin_slip - ut;
            (a, b)
        },
        "equal pair",
    );
}

#[test]
fn unequal_mass_pair_rebound_angle_matches_the_closed_form_in_both_regimes() {
    // Reduced mass and each sphere's lever arm: for solid spheres in vacuum the factor stays 7/2
    // (m* (1/m_a + 1/m_b)(1 + 5/2) = 7/2), which this checks with a 3:1 size and 3:1 density.
    check_curve(
        |ut| {
            let a = sphere(7800.0, 3e-3, DVec3::new(ut, 0.0, -0.2), DVec3::ZERO);
            let b = sphere(2600.0, 1e-3, DVec3::new(0.0, 0.0, 0.1), DVec3::ZERO);
            (a, b)
        },
        "unequal pair",
    );
}

#[test]
fn with_added_mass_the_factor_is_one_plus_five_halves_of_the_inertia_ratio() {
    // In a liquid the translational inertia carries C_M ρ, the rotational does not.
    let (rho_p, rho, d) = (2500.0, 1000.0, 2e-3);
    let m = (rho_p + 0.5 * rho) * sphere_volume(d);
    let a = Spinning { inv_mass: 1.0 / m, ..sphere(rho_p, d, DVec3::new(0.05, 0.0, -0.3), DVec3::ZERO) };
    let f = Friction { mu: 0.1, beta0: 0.0, rolling: 0.0 };
    let (psi1, psi2, sticking) = psi2_of(&a, &Spinning::WALL, DVec3::NEG_Z, 0.3, 0.5, &f);
    let k = 1.0 + 2.5 * (rho_p + 0.5 * rho) / rho_p;
    let (expected, sticks) = psi2_closed_form(psi1, f.mu, f.beta0, 0.5, k);
    assert_eq!(sticking, sticks);
    assert!((psi2 - expected).abs() < 1e-12, "{psi2} vs {expected}");
}

/// A bead thrown at the floor of a vacuum scene with friction: the engine's rebound (velocity
/// and spin right after) against the closed form, with the event's ε.
fn thrown_bead(psi1: f64) -> (f64, f64, wetbounce::ContactEvent) {
    let (psi2, vz, _, e) = spun_bead(psi1, 0.0);
    (psi2, vz, e)
}

/// [`thrown_bead`] with an initial spin `omega_y` (rad/s) about y, given by the scene's
/// `angular_velocity` key: (Ψ2 along x, v_z/vn, the velocity right after, the event).
fn spun_bead(psi1: f64, omega_y: f64) -> (f64, f64, DVec3, wetbounce::ContactEvent) {
    let vn = 0.5;
    let text = format!(
        r#"
[simulation]
dt = 1e-4
duration = 0.01
output_interval = 0.01
[fluid]
density = 0.0
viscosity = 0.0
gravity = [0.0, 0.0, 0.0]
[[kinds]]
name = "steel"
type = "solid"
density = 7800.0
youngs_modulus = 2e11
poisson_ratio = 0.3
restitution_max = 0.8
friction = 0.2
tangential_restitution = 0.3
[[walls]]
name = "floor"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = {{ youngs_modulus = 2e11, poisson_ratio = 0.3 }}
[[particles]]
kind = "steel"
diameter = 2e-3
position = [0.0, 0.0, 1.02e-3]
velocity = [{}, 0.0, {}]
angular_velocity = [0.0, {omega_y}, 0.0]
"#,
        psi1 * vn,
        -vn
    );
    let mut sim = common::scene(&text).simulation();
    let mut events = Vec::new();
    while events.is_empty() {
        sim.step(1e-5);
        events.append(&mut sim.record.events);
    }
    let p = &sim.world.particles;
    let (v, w) = (p.vel[0], p.spin(0));
    let contact = v + w.cross(1e-3 * DVec3::NEG_Z);
    (contact.x / vn, v.z / vn, v, events[0])
}

#[test]
fn a_spinning_bead_leaves_a_frictional_floor_pushed_against_its_spin_slip_as_the_impulse_model_says() {
    // Straight down at 0.5 m/s, spinning about y: the contact point (1 mm below the centre)
    // slips at ω × (−R ẑ) = −R ω_y x̂. Friction opposes that slip, so the bead leaves with
    // v_x of the sign of ω_y, where without spin it leaves straight up (v_x = 0); the contact
    // point's velocity after is Walton's closed form of Ψ1 = R |ω_y| / vn.
    let (vn, r) = (0.5, 1e-3);
    let (_, _, still, _) = spun_bead(0.0, 0.0);
    assert_eq!(still.x, 0.0, "no spin, no tangential velocity: {still}");
    for omega_y in [-2000.0, -100.0, 100.0, 250.0, 2000.0] {
        let (psi2, _, v, e) = spun_bead(0.0, omega_y);
        let psi1: f64 = r * f64::abs(omega_y) / vn;
        assert!(
            v.x * omega_y > 0.0,
            "ω_y = {omega_y}: v_x after = {} must have the sign of ω_y (friction against the slip)",
            v.x
        );
        assert!((e.tangential_speed / e.normal_speed - psi1).abs() < 1e-9, "{e:?}");
        let (expected, _) = psi2_closed_form(psi1, 0.2, 0.3, e.eps, 3.5);
        // The slip is along −sign(ω_y) x̂: Ψ2 along x carries that sign.
        let along = -psi2 * omega_y.signum();
        assert!((along - expected).abs() < 1e-9, "ω_y = {omega_y}: Ψ2 = {along}, closed form {expected}");
    }
}

#[test]
fn bead_thrown_at_a_floor_rebounds_and_spins_as_the_impulse_model_says() {
    let (mut stuck, mut slid) = (false, false);
    for psi1 in [0.2, 0.5, 1.0, 2.0, 4.0] {
        let (psi2, vz, e) = thrown_bead(psi1);
        assert!((e.tangential_speed / e.normal_speed - psi1).abs() < 1e-9, "{e:?}");
        assert!((e.incidence_angle - psi1.atan()).abs() < 1e-9, "{e:?}");
        assert!((vz - e.eps).abs() < 1e-9, "v_z/vn = {vz}, ε = {}", e.eps);
        let (expected, sticks) = psi2_closed_form(psi1, 0.2, 0.3, e.eps, 3.5);
        assert!((psi2 - expected).abs() < 1e-9, "Ψ1 = {psi1}: Ψ2 = {psi2}, closed form {expected}");
        assert!(e.energy_after <= e.energy_before, "{e:?}");
        (stuck, slid) = (stuck || sticks, slid || !sticks);
    }
    assert!(stuck && slid);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The normal impulse (restitution `e`) and Walton's tangential impulse together never add
    /// kinetic energy, translational plus rotational, for any masses, spins, directions,
    /// `μ ≥ 0` and `β0 ∈ [−1, 1]`; a wall is a body of infinite mass.
    #[test]
    fn no_impact_adds_energy(
        (ra, rb) in (0.1e-3..5e-3f64, 0.1e-3..5e-3f64),
        (rho_a, rho_b) in (500.0..20000.0f64, 500.0..20000.0f64),
        added in 0.0..1.0f64,
        va in prop::array::uniform3(-1.0..1.0f64),
        vb in prop::array::uniform3(-1.0..1.0f64),
        wa in prop::array::uniform3(-500.0..500.0f64),
        wb in prop::array::uniform3(-500.0..500.0f64),
        dir in prop::array::uniform3(-1.0..1.0f64),
        (mu, beta0, e) in (0.0..2.0f64, -1.0..=1.0f64, 0.0..=1.0f64),
        wall in any::<bool>(),
    ) {
        let n0 = DVec3::from_array(dir).normalize_or(DVec3::Z);
        let body = |rho: f64, r: f64, v: [f64; 3], w: [f64; 3]| {
            let s = sphere(rho, 2.0 * r, DVec3::from_array(v), DVec3::from_array(w));
            // Some added mass in the translational inertia only, as in a liquid.
            Spinning { inv_mass: s.inv_mass / (1.0 + added * 1000.0 / rho), ..s }
        };
        let a = body(rho_a, ra, va, wa);
        let b = if wall { Spinning::WALL } else { body(rho_b, rb, vb, wb) };
        // The normal from `a` to `b` is the one along which they approach.
        let u = a.v - b.v;
        let n = if u.dot(n0) >= 0.0 { n0 } else { -n0 };
        let vn = u.dot(n);
        prop_assume!(vn > 1e-9);
        let energy = |s: &Spinning| {
            if s.inv_mass == 0.0 { 0.0 } else {
                0.5 * s.v.length_squared() / s.inv_mass + 0.5 * s.omega.length_squared() / s.inv_moment
            }
        };
        // The normal impulse first (the bounce rule), then the tangential one, on the velocities
        // at impact, as the engine does.
        let jn = (1.0 + e) * vn / (a.inv_mass + b.inv_mass);
        let f = Friction { mu, beta0, rolling: 0.0 };
        let t = tangential_impulse(&a, &b, n, vn, e, &f);
        let [(va1, wa1), (vb1, wb1)] = t.apply(&a, &b, n);
        let a1 = Spinning { v: va1 - n * jn * a.inv_mass, omega: wa1, ..a };
        let b1 = Spinning { v: vb1 + n * jn * b.inv_mass, omega: wb1, ..b };
        let (before, after) = (energy(&a) + energy(&b), energy(&a1) + energy(&b1));
        prop_assert!(after <= before * (1.0 + 1e-12) + 1e-30, "before {before}, after {after}");
    }
}
