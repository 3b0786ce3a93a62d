//! Every shipped scene loads, and its first 50 ms run without losing a particle.

use crate::common;
use std::path::Path;
use wetbounce::Scene;

#[test]
fn every_shipped_scene_loads_and_runs_briefly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let mut sim = scene.simulation();
            let t = 0.05f64.min(scene.duration).min(500.0 * scene.setup.dt);
            sim.advance_to(t);
            assert!(sim.record.lost.is_empty(), "{}: lost {:?}", path.display(), sim.record.lost);
            count += 1;
        }
    }
    assert!(count >= 3);
}

#[test]
fn glass_bead_rebounds_with_falling_st_then_stays_on_the_floor() {
    let scene = Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass_bead.toml")).unwrap();
    let mut sim = scene.simulation();
    let events = common::run_collect(&mut sim, scene.duration);
    let first = events[0];
    assert!((first.st - 276.0).abs() / 276.0 < 0.02, "St = {}", first.st);
    for w in events.windows(2) {
        assert!(w[1].st < w[0].st, "St must fall from bounce to bounce");
    }
    assert_eq!(events.last().unwrap().outcome, wetbounce::Outcome::Deposited);
    assert!(events.iter().rev().skip(1).all(|e| e.outcome == wetbounce::Outcome::Bounced));
    // On the floor at the end, touching it.
    assert!((sim.world.particles.pos[0].z - 1.25e-3).abs() < 1e-12);
}
