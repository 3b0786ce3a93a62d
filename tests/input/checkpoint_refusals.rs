//! A checkpoint that is not one, of another format version, truncated, corrupted, or resumed
//! with a scene changed beyond what may change, is refused with an error naming the file and
//! what differs — never a panic, never a silent continuation (issue 27, item 3).

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use wetbounce::run::checkpoint::{self, CheckpointError};
use wetbounce::run::resume;

/// Runs the glass bead for 0.05 s into `dir` with a checkpoint at its end; returns the file.
fn a_checkpoint(dir: &Path) -> PathBuf {
    let scene = scene_copy(dir, "scene.toml", &[("duration", "0.05")]);
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .arg("run")
        .arg(&scene)
        .args(["--formats", "csv", "--quiet", "--checkpoint-every", "0.05", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let list = checkpoint::list(&dir.join("out/checkpoints"));
    list.last().cloned().expect("a checkpoint")
}

/// `scenes/glass_bead.toml` written to `dir/name`, with `key = value` lines replaced.
fn scene_copy(dir: &Path, name: &str, values: &[(&str, &str)]) -> PathBuf {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass_bead.toml"))
        .unwrap();
    let lines: Vec<String> = text
        .lines()
        .map(|l| match values.iter().find(|(k, _)| l.starts_with(&format!("{k} ="))) {
            Some((k, v)) => format!("{k} = {v}"),
            None => l.to_string(),
        })
        .collect();
    let path = dir.join(name);
    std::fs::write(&path, lines.join("\n")).unwrap();
    path
}

fn refused(bytes: &[u8]) -> CheckpointError {
    match checkpoint::decode(Path::new("ck.wbck"), bytes) {
        Ok(_) => panic!("accepted"),
        Err(e) => e,
    }
}

#[test]
fn a_file_that_is_not_a_checkpoint_is_refused_by_the_command_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("notes.txt");
    std::fs::write(&path, "t,id,x\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce")).arg("resume").arg(&path).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("notes.txt") && err.contains("not a wetbounce checkpoint"), "{err}");
    let missing =
        Command::new(env!("CARGO_BIN_EXE_wetbounce")).args(["resume", "no/such.wbck"]).output().unwrap();
    let err = String::from_utf8_lossy(&missing.stderr);
    assert!(missing.status.code() == Some(1) && err.contains("no/such.wbck"), "{err}");
}

#[test]
fn another_version_a_cut_and_a_flipped_byte_are_each_named() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(a_checkpoint(dir.path())).unwrap();
    assert!(checkpoint::decode(Path::new("ck.wbck"), &bytes).is_ok());

    let mut other = bytes.clone();
    other[8..12].copy_from_slice(&7u32.to_le_bytes());
    let e = refused(&other).to_string();
    assert!(e.contains("ck.wbck") && e.contains("format version 7") && e.contains("reads version 3"), "{e}");

    let e = refused(&bytes[..bytes.len() - 10]).to_string();
    assert!(e.contains("truncated") && e.contains(&format!("{} bytes", bytes.len() - 10)), "{e}");
    let e = refused(&bytes[..40]).to_string();
    assert!(e.contains("truncated"), "{e}");

    let mut flipped = bytes.clone();
    let last = flipped.len() - 5;
    flipped[last] ^= 0x10;
    let e = refused(&flipped).to_string();
    assert!(e.contains("corrupted") && e.contains("CRC-32"), "{e}");

    let mut longer = bytes.clone();
    longer.push(0);
    assert!(matches!(refused(&longer), CheckpointError::Corrupted { .. }));
}

#[test]
fn a_scene_changed_beyond_its_length_interval_and_checkpoints_is_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let ck = a_checkpoint(dir.path());
    let viscous = scene_copy(dir.path(), "viscous.toml", &[("duration", "0.05"), ("viscosity", "2e-3")]);
    let Err(e) = resume::resume(&ck, Some(&viscous)) else { panic!("a changed viscosity was accepted") };
    let e = e.to_string();
    assert!(e.contains("viscous.toml") && e.contains("`fluid.viscosity`") && e.contains("0.002"), "{e}");
    // Its length, its output interval and its checkpoints may change.
    let longer = scene_copy(dir.path(), "longer.toml", &[("duration", "0.1"), ("output_interval", "2e-3")]);
    let resumed = resume::resume(&ck, Some(&longer)).unwrap();
    assert_eq!(resumed.scene.duration, 0.1);
    // A duration before the checkpoint's time cannot be.
    let shorter = scene_copy(dir.path(), "shorter.toml", &[("duration", "0.01")]);
    let Err(e) = resume::resume(&ck, Some(&shorter)) else { panic!("a shorter run was accepted") };
    assert!(e.to_string().contains("before the checkpoint's time"), "{e}");
}

#[test]
fn a_resumed_run_made_longer_ends_as_the_longer_run() {
    let dir = tempfile::tempdir().unwrap();
    let ck = a_checkpoint(dir.path());
    let longer = scene_copy(dir.path(), "longer.toml", &[("duration", "0.12")]);
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_wetbounce")).args(args).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    };
    let (whole, resumed) = (dir.path().join("whole"), dir.path().join("resumed"));
    run(&["run", longer.to_str().unwrap(), "--formats", "csv", "-q", "--out", whole.to_str().unwrap()]);
    let args = ["resume", ck.to_str().unwrap(), "--scene", longer.to_str().unwrap(), "-q", "--out"];
    let mut args: Vec<&str> = args.to_vec();
    args.push(resumed.to_str().unwrap());
    run(&args);
    for file in ["trajectories.csv", "events.csv"] {
        assert!(
            std::fs::read(whole.join(file)).unwrap() == std::fs::read(resumed.join(file)).unwrap(),
            "{file}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Any cut or flipped byte of a checkpoint is an error naming the file, never a panic.
    #[test]
    fn a_damaged_checkpoint_is_an_error_never_a_panic(cut in 0.0f64..1.0, at in 0.0f64..1.0, bit in 0u8..8) {
        let bytes = reference();
        let mut damaged = bytes[..((cut * bytes.len() as f64) as usize).max(1)].to_vec();
        let i = ((at * damaged.len() as f64) as usize).min(damaged.len() - 1);
        damaged[i] ^= 1 << bit;
        let e = refused(&damaged).to_string();
        prop_assert!(e.starts_with("ck.wbck: "), "{}", e);
    }
}

/// One checkpoint's bytes, made once for the property.
fn reference() -> Vec<u8> {
    static BYTES: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    BYTES
        .get_or_init(|| {
            let dir = tempfile::tempdir().unwrap();
            std::fs::read(a_checkpoint(dir.path())).unwrap()
        })
        .clone()
}

#[test]
fn wall_clock_checkpoints_are_taken_and_only_the_newest_kept() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // Every 6 ms of wall clock: the 5000 steps of the glass bead take several times that.
    let run = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .args(["run", "scenes/glass_bead.toml", "--formats", "csv", "--quiet", "--checkpoint-wall", "1e-4"])
        .args(["--checkpoint-keep", "3", "--out"])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let kept = checkpoint::list(&out.join("checkpoints"));
    assert_eq!(kept.len(), 3, "{kept:?}");
    // The last is the run's end: resumed, nothing is left to run and the files stay whole.
    let (_, saved) = checkpoint::read(kept.last().unwrap()).unwrap();
    assert_eq!(saved.world.time, 1.0);
}

#[test]
fn bad_checkpoint_options_and_keys_are_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_wetbounce"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap()
    };
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    for (flag, value, says) in [
        ("--checkpoint-every", "-1", "--checkpoint-every: must be a finite number > 0, got -1"),
        ("--checkpoint-wall", "NaN", "--checkpoint-wall: must be a finite number > 0, got NaN"),
        ("--checkpoint-keep", "0", "--checkpoint-keep"),
    ] {
        let given = format!("{flag}={value}");
        let r = run(&["run", "scenes/glass_bead.toml", "--quiet", "--out", out, &given]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success() && err.contains(says), "{flag} {value}: {err}");
    }
    for (key, value, says) in [
        ("every", "0.0", "checkpoint.every: must be > 0, got 0"),
        ("wall_minutes", "-3.0", "checkpoint.wall_minutes: must be > 0, got -3"),
        ("keep", "0", "checkpoint.keep: must be a whole number from 1 to 1000000, got 0"),
        ("often", "1.0", "often"),
    ] {
        let scene = scene_copy(dir.path(), "bad.toml", &[]);
        let mut text = std::fs::read_to_string(&scene).unwrap();
        text.push_str(&format!("\n[checkpoint]\n{key} = {value}\n"));
        std::fs::write(&scene, text).unwrap();
        let r = run(&["check", scene.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success() && err.contains("bad.toml") && err.contains(says), "{key}: {err}");
    }
}
