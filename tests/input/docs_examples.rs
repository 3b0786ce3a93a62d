//! What the README and docs/output.md show of the program's output is what it prints: the
//! end-of-run table, the `check` table and the bad-scene message, run for real. Timings (the
//! wall time and the step rate) depend on the machine and are the only parts not compared.

use std::process::Command;

fn wetbounce(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn doc(path: &str) -> String {
    std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)).unwrap()
}

/// The indented block of `text` that starts with the line containing `first`, unindented by
/// `indent` spaces, up to the first line indented less.
fn block(text: &str, first: &str, indent: usize) -> Vec<String> {
    let mut lines = text.lines().skip_while(|l| !l.contains(first));
    let head = lines.next().unwrap_or_else(|| panic!("no line with {first:?}"));
    let pad = " ".repeat(indent);
    std::iter::once(head)
        .chain(lines.take_while(|l| l.starts_with(&pad)))
        .map(|l| l[indent..].to_string())
        .collect()
}

/// The line with its measured numbers blanked: `steps 10000 (…)` and `wall time …`.
fn without_timings(line: &str) -> String {
    if line.trim_start().starts_with("wall time") {
        return "wall time".into();
    }
    match line.find(" steps/s)") {
        Some(end) => {
            let start = line[..end].rfind('(').unwrap();
            format!("{}(…{}", &line[..start], &line[end..])
        }
        None => line.to_string(),
    }
}

#[test]
fn the_end_of_run_table_shown_in_readme_and_output_docs_is_what_a_run_prints() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("toluene_drop");
    let (ok, stdout, stderr) =
        wetbounce(&["run", "scenes/toluene_drop.toml", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let printed: Vec<String> =
        stdout.replace(&out.display().to_string(), "out/toluene_drop").lines().map(without_timings).collect();
    for file in ["README.md", "docs/output.md"] {
        let shown: Vec<String> = block(&doc(file), "scenes/toluene_drop.toml: 1 particles, rk2", 4)
            .iter()
            .map(|l| without_timings(l))
            .collect();
        assert_eq!(shown, printed, "{file}'s end-of-run table is out of date");
    }
}

#[test]
fn the_check_table_shown_in_the_readme_is_what_check_prints() {
    let (ok, stdout, stderr) = wetbounce(&["check", "scenes/toluene_drop.toml"]);
    assert!(ok, "{stderr}");
    let shown = block(&doc("README.md"), "kind            d [mm]", 4);
    for line in &shown {
        assert!(stdout.lines().any(|l| l == line), "README shows {line:?}; check prints:\n{stdout}");
    }
}

#[test]
fn the_bad_scene_message_quoted_in_the_readme_is_what_check_prints() {
    let readme = doc("README.md");
    let quoted = readme
        .lines()
        .find_map(|l| l.split('`').find(|q| q.starts_with("error: scenes/bad/")))
        .expect("the README quotes a bad scene's message");
    let scene = quoted["error: ".len()..].split(':').next().unwrap();
    let (ok, _, stderr) = wetbounce(&["check", scene]);
    assert!(!ok);
    assert_eq!(stderr.trim_end(), quoted);
}

#[test]
fn the_split_check_ranks_prints_is_the_one_docs_distributed_shows() {
    let (ok, stdout, stderr) = wetbounce(&["check", "scenes/settling_bed.toml", "--ranks", "2"]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("on 2 ranks, at the start:"), "{stdout}");
    // The ranks' line gives no thread count: check runs no rank.
    assert!(stdout.contains("  ranks: 2 (particles per rank at the last re-clustering: ["), "{stdout}");
    // docs/distributed.md: "the settling bed is one cluster of 1964 of its 2000 beads from the start".
    assert!(doc("docs/distributed.md").contains("one cluster of 1964 of its 2000 beads"));
    assert!(stdout.contains("the largest 1964 particles"), "{stdout}");
}
