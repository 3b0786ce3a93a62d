//! Dense contacts stay sound and come to rest: glass beads poured into a box of water never
//! overlap by more than 1 % of a diameter, never go below the floor or through a wall, none is
//! lost, and the bed they form ends at rest (the lasting contacts carry its weight).

use crate::common;
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

/// Deepest overlaps of a pour with friction (issue 25, point 2): `tests/scenes/bed_friction_300.toml`
/// (300 glass beads, μ 0.3, in water) with `changes` applied to its lines, run to `until` (s)
/// and checked every `every` steps. Returns the deepest wall overlap (in radii) and the deepest
/// pair overlap (in diameters) seen.
fn deepest_overlaps_of_friction_pour(changes: &[(&str, &str)], until: f64, every: usize) -> (f64, f64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/bed_friction_300.toml");
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (from, to) in changes {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    let scene = Scene::from_str(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = scene.simulation();
    let (mut wall, mut pair) = (0.0f64, 0.0f64);
    while sim.world.time < until {
        let t = (sim.world.time + every as f64 * scene.setup.dt).min(until);
        common::run_collect(&mut sim, t);
        wall = wall.max(-common::deepest_overlap(&sim).0);
        let p = &sim.world.particles;
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let reach = 0.5 * (p.diameter[i] + p.diameter[j]);
                let o = (reach - (p.pos[j] - p.pos[i]).length()) / reach;
                pair = pair.max(o);
            }
        }
    }
    (wall, pair)
}

const AIR: [(&str, &str); 3] = [
    ("density = 998.2\nviscosity = 1.002e-3", "density = 1.204\nviscosity = 1.81e-5"),
    ("restitution_max = 0.97", "restitution_max = 1.0"),
    ("added_mass = {}", ""),
];

/// Regression (issue 25, point 2): with friction, the lasting-contact solver moved beads after
/// its projection (the displacement that follows the velocity sweeps) into walls and into
/// neighbours: 300 beads poured into a box in air with ε_max = 1 overlapped the walls by 2.6 %
/// of r and each other by 2.5 % of d (1e4 beads: 2 % and 5.3 %); in water 0.68 % of r and
/// 0.93 % of d. Now every wall holds to round-off (1e-9 r) and pairs to 0.5 % of d (measured:
/// 1.7e-3 d in air, 1.0e-3 d in water, over 1 s and 2 s). The stretch checked here, every step,
/// holds the deepest overlaps of both runs (the pour's first impacts, 0.08–0.25 s).
#[test]
fn pours_with_friction_keep_walls_to_round_off_and_pairs_within_half_a_percent() {
    for (name, changes, until) in [("air, ε_max 1", &AIR[..], 0.3), ("water", &[][..], 0.3)] {
        let (wall, pair) = deepest_overlaps_of_friction_pour(changes, until, 1);
        eprintln!("{name}: deepest wall overlap {wall:.3e} r, deepest pair overlap {pair:.3e} d");
        assert!(wall <= 1e-9, "{name}: a bead inside a wall by {wall:.3e} r");
        assert!(pair < 5e-3, "{name}: two beads overlapping by {pair:.3e} d");
    }
}

/// Measures the deepest overlaps of the 300-bead pour with friction, in water and in air with
/// ε_max = 1, every step (`cargo test --test stability stability_dense_pour -- --ignored --nocapture`).
#[test]
#[ignore]
fn measure_overlaps_of_pours_with_friction() {
    for (name, changes, until) in [("water", &[][..], 2.0), ("air, ε_max 1", &AIR[..], 1.0)] {
        let (wall, pair) = deepest_overlaps_of_friction_pour(changes, until, 1);
        eprintln!("{name}: deepest wall overlap {wall:.3e} r, deepest pair overlap {pair:.3e} d");
    }
}
