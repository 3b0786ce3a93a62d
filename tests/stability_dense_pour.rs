//! Dense contacts stay sound and come to rest: glass beads poured into a box of water never
//! overlap by more than 1 % of a diameter, never go below the floor or through a wall, none is
//! lost, and the bed they form ends at rest (the lasting contacts carry its weight).

mod common;
use std::path::Path;
use wetbounce::{Scene, Simulation};

const D: f64 = 2.5e-3;
/// Settling speed of a lone bead (m/s): `wetbounce check` on these beads gives 0.327 m/s.
const SETTLING_SPEED: f64 = 0.327;

/// Speeds of the beads at one instant (m/s): mean, 99th percentile, largest.
#[derive(Debug, Clone, Copy)]
struct Speeds {
    mean: f64,
    p99: f64,
    max: f64,
}

fn speeds(sim: &Simulation) -> Speeds {
    let mut s: Vec<f64> = sim.world.particles.vel.iter().map(|v| v.length()).collect();
    s.sort_by(f64::total_cmp);
    Speeds { mean: s.iter().sum::<f64>() / s.len() as f64, p99: s[s.len() * 99 / 100], max: s[s.len() - 1] }
}

/// Runs the scene to its end, checking overlaps and walls every 20 ms; returns the simulation,
/// the number of particle–particle contact events and the speeds at the checks of the last
/// 0.1 s.
fn pour_checked(scene: &Scene, box_side: f64) -> (Simulation, usize, Vec<Speeds>) {
    let mut sim = scene.simulation();
    let mut pair_events = 0;
    let mut last = Vec::new();
    while sim.world.time < scene.duration {
        let t = (sim.world.time + 0.02).min(scene.duration);
        pair_events += common::run_collect(&mut sim, t)
            .iter()
            .filter(|e| matches!(e.other, wetbounce::Other::Particle(_)))
            .count();
        let p = &sim.world.particles;
        let inside = |c: f64| (0.5 * D * (1.0 - 1e-12)..=box_side - 0.5 * D * (1.0 - 1e-12)).contains(&c);
        for i in 0..p.len() {
            let x = p.pos[i];
            assert!(
                x.z >= 0.5 * D * (1.0 - 1e-12),
                "t = {}: bead {i} below the floor: z = {}",
                sim.world.time,
                x.z
            );
            assert!(inside(x.x) && inside(x.y), "t = {}: bead {i} through a side wall: {x}", sim.world.time);
            for j in i + 1..p.len() {
                let overlap = D - (p.pos[j] - x).length();
                assert!(
                    overlap < 0.01 * D,
                    "t = {}: beads {i}, {j} overlap by {:.2e} d",
                    sim.world.time,
                    overlap / D
                );
            }
        }
        if sim.world.time > scene.duration - 0.1 - 1e-9 {
            last.push(speeds(&sim));
        }
    }
    (sim, pair_events, last)
}

/// At rest over the last 0.1 s (five checks, 20 ms apart): averaged over them, the mean speed
/// is below 0.1 % of the settling speed (0.3 mm/s) and the 99th percentile below 1 %; at every
/// check no bead moves faster than 5 %. Averaged because the beads are frictionless (the engine
/// has no tangential contact force): the bed keeps creeping, and now and then a bead or a small
/// group drops into a hollow below it — a fall of 0.06 mm reaches 8 % of the settling speed —
/// so one instant can land on such a drop.
fn assert_at_rest(last: &[Speeds]) {
    assert!((5..=6).contains(&last.len()), "{last:?}");
    let n = last.len() as f64;
    let mean = last.iter().map(|s| s.mean).sum::<f64>() / n;
    let p99 = last.iter().map(|s| s.p99).sum::<f64>() / n;
    let max = last.iter().map(|s| s.max).fold(0.0, f64::max);
    eprintln!(
        "speeds over the last 0.1 s: mean {mean:.2e}, 99th percentile {p99:.2e}, largest {max:.2e} m/s"
    );
    for s in last {
        eprintln!("  mean {:.2e}, 99th percentile {:.2e}, largest {:.2e}", s.mean, s.p99, s.max);
    }
    assert!(mean < 1e-3 * SETTLING_SPEED, "mean speed {mean:.2e} m/s");
    assert!(p99 < 1e-2 * SETTLING_SPEED, "99th percentile speed {p99:.2e} m/s");
    assert!(max < 5e-2 * SETTLING_SPEED, "largest speed {max:.2e} m/s");
}

#[test]
fn poured_beads_never_overlap_more_than_one_percent_or_leave_the_box_and_come_to_rest() {
    let scene =
        Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/pour_200.toml")).unwrap();
    let (sim, pair_events, last) = pour_checked(&scene, 0.015);
    assert!(sim.record.lost.is_empty());
    assert_eq!(sim.world.particles.len(), 200);
    assert!(pair_events > 100, "{pair_events} pair contacts");
    assert_at_rest(&last);
}

/// The shipped 2000-bead bed (`scenes/settling_bed.toml`, 3 s: at 2 s the bed is still
/// compacting, and in some runs — the path is chaotic: a change in the last bit of the drag, or
/// of the output times, gives another — drops of beads into hollows still reach 18 % of the
/// settling speed). About a minute.
#[test]
fn settling_bed_of_2000_beads_ends_at_rest_without_overlap_or_bead_below_the_floor() {
    let scene = Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/settling_bed.toml")).unwrap();
    let (sim, _, last) = pour_checked(&scene, 0.04);
    assert!(sim.record.lost.is_empty());
    assert_eq!(sim.world.particles.len(), 2000);
    assert_at_rest(&last);
}
