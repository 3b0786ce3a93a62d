//! Every scene in `scenes/bad/` is invalid in one way, announced by its leading comment lines:
//!
//! ```toml
//! # expect: kinds[0].density: must be > 0, got -2500
//! ```
//!
//! The first line of each file has that form; further `# expect:` lines directly below it add
//! more substrings the message must contain (e.g. a mesh file's name, whose folder differs
//! between the library call and the command line). Loading must fail without a panic, with a
//! message that names the scene file and contains every expected substring; `wetbounce check`
//! must exit non-zero and print that message on stderr after `error: `.

use std::path::{Path, PathBuf};
use std::process::Command;
use wetbounce::Scene;

const EXPECT: &str = "# expect: ";

/// Fewer files than this means the fixtures went missing, not that everything passed.
const MIN_BAD_SCENES: usize = 30;

fn bad_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bad")
}

/// The bad scenes, sorted, with their expected substrings.
fn bad_scenes() -> Vec<(PathBuf, Vec<String>)> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(bad_dir())
        .expect("scenes/bad exists")
        .map(|e| e.expect("readable folder entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    assert!(paths.len() >= MIN_BAD_SCENES, "only {} bad scenes in {}", paths.len(), bad_dir().display());
    paths
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let expected: Vec<String> = text
                .lines()
                .map_while(|l| l.strip_prefix(EXPECT))
                .map(|s| s.trim_end().to_string())
                .collect();
            assert!(
                !expected.is_empty() && expected.iter().all(|e| !e.trim().is_empty()),
                "{}: the first line must be `{EXPECT}<substring of the error message>`",
                path.display()
            );
            (path, expected)
        })
        .collect()
}

fn file_name(path: &Path) -> String {
    path.file_name().unwrap().to_string_lossy().into_owned()
}

/// Panics with every collected failure, one per line, so that one run lists them all.
fn report(what: &str, failures: Vec<String>, total: usize) {
    assert!(
        failures.is_empty(),
        "{} of {total} bad scenes {what}:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn every_bad_scene_fails_to_load_with_a_message_naming_the_file_the_key_and_the_value() {
    let scenes = bad_scenes();
    let mut failures = Vec::new();
    for (path, expected) in &scenes {
        let name = file_name(path);
        let loaded = std::panic::catch_unwind(|| Scene::load(path));
        let err = match loaded {
            Err(_) => {
                failures.push(format!("{name}: Scene::load panicked"));
                continue;
            }
            Ok(Ok(_)) => {
                failures.push(format!("{name}: loaded without error"));
                continue;
            }
            Ok(Err(e)) => e.to_string(),
        };
        let shown = path.display().to_string();
        if !err.contains(&shown) {
            failures.push(format!("{name}: the message does not name the file:\n  {err}"));
        }
        for e in expected {
            if !err.contains(e.as_str()) {
                failures.push(format!(
                    "{name}: the message lacks the expected text\n  expected: {e}\n  got:      {err}"
                ));
            }
        }
    }
    report("do not fail as their `# expect:` lines say", failures, scenes.len());
}

#[test]
fn check_command_rejects_every_bad_scene_with_an_error_line_on_stderr_and_no_panic() {
    let scenes = bad_scenes();
    let mut failures = Vec::new();
    for (path, expected) in &scenes {
        let name = file_name(path);
        let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
            .arg("check")
            .arg(path)
            .output()
            .expect("the wetbounce binary runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        let stdout = String::from_utf8_lossy(&out.stdout);
        if out.status.success() {
            failures.push(format!("{name}: `wetbounce check` exited with success\n  stdout: {stdout}"));
        }
        if stderr.contains("panicked") {
            failures.push(format!("{name}: `wetbounce check` panicked:\n{stderr}"));
            continue;
        }
        if !stderr.starts_with("error: ") {
            failures.push(format!("{name}: stderr does not start with `error: `:\n  {stderr}"));
        }
        if !stderr.contains(&path.display().to_string()) {
            failures.push(format!("{name}: stderr does not name the file:\n  {stderr}"));
        }
        for e in expected {
            if !stderr.contains(e.as_str()) {
                failures.push(format!(
                    "{name}: stderr lacks the expected text\n  expected: {e}\n  got:      {stderr}"
                ));
            }
        }
    }
    report("are not rejected by `wetbounce check` as expected", failures, scenes.len());
}

#[test]
fn bad_scene_fixtures_cover_every_error_kind() {
    // One file per error kind the scene loader must catch (stems of `scenes/bad/*.toml`).
    let required = [
        "missing_dt",
        "wrong_type_string_for_dt",
        "unknown_key_typo",
        "negative_density",
        "zero_dt",
        "nan_viscosity",
        "inf_duration",
        "restitution_above_one",
        "unknown_effect",
        "effect_not_a_table",
        "unknown_integrator",
        "unknown_kind_type",
        "unknown_wall_type",
        "particle_unknown_kind",
        "duplicate_kind_name",
        "duplicate_wall_name",
        "box_min_not_below_max",
        "plane_zero_normal",
        "drag_zero_viscosity",
        "st_critical_too_low_with_solid",
        "lattice_spacing_below_diameter",
        "random_fill_too_full",
        "mesh_file_missing",
        "mesh_wrong_extension",
        "mesh_garbage_stl",
        "mesh_degenerate_triangle",
        "mesh_nan_coordinates",
        "mesh_no_triangles",
        "particle_overlapping_plane",
        "particle_outside_box_container",
        "toml_syntax_error",
    ];
    let present: Vec<String> =
        bad_scenes().iter().map(|(p, _)| p.file_stem().unwrap().to_string_lossy().into_owned()).collect();
    let missing: Vec<&str> = required.iter().copied().filter(|r| !present.iter().any(|p| p == r)).collect();
    assert!(missing.is_empty(), "no bad scene for: {missing:?}");
}

#[test]
fn valid_example_scene_loads_and_checks_cleanly() {
    // Control for the two tests above: a valid scene passes both the library and the CLI.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/toluene_drop.toml");
    if let Err(e) = Scene::load(&path) {
        panic!("{e}");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .arg("check")
        .arg(&path)
        .output()
        .expect("the wetbounce binary runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
}
