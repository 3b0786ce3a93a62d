//! Output sinks: what a run writes, each a [`Sink`] with do-nothing defaults.
//!
//! - [`TrajectoryCsv`]: `trajectories.csv`, one row per particle per output frame;
//! - [`EventCsv`]: `events.csv`, one row per contact;
//! - [`Statistics`]: counts and means for the end-of-run summary;
//! - [`McapSink`]: `<scene>.mcap` for Foxglove and rerun (`/particles`, `/walls`, `/scene`, `/events`);
//! - [`VtkSink`]: `<scene>.pvd` and its `.vtp` frames, and `<scene>_walls.vtp`, for ParaView;
//! - [`RerunSink`] (feature `rerun`): `<scene>.rrd`, rerun's native recording;
//! - [`Progress`]: the progress bar on standard error.
//!
//! [`RunSummary`] is the table printed at the end of a run; [`file::write_file`] writes its
//! JSON form. Every file is written through [`file::OutputFile`]: flushed at every frame, synced
//! to the disk about once a second, every error naming the file and the OS error.

mod csv_files;
pub mod file;
pub mod folder;
pub mod geometry;
pub mod mcap;
mod progress;
#[cfg(feature = "rerun")]
pub mod rerun;
pub mod stale;
mod statistics;
mod summary;
pub mod vtk;

pub use csv_files::{EventCsv, TrajectoryCsv};
pub use folder::{Folder, Format, Outputs};
pub use mcap::{McapOptions, McapSink};
pub use progress::Progress;
#[cfg(feature = "rerun")]
pub use rerun::RerunSink;
pub use statistics::Statistics;
pub use summary::RunSummary;
pub use vtk::VtkSink;

use crate::contact::ContactEvent;
use crate::pipeline::{LostParticle, Simulation};
use std::path::PathBuf;

/// A failure to write an output file: `FILE: cannot write: CAUSE`, with the OS error in the cause
/// (`No space left on device (os error 28)`).
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct OutputError {
    /// The file being written.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl OutputError {
    /// An error writing `path`.
    pub fn new(path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Self {
        OutputError { path: path.into(), message: e.to_string() }
    }

    /// `path` could not be created (or opened for writing).
    pub fn create(path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Self {
        OutputError::new(path, format!("cannot create: {e}"))
    }

    /// Writing (or flushing) `path` failed.
    pub fn write(path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Self {
        OutputError::new(path, format!("cannot write: {e}"))
    }
}

/// What a sink is at a checkpoint, for a resumed run to go on from (`crate::run::checkpoint`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum SinkMark {
    /// A file written in sequence (a CSV file): its name in the output folder and its length
    /// (bytes) at the checkpoint. A resumed run cuts it there and appends.
    File {
        /// The file's name in the output folder.
        name: String,
        /// Its length at the checkpoint (bytes).
        bytes: u64,
    },
    /// The summary's statistics.
    Statistics(Statistics),
    /// An output that a resumed run starts afresh as a new part (`<stem>.part<N>.mcap`): the
    /// parts written so far.
    Parts {
        /// The format (`mcap`, `rrd`).
        format: String,
        /// Files written so far, this one included.
        parts: u32,
        /// The recording every part belongs to (rerun's recording id; empty for an MCAP), so
        /// that a viewer shows the parts as one run.
        recording: String,
    },
    /// The ParaView collection: where its closing tags start, the frames written, whether the
    /// walls' file is.
    Vtk {
        /// Where the `.pvd`'s closing tags start (bytes).
        tail_at: u64,
        /// Frames written.
        frames: u64,
        /// The walls' file is written.
        walls_written: bool,
    },
}

/// The file of part `part` of a run's output in format `ext` (`mcap`, `rrd`): `<stem>.<ext>` for
/// the first, `<stem>.part<N>.<ext>` for those of resumed runs ([`SinkMark::Parts`]).
pub fn part_file(stem: &str, part: u32, ext: &str) -> String {
    if part <= 1 { format!("{stem}.{ext}") } else { format!("{stem}.part{part}.{ext}") }
}

/// Something that receives a run's frames and events. Every method defaults to doing nothing.
pub trait Sink {
    /// A frame at the simulation's current time (called at t = 0 and every output interval).
    /// A sink that writes a file hands the frame, and the events since the last one, to the
    /// operating system before it returns, so that a run killed outright (SIGKILL, an OOM kill)
    /// loses at most the frame it was writing.
    fn frame(&mut self, _sim: &Simulation) -> Result<(), OutputError> {
        Ok(())
    }
    /// A step is over (the progress bar); called after every step, so keep it cheap.
    fn step(&mut self, _sim: &Simulation) -> Result<(), OutputError> {
        Ok(())
    }
    /// Contact events since the last call, in time order per particle.
    fn events(&mut self, _sim: &Simulation, _events: &[ContactEvent]) -> Result<(), OutputError> {
        Ok(())
    }
    /// Particles taken out since the last call because their state became non-finite (the
    /// commit stage's check; the run goes on without them).
    fn lost(&mut self, _sim: &Simulation, _lost: &[LostParticle]) -> Result<(), OutputError> {
        Ok(())
    }
    /// The run is over (finished or interrupted): flush and close.
    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(())
    }
    /// A checkpoint is taken: hand everything written so far to the operating system and say
    /// what a resumed run needs to go on from here ([`SinkMark`]); `None` for a sink that
    /// keeps nothing (the progress bar).
    fn mark(&mut self) -> Result<Option<SinkMark>, OutputError> {
        Ok(None)
    }
}
