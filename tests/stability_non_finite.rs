//! Stability case 10 (docs/stability.md): a state forced non-finite at run time by an extreme
//! scene (`tests/scenes/runaway.toml`, gravity 1e308 m/s²) — the particle is taken out and
//! reported (a `removed`/`non_finite` row in events.csv, an `/events` message in the MCAP, the
//! summary's count) and the run goes on to the end with the others.

use std::process::Command;

const RUNAWAY: &str = "tests/scenes/runaway.toml";

#[test]
fn runaway_particle_is_removed_reported_and_the_run_continues() {
    let scene =
        wetbounce::Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(RUNAWAY)).unwrap();
    let mut sim = scene.simulation();
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
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["run", RUNAWAY, "--formats", "mcap,csv", "--quiet", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("removed            1 (1 non-finite)"), "{stdout}");
    let events = std::fs::read_to_string(dir.path().join("events.csv")).unwrap();
    let removed: Vec<&str> = events.lines().filter(|l| l.contains(",removed,")).collect();
    assert_eq!(removed.len(), 1, "{events}");
    assert!(
        removed[0].ends_with(",1,,removed,,,,,non_finite")
            || removed[0].contains(",1,,removed,,,,,non_finite"),
        "{}",
        removed[0]
    );
    let summary = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    assert!(summary.contains("\"lost_non_finite\": 1"), "{summary}");
    let mcap = std::fs::read(dir.path().join("runaway.mcap")).unwrap();
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
