//! Helpers of the tests that stop, kill or starve a run and then read what it left
//! (`output_interrupt.rs`, `output_disk_full.rs`, `output_vtk.rs`).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Output};
use std::time::{Duration, Instant};

/// The header of trajectories.csv.
pub const TRAJECTORY_HEADER: &str = "t,id,x,y,z,vx,vy,vz,state";
/// The header of events.csv.
pub const EVENT_HEADER: &str = "t,id,other,kind,normal_speed,st,eps,contact_time,outcome";

/// `wetbounce` run from the repository's root.
pub fn wetbounce() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_wetbounce"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

/// Writes `dir/name` as the repository's scene `from` (e.g. `tests/scenes/pour_200.toml`) with
/// each `(key, value)` line of its `[simulation]` replaced.
pub fn scene_with(from: &str, name: &str, dir: &Path, values: &[(&str, &str)]) -> PathBuf {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(from)).unwrap();
    let mut replaced = 0;
    let lines: Vec<String> = text
        .lines()
        .map(|l| match values.iter().find(|(k, _)| l.starts_with(&format!("{k} ="))) {
            Some((k, v)) => {
                replaced += 1;
                format!("{k} = {v}")
            }
            None => l.to_string(),
        })
        .collect();
    assert_eq!(replaced, values.len(), "{from} changed its [simulation] lines");
    let path = dir.join(name);
    std::fs::write(&path, lines.join("\n")).unwrap();
    path
}

/// Polls until `ready()` holds; fails if the child ends first or after `limit`.
pub fn wait_until(child: &mut Child, limit: Duration, what: &str, mut ready: impl FnMut() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(start.elapsed() < limit, "waited {limit:?} for {what}");
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before {what}");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Waits for the child's end, at most `limit` (then kills it and fails); returns its output.
pub fn wait_bounded(mut child: Child, limit: Duration) -> Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!("the run did not end within {limit:?}: {}", String::from_utf8_lossy(&out.stderr));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.wait_with_output().unwrap()
}

/// Sends `signal` (`TERM`, `HUP`, `INT`) to the child this test started.
pub fn send(child: &Child, signal: &str) {
    let status =
        Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
    assert!(status.success(), "kill -{signal}");
}

/// A CSV file as a run left it.
pub struct CsvFile {
    /// The lines that end with a newline, the header first.
    pub lines: Vec<String>,
    /// The bytes of those lines.
    pub whole: Vec<u8>,
    /// Bytes after the last newline: a line cut short.
    pub partial: usize,
}

/// Reads a CSV file and checks its header; every whole line has the header's field count.
pub fn read_csv(path: &Path, header: &str) -> CsvFile {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let end = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let whole = bytes[..end].to_vec();
    let text = String::from_utf8(whole.clone()).unwrap();
    let lines: Vec<String> = text.lines().map(str::to_string).collect();
    assert_eq!(lines.first().map(String::as_str), Some(header), "{}: no header", path.display());
    let fields = header.split(',').count();
    for l in &lines {
        assert_eq!(l.split(',').count(), fields, "{}: line {l:?}", path.display());
    }
    CsvFile { partial: bytes.len() - end, lines, whole }
}

/// The frames of trajectories.csv: (time as written, rows).
pub fn frames(csv: &CsvFile) -> Vec<(String, usize)> {
    let mut frames: Vec<(String, usize)> = Vec::new();
    for l in csv.lines.iter().skip(1) {
        let t = l.split(',').next().unwrap();
        match frames.last_mut() {
            Some((last, n)) if last == t => *n += 1,
            _ => frames.push((t.to_string(), 1)),
        }
    }
    frames
}

/// The messages of an MCAP per topic, in file order: (log time, payload).
pub type Topics = std::collections::BTreeMap<String, Vec<(u64, Vec<u8>)>>;

/// Reads a closed MCAP as the standard readers do: its summary must be there (else the file
/// is not closed), its statistics must count what the stream holds.
pub fn read_closed_mcap(path: &Path) -> Topics {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let summary = mcap::Summary::read(&bytes)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .unwrap_or_else(|| panic!("{}: no summary: the file was not closed", path.display()));
    let mut topics = Topics::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        topics.entry(m.channel.topic.clone()).or_default().push((m.log_time, m.data.into_owned()));
    }
    let stats = summary.stats.expect("a statistics record");
    assert_eq!(stats.message_count as usize, topics.values().map(Vec::len).sum::<usize>());
    topics
}

/// Runs `wetbounce recover IN OUT` and reads OUT back as a closed MCAP.
pub fn recover(input: &Path) -> (Topics, String) {
    let output = input.with_extension("recovered.mcap");
    let out = wetbounce().arg("recover").arg(input).arg(&output).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "recover: {}{stdout}", String::from_utf8_lossy(&out.stderr));
    (read_closed_mcap(&output), stdout)
}

/// An exit status as a shell shows it: the code, or 128 + the signal that killed the process.
pub fn shell_status(status: ExitStatus) -> i32 {
    use std::os::unix::process::ExitStatusExt;
    status.code().unwrap_or_else(|| 128 + status.signal().unwrap_or(0))
}

/// The JSON of summary.json.
pub fn read_summary(dir: &Path) -> serde_json::Value {
    let path = dir.join("summary.json");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// MCAP log time of a time written in the CSV.
pub fn log_time(t: &str) -> u64 {
    (t.parse::<f64>().unwrap() * 1e9).round() as u64
}

/// Runs `wetbounce run SCENE` (a path relative to the repository) into `out` with every file it
/// writes limited to `bytes`, and SIGXFSZ ignored, so that a write past the limit fails with
/// EFBIG ("File too large") as a write to a full disk fails with ENOSPC: a disk that fills in
/// the middle of a run, without root.
pub fn run_with_file_limit(scene: &Path, out: &Path, formats: &str, bytes: u64) -> Output {
    use std::os::unix::process::CommandExt;
    let mut cmd = wetbounce();
    cmd.arg("run").arg(scene).args(["--formats", formats, "--quiet", "--threads", "1", "--out"]).arg(out);
    // SAFETY: between fork and exec the closure calls only setrlimit and signal, which are
    // async-signal-safe, and allocates nothing.
    unsafe {
        cmd.pre_exec(move || {
            let limit = libc::rlimit { rlim_cur: bytes, rlim_max: bytes };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            Ok(())
        });
    }
    cmd.output().unwrap()
}
