//! Lasting contacts with friction and the spin of a particle in a fluid (docs/physics.md §9):
//! rolling and sliding down an incline, spin relaxing at the Stokes rate.

use crate::common;
use glam::DVec3;
use wetbounce::particles::State;

const G: f64 = 9.81;

/// A 2 mm steel bead resting on an incline of `theta` (rad) in vacuum, gravity −z, with
/// friction `mu` (on the bead; the plane gives none, so the bead's is the contact's).
fn incline(theta: f64, mu: f64) -> wetbounce::Simulation {
    let (s, c) = theta.sin_cos();
    let text = format!(
        r#"
[simulation]
dt = 1e-4
duration = 0.2
output_interval = 0.01
[fluid]
density = 0.0
viscosity = 0.0
gravity = [0.0, 0.0, -{G}]
[effects]
gravity = {{}}
[[kinds]]
name = "steel"
type = "solid"
density = 7800.0
youngs_modulus = 2e11
poisson_ratio = 0.3
restitution_max = 0.8
friction = {mu}
[[walls]]
name = "incline"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [{s}, 0.0, {c}]
material = {{ youngs_modulus = 2e11, poisson_ratio = 0.3 }}
[[particles]]
kind = "steel"
diameter = 2e-3
position = [{}, 0.0, {}]
velocity = [0.0, 0.0, 0.0]
"#,
        1e-3 * s,
        1e-3 * c
    );
    let mut sim = common::scene(&text).simulation();
    // In vacuum every impact rebounds (St is infinite): start it resting on the incline.
    sim.world.particles.state[0] = State::Resting;
    sim.world.particles.wall[0] = 0;
    sim
}

/// Speed down the slope and the contact point's slip after `t` (s).
fn down_the_slope(sim: &mut wetbounce::Simulation, theta: f64, t: f64) -> (f64, f64) {
    sim.advance_to(t);
    let p = &sim.world.particles;
    assert_eq!(p.state[0], State::Resting, "left the incline");
    let n = DVec3::new(theta.sin(), 0.0, theta.cos());
    let down = DVec3::new(theta.cos(), 0.0, -theta.sin());
    let slip = p.vel[0] + p.spin(0).cross(-1e-3 * n);
    (p.vel[0].dot(down), slip.length())
}

#[test]
fn sphere_rolls_down_an_incline_at_five_sevenths_g_sin_theta_without_slipping() {
    let theta = 20f64.to_radians();
    // Rolling needs μ ≥ (2/7) tan θ = 0.104.
    let mut sim = incline(theta, 0.5);
    let (v1, _) = down_the_slope(&mut sim, theta, 0.1);
    let (v2, slip) = down_the_slope(&mut sim, theta, 0.2);
    let a = (v2 - v1) / 0.1;
    let expected = 5.0 / 7.0 * G * theta.sin();
    assert!((a / expected - 1.0).abs() < 1e-6, "a = {a}, 5/7 g sin θ = {expected}");
    assert!(slip < 1e-9 * v2, "slip {slip} m/s at {v2} m/s");
}

#[test]
fn sphere_slides_down_an_incline_at_g_sin_minus_mu_cos_when_friction_is_too_small() {
    let theta = 20f64.to_radians();
    let mu = 0.05;
    let mut sim = incline(theta, mu);
    let (v1, _) = down_the_slope(&mut sim, theta, 0.1);
    let (v2, slip) = down_the_slope(&mut sim, theta, 0.2);
    let a = (v2 - v1) / 0.1;
    let expected = G * (theta.sin() - mu * theta.cos());
    assert!((a / expected - 1.0).abs() < 1e-6, "a = {a}, g (sin θ − μ cos θ) = {expected}");
    assert!(slip > 0.1 * v2, "it slides: slip {slip} m/s at {v2} m/s");
}

/// A 2 mm glass bead spinning at `omega0` in water, gravity off, in `flow`.
fn spinning_bead(omega0: [f64; 3], flow: &str) -> wetbounce::Simulation {
    let text = format!(
        r#"
[simulation]
dt = 1e-3
duration = 1.0
output_interval = 0.1
[fluid]
density = 1000.0
viscosity = 1e-3
gravity = [0.0, 0.0, 0.0]
flow = {flow}
[effects]
drag = {{ law = "stokes" }}
rotation = {{}}
[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.22
[[particles]]
kind = "glass"
diameter = 2e-3
position = [0.003, 0.0, 0.0]
velocity = [0.0, 0.0, 0.0]
"#
    );
    let mut sim = common::scene(&text).simulation();
    sim.world.particles.omega.values_mut()[0] = DVec3::from_array(omega0);
    sim
}

#[test]
fn spinning_sphere_in_still_fluid_loses_its_spin_at_the_stokes_rate() {
    // I dω/dt = −8π μ a³ ω, I = (2/5) m a²: ω = ω0 exp(−15 μ t / (ρp a²)).
    let mut sim = spinning_bead([0.0, 300.0, 100.0], r#"{ type = "quiescent" }"#);
    let rate = 15.0 * 1e-3 / (2500.0 * 1e-6);
    for t in [0.05, 0.2, 0.5] {
        sim.advance_to(t);
        let w = sim.world.particles.spin(0);
        let expected = DVec3::new(0.0, 300.0, 100.0) * (-rate * t).exp();
        assert!((w - expected).length() < 1e-12 * 300.0, "t = {t}: ω = {w}, expected {expected}");
    }
}

#[test]
fn sphere_in_a_pipe_flow_takes_half_the_vorticity_as_its_spin() {
    // Poiseuille along z, u_max 0.1 m/s, R = 1 cm: at x = 3 mm, ½∇×u = (u_max/R²) z × (x, 0, 0).
    let flow = r#"{ type = "poiseuille", point = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.01, max_velocity = 0.1 }"#;
    let mut sim = spinning_bead([0.0; 3], flow);
    sim.advance_to(1.0);
    let (x, w) = (sim.world.particles.pos[0], sim.world.particles.spin(0));
    let half_vorticity = 0.1 / 1e-4 * DVec3::Z.cross(DVec3::new(x.x, x.y, 0.0));
    // From rest, at the Stokes rate 15 μ / (ρp a²) = 6 /s: ω = Ω (1 − e^{−6 t}).
    let expected = half_vorticity * (1.0 - (-6.0f64).exp());
    assert!((w - expected).length() < 1e-9 * expected.length(), "ω = {w}, expected {expected}");
    assert!(half_vorticity.y > 0.0);
}
