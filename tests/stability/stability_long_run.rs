//! Stability case 12 (docs/stability.md): a long run. The column scene (`scenes/column.toml`:
//! toluene drops injected at the bottom of a water column, held and rebounding under a top
//! plate, leaving through an outlet) with its injector kept on at 50 drops/s for 10⁶ steps
//! (2000 s simulated). Every 10⁴ steps it prints the particles, their kinetic energy, the
//! fastest speed and the resident memory, and it checks: no non-finite state, no particle
//! inside a wall, the kinetic energy bounded (no drop faster than 0.5 m/s, three times the
//! terminal velocity of the largest), the memory flat (the resident set grows by less than
//! 10 % + 8 MB from step 10⁵ (a tenth of the run) to the end, once the column is in its steady state).
//!
//! Ignored in CI (minutes in release): `cargo test --release --test stability stability_long_run --
//! --ignored --nocapture` (`WETBOUNCE_STEPS=N` for another length).

use crate::common;

/// Resident set size (bytes), from /proc/self/statm (0 where there is no /proc).
fn resident_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1).and_then(|p| p.parse::<u64>().ok()))
        .map_or(0, |pages| pages * 4096)
}

#[test]
#[ignore]
fn column_for_a_million_steps_stays_finite_bounded_and_flat_in_memory() {
    let steps: u64 = std::env::var("WETBOUNCE_STEPS").ok().and_then(|s| s.parse().ok()).unwrap_or(1_000_000);
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/column.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let dt = 2e-3;
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("stop ="))
        .map(|l| {
            if l.starts_with("rate =") {
                "rate = 50.0".to_string()
            } else if l.starts_with("duration =") {
                format!("duration = {:e}", steps as f64 * dt)
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert!(text.contains("dt = 2e-3"), "the column's step is 2 ms");
    let scene = wetbounce::Scene::from_str(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = scene.simulation();
    let inertia = (860.0 + 0.5 * 997.0) * std::f64::consts::PI / 6.0;
    let start = std::time::Instant::now();
    let (mut rss_at_1e5, mut max_speed_all, mut max_n, mut contacts) = (0u64, 0.0f64, 0usize, 0u64);
    println!(
        "{:>9} {:>9} {:>6} {:>12} {:>10} {:>9} {:>8}",
        "step", "t [s]", "N", "KE [J]", "vmax [m/s]", "RSS [MB]", "wall [s]"
    );
    for k in 1..=steps {
        sim.step(dt);
        contacts += sim.record.events.len() as u64;
        for e in sim.record.events.drain(..) {
            assert!(e.energy_not_gained(), "{e:?}");
        }
        if k % 10_000 == 0 || k == steps {
            let p = &sim.world.particles;
            assert!(sim.record.lost.is_empty(), "step {k}: non-finite state: {:?}", sim.record.lost);
            let (mut ke, mut vmax) = (0.0f64, 0.0f64);
            for i in 0..p.len() {
                assert!(p.pos[i].is_finite() && p.vel[i].is_finite());
                let v = p.vel[i].length();
                ke += 0.5 * inertia * p.diameter[i].powi(3) * v * v;
                vmax = vmax.max(v);
            }
            common::assert_clear_of_walls(&sim);
            let rss = resident_bytes();
            if rss_at_1e5 == 0 && k >= steps / 10 {
                rss_at_1e5 = rss;
            }
            max_speed_all = max_speed_all.max(vmax);
            max_n = max_n.max(p.len());
            println!(
                "{k:>9} {:>9.1} {:>6} {:>12.4e} {:>10.4} {:>9.1} {:>8.1}",
                sim.world.time,
                p.len(),
                ke,
                vmax,
                rss as f64 / 1e6,
                start.elapsed().as_secs_f64()
            );
            assert!(vmax < 0.5, "step {k}: a drop at {vmax} m/s");
        }
    }
    let rss_end = resident_bytes();
    let removed: usize = sim.record.removed.iter().map(Vec::len).sum();
    println!(
        "{steps} steps, {:.1} s simulated, in {:.0} s: at most {max_n} drops, {} injected, {removed} left through the outlets, {contacts} contacts, none non-finite, fastest {max_speed_all:.4} m/s, resident memory {:.1} MB at step {} and {:.1} MB at the end",
        sim.world.time,
        start.elapsed().as_secs_f64(),
        sim.world.injection.iter().map(|i| i.injected).sum::<u64>(),
        rss_at_1e5 as f64 / 1e6,
        (steps / 10).div_ceil(10_000) * 10_000,
        rss_end as f64 / 1e6
    );
    assert!(
        rss_end as f64 <= rss_at_1e5 as f64 * 1.1 + 8e6,
        "memory grew from {rss_at_1e5} to {rss_end} bytes"
    );
}
