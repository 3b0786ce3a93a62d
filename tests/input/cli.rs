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

/// Writes `text` as `scene.toml` in a new folder and returns both.
fn scene_file(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// A bead scene with `extra` (TOML tables) appended; 1 s of beads in oil on a floor.
fn beads_scene(output_interval: &str, effects: &str, extra: &str) -> String {
    format!(
        r#"
[simulation]
dt = 1e-4
duration = 1.0
output_interval = {output_interval}
[fluid]
density = 1000.0
viscosity = 0.1
[effects]
gravity = {{}}
drag = {{}}
{effects}
[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.23
[[walls]]
name = "floor"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
{extra}
"#
    )
}

#[test]
fn check_refuses_a_run_whose_memory_exceeds_the_machine_naming_the_count_key_before_placing_a_particle() {
    // 4e7 beads with a 102-mode history (tolerance 1e-9), 76 stored at this Δt: 3.9 kB each,
    // 156 GB. Refused from the counts, before the random fill places any (which would take
    // minutes and the memory).
    let fill = "[[random_fill]]\nkind = \"glass\"\ndiameter = 1e-4\nmin = [-10.0, -10.0, 0.0]\n\
                max = [10.0, 10.0, 1.0]\ncount = 40000000\nseed = 1";
    let (_dir, path) = scene_file(&beads_scene("0.1", "history = { tolerance = 1e-9 }", fill));
    let start = std::time::Instant::now();
    let out = wetbounce().arg("check").arg(&path).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(start.elapsed().as_secs_f64() < 30.0, "took {:?}", start.elapsed());
    assert!(stderr.contains("random_fill[0].count: the run would need about 156 GB of memory"), "{stderr}");
    assert!(
        stderr.contains("up to 4e7 particles × 3.90 kB each, 3.65 kB of it the history effect's 76 modes"),
        "{stderr}"
    );
    assert!(
        stderr.contains("MemAvailable in /proc/meminfo") && stderr.contains("--allow-large-memory"),
        "{stderr}"
    );
}

#[test]
fn check_prints_the_runs_memory_and_output_size_and_warns_of_terabytes_of_output() {
    // 25,000 beads × 1e7 frames (issue 25, point 12): about 25 TB of CSV, accepted silently
    // before. A lattice of 50 × 50 × 10 at 2 mm.
    let lattice = "[[lattice]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [0.0, 0.0, 0.0]\n\
                   max = [0.1, 0.1, 0.02]\nspacing = 2e-3";
    let (_dir, path) = scene_file(&beads_scene("1e-7", "", lattice));
    let out = wetbounce().arg("check").arg(&path).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("  memory: about 6.40 MB (up to 25000 particles × 256 B each)"), "{stdout}");
    assert!(
        stdout.contains("  output: 10000001 frames, 2.5e11 particle-frames: trajectories.csv about 25.0 TB"),
        "{stdout}"
    );
    assert!(stdout.contains("  warning: the outputs may reach 25.0 TB"), "{stdout}");
    // `run` refuses it before it starts: no disk here has 25 TB free.
    let dir = tempfile::tempdir().unwrap();
    let out = wetbounce()
        .args(["run", "--quiet", "--formats", "csv", "--out"])
        .arg(dir.path())
        .arg(&path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains(
            "the outputs would take 10000001 frames of up to 25000 particles: about 25.0 TB (csv 25.0 TB)"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("free in") && stderr.contains("--allow-large-output"), "{stderr}");
    assert!(!dir.path().join("trajectories.csv").exists(), "nothing written");
}

#[test]
fn the_estimated_rows_of_trajectories_csv_bound_the_rows_a_run_with_an_injector_writes() {
    // An injector at 200/s from 0.2 s to 0.7 s over 1 s, frames every 0.05 s, and one bead.
    let extra = "[[particles]]\nkind = \"glass\"\ndiameter = 1e-3\nposition = [0.0, 0.0, 0.05]\n\
                 [[injectors]]\nkind = \"glass\"\nrate = 200.0\nseed = 3\nstart = 0.2\nstop = 0.7\n\
                 region = { type = \"box\", min = [-0.02, -0.02, 0.02], max = [0.02, 0.02, 0.04] }\n\
                 diameter = { distribution = \"fixed\", value = 1e-3 }";
    let (dir, path) = scene_file(&beads_scene("0.05", "", extra));
    let scene = wetbounce::Scene::load(&path).unwrap();
    let out = wetbounce()
        .args(["run", "--quiet", "--formats", "csv", "--out"])
        .arg(dir.path())
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = std::fs::read_to_string(dir.path().join("trajectories.csv")).unwrap().lines().count() - 1;
    let e = &scene.estimate;
    assert_eq!(e.frames, 21.0);
    assert!((e.max_particles - 101.0).abs() < 1e-9, "{}", e.max_particles);
    // Nothing leaves: the estimate is the rows within the injections' rounding (one frame's).
    assert!(
        rows as f64 <= e.particle_frames && e.particle_frames <= rows as f64 + 100.0,
        "{rows} rows, estimated {}",
        e.particle_frames
    );
}
