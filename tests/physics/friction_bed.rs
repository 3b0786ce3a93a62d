//! A bed with friction comes truly to rest (docs/physics.md §9): glass beads with friction and
//! rolling resistance poured into a box of water end with every bead below 1e-6 m/s — the
//! shipped 2000-bead bed, and its 300-bead version in CI.

use std::path::Path;
use wetbounce::Scene;

/// Runs `scene` (relative to the crate) to its end, reporting the speeds every 0.25 s, and
/// returns the fastest bead: its id, position and speed (m/s).
fn fastest_at_the_end(scene: &str, beads: usize) -> (u32, glam::DVec3, f64) {
    let scene = Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join(scene)).unwrap();
    assert!(scene.setup.rule.friction, "the bed has friction");
    let mut sim = scene.simulation();
    let mut t = 0.0;
    while t < scene.duration {
        t = (t + 0.25).min(scene.duration);
        sim.advance_to(t);
        let mut s: Vec<f64> = sim.world.particles.vel.iter().map(|v| v.length()).collect();
        s.sort_by(f64::total_cmp);
        eprintln!(
            "t = {t:.2} s: median {:.2e}, 99th percentile {:.2e}, largest {:.2e} m/s",
            s[s.len() / 2],
            s[s.len() * 99 / 100],
            s[s.len() - 1]
        );
    }
    let p = &sim.world.particles;
    assert_eq!(p.len(), beads);
    assert!(sim.record.lost.is_empty());
    let (i, v) = (0..p.len()).map(|i| (i, p.vel[i].length())).max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    (p.id[i], p.pos[i], v)
}

/// The 300-bead version of the shipped bed (2 s): measured at its end, the fastest bead moves
/// at 3.1e-10 m/s (`cargo run --release --bin rest -- tests/scenes/bed_friction_300.toml 0.25`).
#[test]
fn bed_of_300_beads_with_friction_ends_with_every_bead_below_a_micrometre_per_second() {
    let (id, x, v) = fastest_at_the_end("tests/scenes/bed_friction_300.toml", 300);
    assert!(v < 1e-6, "bead {id} at {x} moves at {v:.3e} m/s");
}

/// The shipped 2000-bead bed (3 s): measured at its end, the fastest bead moves at 2.7e-10 m/s,
/// after 109 s of CPU (`/usr/bin/time -v target/release/rest scenes/settling_bed_friction.toml
/// 0.5`; docs/performance.md, "Speed with rotation and friction"). The longest test in CI, about two minutes.
#[test]
fn settling_bed_with_friction_ends_with_every_bead_below_a_micrometre_per_second() {
    let (id, x, v) = fastest_at_the_end("scenes/settling_bed_friction.toml", 2000);
    assert!(v < 1e-6, "bead {id} at {x} moves at {v:.3e} m/s");
}
