//! Issue 13, finding 1: a particle that reaches two faces of one box (or two facets of one mesh)
//! in the same step must rebound off both. It used to be recorded `deposited` with
//! `normal_speed 0` at the second contact and end at rest: the bounce took the wall's *nearest*
//! part as the contact normal, and right after the first rebound the particle is as near to
//! the face it has just left as to the one it still approaches.
//!
//! The class test throws beads, in vacuum with ε = 1 (no loss anywhere), into the corners and
//! edges of a box and into the crease of a mesh: the kinetic energy must stay what it was —
//! the stability tests only check that it never rises, which cannot see a loss.

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;
use proptest::prelude::*;
use wetbounce::{Outcome, Simulation};

const D: f64 = 2.5e-3;

/// A steel bead in vacuum (no force: straight flights, St = ∞, ε = ε_max = 1) in `walls`.
fn steel_in_vacuum(dt: f64, walls: &str) -> BeadOnFloor {
    BeadOnFloor::new()
        .dt(dt)
        .vacuum()
        .effects("")
        .kind("steel")
        .density(7800.0)
        .elastic(2e11, 0.3)
        .restitution_max(1.0)
        .walls(walls)
        .diameter(D)
}

fn vacuum(dt: f64, walls: &str, starts: &[(DVec3, DVec3)]) -> Simulation {
    steel_in_vacuum(dt, walls).particles(starts).scene().simulation()
}

const BOX: &str = r#"
[[walls]]
name = "box"
type = "box"
min = [0.0, 0.0, 0.0]
max = [0.02, 0.02, 0.02]
inside = true
"#;

fn kinetic(sim: &Simulation) -> f64 {
    sim.world.particles.vel.iter().map(|v| 0.5 * v.length_squared()).sum()
}

#[test]
fn bead_reaching_two_box_faces_in_one_step_keeps_its_speed() {
    // The reproducer of the finding: both side faces reached at t = 10 ms, inside one step.
    let v0 = DVec3::new(-0.1, -0.1, 0.0);
    let mut sim = vacuum(1e-3, BOX, &[(DVec3::new(0.00225, 0.00225, 0.01), v0)]);
    let events = common::run_collect(&mut sim, 1.0);
    assert!(events.len() >= 10, "it keeps bouncing: {} contacts", events.len());
    for e in &events {
        assert_eq!(e.outcome, Outcome::Bounced, "{e:?}");
        assert!((e.normal_speed - 0.1).abs() < 1e-12, "each face is met at 0.1 m/s: {e:?}");
    }
    let speed = sim.world.particles.vel[0].length();
    assert!((speed - v0.length()).abs() < 1e-12 * v0.length(), "speed {speed}");
}

#[test]
fn glass_bead_released_touching_a_side_face_rebounds_off_the_floor() {
    // L06's glass bead in water, released at rest touching the box's side face: it settles and
    // rebounds off the floor with falling St (six times), as beside no side face (finding 1:
    // one deposit at normal_speed 0).
    let box_wall = r#"
[[walls]]
name = "box"
type = "box"
min = [0.0, 0.0, 0.0]
max = [0.05, 0.05, 0.1]
inside = true
material = { youngs_modulus = 6.3e10, poisson_ratio = 0.23 }
"#;
    let beside = |x: f64| {
        let mut sim = BeadOnFloor::new()
            .dt(2e-4)
            .output_interval(0.01)
            .fluid(998.0, 1.0e-3)
            .effects("gravity = {}\nbuoyancy = {}\ndrag = { law = \"schiller_naumann\" }\nadded_mass = {}")
            .density(2540.0)
            .elastic(6.3e10, 0.23)
            .restitution_max(0.97)
            .walls(box_wall)
            .diameter(D)
            .at([x, 0.025, 0.05])
            .scene()
            .simulation();
        common::run_collect(&mut sim, 1.0)
    };
    let touching = beside(0.5 * D);
    let apart = beside(0.025);
    let floor_bounces = |events: &[wetbounce::ContactEvent]| {
        events.iter().filter(|e| e.outcome == Outcome::Bounced && e.normal_speed > 0.0).count()
    };
    assert!(floor_bounces(&apart) >= 5, "the reference bead rebounds: {apart:?}");
    assert_eq!(floor_bounces(&touching), floor_bounces(&apart), "{touching:?}");
    for (a, b) in touching.iter().zip(&apart) {
        assert!((a.normal_speed - b.normal_speed).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

/// A V-shaped crease of two facets meeting along the y axis at z = 0, 90° between them.
const CREASE_OBJ: &str = "v -0.05 -0.05 0.05\nv -0.05 0.05 0.05\nv 0 -0.05 0\nv 0 0.05 0\nv 0.05 -0.05 0.05\nv 0.05 0.05 0.05\n\
                          f 1 3 4\nf 1 4 2\nf 3 5 6\nf 3 6 4\n";

#[test]
fn bead_into_a_mesh_crease_keeps_its_speed() {
    let dir = tempfile::tempdir().unwrap();
    // Straight down into the crease's bottom line: it meets both facets at once.
    let v0 = DVec3::new(0.0, 0.0, -0.2);
    let crease = "[[walls]]\nname = \"crease\"\ntype = \"mesh\"\nfile = \"crease.obj\"\n";
    let sim_text = |x: f64| steel_in_vacuum(1e-3, crease).particle([x, 0.0, 0.02], v0).toml();
    std::fs::write(dir.path().join("crease.obj"), CREASE_OBJ).unwrap();
    for x in [0.0, 1e-4, -3e-4] {
        let path = dir.path().join("s.toml");
        std::fs::write(&path, sim_text(x)).unwrap();
        let mut sim = wetbounce::Scene::load(&path).unwrap_or_else(|e| panic!("{e}")).simulation();
        let events = common::run_collect(&mut sim, 0.3);
        assert!(!events.is_empty());
        assert!(events.iter().all(|e| e.outcome == Outcome::Bounced), "x = {x}: {events:?}");
        let speed = sim.world.particles.vel[0].length();
        assert!((speed - 0.2).abs() < 1e-9, "x = {x}: speed {speed}");
        common::assert_clear_of_walls(&sim);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Class test: beads thrown at random into the corners and edges of a box, in vacuum with
    /// ε = 1, keep their kinetic energy through every contact, and never deposit.
    #[test]
    fn beads_in_box_corners_and_edges_lose_no_energy_in_vacuum(
        corner in 0usize..8,
        offset in prop::array::uniform3(0.0f64..1.5),
        direction in prop::array::uniform3(-1.0f64..1.0),
        speed in 0.01f64..2.0,
        dt in prop::sample::select(vec![1e-4, 1e-3, 1e-2]),
    ) {
        // A start within 1.5 diameters of a corner (on each axis), moving towards it.
        let c = DVec3::new((corner & 1) as f64, ((corner >> 1) & 1) as f64, ((corner >> 2) & 1) as f64) * 0.02;
        let inward = DVec3::ONE - 2.0 * c / 0.02;
        let x = c + inward * (0.5 * D + DVec3::from(offset) * D);
        let dir = DVec3::from(direction) - inward;
        prop_assume!(dir.length() > 1e-3);
        let v = dir.normalize() * speed;
        let mut sim = vacuum(dt, BOX, &[(x, v)]);
        let e0 = kinetic(&sim);
        let events = common::run_collect(&mut sim, 0.2);
        for e in &events {
            prop_assert_eq!(e.outcome, Outcome::Bounced, "{:?}", e);
        }
        let e1 = kinetic(&sim);
        prop_assert!((e1 - e0).abs() <= 1e-9 * e0, "energy {} -> {} after {} contacts", e0, e1, events.len());
        common::assert_clear_of_walls(&sim);
    }

    /// Class test, for the facets of a mesh: beads thrown at random into the crease (near its
    /// bottom line, where one step can reach both facets), in vacuum with ε = 1, keep their
    /// kinetic energy through every contact and never deposit. Slow enough (≤ 0.1 m/s for
    /// 0.3 s) to stay over the mesh, whose open edges are another matter.
    #[test]
    fn beads_into_a_mesh_crease_lose_no_energy_in_vacuum(
        across in -0.5f64..0.5,
        along in -0.01f64..0.01,
        height in 0.0f64..1.5,
        direction in prop::array::uniform3(-1.0f64..1.0),
        speed in 0.01f64..0.1,
        dt in prop::sample::select(vec![1e-4, 1e-3, 1e-2]),
    ) {
        // Above the bottom line, clear of both facets (z = |x|): a gap of `height` diameters.
        let r = 0.5 * D;
        let x = DVec3::new(across * D, along, (across * D).abs() + std::f64::consts::SQRT_2 * (r + height * D));
        let dir = DVec3::from(direction) - DVec3::Z;
        prop_assume!(dir.length() > 1e-3);
        let v = dir.normalize() * speed;
        let dir_path = tempfile::tempdir().unwrap();
        std::fs::write(dir_path.path().join("crease.obj"), CREASE_OBJ).unwrap();
        let crease = "[[walls]]\nname = \"crease\"\ntype = \"mesh\"\nfile = \"crease.obj\"\n";
        let path = dir_path.path().join("s.toml");
        std::fs::write(&path, steel_in_vacuum(dt, crease).particle(x.to_array(), v).toml()).unwrap();
        let mut sim = wetbounce::Scene::load(&path).unwrap_or_else(|e| panic!("{e}")).simulation();
        let e0 = kinetic(&sim);
        let events = common::run_collect(&mut sim, 0.3);
        for e in &events {
            prop_assert_eq!(e.outcome, Outcome::Bounced, "{:?}", e);
        }
        let e1 = kinetic(&sim);
        prop_assert!((e1 - e0).abs() <= 1e-9 * e0, "energy {} -> {} after {} contacts", e0, e1, events.len());
        common::assert_clear_of_walls(&sim);
    }
}
