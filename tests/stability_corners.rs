//! Stability case 4 (docs/stability.md): corners and edges. Beads thrown into the corner of a
//! box (inside, and at the convex corner of a box obstacle), at the rims of an annular baffle
//! (its hole and its outer edge), and grazing (89°) along the inside of a cylinder. With no
//! force acting, the kinetic energy must never rise — not at a contact, not between steps —
//! and after every step each bead is outside every wall.

mod common;
use common::fixture::BeadOnFloor;
use glam::DVec3;

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
    // Regression (found by tests/stability_properties.rs): a bead resting on one face of a box
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
