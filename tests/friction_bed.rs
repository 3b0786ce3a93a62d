//! A bed with friction comes truly to rest (PHYSICS.md §9): the shipped settling bed, 2000
//! glass beads with friction and rolling resistance, ends with every bead below 1e-6 m/s.

use std::path::Path;
use wetbounce::Scene;

/// NOT MET YET, hence ignored: measured at 3 s (commit 128a443, before the friction solver's
/// tighter tolerance), median 8e-6 m/s, 99th percentile 2e-4, largest 1.3e-3 — lasting
/// contacts keep breaking and re-forming (a few deposit events per step), and the solver's
/// residual is ~1e-5 m/s. Since the wall rows are warm-started (README, "Speed with rotation
/// and friction"), the 300-bead version of this bed has 99 % of its beads below 2e-7 m/s but
/// its fastest bead still between 1e-6 and a few 1e-3 m/s, from pair contacts that break and
/// re-form, driven apart by the friction sweeps, which crawl instead of converging (README,
/// "Why": a mode that decays by 5e-5 of itself per sweep; more sweeps made it worse), so the fix is a
/// different solver, not more sweeps. This 2000-bead bed, re-measured at 89e3595 with
/// `target/release/rest scenes/settling_bed_friction.toml 0.5`: at 3 s median 1.7e-9 m/s, 99th
/// percentile 1.5e-4, largest 5.0e-4. Run with
/// `cargo test --release --test friction_bed -- --ignored` (tens of minutes on a loaded machine).
#[test]
#[ignore = "criterion of issue 16 not met yet: the bed ends at ~5e-4 m/s, not 1e-6 (see doc)"]
fn settling_bed_with_friction_ends_with_every_bead_below_a_micrometre_per_second() {
    let scene =
        Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/settling_bed_friction.toml")).unwrap();
    assert!(scene.setup.rule.friction, "the shipped bed has friction");
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
    assert_eq!(p.len(), 2000);
    assert!(sim.record.lost.is_empty());
    let (i, v) = (0..p.len()).map(|i| (i, p.vel[i].length())).max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    assert!(v < 1e-6, "bead {} at {} moves at {v:.3e} m/s", p.id[i], p.pos[i]);
}
