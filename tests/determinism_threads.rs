//! Results do not depend on the thread count (ARCHITECTURE.md rule 7): the same scene run with
//! 1 and 2 threads, and twice, writes byte-identical output files.

use std::process::Command;

fn run(scene: &str, threads: &str, dir: &std::path::Path) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["run", scene, "--formats", "csv", "--quiet", "--threads", threads, "--out"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut bytes = std::fs::read(dir.join("trajectories.csv")).unwrap();
    bytes.extend(std::fs::read(dir.join("events.csv")).unwrap());
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
