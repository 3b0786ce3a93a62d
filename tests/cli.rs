//! The command line: `run` writes the documented files, `check` prints the time scales.

use std::process::Command;

fn wetbounce() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_wetbounce"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

#[test]
fn check_prints_st_38_for_the_toluene_drop() {
    let out = wetbounce().args(["check", "scenes/toluene_drop.toml"]).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let row = text.lines().find(|l| l.trim_start().starts_with("toluene")).expect("toluene row");
    let st: f64 = row.split_whitespace().nth(4).unwrap().parse().unwrap();
    assert!((st - 38.0).abs() < 1.0, "{row}");
    assert!(row.contains("yes"));
}

#[test]
fn run_with_formats_csv_writes_trajectories_and_events_with_documented_headers() {
    let dir = tempfile::tempdir().unwrap();
    let out = wetbounce()
        .args(["run", "scenes/toluene_drop.toml", "--formats", "csv", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let traj = std::fs::read_to_string(dir.path().join("trajectories.csv")).unwrap();
    let mut lines = traj.lines();
    assert_eq!(lines.next(), Some("t,id,x,y,z,vx,vy,vz,state"));
    // 1 s at 1 ms output interval: 1001 frames of one particle.
    assert_eq!(lines.count(), 1001);
    let last = traj.lines().last().unwrap();
    assert!(last.starts_with("1.0,0,") && last.ends_with(",resting"), "{last}");
    let events = std::fs::read_to_string(dir.path().join("events.csv")).unwrap();
    let rows: Vec<&str> = events.lines().collect();
    assert_eq!(rows[0], "t,id,other,kind,normal_speed,st,eps,contact_time,outcome");
    assert!(rows[1].contains(",top,wall,") && rows[1].ends_with(",held"), "{}", rows[1]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.contains("held 2") && stdout.contains("deposited 1"), "{stdout}");
    // Only what was asked for.
    assert!(!dir.path().join("toluene_drop.mcap").exists());
}

#[test]
fn run_defaults_to_out_slash_scene_stem() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/glass_bead.toml"),
        dir.path().join("bead.toml"),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .current_dir(dir.path())
        .args(["run", "bead.toml", "--threads", "1"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(dir.path().join("out/bead/bead.mcap").is_file());
    // CSV only on request.
    assert!(!dir.path().join("out/bead/trajectories.csv").exists());
}

#[test]
fn run_ends_with_a_table_of_steps_impacts_and_particles_and_no_progress_bar_off_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let out =
        wetbounce().args(["run", "scenes/toluene_drop.toml", "--out"]).arg(dir.path()).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8(out.stdout).unwrap();
    let row = |name: &str| {
        stdout
            .lines()
            .find(|l| l.trim_start().starts_with(name))
            .unwrap_or_else(|| panic!("no {name} row in\n{stdout}"))
            .to_string()
    };
    assert!(row("steps").contains("10000"), "{stdout}");
    assert!(row("wall time").ends_with(" s"), "{stdout}");
    assert!(row("impacts").contains("3 (held 2, bounced 0, deposited 1)"), "{stdout}");
    assert!(row("mean St").ends_with("17.179"), "{stdout}");
    assert!(row("mean ε of rebounds").ends_with("0.210"), "{stdout}");
    assert!(row("particles").contains("0 held, 1 deposited"), "{stdout}");
    assert!(row("removed").ends_with("removed            0 (0 non-finite)"), "{stdout}");
    assert!(stdout.contains("toluene_drop.mcap"), "{stdout}");
    // Standard error is a pipe here: no bar, no control characters.
    assert_eq!(String::from_utf8(out.stderr).unwrap(), "");
}

#[test]
fn formats_rrd_without_the_rerun_feature_is_refused_with_the_fix() {
    if cfg!(feature = "rerun") {
        return;
    }
    let out = wetbounce().args(["run", "scenes/glass_bead.toml", "--formats", "rrd"]).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("--formats rrd") && err.contains("--features rerun"), "{err}");
}

#[test]
fn bad_output_interval_is_refused_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let out = wetbounce()
        .args(["run", "scenes/glass_bead.toml", "--output-interval", "0", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("--output-interval") && err.contains("got 0"), "{err}");
}

#[test]
fn missing_scene_file_is_an_error_naming_it() {
    let out = wetbounce().args(["run", "scenes/no_such_scene.toml"]).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.starts_with("error: scenes/no_such_scene.toml: cannot read"), "{err}");
}

#[test]
fn zero_threads_is_refused() {
    let out = wetbounce().args(["run", "scenes/glass_bead.toml", "--threads", "0"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8(out.stderr).unwrap().contains("--threads"));
}
