//! Triangle-mesh walls: the 40 mm × 40 mm × 1 mm plate of `scenes/meshes/` (top face at z = 0,
//! centred on the z axis) in ASCII STL, binary STL and OBJ loads with its 12 triangles, a bead
//! dropped on it bounces as on the plane z = 0, and a fast bead with a huge step does not
//! tunnel through it (nor through the equal closed-form box).

use crate::common;

use common::fixture::{BeadOnFloor, FLOOR};
use glam::DVec3;
use std::path::{Path, PathBuf};
use wetbounce::Outcome;
use wetbounce::{Other, Scene, Simulation};

/// The plate in its three formats, relative to `scenes/`.
const PLATE_FILES: [&str; 3] = ["meshes/plate_ascii.stl", "meshes/plate_binary.stl", "meshes/plate.obj"];

/// Half-width and thickness of the plate (m).
const HALF_WIDTH: f64 = 0.02;
const THICKNESS: f64 = 0.001;

/// Bead diameter and radius (m).
const D: f64 = 2e-3;
const R: f64 = 0.5 * D;

/// Initial gap between the bead and the plate's top face (m).
const DROP_GAP: f64 = 0.010;

/// Bead centres over the plate: on the diagonal shared by the two top triangles, and inside one.
const XY: [[f64; 2]; 2] = [[0.0, 0.0], [0.005, -0.007]];

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn mesh_wall(file: &str) -> String {
    format!("[[walls]]\nname = \"plate\"\ntype = \"mesh\"\nfile = \"{file}\"\n")
}

fn plate_box() -> String {
    format!(
        "[[walls]]\nname = \"plate\"\ntype = \"box\"\nmin = [{m}, {m}, {b}]\nmax = [{h}, {h}, 0.0]\ninside = false\n",
        m = -HALF_WIDTH,
        h = HALF_WIDTH,
        b = -THICKNESS
    )
}

/// A vacuum scene with one elastic 2 mm glass bead at `pos` moving at `vel`.
fn vacuum_scene(dt: f64, effects: &str, wall: &str, pos: DVec3, vel: DVec3) -> Scene {
    BeadOnFloor::new()
        .dt(dt)
        .output_interval(1e-3)
        .vacuum()
        .gravity([0.0, 0.0, -9.81])
        .effects(effects)
        .kind("bead")
        .restitution_max(1.0)
        .walls(wall)
        .particle(pos, vel)
        .scene()
}

/// Advances `sim` by `steps` steps of `dt`, returning the lowest centre height at a step end.
fn run_steps(sim: &mut Simulation, dt: f64, steps: usize) -> f64 {
    let mut lowest = sim.world.particles.pos[0].z;
    for k in 1..=steps {
        sim.advance_to(k as f64 * dt);
        lowest = lowest.min(sim.world.particles.pos[0].z);
    }
    lowest
}

#[test]
fn plate_loads_with_12_triangles_from_ascii_stl_binary_stl_and_obj() {
    for file in PLATE_FILES {
        let path = scenes_dir().join(file);
        let mesh =
            wetbounce::walls::load_mesh(&path, 1.0, DVec3::ZERO).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(mesh.mesh.num_triangles(), 12, "{file}");
        // The files hold f32 coordinates: 0.02 is off by ~5e-10.
        let aabb = mesh.mesh.local_aabb();
        let (lo, hi) =
            (DVec3::new(-HALF_WIDTH, -HALF_WIDTH, -THICKNESS), DVec3::new(HALF_WIDTH, HALF_WIDTH, 0.0));
        assert!(
            (aabb.mins - lo).abs().max_element() < 1e-8 && (aabb.maxs - hi).abs().max_element() < 1e-8,
            "{file}: bounding box {:?} .. {:?}",
            aabb.mins,
            aabb.maxs
        );
        assert_eq!(aabb.maxs.z, 0.0, "{file}: the top face must be exactly at z = 0");
    }
}

/// Drops the bead from `DROP_GAP` above z = 0 onto `wall` in vacuum; returns the impact time,
/// after checking there is exactly one bounce on wall 0 and the bead never goes below z = R.
fn drop_on(wall: &str, xy: [f64; 2], what: &str) -> f64 {
    let dt = 1e-4;
    let start = DVec3::new(xy[0], xy[1], R + DROP_GAP);
    let scene = vacuum_scene(dt, "gravity = {}", wall, start, DVec3::ZERO);
    let mut sim = scene.simulation();
    // Impact at ~45 ms, back at the top at ~90 ms, second impact at ~135 ms.
    let lowest = run_steps(&mut sim, dt, 1200);
    assert!(lowest >= R * (1.0 - 1e-9), "{what}: the bead went down to z = {lowest}, below its radius {R}");
    assert_eq!(sim.record.events.len(), 1, "{what}: {:?}", sim.record.events);
    let e = sim.record.events[0];
    assert_eq!(e.other, Other::Wall(0), "{what}");
    assert_eq!(e.outcome, Outcome::Bounced, "{what}: {e:?}");
    assert!((e.eps - 1.0).abs() < 1e-12, "{what}: vacuum gives eps_max: {e:?}");
    // Elastic bounce straight up: at 0.12 s the bead is where the mirrored parabola puts it.
    let (g, t1, t) = (9.81, e.time, sim.world.time);
    let z = R + g * t1 * (t - t1) - 0.5 * g * (t - t1) * (t - t1);
    let p = sim.world.particles.pos[0];
    assert!(
        (p - DVec3::new(xy[0], xy[1], z)).length() < 1e-9,
        "{what}: at t = {t} s the bead is at {p}, expected z = {z}"
    );
    e.time
}

#[test]
fn bead_dropped_on_mesh_plate_bounces_at_the_same_time_as_on_a_plane() {
    let free_fall = (2.0 * DROP_GAP / 9.81f64).sqrt();
    for xy in XY {
        let on_plane = drop_on(FLOOR, xy, "plane");
        assert!(
            ((on_plane - free_fall) / free_fall).abs() < 1e-9,
            "plane: impact at {on_plane} s, free fall gives {free_fall} s"
        );
        for file in PLATE_FILES {
            let what = format!("{file} at {xy:?}");
            let on_mesh = drop_on(&mesh_wall(file), xy, &what);
            assert!(
                ((on_mesh - on_plane) / on_plane).abs() < 1e-9,
                "{what}: impact at {on_mesh} s on the mesh, {on_plane} s on the plane"
            );
        }
    }
}

/// A bead 10 mm above the 1 mm plate moving down at 10 m/s with Δt = 10 ms (it would cross
/// the plate 100 times over in one step): it must bounce once and stay above the plate.
fn fast_bead_stays_above(wall: &str, xy: [f64; 2], what: &str) {
    let dt = 1e-2;
    let start = DVec3::new(xy[0], xy[1], R + DROP_GAP);
    let scene = vacuum_scene(dt, "", wall, start, DVec3::new(0.0, 0.0, -10.0));
    let mut sim = scene.simulation();
    let mut lowest = f64::INFINITY;
    for k in 1..=5 {
        sim.advance_to(k as f64 * dt);
        let z = sim.world.particles.pos[0].z;
        assert!(z > 0.0, "{what}: after step {k} the bead is at z = {z}, inside or below the plate");
        lowest = lowest.min(z);
    }
    assert!(lowest >= R * (1.0 - 1e-9), "{what}: lowest z = {lowest}");
    assert_eq!(sim.record.events.len(), 1, "{what}: {:?}", sim.record.events);
    let e = sim.record.events[0];
    assert_eq!(e.other, Other::Wall(0), "{what}");
    assert_eq!(e.outcome, Outcome::Bounced, "{what}: {e:?}");
    let t_hit = DROP_GAP / 10.0;
    assert!((e.time - t_hit).abs() < 1e-12, "{what}: impact at {} s, expected {t_hit} s", e.time);
    let v = sim.world.particles.vel[0];
    assert!((v - DVec3::new(0.0, 0.0, 10.0)).length() < 1e-9, "{what}: velocity after the bounce {v}");
}

#[test]
fn fast_bead_with_large_step_does_not_tunnel_through_thin_mesh_plate_or_box() {
    for xy in XY {
        for file in PLATE_FILES {
            fast_bead_stays_above(&mesh_wall(file), xy, &format!("{file} at {xy:?}"));
        }
        fast_bead_stays_above(&plate_box(), xy, &format!("box at {xy:?}"));
    }
}
