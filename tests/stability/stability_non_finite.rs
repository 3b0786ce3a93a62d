//! Stability case 10 (docs/stability.md): a state forced non-finite at run time — the middle
//! bead of `tests/scenes/runaway.toml` launched at 1.5e308 m/s with Δt = 0.5 s — the particle is
//! taken out and reported (a `removed`/`non_finite` row in events.csv, an `/events` message in
//! the MCAP, the summary's count) and the run goes on to the end with the others.
//!
//! The scene loader refuses such a speed (speeds are limited to 1e4 m/s), so the speed is set
//! on the simulation after loading, and the outputs are written through the same sinks and
//! summary as `wetbounce run` uses.

use std::sync::atomic::AtomicBool;
use wetbounce::output::{EventCsv, McapOptions, McapSink, RunSummary, Sink, Statistics};

const RUNAWAY: &str = "tests/scenes/runaway.toml";

/// The runaway scene at t = 0 with its middle bead (id 1) at 1.5e308 m/s.
fn runaway() -> (wetbounce::Scene, wetbounce::Simulation) {
    let scene =
        wetbounce::Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(RUNAWAY)).unwrap();
    let mut sim = scene.simulation();
    assert_eq!(sim.world.particles.id[1], 1);
    sim.world.particles.vel[1] = glam::DVec3::new(1.5e308, 0.0, 0.0);
    (scene, sim)
}

#[test]
fn runaway_particle_is_removed_reported_and_the_run_continues() {
    let (scene, mut sim) = runaway();
    sim.advance_to(scene.duration);
    assert_eq!(sim.record.lost.len(), 1, "{:?}", sim.record.lost);
    assert_eq!(sim.record.lost[0].id, 1);
    assert!(sim.record.lost[0].time <= 1.0, "removed at {}", sim.record.lost[0].time);
    assert_eq!(sim.world.particles.len(), 2);
    assert_eq!(sim.world.time, scene.duration);
    for i in 0..2 {
        assert!(sim.world.particles.pos[i].is_finite() && sim.world.particles.vel[i].is_finite());
        assert!(sim.world.particles.pos[i].z >= 1e-3 * (1.0 - 1e-9), "{:?}", sim.world.particles.pos[i]);
    }
}

#[test]
fn removal_is_an_event_in_events_csv_and_the_mcap_and_counted_in_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, mut sim) = runaway();
    let (events_path, mcap_path) = (dir.path().join("events.csv"), dir.path().join("runaway.mcap"));
    let options =
        McapOptions { max_spheres: 1000, scene_path: RUNAWAY.into(), scene_source: scene.source.clone() };
    let mut mcap_sink = McapSink::create(&mcap_path, options).unwrap();
    let mut events_sink = EventCsv::create(&events_path).unwrap();
    let mut stats = Statistics::default();
    let report = {
        let mut sinks: Vec<&mut dyn Sink> = vec![&mut mcap_sink, &mut events_sink, &mut stats];
        wetbounce::run::run(
            &mut sim,
            scene.duration,
            scene.output_interval,
            &mut sinks,
            &AtomicBool::new(false),
        )
        .unwrap()
    };
    drop((mcap_sink, events_sink));
    let summary = RunSummary::new(&sim, &report, &stats);
    let shown = summary.to_string();
    assert!(shown.contains("removed            1 (1 non-finite)"), "{shown}");
    assert_eq!(summary.to_json()["particles"]["lost_non_finite"], 1, "{}", summary.to_json());
    let events = std::fs::read_to_string(&events_path).unwrap();
    let removed: Vec<&str> = events.lines().filter(|l| l.contains(",removed,")).collect();
    assert_eq!(removed.len(), 1, "{events}");
    assert!(removed[0].contains(",1,,removed,,,,,non_finite"), "{}", removed[0]);
    let mcap = std::fs::read(&mcap_path).unwrap();
    let messages: Vec<String> = mcap::MessageStream::new(&mcap)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == "/events")
        .map(|m| String::from_utf8(m.data.to_vec()).unwrap())
        .collect();
    let json: Vec<&String> = messages.iter().filter(|m| m.contains("\"removed\"")).collect();
    assert_eq!(json.len(), 1, "{messages:?}");
    assert!(json[0].contains("\"outcome\":\"non_finite\"") && json[0].contains("\"id\":1"), "{}", json[0]);
}
