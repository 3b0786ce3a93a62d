//! Results do not depend on the thread count (docs/architecture.md: determinism by construction): the same scene run with
//! 1 and 2 threads, and twice, writes byte-identical output files (stability case 11,
//! docs/stability.md).

use std::process::Command;

fn run(scene: &str, threads: &str, dir: &std::path::Path) -> Vec<u8> {
    run_formats(scene, threads, dir, "csv")
}

/// Runs `scene` and returns the bytes of every file it wrote: the CSV files, the MCAP if asked
/// for, and summary.json without its one measured field, the wall-clock time.
fn run_formats(scene: &str, threads: &str, dir: &std::path::Path, formats: &str) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["run", scene, "--formats", formats, "--quiet", "--threads", threads, "--out"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut bytes = std::fs::read(dir.join("trajectories.csv")).unwrap();
    bytes.extend(std::fs::read(dir.join("events.csv")).unwrap());
    let stem = std::path::Path::new(scene).file_stem().unwrap().to_string_lossy().into_owned();
    if formats.contains("mcap") {
        bytes.extend(std::fs::read(dir.join(format!("{stem}.mcap"))).unwrap());
    }
    let mut summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap();
    summary.as_object_mut().unwrap().remove("wall_time_s");
    bytes.extend(summary.to_string().into_bytes());
    bytes
}

/// 200 glass beads poured into a box: wall and pair contacts, lasting contacts, islands
/// resolved in parallel.
const POUR: &str = "tests/scenes/pour_200.toml";

#[test]
fn one_and_two_threads_write_identical_files_for_a_pour_with_pair_contacts() {
    let dirs: Vec<_> = (0..3).map(|_| tempfile::tempdir().unwrap()).collect();
    let one = run(POUR, "1", dirs[0].path());
    let two = run(POUR, "2", dirs[1].path());
    let again = run(POUR, "2", dirs[2].path());
    assert!(one.len() > 100_000, "{} bytes", one.len());
    assert!(one == two, "1 and 2 threads differ");
    assert!(two == again, "two runs with 2 threads differ");
    let events = std::fs::read_to_string(dirs[0].path().join("events.csv")).unwrap();
    assert!(events.contains(",particle,"), "the pour must have particle contacts");
}

/// The column scene (seeded injector, log-normal sizes, outlet, baffle-like plate, holds)
/// shortened to 1.5 s: about 750 drops injected, the first reaching the plate.
#[test]
fn seeded_column_writes_identical_csv_mcap_and_summary_with_1_and_2_threads_and_twice() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/column.toml")).unwrap();
    let text: String = text
        .lines()
        .map(|l| if l.starts_with("duration =") { "duration = 1.5".to_string() } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let scenes = tempfile::tempdir().unwrap();
    let scene = scenes.path().join("column_short.toml");
    std::fs::write(&scene, text).unwrap();
    let scene = scene.to_str().unwrap();
    let dirs: Vec<_> = (0..3).map(|_| tempfile::tempdir().unwrap()).collect();
    let one = run_formats(scene, "1", dirs[0].path(), "mcap,csv");
    let two = run_formats(scene, "2", dirs[1].path(), "mcap,csv");
    let again = run_formats(scene, "2", dirs[2].path(), "mcap,csv");
    assert!(one.len() > 100_000, "{} bytes", one.len());
    assert!(one == two, "1 and 2 threads differ");
    assert!(two == again, "two runs with 2 threads differ");
}
