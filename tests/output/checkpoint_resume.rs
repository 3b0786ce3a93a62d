//! Checkpoint and resume are exact (issue 27): a run checkpointed at step N and resumed from it
//! writes the same `trajectories.csv`, `events.csv` and `summary.json` (less its wall time) as
//! the run never stopped — for every shipped scene (shortened), resumed on 1 and on 2 threads,
//! from cut points inside a hold, inside lasting contacts and between injections.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use wetbounce::output::{Folder, Format};
use wetbounce::run::checkpoint::{self, SavedScene};
use wetbounce::run::{CheckpointPolicy, Checkpoints, Driver, resume};
use wetbounce::scene::{LoadOptions, Scene};

/// The repository's scene `name`, its `duration` replaced (s).
fn scene(name: &str, duration: Option<f64>) -> (PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(format!("{name}.toml"));
    let text = std::fs::read_to_string(&path).unwrap();
    let text = match duration {
        None => text,
        Some(d) => {
            let mut done = false;
            let lines: Vec<String> = text
                .lines()
                .map(|l| {
                    if !done && l.starts_with("duration =") {
                        done = true;
                        format!("duration = {d}")
                    } else {
                        l.to_string()
                    }
                })
                .collect();
            assert!(done, "{name} has no duration line");
            lines.join("\n")
        }
    };
    (path, text)
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
}

/// Runs the scene whole into `out` with `formats`, a checkpoint every `every` (s), all kept;
/// returns the checkpoints, oldest first.
fn run_whole(
    name: &str,
    source: &(PathBuf, String),
    formats: &[Format],
    every: f64,
    out: &Path,
) -> Vec<PathBuf> {
    let policy = CheckpointPolicy { every: Some(every), wall: None, keep: 100_000 };
    run_checkpointed(name, source, formats, policy, out, None).1
}

/// Runs the scene into `out` with `formats` and checkpoints as `policy` says, on one thread;
/// with `stop_in_frame`, a stop is asked while that frame is written ([`StopInFrame`]).
/// Returns the time it stopped at and the checkpoints, oldest first.
fn run_checkpointed(
    name: &str,
    (path, text): &(PathBuf, String),
    formats: &[Format],
    policy: CheckpointPolicy,
    out: &Path,
    stop_in_frame: Option<u64>,
) -> (f64, Vec<PathBuf>) {
    let options = LoadOptions { allow_long_run: true, allow_large_memory: true };
    let mut scene = Scene::from_str_with(text, path, options).unwrap();
    let folder = Folder {
        out,
        stem: name,
        scene_path: path,
        scene_source: text,
        max_spheres: 1000,
        rotation: scene.setup.physics.rotation,
    };
    let saved = SavedScene {
        path: path.clone(),
        given: path.clone(),
        source: text.clone(),
        output_interval: scene.output_interval,
        formats: formats.iter().map(|f| f.name().to_string()).collect(),
        stem: name.to_string(),
        max_spheres: 1000,
    };
    let checkpoints = Checkpoints::new(policy, &out.join("checkpoints"), saved, 0.0);
    let mut driver = Driver::new(Some(&folder), formats, scene.duration, scene.output_interval)
        .unwrap()
        .checkpointing(checkpoints);
    let mut sim = scene.take_simulation().unwrap();
    let stop = AtomicBool::new(false);
    let mut sink = stop_in_frame.map(|at| StopInFrame { frames: 0, at, stop: &stop });
    let result = pool(1).install(|| {
        let extra: Vec<&mut dyn wetbounce::output::Sink> = sink.iter_mut().map(|s| s as _).collect();
        driver.run(&mut sim, extra, &stop)
    });
    let ended = driver.finish(&sim, result, None);
    assert!(ended.errors.is_empty(), "{:?}", ended.errors);
    (sim.world.time, checkpoint::list(&out.join("checkpoints")))
}

/// Resumes `from` (a checkpoint of the run in its folder) into `out` on `threads` threads.
fn resume_into(from: &Path, out: &Path, threads: usize) {
    let resume::Resumed { saved, scene, mut sim, .. } = resume::resume(from, None).unwrap();
    resume::carry_outputs(&resume::run_folder(from), out, &saved).unwrap();
    let formats: Vec<Format> = saved.scene.formats.iter().map(|f| Format::parse(f).unwrap()).collect();
    let folder = Folder {
        out,
        stem: &saved.scene.stem,
        scene_path: &saved.scene.given,
        scene_source: &scene.source,
        max_spheres: saved.scene.max_spheres,
        rotation: scene.setup.physics.rotation,
    };
    let mut driver = Driver::resume(&folder, &formats, scene.duration, &saved).unwrap();
    let result = pool(threads).install(|| driver.run(&mut sim, vec![], &AtomicBool::new(false)));
    let ended = driver.finish(&sim, result, None);
    assert!(ended.errors.is_empty(), "{:?}", ended.errors);
}

/// `summary.json` without its wall time (which no two runs share).
fn summary(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    text.lines().filter(|l| !l.contains("wall_time")).collect::<Vec<_>>().join("\n")
}

fn assert_same_outputs(whole: &Path, resumed: &Path, what: &str) {
    for file in ["trajectories.csv", "events.csv"] {
        let (a, b) = (std::fs::read(whole.join(file)).unwrap(), std::fs::read(resumed.join(file)).unwrap());
        assert!(a == b, "{what}: {file} differs ({} and {} bytes)", a.len(), b.len());
    }
    assert_eq!(summary(whole), summary(resumed), "{what}: summary.json differs");
}

/// Runs `name` shortened to `duration` with a checkpoint every `every`, then resumes it from
/// the checkpoints `picks` picks among those written (on 2 threads, then on 1, alternately),
/// each into a fresh folder, and checks every resumed run against the whole one. Returns the
/// checkpoints.
fn exact(name: &str, duration: Option<f64>, every: f64, picks: fn(&[PathBuf]) -> Vec<usize>) -> Vec<PathBuf> {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole");
    let source = scene(name, duration);
    let checkpoints = run_whole(name, &source, &[Format::Csv], every, &whole);
    assert!(checkpoints.len() >= 2, "{name}: {} checkpoints", checkpoints.len());
    for (n, k) in picks(&checkpoints).into_iter().enumerate() {
        let resumed = dir.path().join(format!("resumed{n}"));
        let threads = if n % 2 == 0 { 2 } else { 1 };
        resume_into(&checkpoints[k], &resumed, threads);
        let what = format!("{name} resumed from {} on {threads} threads", checkpoints[k].display());
        assert_same_outputs(&whole, &resumed, &what);
    }
    checkpoints
}

/// A middle checkpoint and one near the end.
fn middle_and_late(c: &[PathBuf]) -> Vec<usize> {
    vec![c.len() / 2, c.len() - 2]
}

#[test]
fn single_particle_scenes_resume_exactly() {
    for name in ["glass_bead", "glass_bead_lubrication", "toluene_drop", "wc_bead_air", "steel_bead_oil"] {
        exact(name, None, 0.1234, middle_and_late);
    }
}

#[test]
fn history_resumes_exactly_with_its_memory() {
    exact("steel_bead_oil_history", None, 0.01234, middle_and_late);
}

#[test]
fn beds_with_and_without_friction_and_the_heap_resume_exactly() {
    exact("settling_bed", Some(0.15), 0.0213, middle_and_late);
    exact("heap", Some(0.1), 0.0173, middle_and_late);
}

#[test]
fn a_cut_inside_lasting_contacts_with_friction_resumes_exactly() {
    // Cut where the bed has lasting contacts with their warm starts and tangential state.
    let lasting = |c: &[PathBuf]| {
        // Not the last: the run's end, from which nothing is left to run.
        let k = (0..c.len() - 1)
            .rev()
            .find(|&k| {
                let (_, saved) = checkpoint::read(&c[k]).unwrap();
                saved.world.lasting.iter().any(|l| l.friction.is_some())
                    && !saved.world.wall_contacts.is_empty()
            })
            .expect("a checkpoint inside lasting contacts with friction");
        vec![k]
    };
    exact("settling_bed_friction", Some(0.3), 0.0371, lasting);
}

#[test]
fn a_cut_inside_a_hold_resumes_exactly() {
    let held = |c: &[PathBuf]| {
        let k = (0..c.len() - 1)
            .find(|&k| {
                let (_, saved) = checkpoint::read(&c[k]).unwrap();
                saved.world.particles.state.iter().any(|s| s.is_held())
            })
            .expect("a checkpoint inside a hold");
        vec![k]
    };
    // The drop's holds last ~20 ms: a checkpoint every 3 ms lands in one.
    exact("toluene_drop", None, 0.003, held);
}

#[test]
fn a_cut_between_injections_with_outlets_resumes_exactly() {
    let injecting = |c: &[PathBuf]| {
        let ks: Vec<usize> = (0..c.len() - 1)
            .filter(|&k| {
                let (_, saved) = checkpoint::read(&c[k]).unwrap();
                saved.world.injection.iter().any(|i| i.injected > 0)
            })
            .collect();
        assert!(ks.len() >= 2, "checkpoints while injecting");
        vec![ks[ks.len() / 3], ks[2 * ks.len() / 3]]
    };
    exact("column", Some(0.5), 0.0731, injecting);
}

#[test]
fn flow_fields_resume_exactly() {
    // The OpenFOAM field on an unstructured grid (cell hints carried), and the analytic one.
    exact("contactor", Some(0.25), 0.0519, middle_and_late);
    exact("contactor_poiseuille", Some(0.25), 0.0519, middle_and_late);
}

#[test]
fn bench_scenes_resume_exactly() {
    for name in ["bench_dilute", "bench_paper", "bench_paper_lubrication", "bench_paper_history"] {
        // 40 steps of 8.77 µs, a checkpoint every 9.
        exact(name, Some(40.0 * 8.77e-6), 9.0 * 8.77e-6, middle_and_late);
    }
}

#[test]
fn vtk_and_mcap_continue_a_resumed_run() {
    let dir = tempfile::tempdir().unwrap();
    let (whole, resumed) = (dir.path().join("whole"), dir.path().join("resumed"));
    let source = scene("glass_bead", Some(0.2));
    let formats = [Format::Csv, Format::Vtk, Format::Mcap];
    let checkpoints = run_whole("glass_bead", &source, &formats, 0.0617, &whole);
    resume_into(&checkpoints[1], &resumed, 2);
    assert_same_outputs(&whole, &resumed, "glass_bead with VTK and MCAP");
    // The ParaView collection and every frame are the whole run's.
    let pvd = |d: &Path| std::fs::read(d.join("glass_bead.pvd")).unwrap();
    assert!(pvd(&whole) == pvd(&resumed), "the .pvd differs");
    let frames = std::fs::read_dir(whole.join("glass_bead_vtk")).unwrap().count();
    assert_eq!(frames, 201);
    for e in std::fs::read_dir(whole.join("glass_bead_vtk")).unwrap() {
        let name = e.unwrap().file_name();
        let a = std::fs::read(whole.join("glass_bead_vtk").join(&name)).unwrap();
        let b = std::fs::read(resumed.join("glass_bead_vtk").join(&name)).unwrap();
        assert!(a == b, "frame {name:?} differs");
    }
    // The MCAP goes on as a second part: the first up to the checkpoint, the second from it.
    let (_, saved) = checkpoint::read(&checkpoints[1]).unwrap();
    let cut = (saved.world.time * 1e9).round() as u64;
    let times = |p: &Path| -> Vec<u64> {
        let bytes = std::fs::read(p).unwrap();
        mcap::MessageStream::new(&bytes)
            .unwrap()
            .map(|m| m.unwrap())
            .filter(|m| m.channel.topic == "/particles")
            .map(|m| m.log_time)
            .collect()
    };
    let first = times(&resumed.join("glass_bead.mcap"));
    let second = times(&resumed.join("glass_bead.part2.mcap"));
    let all = times(&whole.join("glass_bead.mcap"));
    assert!(first.iter().all(|&t| t <= cut + 1) || first.len() == all.len());
    let together: Vec<u64> =
        first.iter().copied().filter(|&t| t <= cut).chain(second.iter().copied()).collect();
    assert_eq!(together, all, "the two parts' frames are the whole run's");
}

/// The shipped column (1 s of it: injections, holds under the plate) stopped by SIGTERM takes a
/// checkpoint before its last frame; resumed from it, it ends with the files of the run never
/// stopped (the stop's extra frame is cut away).
#[test]
fn a_column_stopped_by_sigterm_and_resumed_ends_as_the_run_never_stopped() {
    use crate::outputs_common::{scene_with, send, wait_bounded, wait_until, wetbounce};
    use std::process::Stdio;
    use std::time::Duration;
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_with(
        "scenes/column.toml",
        "column.toml",
        dir.path(),
        &[("duration", "1.0"), ("output_interval", "0.01")],
    );
    let (whole, stopped) = (dir.path().join("whole"), dir.path().join("stopped"));
    let run = |out: &Path| {
        wetbounce()
            .arg("run")
            .arg(&scene)
            .args(["--formats", "csv", "--quiet", "--threads", "1", "--out"])
            .arg(out)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let done = wait_bounded(run(&whole), Duration::from_secs(300));
    assert!(done.status.success(), "{}", String::from_utf8_lossy(&done.stderr));
    let mut child = run(&stopped);
    let traj = stopped.join("trajectories.csv");
    // A few frames in (the frame at t = 0.3 s written), then SIGTERM.
    wait_until(&mut child, Duration::from_secs(120), "the frame at 0.3 s", || {
        std::fs::read_to_string(&traj).is_ok_and(|t| t.contains("\n0.3,"))
    });
    send(&child, "TERM");
    let out = wait_bounded(child, Duration::from_secs(60));
    assert_eq!(out.status.code(), Some(143), "{}", String::from_utf8_lossy(&out.stderr));
    let checkpoints = checkpoint::list(&stopped.join("checkpoints"));
    assert_eq!(checkpoints.len(), 1, "one checkpoint, taken at the stop");
    let resumed =
        wetbounce().arg("resume").arg(&checkpoints[0]).args(["--quiet", "--threads", "2"]).output().unwrap();
    assert!(resumed.status.success(), "{}", String::from_utf8_lossy(&resumed.stderr));
    for file in ["trajectories.csv", "events.csv"] {
        let (a, b) = (std::fs::read(whole.join(file)).unwrap(), std::fs::read(stopped.join(file)).unwrap());
        assert!(a == b, "{file} differs ({} and {} bytes)", a.len(), b.len());
    }
    assert_eq!(summary(&whole), summary(&stopped));
}

/// Raises the stop flag while frame `at` is written, as a signal landing in that write would.
struct StopInFrame<'a> {
    frames: u64,
    at: u64,
    stop: &'a AtomicBool,
}

impl wetbounce::output::Sink for StopInFrame<'_> {
    fn frame(
        &mut self,
        _sim: &wetbounce::pipeline::Simulation,
    ) -> Result<(), wetbounce::output::OutputError> {
        if self.frames == self.at {
            self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        self.frames += 1;
        Ok(())
    }
}

/// A stop asked while a frame is written (the run stops at that frame, no step after it) still
/// takes its checkpoint, after the frame; resumed from it, the column ends with the files of the
/// run never stopped. (Such a stop once left no checkpoint: the SIGTERM test above failed when
/// its signal landed in a frame's write.)
#[test]
fn a_stop_asked_while_a_frame_is_written_takes_its_checkpoint_there_and_resumes_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let (whole, stopped) = (dir.path().join("whole"), dir.path().join("stopped"));
    let source = scene("column", Some(0.3));
    run_whole("column", &source, &[Format::Csv], 10.0, &whole);
    // No periodic checkpoint: only the stop's.
    let policy = CheckpointPolicy { every: None, wall: None, keep: 2 };
    let (time, checkpoints) = run_checkpointed("column", &source, &[Format::Csv], policy, &stopped, Some(3));
    assert!(time < 0.3, "stopped at {time} s");
    assert_eq!(checkpoints.len(), 1, "one checkpoint, taken at the stop");
    let (_, at) = checkpoint::read(&checkpoints[0]).unwrap();
    assert_eq!(at.world.time, time, "the checkpoint is the stop's frame");
    let resumed = dir.path().join("resumed");
    resume_into(&checkpoints[0], &resumed, 2);
    assert_same_outputs(&whole, &resumed, "column stopped in a frame's write");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 8, ..Default::default() })]

    /// Any cut point: checkpoints every `every` (s) of the rising column (injections, holds
    /// under the plate) and a resume from the one at `at` (a fraction of the run), on 1 or 2
    /// threads, give the whole run's files.
    #[test]
    fn a_resume_from_any_cut_point_is_exact(every in 0.011f64..0.09, at in 0.0f64..1.0) {
        let dir = tempfile::tempdir().unwrap();
        let whole = dir.path().join("whole");
        let source = scene("column", Some(0.3));
        let checkpoints = run_whole("column", &source, &[Format::Csv], every, &whole);
        let k = ((at * (checkpoints.len() - 1) as f64) as usize).min(checkpoints.len() - 2);
        let resumed = dir.path().join("resumed");
        let threads = 1 + k % 2;
        resume_into(&checkpoints[k], &resumed, threads);
        assert_same_outputs(&whole, &resumed, &format!("column cut at checkpoint {k}, every {every} s"));
    }
}
