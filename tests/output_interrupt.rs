//! Ctrl-C: a run that gets SIGINT finishes its step, closes every output and exits non-zero,
//! and its MCAP is a valid file holding every frame up to where it stopped.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn sigint_leaves_a_valid_mcap_up_to_the_stop_time_and_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    // The Fig. 6 drop for an hour of simulated time: far longer than the test waits.
    let source =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/toluene_drop.toml"))
            .unwrap()
            .replace("duration = 1.0 ", "duration = 3600.0 ");
    assert!(source.contains("duration = 3600.0"), "the shipped scene changed its duration line");
    let scene = dir.path().join("long.toml");
    std::fs::write(&scene, source).unwrap();
    let out = dir.path().join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .arg("run")
        .arg(&scene)
        .args(["--formats", "mcap,csv", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();

    // Wait until the run has written a few frames (the CSV grows), then interrupt it.
    let csv = out.join("trajectories.csv");
    let start = Instant::now();
    while std::fs::metadata(&csv).map_or(0, |m| m.len()) < 1 << 20 {
        assert!(start.elapsed() < Duration::from_secs(60), "the run wrote nothing for a minute");
        assert!(child.try_wait().unwrap().is_none(), "the run ended before it was interrupted");
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(status.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");

    // "interrupted: stopped at t = T s of 3600 s after N steps; ..."
    let line = stderr.lines().find(|l| l.starts_with("interrupted: stopped at t = ")).expect(&stderr);
    let t_stop: f64 =
        line["interrupted: stopped at t = ".len()..].split(' ').next().unwrap().parse().unwrap();
    assert!(t_stop > 0.0 && t_stop < 3600.0, "{line}");

    // The MCAP is finished (summary, statistics) and its last cloud is at the stop time.
    let bytes = std::fs::read(out.join("long.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a closed MCAP has a summary");
    assert!(summary.stats.is_some());
    let mut clouds = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == "/particles" {
            clouds.push(m.log_time);
        }
    }
    let last = *clouds.last().unwrap();
    assert!((last as f64 * 1e-9 - t_stop).abs() < 1e-6, "last frame at {last} ns, stopped at {t_stop} s");
    // Every output interval (1 ms) up to the stop has its frame, then the stop frame.
    let full = (t_stop / 1e-3 + 1e-6).floor() as usize + 1;
    assert!(clouds.len() == full || clouds.len() == full + 1, "{} frames up to {t_stop} s", clouds.len());
    assert!(clouds.windows(2).all(|w| w[0] < w[1]));
    // The CSV was flushed too: as many frames as the MCAP.
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count() - 1;
    assert_eq!(rows, clouds.len());
    // And the summary still went to stdout.
    assert!(String::from_utf8_lossy(&output.stdout).contains("(interrupted)"));
}
