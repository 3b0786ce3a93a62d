//! When a run takes its checkpoints, and taking one: the sinks' marks gathered, the state
//! written by [`super::checkpoint::write`].

use super::checkpoint::{self, RunPosition, SavedScene};
use crate::output::{OutputError, Sink};
use crate::pipeline::Simulation;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How often a run checkpoints: every `every` simulated seconds, every `wall` of wall-clock
/// time (what a batch queue's time limit needs), or both; the newest `keep` kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckpointPolicy {
    /// Simulated seconds between checkpoints.
    pub every: Option<f64>,
    /// Wall-clock time between checkpoints.
    pub wall: Option<Duration>,
    /// Checkpoints kept (the newest); at least 1.
    pub keep: usize,
}

impl CheckpointPolicy {
    /// The policy of `every` simulated seconds, every `wall_minutes`, the newest `keep` kept
    /// (default 2): each given value checked (finite and > 0; `keep` ≥ 1), the error naming it by
    /// `names` (the option or argument it came as: `--checkpoint-every`, `checkpoint_every`).
    pub fn checked(
        (every, wall_minutes, keep): (Option<f64>, Option<f64>, Option<usize>),
        names: [&str; 3],
    ) -> Result<Self, String> {
        for (name, v) in [(names[0], every), (names[1], wall_minutes)] {
            if let Some(x) = v
                && !(x.is_finite() && x > 0.0)
            {
                return Err(format!("{name}: must be a finite number > 0, got {x}"));
            }
        }
        if keep == Some(0) {
            return Err(format!("{}: must be at least 1, got 0", names[2]));
        }
        Ok(CheckpointPolicy {
            every,
            wall: wall_minutes.map(|m| Duration::from_secs_f64(m * 60.0)),
            keep: keep.unwrap_or(2),
        })
    }
}

impl Default for CheckpointPolicy {
    /// No periodic checkpoint (a run stopped by a signal still takes one), the newest 2 kept.
    fn default() -> Self {
        CheckpointPolicy { every: None, wall: None, keep: 2 }
    }
}

/// A run's checkpoints: the policy, the folder they go to, the scene they are of, and when the
/// next is due.
#[derive(Debug)]
pub struct Checkpoints {
    policy: CheckpointPolicy,
    folder: PathBuf,
    scene: SavedScene,
    /// Simulated time of the next periodic checkpoint (s).
    next_time: Option<f64>,
    last_wall: Instant,
    /// The checkpoint being written by a thread of its own: its file, and the thread.
    pending: Option<(PathBuf, std::thread::JoinHandle<Result<(), checkpoint::CheckpointError>>)>,
    /// The checkpoints written, oldest first (some may have been removed since).
    pub written: Vec<PathBuf>,
}

/// The payload as written: [`checkpoint::Saved`]'s fields in its order, borrowed from the run
/// (the world is not copied to be saved).
#[derive(Serialize)]
struct SavedRef<'a> {
    scene: &'a SavedScene,
    world: &'a crate::pipeline::World,
    lost: &'a [crate::pipeline::LostParticle],
    removed: &'a [Vec<crate::pipeline::outlets::Removal>],
    left_field: &'a Option<crate::fluid::field::OutsideField>,
    position: RunPosition,
    sinks: &'a [crate::output::SinkMark],
}

impl<'a> SavedRef<'a> {
    /// The payload of a checkpoint of `sim`, the run of `scene` with its loop at `at` and its
    /// sinks' `marks`.
    fn of(
        sim: &'a Simulation,
        scene: &'a SavedScene,
        at: RunPosition,
        marks: &'a [crate::output::SinkMark],
    ) -> Self {
        SavedRef {
            scene,
            world: &sim.world,
            lost: &sim.record.lost,
            removed: &sim.record.removed,
            left_field: &sim.record.left_field,
            position: at,
            sinks: marks,
        }
    }
}

impl Checkpoints {
    /// Checkpoints of the run of `scene` into `folder` (created when the first is written), by
    /// `policy`, starting at simulated time `time` (s): 0, or the time a resumed run goes on from.
    pub fn new(policy: CheckpointPolicy, folder: &Path, scene: SavedScene, time: f64) -> Self {
        let next_time = policy.every.map(|every| next_multiple(time, every));
        Checkpoints {
            policy,
            folder: folder.to_path_buf(),
            scene,
            next_time,
            last_wall: Instant::now(),
            pending: None,
            written: Vec::new(),
        }
    }

    /// Whether checkpoints are taken as the run goes (not only when a signal stops it): then one
    /// is also taken at its end, from which a longer run goes on.
    pub fn periodic(&self) -> bool {
        self.policy.every.is_some() || self.policy.wall.is_some()
    }

    /// The folder the checkpoints go to.
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// Whether a periodic checkpoint is due after the step that brought `sim` where it is.
    pub fn due(&self, sim: &Simulation) -> bool {
        let by_time = self.next_time.is_some_and(|t| sim.world.time >= t);
        let by_wall = self.policy.wall.is_some_and(|w| self.last_wall.elapsed() >= w);
        by_time || by_wall
    }

    /// Takes a checkpoint of `sim` with the run loop at `at`: every sink's mark (each flushes
    /// its file), the state encoded — the run waits for that — then the file written and synced
    /// by a thread of its own while the run goes on ([`Checkpoints::wait`] joins it; the next
    /// checkpoint waits for the last). A failure is an output error naming the checkpoint.
    pub fn take(
        &mut self,
        sim: &Simulation,
        at: RunPosition,
        sinks: &mut [&mut dyn Sink],
    ) -> Result<(), OutputError> {
        let mut marks = Vec::new();
        for s in sinks.iter_mut() {
            marks.extend(s.mark()?);
        }
        let saved = SavedRef::of(sim, &self.scene, at, &marks);
        let path = checkpoint::path_in(&self.folder, sim.world.steps);
        let bytes = checkpoint::encode_with(&saved, (sim.world.steps, sim.world.time), &self.scene.source)
            .map_err(|e| OutputError::new(&path, format!("cannot encode the checkpoint: {e}")))?;
        self.wait()?;
        let (folder, file, keep) = (self.folder.clone(), path.clone(), self.policy.keep);
        let writer = std::thread::Builder::new()
            .name("checkpoint".into())
            .spawn(move || checkpoint::write_and_prune(&folder, &file, &bytes, keep))
            .map_err(|e| OutputError::new(&path, format!("cannot write the checkpoint: {e}")))?;
        self.pending = Some((path, writer));
        if let (Some(every), Some(t)) = (self.policy.every, self.next_time)
            && sim.world.time >= t
        {
            self.next_time = Some(next_multiple(sim.world.time, every));
        }
        self.last_wall = Instant::now();
        Ok(())
    }

    /// Waits for the checkpoint being written, if any; its error, naming the file.
    pub fn wait(&mut self) -> Result<(), OutputError> {
        let Some((path, writer)) = self.pending.take() else { return Ok(()) };
        match writer.join() {
            Ok(Ok(())) => {
                self.written.push(path);
                Ok(())
            }
            Ok(Err(checkpoint::CheckpointError::Write { path, problem })) => {
                Err(OutputError::new(path, format!("cannot write the checkpoint: {problem}")))
            }
            Ok(Err(other)) => Err(OutputError::new(path, other)),
            Err(_) => Err(OutputError::new(path, "the thread writing the checkpoint failed")),
        }
    }
}

/// The first multiple of `every` after `time` (by more than round-off).
fn next_multiple(time: f64, every: f64) -> f64 {
    RunPosition::next_index(time, every) as f64 * every
}

/// Writes a checkpoint of `sim` to the file `path` (not one of a folder's series): the run of
/// `scene`, its loop at `at`, its sinks' `marks`. What Python's `Simulation.save` writes; the
/// same format as a run's checkpoints.
pub fn save_to(
    path: &Path,
    sim: &Simulation,
    scene: &SavedScene,
    at: RunPosition,
    marks: &[crate::output::SinkMark],
) -> Result<(), checkpoint::CheckpointError> {
    let saved = SavedRef::of(sim, scene, at, marks);
    let failed = |problem: String| checkpoint::CheckpointError::Write { path: path.to_path_buf(), problem };
    let bytes =
        checkpoint::encode_with(&saved, (sim.world.steps, sim.world.time), &scene.source).map_err(failed)?;
    checkpoint::write_file(path, &bytes).map_err(|e| failed(e.to_string()))
}
