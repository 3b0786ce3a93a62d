//! Stopping a run: a run that gets SIGINT, SIGTERM or SIGHUP finishes its step, closes every
//! output and exits with 128 + the signal, and its files are whole (headers, whole lines,
//! summary.json, an MCAP the standard readers open) up to where it stopped; a run killed
//! outright (SIGKILL) keeps every frame but the last, and `wetbounce recover` reads its MCAP
//! back (issue 13, findings 3).

use crate::outputs_common;

use outputs_common::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
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

/// 200 beads poured into a box (wall and pair contacts all along), far longer than any test
/// waits, with a frame every 2 ms of simulated time: frames of 200 rows come several times a
/// second of wall time.
fn long_pour(dir: &Path) -> std::path::PathBuf {
    scene_with(
        "tests/scenes/pour_200.toml",
        "pour.toml",
        dir,
        &[("duration", "3600.0"), ("output_interval", "0.002")],
    )
}

/// Starts `wetbounce run SCENE --formats mcap,csv` into `out`, one thread, no bar.
fn start(scene: &Path, out: &Path) -> std::process::Child {
    wetbounce()
        .arg("run")
        .arg(scene)
        // The hour-long pour would not fit on the disk (it is always stopped long before).
        .args(["--formats", "mcap,csv", "--quiet", "--threads", "1", "--allow-large-output", "--out"])
        .arg(out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Checks that a run stopped by a signal left whole files that agree with each other: the
/// CSV files' headers and whole lines only, as many frames in trajectories.csv as clouds in
/// the MCAP (which is closed), the last at the time summary.json gives, as many events in
/// events.csv as on `/events`.
fn check_stopped_cleanly(out: &Path, signal: &str) {
    let summary = read_summary(out);
    assert_eq!(summary["interrupted"], true, "{summary}");
    assert_eq!(summary["signal"], signal, "{summary}");
    assert_eq!(summary["output_errors"], serde_json::json!([]), "{summary}");
    let t_stop = summary["time_s"].as_f64().unwrap();

    let traj = read_csv(&out.join("trajectories.csv"), TRAJECTORY_HEADER);
    assert_eq!(traj.partial, 0, "trajectories.csv ends inside a line");
    let frames = frames(&traj);
    assert!(frames.iter().all(|(_, n)| *n == 200), "a frame without all 200 beads: {frames:?}");
    let events = read_csv(&out.join("events.csv"), EVENT_HEADER);
    assert_eq!(events.partial, 0, "events.csv ends inside a line");

    let topics = read_closed_mcap(&out.join("pour.mcap"));
    let clouds = &topics["/particles"];
    assert_eq!(clouds.len(), frames.len(), "clouds in the MCAP, frames in trajectories.csv");
    for ((log_time, _), (t, _)) in clouds.iter().zip(&frames) {
        assert_eq!(*log_time, outputs_common::log_time(t));
    }
    let last = frames.last().unwrap().0.parse::<f64>().unwrap();
    // (serde_json's default parser may miss the last bit of a number.)
    assert!((last - t_stop).abs() <= 1e-15, "the last frame at {last} s, the stop at {t_stop} s");
    let on_topic = topics.get("/events").map_or(0, Vec::len);
    assert_eq!(on_topic, events.lines.len() - 1, "events on /events and in events.csv");
}

#[test]
fn sigterm_sighup_and_sigint_at_random_moments_leave_whole_files_and_exit_128_plus_the_signal() {
    let dir = tempfile::tempdir().unwrap();
    let scene = long_pour(dir.path());
    // Seeded moments: from at once (the first frame may not be written yet) to well into the
    // run. Whatever the moment, the outcome is the same.
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let cases = [("TERM", 15), ("HUP", 1), ("INT", 2), ("TERM", 15), ("HUP", 1), ("TERM", 15)];
    for (case, (signal, number)) in cases.into_iter().enumerate() {
        let delay = Duration::from_millis(if case == 0 { 0 } else { rng.random_range(0..800) });
        let out = dir.path().join(format!("case{case}"));
        let mut child = start(&scene, &out);
        // The handlers are installed before any output file is created.
        wait_until(&mut child, Duration::from_secs(120), "the MCAP was created", || {
            out.join("pour.mcap").exists()
        });
        std::thread::sleep(delay);
        send(&child, signal);
        let output = wait_bounded(child, Duration::from_secs(120));
        let stderr = String::from_utf8_lossy(&output.stderr);
        let what = format!("case {case}: SIG{signal} after {delay:?}");
        // The files first: what a signal that kills the run loses.
        check_stopped_cleanly(&out, &format!("SIG{signal}"));
        // An exit with 128 + the signal, not a death by the signal (which a shell also shows as
        // 128 + the signal).
        assert_eq!(output.status.code(), Some(128 + number), "{what}: {} {stderr}", output.status);
        assert!(stderr.contains(&format!("by SIG{signal}")), "{what}: {stderr}");
    }
}

/// GNU `timeout` sends SIGTERM to the run and then, microseconds later, to its whole process
/// group, so the run gets it twice; `kill -TERM` sent twice in a row does the same. Each of
/// these must give the graceful stop (whole files, summary.json, exit 143), not the "second
/// signal exits at once" of a user who insists (issue 25, finding 10: 10 of 46 runs under
/// `timeout` lost their summary and their MCAP's footer).
#[test]
fn gnu_timeout_and_a_doubled_sigterm_stop_the_run_gracefully_every_time() {
    let dir = tempfile::tempdir().unwrap();
    let scene = long_pour(dir.path());
    let mut rng = ChaCha8Rng::seed_from_u64(25);
    for case in 0..8 {
        let out = dir.path().join(format!("timeout{case}"));
        // Seeded limits from half a second (the first frames) to two seconds into the run.
        let limit = format!("{:.3}", rng.random_range(0.5..2.0));
        // --preserve-status: timeout exits with the run's own status rather than 124.
        let child = Command::new("timeout")
            .args(["--preserve-status", "-s", "TERM", &limit])
            .arg(env!("CARGO_BIN_EXE_wetbounce"))
            .arg("run")
            .arg(&scene)
            // An hour of frames is estimated far above any disk: the run is stopped long before.
            .args(["--formats", "mcap,csv", "--quiet", "--threads", "1", "--allow-large-output", "--out"])
            .arg(&out)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let output = wait_bounded(child, Duration::from_secs(120));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(143), "timeout {limit}: {} {stderr}", output.status);
        assert!(stderr.contains("by SIGTERM"), "timeout {limit}: {stderr}");
        check_stopped_cleanly(&out, "SIGTERM");
    }
    for case in 0..4 {
        let out = dir.path().join(format!("twice{case}"));
        let mut child = start(&scene, &out);
        wait_until(&mut child, Duration::from_secs(120), "the MCAP was created", || {
            out.join("pour.mcap").exists()
        });
        std::thread::sleep(Duration::from_millis(rng.random_range(0..500)));
        send(&child, "TERM");
        send(&child, "TERM");
        let output = wait_bounded(child, Duration::from_secs(120));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(143), "kill -TERM twice: {} {stderr}", output.status);
        check_stopped_cleanly(&out, "SIGTERM");
    }
}

#[test]
fn sigkill_at_a_random_moment_loses_at_most_the_last_frame_and_recover_reads_the_mcap_back() {
    let dir = tempfile::tempdir().unwrap();
    let scene = long_pour(dir.path());
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let frame_bytes = 200 * 120; // about, for a frame of 200 rows
    let mut killed = Vec::new();
    for case in 0..5 {
        let out = dir.path().join(format!("case{case}"));
        let mut child = start(&scene, &out);
        // A seeded moment: once trajectories.csv holds a random number of frames, and a random
        // part of a frame's time later.
        let threshold = rng.random_range(0..120) * frame_bytes;
        let extra = Duration::from_micros(rng.random_range(0..30_000));
        let csv = out.join("trajectories.csv");
        wait_until(&mut child, Duration::from_secs(120), "trajectories.csv grew", || {
            std::fs::metadata(&csv).map_or(0, |m| m.len()) as usize > threshold
        });
        std::thread::sleep(extra);
        child.kill().unwrap(); // SIGKILL
        let output = wait_bounded(child, Duration::from_secs(60));
        assert_eq!(shell_status(output.status), 128 + 9);
        killed.push(out);
    }

    // What the run would have written had it not been killed: the same scene, run to a little
    // past the last frame any killed run reached (a frame's numbers do not depend on the
    // duration).
    let mut cut = Vec::new();
    for out in &killed {
        let traj = read_csv(&out.join("trajectories.csv"), TRAJECTORY_HEADER);
        let events = read_csv(&out.join("events.csv"), EVENT_HEADER);
        let (recovered, report) = recover(&out.join("pour.mcap"));
        cut.push((recovered, report, traj, events));
    }
    let most = cut.iter().map(|c| c.0.get("/particles").map_or(0, Vec::len)).max().unwrap();
    let reference_dir = dir.path().join("reference");
    let reference_scene = scene_with(
        "tests/scenes/pour_200.toml",
        "pour.toml",
        &dir.path().join("."),
        &[("duration", &format!("{}", (most + 3) as f64 * 0.002)), ("output_interval", "0.002")],
    );
    let status = wetbounce()
        .arg("run")
        .arg(&reference_scene)
        .args(["--formats", "mcap,csv", "--quiet", "--threads", "1", "--out"])
        .arg(&reference_dir)
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let reference = read_closed_mcap(&reference_dir.join("pour.mcap"));
    let ref_traj = std::fs::read(reference_dir.join("trajectories.csv")).unwrap();
    let ref_events = read_csv(&reference_dir.join("events.csv"), EVENT_HEADER);
    let ref_event_times: Vec<f64> =
        ref_events.lines.iter().skip(1).map(|l| l.split(',').next().unwrap().parse().unwrap()).collect();

    for (case, (recovered, report, traj, events)) in cut.iter().enumerate() {
        // trajectories.csv: whole lines are what the full run wrote; whole frames counted.
        assert!(ref_traj.starts_with(&traj.whole), "case {case}: trajectories.csv differs from the full run");
        let csv_frames = frames(traj);
        let whole_frames = csv_frames.iter().take_while(|(_, n)| *n == 200).count();
        // The MCAP: every cloud it had whole, read back, as the full run wrote them; a frame's
        // chunk reaches the file before the CSV files get the frame, so it holds the CSV's
        // whole frames and at most one more.
        let clouds = recovered.get("/particles").cloned().unwrap_or_default();
        assert!(
            clouds.len() >= whole_frames && clouds.len() <= whole_frames + 1,
            "case {case}: {} clouds recovered, {whole_frames} whole frames in trajectories.csv ({report})",
            clouds.len()
        );
        assert!(!clouds.is_empty(), "case {case}: no cloud recovered ({report})");
        eprintln!(
            "case {case}: {} clouds recovered, {whole_frames} whole frames and {} bytes of a cut line in \
             trajectories.csv, {} events",
            clouds.len(),
            traj.partial,
            events.lines.len() - 1
        );
        assert_eq!(clouds[..], reference["/particles"][..clouds.len()], "case {case}: clouds");
        // Events: every one before the last frame the file holds whole. (One at the frame's
        // very time may come from the step after the frame, in the next chunk.)
        let t_last_cloud = clouds.last().unwrap().0;
        let mcap_events = recovered.get("/events").cloned().unwrap_or_default();
        let due = reference["/events"].iter().take_while(|(t, _)| *t < t_last_cloud).count();
        assert!(mcap_events.len() >= due, "case {case}: {} of {due} events on /events", mcap_events.len());
        assert_eq!(mcap_events[..], reference["/events"][..mcap_events.len()], "case {case}: /events");
        assert!(ref_events.whole.starts_with(&events.whole), "case {case}: events.csv differs");
        // events.csv gets the events of an interval at the frame, after the trajectories: all
        // those before the last whole frame but one are there.
        if whole_frames >= 2 {
            let t = csv_frames[whole_frames - 2].0.parse::<f64>().unwrap();
            let due = ref_event_times.iter().filter(|&&e| e < t).count();
            let rows = events.lines.len() - 1;
            assert!(rows >= due, "case {case}: {rows} of {due} events");
        }
    }
}

#[test]
fn recover_rewrites_a_complete_mcap_message_for_message_and_says_it_was_complete() {
    let dir = tempfile::tempdir().unwrap();
    let out = wetbounce()
        .args(["run", "scenes/toluene_drop.toml", "--quiet", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(out.status.success());
    let file = dir.path().join("toluene_drop.mcap");
    let (recovered, report) = recover(&file);
    assert_eq!(recovered, read_closed_mcap(&file));
    assert!(report.contains("the file was complete"), "{report}");
    // The scene and the version travel along.
    let bytes = std::fs::read(file.with_extension("recovered.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    assert_eq!(summary.metadata_indexes.len(), 2);
}

/// Every way a closed MCAP can be cut — at each chunk's end, inside chunks, in the header, in
/// the summary — leaves a file `recover` turns into a valid one holding exactly the messages of
/// the chunks before the cut, never a panic. (The class of finding 3's unreadable MCAP, checked
/// on the bytes rather than on a killed process.)
#[test]
fn recover_reads_every_whole_chunk_of_an_mcap_cut_anywhere() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = drop_mcap(dir.path(), "0.05");
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let all: Vec<(u64, Vec<u8>)> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .map(|m| (m.log_time, m.data.into_owned()))
        .collect();
    // One chunk per frame: 21 frames (0, 0.05, …, 1 s).
    assert_eq!(summary.chunk_indexes.len(), 21, "a chunk per frame");
    // Messages in the chunks that end at or before each cut.
    let whole_before = |cut: u64| -> usize {
        summary
            .chunk_indexes
            .iter()
            .filter(|c| c.chunk_start_offset + c.chunk_length <= cut)
            .map(|c| count_in_chunk(&summary, &bytes, c))
            .sum()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut cuts: Vec<u64> =
        summary.chunk_indexes.iter().map(|c| c.chunk_start_offset + c.chunk_length).collect();
    cuts.extend((0..40).map(|_| rng.random_range(0..bytes.len() as u64)));
    cuts.extend([0, 4, 8, 20, bytes.len() as u64 - 1]);
    for (k, cut) in cuts.into_iter().enumerate() {
        let input = dir.path().join(format!("cut{k}.mcap"));
        std::fs::write(&input, &bytes[..cut as usize]).unwrap();
        let output = dir.path().join(format!("cut{k}.out.mcap"));
        let run = wetbounce().arg("recover").arg(&input).arg(&output).output().unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!stderr.contains("panicked"), "cut at {cut}: {stderr}");
        let first_chunk = summary.chunk_indexes[0].chunk_start_offset;
        if !run.status.success() {
            // Only a file cut inside its first records (magic, header) is refused, naming it.
            assert!(cut < first_chunk, "cut at {cut}: {stderr}");
            assert!(
                stderr.contains(&input.display().to_string()) && stderr.contains("not an MCAP"),
                "{stderr}"
            );
            continue;
        }
        let topics = read_closed_mcap(&output);
        let mut got: Vec<(u64, Vec<u8>)> = Vec::new();
        let back = std::fs::read(&output).unwrap();
        for m in mcap::MessageStream::new(&back).unwrap() {
            let m = m.unwrap();
            got.push((m.log_time, m.data.into_owned()));
        }
        assert_eq!(got.len(), topics.values().map(Vec::len).sum::<usize>());
        assert_eq!(got[..], all[..got.len()], "cut at {cut}: not a prefix of the messages");
        assert_eq!(got.len(), whole_before(cut).min(all.len()), "cut at {cut}: whole chunks lost");
    }
}

/// Messages in one chunk, read through the summary's index.
fn count_in_chunk(summary: &mcap::Summary, bytes: &[u8], chunk: &mcap::records::ChunkIndex) -> usize {
    summary.stream_chunk(bytes, chunk).unwrap().count()
}

#[test]
fn recover_refuses_to_write_over_its_input_under_another_name() {
    let dir = tempfile::tempdir().unwrap();
    let out = wetbounce()
        .args(["run", "scenes/toluene_drop.toml", "--quiet", "--output-interval", "0.1", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(out.status.success());
    let file = dir.path().join("toluene_drop.mcap");
    let before = std::fs::read(&file).unwrap();
    let same = dir.path().join(".").join("toluene_drop.mcap");
    let run = wetbounce().arg("recover").arg(&file).arg(&same).output().unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("is the input"), "{stderr}");
    assert_eq!(std::fs::read(&file).unwrap(), before, "the input was changed");
}

/// Issue 25, finding 13: a 140-byte MCAP whose chunk length field said 2^63 made `recover`
/// allocate 2 GB (an abort under a 1 GB limit), and a failed recovery left a 0-byte or partial
/// output. Every length field of the first chunk is set to lying values, in whole files and in
/// files cut short: under a 256 MiB address-space limit, `recover` keeps what is whole before the
/// lie or refuses naming the input, never aborts, and leaves no output when it refuses.
#[test]
fn recover_of_an_mcap_whose_lengths_lie_allocates_nothing_of_that_size_and_leaves_no_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = drop_mcap(dir.path(), "0.1");
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let chunk = summary.chunk_indexes[0].chunk_start_offset as usize;
    // A chunk record: opcode, record length (u64), start and end times (u64), uncompressed
    // size (u64), CRC (u32), compression (u32 length + text), records length (u64), records.
    let record_length_at = chunk + 1;
    let uncompressed_at = chunk + 1 + 8 + 16;
    let compression_len =
        u32::from_le_bytes(bytes[uncompressed_at + 12..uncompressed_at + 16].try_into().unwrap());
    let records_length_at = uncompressed_at + 16 + compression_len as usize;
    let lies = [1u64 << 63, u64::MAX - 1, 1 << 31, 3 << 30, 1 << 40];
    let mut k = 0;
    for at in [record_length_at, uncompressed_at, records_length_at] {
        for lie in lies {
            for keep in [chunk + 60, bytes.len()] {
                let mut b = bytes[..keep.min(bytes.len())].to_vec();
                b[at..at + 8].copy_from_slice(&lie.to_le_bytes());
                let input = dir.path().join(format!("lie{k}.mcap"));
                let output = dir.path().join(format!("lie{k}.out.mcap"));
                k += 1;
                std::fs::write(&input, &b).unwrap();
                let run = Command::new("bash")
                    .arg("-c")
                    .arg("ulimit -v 262144; exec \"$0\" recover \"$1\" \"$2\"")
                    .arg(env!("CARGO_BIN_EXE_wetbounce"))
                    .arg(&input)
                    .arg(&output)
                    .output()
                    .unwrap();
                let stderr = String::from_utf8_lossy(&run.stderr);
                let what = format!("length at byte {at} = {lie}, file of {} bytes", b.len());
                assert!(
                    !stderr.contains("panicked") && !stderr.contains("memory allocation"),
                    "{what}: {stderr}"
                );
                match run.status.code() {
                    Some(0) => {
                        // What it kept is a closed MCAP the standard reader opens.
                        read_closed_mcap(&output);
                    }
                    Some(1) => {
                        assert!(stderr.contains(&input.display().to_string()), "{what}: {stderr}");
                        assert!(!output.exists(), "{what}: a failed recovery left {}", output.display());
                    }
                    other => panic!("{what}: exit {other:?}: {stderr}"),
                }
            }
        }
    }
    // Not an MCAP at all: refused, and no output.
    let input = dir.path().join("text.mcap");
    std::fs::write(&input, "not an mcap").unwrap();
    let output = dir.path().join("text.out.mcap");
    let run = wetbounce().arg("recover").arg(&input).arg(&output).output().unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(!output.exists(), "a failed recovery left {}", output.display());
}

/// The closed MCAP of the Fig. 6 drop with frames every `interval` (s), written into `dir`.
fn drop_mcap(dir: &Path, interval: &str) -> Vec<u8> {
    let out = wetbounce()
        .args(["run", "scenes/toluene_drop.toml", "--quiet", "--output-interval", interval, "--out"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::read(dir.join("toluene_drop.mcap")).unwrap()
}
