//! A file that cannot be written — a full disk, a file-size limit — stops the run with an error
//! naming the file and the OS error, and every other output is still finished: the CSV files
//! hold whole lines, summary.json lists the error, the MCAP is closed or recoverable (issue 13,
//! finding 4). Unix only: /dev/full, setrlimit, mount namespaces.

use crate::outputs_common;

use outputs_common::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const FULL: &str = "No space left on device (os error 28)";
const TOO_LARGE: &str = "File too large (os error 27)";

/// Points `dir/name` at /dev/full: every write to it fails as on a full disk.
fn full_file(dir: &Path, name: &str) {
    std::os::unix::fs::symlink("/dev/full", dir.join(name)).unwrap();
}

fn run_into(scene: &str, out: &Path, formats: &str) -> Output {
    wetbounce()
        .args(["run", scene, "--formats", formats, "--quiet", "--threads", "1", "--out"])
        .arg(out)
        .output()
        .unwrap()
}

/// Checks the error lines: each names a file of `out` and says `cause`; none hides it behind the
/// MCAP writer's own words, and nothing panicked. Returns the files named.
fn errors_named(stderr: &str, out: &Path, cause: &str) -> Vec<String> {
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!stderr.contains("attempted another write"), "the cause is hidden: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert!(!errors.is_empty(), "no error line: {stderr}");
    errors
        .iter()
        .map(|l| {
            let rest = l
                .strip_prefix(&format!("error: {}/", out.display()))
                .unwrap_or_else(|| panic!("the error does not start with a file of {}: {l}", out.display()));
            let (file, message) = rest.split_once(": ").unwrap();
            assert!(message.starts_with(&format!("cannot write: {cause}")), "{l}");
            file.to_string()
        })
        .collect()
}

/// Regression (finding 4): with the MCAP alone on a full disk the error said "attempted another
/// write after a write method failed", naming neither the cause nor, usefully, what to do.
#[test]
fn mcap_alone_on_a_full_disk_is_an_error_naming_the_file_and_the_os_error() {
    let dir = tempfile::tempdir().unwrap();
    full_file(dir.path(), "toluene_drop.mcap");
    let out = run_into("scenes/toluene_drop.toml", dir.path(), "mcap");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(errors_named(&stderr, dir.path(), FULL), ["toluene_drop.mcap"]);
}

/// The class: each file a run writes, put on a full disk in turn, is named with the OS error,
/// and every other file is finished — whole CSV lines under their header, a closed MCAP, a
/// summary.json that lists the error. Files created after the one that failed at creation are
/// not created (the run does not start).
#[test]
fn each_output_file_on_a_full_disk_is_named_and_the_others_are_finished() {
    for failing in ["toluene_drop.mcap", "trajectories.csv", "events.csv", "summary.json"] {
        let dir = tempfile::tempdir().unwrap();
        let out_dir = dir.path();
        full_file(out_dir, failing);
        let out = run_into("scenes/toluene_drop.toml", out_dir, "mcap,csv");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{failing}: {stderr}");
        assert_eq!(errors_named(&stderr, out_dir, FULL), [failing], "{failing}");
        let whole = |name: &str| out_dir.join(name).is_file() && name != failing;
        if whole("toluene_drop.mcap") {
            read_closed_mcap(&out_dir.join("toluene_drop.mcap"));
        }
        if whole("trajectories.csv") {
            assert_eq!(read_csv(&out_dir.join("trajectories.csv"), TRAJECTORY_HEADER).partial, 0);
        }
        if whole("events.csv") {
            assert_eq!(read_csv(&out_dir.join("events.csv"), EVENT_HEADER).partial, 0);
        }
        if failing == "summary.json" {
            // The run itself went to its end; only the summary is missing.
            let topics = read_closed_mcap(&out_dir.join("toluene_drop.mcap"));
            assert_eq!(topics["/particles"].len(), 1001);
            assert_eq!(frames(&read_csv(&out_dir.join("trajectories.csv"), TRAJECTORY_HEADER)).len(), 1001);
        } else {
            assert!(!whole("summary.json"), "{failing}: no run, no summary");
        }
    }
}

/// Multiples of the output interval strictly before `t`: the frames a file cut at `t` holds.
fn frames_before(t: f64, interval: f64) -> usize {
    (0..).take_while(|&k| (k as f64) * interval < t - 1e-12).count()
}

/// The class, in the middle of a run: each sink's file, alone, grows past a file-size limit
/// after some frames. The run stops there with the file and the OS error named; summary.json
/// says where; the CSV files keep their whole lines; the MCAP's frames before the failure are
/// read back by `recover`.
#[test]
fn a_file_that_cannot_grow_mid_run_stops_the_run_naming_it_and_the_rest_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_with("tests/scenes/pour_200.toml", "pour.toml", dir.path(), &[("duration", "0.2")]);
    let interval = 0.01;
    for (formats, failing) in [("mcap", "pour.mcap"), ("csv", "trajectories.csv")] {
        let out_dir = dir.path().join(formats);
        let out = run_with_file_limit(&scene, &out_dir, formats, 100_000);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{formats}: {stderr}");
        assert_eq!(errors_named(&stderr, &out_dir, TOO_LARGE), [failing], "{formats}");
        let summary = read_summary(&out_dir);
        let t_stop = summary["time_s"].as_f64().unwrap();
        assert!(t_stop > 0.0 && t_stop < 0.2, "{formats}: stopped at {t_stop}");
        // Stopped before its end by the error: interrupted, as after a signal, with no signal
        // (issue 25, finding 13: it said false).
        assert_eq!(summary["interrupted"], true, "{summary}");
        assert_eq!(summary["signal"], serde_json::Value::Null, "{summary}");
        let listed = summary["output_errors"].as_array().unwrap();
        assert_eq!(listed.len(), 1, "{summary}");
        assert!(listed[0].as_str().unwrap().contains(failing), "{summary}");
        if formats == "mcap" {
            let (topics, report) = recover(&out_dir.join("pour.mcap"));
            let clouds = &topics["/particles"];
            // Every frame before the one whose write failed; and that one too when only the
            // message indexes that follow its chunk were cut (the chunk itself is whole).
            let before = frames_before(t_stop, interval);
            assert!(
                clouds.len() == before
                    || clouds.len() == before + 1 && (t_stop - before as f64 * interval).abs() < 1e-9,
                "stopped at {t_stop} s, {} frames: {report}",
                clouds.len()
            );
            for (k, (t, _)) in clouds.iter().enumerate() {
                assert_eq!(*t, (k as f64 * interval * 1e9).round() as u64);
            }
        } else {
            let traj = read_csv(&out_dir.join("trajectories.csv"), TRAJECTORY_HEADER);
            let frames = frames(&traj);
            let whole = frames.iter().filter(|(_, n)| *n == 200).count();
            assert!(whole >= frames.len().saturating_sub(1), "{frames:?}");
            assert!(whole >= frames_before(t_stop, interval).saturating_sub(1), "{frames:?} at {t_stop}");
            let events = read_csv(&out_dir.join("events.csv"), EVENT_HEADER);
            assert_eq!(events.partial, 0, "events.csv was finished");
        }
    }
}

/// A real full disk: a 256 KiB tmpfs, mounted in a mount namespace of the child's own
/// (`unshare -m`, root). Every file on it may fail; each error names its file and ENOSPC, the
/// CSV files hold whole lines, the MCAP is closed or recovered. Skips, saying so, where a
/// namespace or a mount is not allowed (CI in an unprivileged container).
#[test]
fn a_disk_that_fills_mid_run_stops_it_with_each_file_named_and_what_was_written_readable() {
    let dir = tempfile::tempdir().unwrap();
    // --allow-large-output: the run is estimated at 2.0 MB, so without it the run would be
    // refused before it starts (the next test); here the disk must fill mid-run.
    let Some((out, mnt, keep)) = run_on_a_small_tmpfs(dir.path(), "--allow-large-output") else { return };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    let named = errors_named(&stderr, &mnt.join("o"), FULL);
    assert!(!named.is_empty());
    for csv in ["trajectories.csv", "events.csv"] {
        let header = if csv == "events.csv" { EVENT_HEADER } else { TRAJECTORY_HEADER };
        let file = read_csv(&keep.join(csv), header);
        if !named.iter().any(|n| n == csv) {
            assert_eq!(file.partial, 0, "{csv} was finished");
        }
    }
    let (topics, report) = recover(&keep.join("pour.mcap"));
    let clouds = topics.get("/particles").map_or(0, Vec::len);
    assert!(clouds >= 1, "{report}");
}

/// The same 256 KiB tmpfs, without `--allow-large-output`: the run's outputs, estimated at
/// 2.0 MB, cannot fit, so it is refused before it starts (issue 25, point 12), saying the
/// estimate and the free space, and writes nothing. Skips where a mount is not allowed.
#[test]
fn a_run_whose_estimated_output_exceeds_the_free_disk_space_is_refused_before_it_writes() {
    let dir = tempfile::tempdir().unwrap();
    let Some((out, _mnt, keep)) = run_on_a_small_tmpfs(dir.path(), "") else { return };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("pour.toml: the outputs would take 51 frames of up to 200 particles: about 1.96 MB"),
        "{stderr}"
    );
    assert!(
        stderr.contains("more than the 262 kB free in") && stderr.contains("--allow-large-output"),
        "{stderr}"
    );
    let left: Vec<_> = std::fs::read_dir(&keep).unwrap().collect();
    assert!(left.is_empty(), "nothing written: {left:?}");
}

/// Runs the 200-bead pour (0.5 s) with `--formats mcap,csv` and `extra` (flags) into a 256 KiB
/// tmpfs mounted in a mount namespace of its own, copying what it wrote to `dir/keep`; returns
/// the run's output, the mount point and the copy, or `None` (and says "skipped") where a mount
/// is not allowed.
fn run_on_a_small_tmpfs(dir: &Path, extra: &str) -> Option<(Output, PathBuf, PathBuf)> {
    let scene = scene_with("tests/scenes/pour_200.toml", "pour.toml", dir, &[("duration", "0.5")]);
    let (mnt, keep) = (dir.join("mnt"), dir.join("keep"));
    std::fs::create_dir_all(&mnt).unwrap();
    std::fs::create_dir_all(&keep).unwrap();
    let script = r#"mount -t tmpfs -o size=256k tmpfs "$MNT" || exit 99
"$BIN" run "$SCENE" --formats mcap,csv --quiet --threads 1 $EXTRA --out "$MNT/o"
status=$?
cp -a "$MNT/o/." "$KEEP/"
exit $status"#;
    let out = Command::new("unshare")
        .args(["-m", "sh", "-c", script])
        .env("MNT", &mnt)
        .env("KEEP", &keep)
        .env("BIN", env!("CARGO_BIN_EXE_wetbounce"))
        .env("SCENE", &scene)
        .env("EXTRA", extra)
        .output();
    match out {
        Ok(out)
            if out.status.code() != Some(99)
                && !String::from_utf8_lossy(&out.stderr).contains("unshare:") =>
        {
            Some((out, mnt, keep))
        }
        other => {
            eprintln!("skipped: cannot mount a tmpfs in a mount namespace here ({other:?})");
            None
        }
    }
}
