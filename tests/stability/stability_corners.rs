//! Stability case 4 (docs/stability.md): corners and edges. Beads thrown into the corner of a
//! box (inside, and at the convex corner of a box obstacle), at the rims of an annular baffle
//! (its hole and its outer edge), and grazing (89°) along the inside of a cylinder. With no
//! force acting, the kinetic energy must never rise — not at a contact, not between steps —
//! and after every step each bead is outside every wall.

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;
use wetbounce::particles::State;
use wetbounce::walls::Surface;

const D: f64 = 2e-3;

/// 2 mm beads (ν = 0.22) with no force acting: straight flights, so any rise of the kinetic
/// energy comes from the contacts. Vacuum (St = ∞: ε = ε_max) or water (St finite: the beads
/// slow down and deposit).
fn beads(fluid: (f64, f64), eps_max: f64, dt: f64) -> BeadOnFloor {
    BeadOnFloor::new()
        .kind("bead")
        .poisson_ratio(0.22)
        .restitution_max(eps_max)
        .fluid(fluid.0, fluid.1)
        .effects("")
        .dt(dt)
}

/// Runs `steps` steps, checking after each that every bead is clear of every wall, and that the
/// kinetic energy of the beads (equal masses: the sum of the squared speeds; beads may trade
/// energy when they meet) never rises (to a relative 1e-12).
fn run_checked(mut sim: wetbounce::Simulation, steps: usize, what: &str) -> usize {
    let mut contacts = 0;
    let speed2 =
        |s: &wetbounce::Simulation| -> f64 { s.world.particles.vel.iter().map(|v| v.length_squared()).sum() };
    let mut before = speed2(&sim);
    for _ in 0..steps {
        let t = sim.world.time + sim.setup.dt;
        contacts += common::run_collect(&mut sim, t).len();
        common::assert_clear_of_walls(&sim);
        assert!(sim.record.lost.is_empty(), "{what}: {:?}", sim.record.lost);
        let after = speed2(&sim);
        assert!(
            after <= before * (1.0 + 1e-12),
            "{what}: t = {}: Σv² rose from {before} to {after}",
            sim.world.time
        );
        before = after;
    }
    contacts
}

const VACUUM: (f64, f64) = (0.0, 0.0);
const WATER: (f64, f64) = (998.2, 1.0e-3);
/// The inside of a 10 mm cube with a corner at the origin.
const BOX: &str = "[[walls]]\nname = \"box\"\ntype = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [0.01, 0.01, 0.01]\ninside = true\n";

#[test]
fn beads_thrown_into_a_box_corner_stay_inside_and_never_gain_energy() {
    for (fluid, eps) in [(VACUUM, 1.0), (VACUUM, 0.5), (WATER, 0.97)] {
        for dt in [1e-4, 1e-2] {
            // Straight into the corner (1, 1, 1) and just off it, fast and slow.
            let starts: Vec<(DVec3, DVec3)> = [(1.0, 1.0, 1.0), (1.0, 1.0001, 0.9999), (1.0, 1.0, 0.0)]
                .iter()
                .zip([0.8, 5.0, 0.3])
                .map(|(&(a, b, c), s)| (DVec3::splat(0.005), s * DVec3::new(a, b, c).normalize()))
                .enumerate()
                .map(|(k, (x, v))| (x + DVec3::new(0.0, 0.0, (k as f64 - 1.0) * 2.5e-3), v))
                .collect();
            let sim = beads(fluid, eps, dt).walls(BOX).particles(&starts).scene().simulation();
            let n = run_checked(sim, 200, &format!("box corner, {fluid:?}, ε {eps}, dt {dt}"));
            assert!(n >= 3, "only {n} contacts");
        }
    }
}

#[test]
fn beads_thrown_at_the_convex_corner_and_edges_of_a_box_obstacle_stay_outside() {
    let walls = "[[walls]]\nname = \"block\"\ntype = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [0.01, 0.01, 0.01]\ninside = false\n";
    for (fluid, eps) in [(VACUUM, 1.0), (WATER, 0.97)] {
        for dt in [1e-4, 1e-2] {
            let starts: Vec<(DVec3, DVec3)> = [
                // At the corner (0.01, 0.01, 0.01) along the diagonal, at an edge, grazing a face.
                (DVec3::splat(0.02), DVec3::splat(-1.0)),
                (DVec3::new(0.02, 0.02, 0.005), DVec3::new(-1.0, -1.0, 0.0)),
                (DVec3::new(-0.01, 0.005, 0.0101), DVec3::new(1.0, 0.0, -0.0175)),
            ]
            .into_iter()
            .map(|(x, v)| (x, 2.0 * v.normalize()))
            .collect();
            let sim = beads(fluid, eps, dt).walls(walls).particles(&starts).scene().simulation();
            let n = run_checked(sim, 100, &format!("block corner, {fluid:?}, dt {dt}"));
            assert!(n >= 2, "only {n} contacts");
        }
    }
}

#[test]
fn beads_thrown_at_the_rims_of_an_annular_baffle_stay_outside_and_never_gain_energy() {
    // Flat and conical rings, hole radius 5 mm, outer radius 15 mm, in the plane z = 0.
    for cone in [0.0, -0.003] {
        let walls = format!(
            "[[walls]]\nname = \"baffle\"\ntype = \"annulus\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\ninner_radius = 0.005\nouter_radius = 0.015\ncone_height = {cone:e}\nsegments = 32\n"
        );
        for (fluid, eps) in [(VACUUM, 1.0), (WATER, 0.97)] {
            for dt in [1e-4, 1e-2] {
                // Falling onto the hole's rim and onto the outer rim, straight and at 45°, from
                // above and from below; each aimed at a point within a radius of the rim.
                let mut starts = Vec::new();
                for (k, rim) in [0.005, 0.015].into_iter().enumerate() {
                    for (j, offset) in [-0.6, 0.0, 0.4].into_iter().enumerate() {
                        let phi = 0.3 * (3 * k + j) as f64;
                        let at = (rim + offset * 0.5 * D) * DVec3::new(phi.cos(), phi.sin(), 0.0);
                        let up = if j % 2 == 0 { 1.0 } else { -1.0 };
                        let dir = DVec3::new(0.3 * (k as f64 - 0.5), 0.0, -up).normalize();
                        starts.push((at - 0.004 * dir, 0.5 * dir));
                    }
                }
                let sim = beads(fluid, eps, dt).walls(&walls).particles(&starts).scene().simulation();
                let n = run_checked(sim, 100, &format!("baffle rims, cone {cone}, {fluid:?}, dt {dt}"));
                assert!(n >= 4, "only {n} contacts");
            }
        }
    }
}

#[test]
fn beads_grazing_the_inside_of_a_cylinder_at_89_degrees_stay_inside() {
    let walls = "[[walls]]\nname = \"pipe\"\ntype = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\naxis = [0.0, 0.0, 1.0]\nradius = 0.01\n";
    for (fluid, eps) in [(VACUUM, 1.0), (WATER, 0.97)] {
        for dt in [1e-4, 1e-2] {
            // 89° from the wall's normal: nearly along the wall, spiralling round it.
            let starts: Vec<(DVec3, DVec3)> = (0..3)
                .map(|k| {
                    let a = 89f64.to_radians();
                    let x = DVec3::new(0.008, 0.0, 0.01 * k as f64);
                    (x, (1.0 + k as f64) * DVec3::new(a.cos(), a.sin() * 0.99, a.sin() * 0.141))
                })
                .collect();
            let sim = beads(fluid, eps, dt).walls(walls).particles(&starts).scene().simulation();
            let n = run_checked(sim, 300, &format!("cylinder grazing, {fluid:?}, dt {dt}"));
            assert!(n >= 3, "only {n} contacts");
        }
    }
}

#[test]
fn bead_resting_in_a_box_corner_under_oblique_gravity_stays_in_the_corner() {
    // Regression (found by tests/stability/stability_properties.rs): a bead resting on one face of a box
    // slid through the next face — a resting particle ignores contacts with its own wall, and
    // only the face it rested on was enforced.
    let mut sim = BeadOnFloor::new()
        .kind("bead")
        .poisson_ratio(0.22)
        .dt(1e-2)
        .gravity([-5.0, -3.0, -7.0])
        .walls(BOX)
        .at([0.002, 0.005, 0.005])
        .scene()
        .simulation();
    for _ in 0..100 {
        let t = sim.world.time + sim.setup.dt;
        common::run_collect(&mut sim, t);
        common::assert_clear_of_walls(&sim);
    }
    let x = sim.world.particles.pos[0];
    assert!((x - DVec3::splat(0.5 * D)).length() < 1e-12, "the bead should sit in the corner, at {x:?}");
}

// ---- Creases of separate walls (issue 25, point 1) ----

/// What a bead's run in a crease gave: contacts per wall and outcome, the steps with contacts
/// after `settle`, and where it ended.
struct CreaseRun {
    events: Vec<wetbounce::ContactEvent>,
    late_events: usize,
    /// The most contacts in one step.
    most_in_a_step: usize,
    /// Contacts after the first step that ended with the bead resting against two walls.
    after_crease: Option<usize>,
    state: wetbounce::particles::State,
    velocity: DVec3,
}

impl CreaseRun {
    /// The contacts in short: time, what was touched, normal speed, outcome.
    fn listed(&self) -> Vec<String> {
        self.events
            .iter()
            .map(|e| format!("{:.6} {:?} {:.3e} {:?}", e.time, e.other, e.normal_speed, e.outcome))
            .collect()
    }

    /// Deposits recorded on wall `w`.
    fn deposits_on(&self, w: u32) -> usize {
        self.events
            .iter()
            .filter(|e| e.other == wetbounce::Other::Wall(w) && e.outcome == wetbounce::Outcome::Deposited)
            .count()
    }
}

/// Runs one bead `steps` steps, checking after each that it is clear of every wall (1e-9 r) and
/// that its kinetic energy (with added mass) never exceeds the work of its weight less buoyancy
/// since the start (relative 1e-9): no contact and no crease slide gives it energy. Counts the
/// contacts after step `settle`.
fn run_in_crease(mut sim: wetbounce::Simulation, steps: usize, settle: usize, what: &str) -> CreaseRun {
    let kind = &sim.setup.kinds[0];
    let (rho_p, rho) = (kind.density, sim.setup.fluid.density);
    let g = sim.setup.fluid.gravity;
    let x0 = sim.world.particles.pos[0];
    let v0 = sim.world.particles.vel[0];
    let r = 0.5 * sim.world.particles.diameter[0];
    let kinetic = |v: DVec3| 0.5 * (rho_p + 0.5 * rho) * v.length_squared();
    let mut events = Vec::new();
    let mut late_events = 0;
    let mut most_in_a_step = 0;
    let mut after_crease: Option<usize> = None;
    for step in 0..steps {
        let t = sim.world.time + sim.setup.dt;
        let e = common::run_collect(&mut sim, t);
        if step >= settle {
            late_events += e.len();
        }
        most_in_a_step = most_in_a_step.max(e.len());
        if let Some(n) = after_crease.as_mut() {
            *n += e.len();
        }
        events.extend(e);
        common::assert_clear_of_walls(&sim);
        let (x, v) = (sim.world.particles.pos[0], sim.world.particles.vel[0]);
        let touched = sim.setup.walls.iter().filter(|w| w.shape.gap(x, r).gap <= 1e-9 * r).count();
        if after_crease.is_none() && touched >= 2 && sim.world.particles.state[0] == State::Resting {
            after_crease = Some(0);
        }
        let work = (rho_p - rho) * g.dot(x - x0) + kinetic(v0);
        assert!(
            // Round-off: a bead put back on a wall moves by up to 1e-9 of its radius.
            kinetic(v) <= work + 1e-9 * work.abs().max(kinetic(v0)) + (rho_p - rho) * g.length() * 1e-9 * r,
            "{what}: step {step}: kinetic energy {} above the work of the weight {work} (per volume)",
            kinetic(v)
        );
    }
    let p = &sim.world.particles;
    CreaseRun { events, late_events, most_in_a_step, after_crease, state: p.state[0], velocity: p.vel[0] }
}

/// §7.4's column (radius 20 mm) with §7.6's doughnut baffle (outer radius 25 mm, beyond the
/// column wall, inner rim 6 mm above the outer one): its cone slopes down to the column wall.
fn column_with_doughnut(cone_height: f64) -> String {
    format!(
        "[[walls]]\nname = \"column\"\ntype = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\naxis = [0.0, 0.0, 1.0]\nradius = 0.02\nlength = 0.3\n\n\
         [[walls]]\nname = \"doughnut\"\ntype = \"annulus\"\ncenter = [0.0, 0.0, 0.08]\nnormal = [0.0, 0.0, 1.0]\ninner_radius = 0.012\nouter_radius = 0.025\ncone_height = {cone_height:e}\n"
    )
}

#[test]
fn bead_in_the_corner_of_a_column_and_a_conical_baffle_deposits_once_per_wall_and_rests() {
    // Regression (issue 25): a 2.5 mm glass bead dropped on the doughnut's cone slid into the
    // corner with the column wall and recorded 32 deposits per step for ever (the island's
    // event budget), alternating between the two walls: resting knew one wall, and the other's
    // contact was a new impact at every step. 495 steps/s as in the report; 0.5 s.
    for cone_height in [0.006, 0.002, 0.012] {
        let sim = BeadOnFloor::new()
            .diameter(2.5e-3)
            .dt(1.0 / 495.0)
            .walls(&column_with_doughnut(cone_height))
            .at([0.016, 0.0, 0.095])
            .scene()
            .simulation();
        let what = format!("column and cone {cone_height}");
        let run = run_in_crease(sim, 248, 150, &what);
        assert!(run.deposits_on(0) <= 1 && run.deposits_on(1) <= 1, "{what}: {:#?}", run.listed());
        let column = wetbounce::Other::Wall(0);
        assert!(
            run.events.iter().any(|e| e.other == column),
            "{what}: the bead should reach the column wall"
        );
        assert_eq!(run.late_events, 0, "{what}: contacts after settling");
        assert_eq!(run.after_crease, Some(0), "{what}: contacts once in the corner: {:#?}", run.listed());
        assert!(run.events.len() <= 12, "{what}: {} contacts", run.events.len());
        assert_eq!(run.state, wetbounce::particles::State::Resting, "{what}");
        // At rest, or creeping along the crease: the cone is faceted (128 flat sectors), so
        // its crease with the column dips by 1-5 µm between sectors (more for a steeper
        // cone), and a 2.5 mm bead in water swings to and fro in such a dip, at up to
        // √(2 g Δz) ≈ 7 mm/s, for a second or so (its drag relaxation time).
        assert!(run.velocity.length() < 1e-2, "{what}: still moving at {:?}", run.velocity);
    }
}

/// Two planes in a V along the y axis, each at 45°.
const VEE: &str = "[[walls]]\nname = \"a\"\ntype = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 1.0]\n\n[[walls]]\nname = \"b\"\ntype = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [-1.0, 0.0, 1.0]\n";

#[test]
fn bead_in_a_vee_of_two_planes_slides_along_its_crease_with_one_deposit_per_plane() {
    // Regression (issue 25): with gravity along the V's crease as well, the bead reached the
    // crease and recorded 32 deposits per step while it slid along it.
    let sim = BeadOnFloor::new()
        .dt(1e-3)
        .gravity([0.0, -1.0, -9.8])
        .walls(VEE)
        .at([0.005, 0.001, 0.01])
        .scene()
        .simulation();
    let run = run_in_crease(sim, 500, 300, "vee");
    assert!(run.deposits_on(0) <= 1 && run.deposits_on(1) <= 1, "{:#?}", run.listed());
    assert_eq!(run.late_events, 0);
    assert_eq!(run.after_crease, Some(0), "{:#?}", run.listed());
    assert_eq!(run.state, wetbounce::particles::State::Resting);
    // Sliding along the crease (the y axis), at its terminal speed there.
    let v = run.velocity;
    assert!(v.y < -1e-3 && v.x.abs() + v.z.abs() < 1e-12 * v.length(), "velocity {v:?}");
}

mod creases {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::Config;

    /// A wall through the y axis (the crease line) with unit normal `n` (in the xz plane).
    #[derive(Debug, Clone, Copy)]
    pub enum Flat {
        Plane,
        /// A flat mesh: an annulus of no hole, 0.2 m across.
        Mesh,
        /// The top face of a box obstacle (only for a horizontal face).
        Box,
        /// The inside of a pipe along y, 5 mm in radius, touching the crease line.
        Pipe,
    }

    pub fn wall(name: &str, kind: Flat, n: DVec3) -> String {
        let v = |v: DVec3| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z);
        match kind {
            Flat::Plane => {
                format!("[[walls]]\nname = \"{name}\"\ntype = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = {}\n\n", v(n))
            }
            Flat::Mesh => format!(
                "[[walls]]\nname = \"{name}\"\ntype = \"annulus\"\ncenter = [0.0, 0.0, 0.0]\nnormal = {}\nouter_radius = 0.1\nsegments = 16\n\n",
                v(n)
            ),
            Flat::Box => "[[walls]]\nname = \"box\"\ntype = \"box\"\nmin = [-0.1, -0.1, -0.1]\nmax = [0.1, 0.1, 0.0]\ninside = false\n\n".to_string(),
            Flat::Pipe => format!(
                "[[walls]]\nname = \"{name}\"\ntype = \"cylinder\"\nbase = {}\naxis = [0.0, 1.0, 0.0]\nradius = 0.005\n\n",
                v(0.005 * n)
            ),
        }
    }

    fn pair() -> impl Strategy<Value = (Flat, Flat)> {
        prop_oneof![
            Just((Flat::Plane, Flat::Plane)),
            Just((Flat::Mesh, Flat::Plane)),
            Just((Flat::Plane, Flat::Mesh)),
            Just((Flat::Mesh, Flat::Mesh)),
            Just((Flat::Box, Flat::Plane)),
            Just((Flat::Box, Flat::Mesh)),
            Just((Flat::Pipe, Flat::Plane)),
            Just((Flat::Pipe, Flat::Mesh)),
        ]
    }

    proptest! {
        // A fixed seed, so that CI runs the same 256 cases every time; `WETBOUNCE_CREASE_SEED=N`
        // runs others (seeds 1 to 120 pass; before the fixes of the cases below, about one
        // seed in four found one).
        #![proptest_config(Config {
            cases: 256,
            failure_persistence: None,
            rng_seed: proptest::test_runner::RngSeed::Fixed(crease_seed()),
            ..Config::default()
        })]

        /// A bead put on a wall, or dropped onto it, next to its crease with a second wall —
        /// closed-form with mesh, mesh with mesh, cylinder with plane or mesh, box with plane or
        /// mesh — of any opening (10° to 170°), under gravity into the crease from any side and
        /// possibly along it: at most one deposit per wall (from rest into a crease of 90° or
        /// less; a few otherwise), then resting (still or sliding along the crease) with no
        /// further contact — not 32 per step as before; never inside a wall (1e-9 r), never more
        /// kinetic energy than its weight gave it. In an oil (St < St_c at any speed it
        /// reaches): every contact is a deposit.
        #[test]
        fn a_bead_in_a_crease_of_two_walls_deposits_at_most_once_per_wall_then_rests_or_slides(
            (a_kind, b_kind) in pair(),
            a_deg in 5.0f64..85.0,
            b_deg in 5.0f64..85.0,
            share in 0.0f64..1.0,
            along in prop_oneof![Just(0.0), -0.5f64..0.5],
            offset in 0.0f64..0.3,
            height in prop_oneof![Just(0.0), 0.0f64..0.5],
        ) {
            crease_case((a_kind, b_kind), (a_deg, b_deg), share, along, offset, height)?;
        }
    }

    /// The property's seed: `WETBOUNCE_CREASE_SEED`, or the one CI runs.
    fn crease_seed() -> u64 {
        std::env::var("WETBOUNCE_CREASE_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(2)
    }

    /// One case of the property above.
    #[allow(clippy::too_many_arguments)]
    fn crease_case(
        (a_kind, b_kind): (Flat, Flat),
        (a_deg, b_deg): (f64, f64),
        share: f64,
        along: f64,
        offset: f64,
        height: f64,
    ) -> Result<(), TestCaseError> {
        let a_deg = if matches!(a_kind, Flat::Box) { 0.0 } else { a_deg };
        // A pipe 2.5 bead diameters across leaves no room for the bead in a crease sharper
        // than 90° with a plane through its tangent line.
        let b_deg = if matches!(a_kind, Flat::Pipe) { b_deg.min(90.0 - a_deg).max(1.0) } else { b_deg };
        let (a, b) = (a_deg.to_radians(), b_deg.to_radians());
        let na = DVec3::new(a.sin(), 0.0, a.cos());
        let nb = DVec3::new(-b.sin(), 0.0, b.cos());
        let walls = wall("a", a_kind, na) + &wall("b", b_kind, nb);
        let into = -(share * na + (1.0 - share) * nb).normalize();
        let g = 9.81 * (into + DVec3::new(0.0, along, 0.0)).normalize();
        let r = 1e-3;
        // `offset` radii along wall a from where it would touch wall b as well (the crease
        // position: on both tangent planes), raised `height` radii along their bisector.
        let crease = {
            let (c, s) = (na.dot(nb), 1.0 - na.dot(nb).powi(2));
            r * ((1.0 - c) / s) * (na + nb)
        };
        let up_a = na.cross(DVec3::Y).normalize();
        let away = if up_a.dot(nb) > 0.0 { up_a } else { -up_a };
        let mut x = crease + r * (offset * away + height * (na + nb).normalize());
        if matches!(a_kind, Flat::Pipe) {
            // The pipe curves in from its tangent plane: inside it, and clear of b.
            let axis = 0.005 * na;
            let (reach, above) = (0.005 - r * (1.0 + 1e-6), r * (1.0 + 1e-6));
            for _ in 0..10_000 {
                let d = (x - axis).length();
                if d > reach {
                    x = axis + (x - axis) * (reach / d);
                }
                x += (above - x.dot(nb)).max(0.0) * nb;
            }
        }
        let sim = BeadOnFloor::new()
            .fluid(900.0, 0.05)
            .dt(1e-3)
            .gravity(g)
            .walls(&walls)
            .at(x)
            .scene()
            .simulation();
        let what = format!("{a_kind:?} at {a_deg:.1}°, {b_kind:?} at {b_deg:.1}°, g {g:?}, start {x:?}");
        let run = run_in_crease(sim, 300, 150, &what);
        // From rest on one wall into a crease of 90° or less: one deposit per wall, the
        // second putting it into the crease for good. Dropped from a height, or into a
        // wider crease, it may cross or be turned up the other wall (frictionless sliding
        // keeps the velocity along the wall it meets) and arrive again: a few deposits.
        // Across a wide crease under tilted gravity it may also swing to and fro, a
        // deposit at each crossing, slower each time: never more than two in a step (the
        // bug gave 32 in every step).
        let acute = a_deg + b_deg >= 90.0;
        if acute {
            if height == 0.0 {
                prop_assert!(
                    run.deposits_on(0) <= 1 && run.deposits_on(1) <= 1,
                    "{}: {:#?}",
                    what,
                    run.listed()
                );
            }
            prop_assert!(run.events.len() <= 6, "{}: {:#?}", what, run.listed());
            prop_assert!(run.after_crease.is_none_or(|n| n == 0), "{}: {:#?}", what, run.listed());
        }
        prop_assert!(run.most_in_a_step <= 2, "{}: {:#?}", what, run.listed());
        prop_assert!(
            run.events.iter().all(|e| e.outcome == wetbounce::Outcome::Deposited),
            "{}: {:#?}",
            what,
            run.listed()
        );
        prop_assert_eq!(run.state, wetbounce::particles::State::Resting, "{}", what);
        Ok(())
    }

    /// Found by unseeded runs of the property (issue 25): the bead ended a step 2.4e-7 of its
    /// radius inside a facet of a narrow crease (20°) of two meshes. Pushed out of each wall in
    /// turn, 64 rounds shrank the overlap by only 0.88 each; now it is put on the crease line.
    #[test]
    fn mesh_mesh_crease_keeps_the_bead_outside_both_meshes() {
        crease_case(
            (Flat::Mesh, Flat::Mesh),
            (77.0481658655939, 82.72321754995679),
            0.5069522134148056,
            0.0,
            0.0,
            0.0,
        )
        .unwrap();
    }

    /// Found by unseeded runs of the property (issue 25): resting on a plane and sliding at a
    /// grazing angle into a mesh facet, the bead ended 2.3e-6 r inside it and no contact was
    /// found (parry's cast misses a crossing shallower than its tolerance).
    #[test]
    fn sliding_at_a_grazing_angle_into_a_mesh_meets_it() {
        crease_case(
            (Flat::Mesh, Flat::Plane),
            (23.757265257594618, 72.79442669979896),
            0.00213006446536602,
            0.0,
            0.0991940066479987,
            0.0,
        )
        .unwrap();
        crease_case(
            (Flat::Mesh, Flat::Mesh),
            (52.91595688085716, 50.190618133433745),
            0.0034309143499687412,
            0.0,
            0.21718199450251013,
            0.0,
        )
        .unwrap();
        crease_case(
            (Flat::Plane, Flat::Mesh),
            (37.32803163103946, 81.33337387529227),
            0.45759971855186643,
            0.0,
            0.17756759515367018,
            0.05235833054666239,
        )
        .unwrap();
    }

    /// Found by unseeded runs of the property (issue 25): in a crease of two planes at 5° and
    /// 14.3° under tilted gravity, the kinetic energy at the second step was three times the
    /// work of the weight. Deposited on one wall and moving away from the other, the bead was
    /// turned back by its weight within the step, integrated through the crease and pushed
    /// back out with the speed it gained below it; now it stops where it reaches the crease.
    #[test]
    fn wide_crease_of_two_planes_gains_no_energy() {
        crease_case(
            (Flat::Plane, Flat::Plane),
            (5.0, 14.347503844952508),
            0.9154358025743472,
            0.0,
            0.00042455011536845393,
            0.0,
        )
        .unwrap();
    }

    /// The same on the top of a box, into a plane at 55° (found by the property's seed 7): the
    /// kinetic energy at step 194 was twice the work of the weight.
    #[test]
    fn box_top_and_steep_plane_crease_gains_no_energy() {
        crease_case(
            (Flat::Box, Flat::Plane),
            (5.0, 55.20698740174204),
            0.9953962138522325,
            0.0,
            0.047588284184299716,
            0.0,
        )
        .unwrap();
    }
}
