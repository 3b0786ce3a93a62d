//! Dense contacts stay sound and come to rest: glass beads poured into a box of water never
//! overlap by more than 1 % of a diameter, never go below the floor or through a wall, none is
//! lost, and the bed they form ends at rest (the lasting contacts carry its weight).

mod common;
use std::path::Path;
use wetbounce::{Scene, Simulation};

const D: f64 = 2.5e-3;
/// Settling speed of a lone bead (m/s): `wetbounce check` on these beads gives 0.327 m/s.
const SETTLING_SPEED: f64 = 0.327;

/// Runs the scene to its end, checking overlaps and walls every 20 ms; returns the simulation
/// and the number of particle–particle contact events.
fn pour_checked(scene: &Scene, box_side: f64) -> (Simulation, usize) {
    let mut sim = scene.simulation();
    let mut pair_events = 0;
    while sim.time < scene.duration {
        let t = (sim.time + 0.02).min(scene.duration);
        pair_events += common::run_collect(&mut sim, t)
            .iter()
            .filter(|e| matches!(e.other, wetbounce::Other::Particle(_)))
            .count();
        let p = &sim.particles;
        let inside = |c: f64| (0.5 * D * (1.0 - 1e-12)..=box_side - 0.5 * D * (1.0 - 1e-12)).contains(&c);
        for i in 0..p.len() {
            let x = p.pos[i];
            assert!(
                x.z >= 0.5 * D * (1.0 - 1e-12),
                "t = {}: bead {i} below the floor: z = {}",
                sim.time,
                x.z
            );
            assert!(inside(x.x) && inside(x.y), "t = {}: bead {i} through a side wall: {x}", sim.time);
            for j in i + 1..p.len() {
                let overlap = D - (p.pos[j] - x).length();
                assert!(
                    overlap < 0.01 * D,
                    "t = {}: beads {i}, {j} overlap by {:.2e} d",
                    sim.time,
                    overlap / D
                );
            }
        }
    }
    (sim, pair_events)
}

/// At rest: the mean speed is below 0.1 % of the settling speed (0.3 mm/s), 99 % of the beads
/// move slower than 1 % of it, and none faster than 5 %. Not zero: the beads are frictionless
/// (the engine has no tangential contact force), so a bed keeps creeping slowly into hollows.
fn assert_at_rest(sim: &Simulation) {
    let mut speeds: Vec<f64> = sim.particles.vel.iter().map(|v| v.length()).collect();
    speeds.sort_by(f64::total_cmp);
    let mean = speeds.iter().sum::<f64>() / speeds.len() as f64;
    let p99 = speeds[speeds.len() * 99 / 100];
    let max = speeds[speeds.len() - 1];
    eprintln!("speeds at the end: mean {mean:.2e}, 99th percentile {p99:.2e}, largest {max:.2e} m/s");
    assert!(mean < 1e-3 * SETTLING_SPEED, "mean speed {mean:.2e} m/s");
    assert!(p99 < 1e-2 * SETTLING_SPEED, "99th percentile speed {p99:.2e} m/s");
    assert!(max < 5e-2 * SETTLING_SPEED, "largest speed {max:.2e} m/s");
}

#[test]
fn poured_beads_never_overlap_more_than_one_percent_or_leave_the_box_and_come_to_rest() {
    let scene =
        Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/pour_200.toml")).unwrap();
    let (sim, pair_events) = pour_checked(&scene, 0.015);
    assert!(sim.lost.is_empty());
    assert_eq!(sim.particles.len(), 200);
    assert!(pair_events > 100, "{pair_events} pair contacts");
    assert_at_rest(&sim);
}

/// The shipped 2000-bead bed (`scenes/settling_bed.toml`, 2 s): about a minute.
#[test]
fn settling_bed_of_2000_beads_ends_at_rest_without_overlap_or_bead_below_the_floor() {
    let scene = Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/settling_bed.toml")).unwrap();
    let (sim, _) = pour_checked(&scene, 0.04);
    assert!(sim.lost.is_empty());
    assert_eq!(sim.particles.len(), 2000);
    assert_at_rest(&sim);
}
