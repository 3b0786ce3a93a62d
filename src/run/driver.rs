//! One run into an output folder, the same for `wetbounce run` and Python's `Simulation.run`:
//! the folder's sinks created (and an earlier run's stale outputs removed), the run stepped by
//! [`super::run`] with the statistics of the summary, and `summary.json` written however the run
//! ended. The two callers had drifted (issue 26, item 3): Python could not write VTK, never
//! removed stale outputs and left the flow error out of its summary.

use super::checkpoint::Saved;
use super::{Checkpoints, Plan, RunFailed, RunPosition, RunReport, run_plan};
use crate::output::file::write_file;
use crate::output::stale::Removed;
use crate::output::{Folder, Format, OutputError, Outputs, RunSummary, Sink, Statistics};
use crate::pipeline::Simulation;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// A run ready to start: its files are open. `Send`, so that a caller may step it on another
/// thread (Python releases the GIL that way).
pub struct Driver {
    outputs: Outputs,
    /// The output folder; none for a run that writes no files (Python without `out`).
    out: Option<PathBuf>,
    scene_path: PathBuf,
    stats: Statistics,
    duration: f64,
    output_interval: f64,
    /// Where a resumed run's loop stands; `None` for a run from its start.
    from: Option<RunPosition>,
    checkpoints: Option<Checkpoints>,
}

/// How a driven run ended, with its summary and files.
pub struct Ended {
    /// How far it went.
    pub report: RunReport,
    /// What `summary.json` holds.
    pub summary: RunSummary,
    /// Every output error, `summary.json`'s included, each naming its file.
    pub errors: Vec<OutputError>,
    /// The files written whole (one that failed is in `errors` instead), `summary.json` last.
    pub written: Vec<PathBuf>,
}

impl Driver {
    /// Opens the files of `formats` in `folder` (none without a folder) for a run of
    /// `duration` (s) with a frame every `output_interval` (s). On an error no file of an
    /// earlier run has been removed, and the files opened are closed.
    pub fn new(
        folder: Option<&Folder>,
        formats: &[Format],
        duration: f64,
        output_interval: f64,
    ) -> Result<Driver, Vec<OutputError>> {
        let (outputs, out, scene_path) = match folder {
            Some(f) => (f.create(formats)?, Some(f.out.to_path_buf()), f.scene_path.to_path_buf()),
            None => (
                Outputs { sinks: Vec::new(), written: Vec::new(), stale: Removed::default() },
                None,
                PathBuf::new(),
            ),
        };
        Ok(Driver {
            outputs,
            out,
            scene_path,
            stats: Statistics::default(),
            duration,
            output_interval,
            from: None,
            checkpoints: None,
        })
    }

    /// The driver of a run that goes on from the checkpoint `saved`: the folder's files opened
    /// where the checkpoint left them (`Folder::resume`: the CSV files and the ParaView
    /// collection cut there and appended to, an MCAP started as the run's next part), the
    /// summary's statistics and the run loop's position restored, to `duration` (s, the
    /// checkpointed run's or longer).
    pub fn resume(
        folder: &Folder,
        formats: &[Format],
        duration: f64,
        saved: &Saved,
    ) -> Result<Driver, Vec<OutputError>> {
        let outputs = folder.resume(formats, &saved.sinks)?;
        Ok(Driver {
            outputs,
            out: Some(folder.out.to_path_buf()),
            scene_path: folder.scene_path.to_path_buf(),
            stats: saved.statistics().cloned().unwrap_or_default(),
            duration,
            output_interval: saved.scene.output_interval,
            from: Some(saved.position),
            checkpoints: None,
        })
    }

    /// A driver whose run loop starts where a checkpoint left it (`position`), with the files
    /// it has (none, on a rank other than 0 of a run on ranks).
    pub fn from_position(mut self, position: RunPosition) -> Self {
        self.from = Some(position);
        self
    }

    /// Takes `checkpoints` as the run goes (docs/output.md, "Checkpoints").
    pub fn checkpointing(mut self, checkpoints: Checkpoints) -> Self {
        self.checkpoints = Some(checkpoints);
        self
    }

    /// The checkpoints written so far, oldest first.
    pub fn checkpoints_written(&self) -> &[PathBuf] {
        self.checkpoints.as_ref().map_or(&[], |c| &c.written)
    }

    /// The earlier run's outputs removed from the folder, for the caller to report.
    pub fn stale(&self) -> &Removed {
        &self.outputs.stale
    }

    /// Steps `sim` to the run's end ([`run`]): the folder's sinks, the summary's statistics and
    /// the caller's `extra` sinks (a progress bar, a collector of events) get every frame, step
    /// and event; `stop` ends it early.
    pub fn run<'a>(
        &'a mut self,
        sim: &mut Simulation,
        extra: Vec<&'a mut dyn Sink>,
        stop: &AtomicBool,
    ) -> Result<RunReport, RunFailed> {
        self.run_with(sim, extra, stop, None)
    }

    /// [`Self::run`], stepped by `steps` (a run split over ranks, `crate::ranks`) rather than
    /// by this process alone.
    pub fn run_with<'a>(
        &'a mut self,
        sim: &mut Simulation,
        extra: Vec<&'a mut dyn Sink>,
        stop: &AtomicBool,
        steps: Option<&'a mut dyn super::Steps>,
    ) -> Result<RunReport, RunFailed> {
        let mut all: Vec<&mut dyn Sink> =
            self.outputs.sinks.iter_mut().map(|s| s.as_mut() as &mut dyn Sink).collect();
        all.push(&mut self.stats);
        all.extend(extra);
        let plan = Plan {
            duration: self.duration,
            output_interval: self.output_interval,
            from: self.from.take(),
            checkpoints: self.checkpoints.as_mut(),
            steps,
        };
        run_plan(sim, plan, &mut all, stop)
    }

    /// Ends the run `result` of [`Self::run`] left: writes `summary.json` (with a folder) — the
    /// scene, the `signal` that stopped it (kept only when the run was interrupted: one that
    /// came after its end stopped nothing), the flow error and the output errors.
    pub fn finish(
        self,
        sim: &Simulation,
        result: Result<RunReport, RunFailed>,
        signal: Option<&str>,
    ) -> Ended {
        let (report, mut errors) = match result {
            Ok(report) => (report, Vec::new()),
            Err(failed) => (failed.report, failed.errors),
        };
        let summary = RunSummary::new(sim, &report, &self.stats);
        let mut written = self.outputs.written;
        if let Some(out) = &self.out {
            let signal = signal.filter(|_| report.interrupted);
            match write_summary(out, &self.scene_path, sim, &summary, signal, &errors) {
                Ok(path) => written.push(path),
                Err(e) => errors.push(e),
            }
        }
        written.retain(|p| !errors.iter().any(|e| &e.path == p));
        Ended { report, summary, errors, written }
    }
}

/// Writes `out/summary.json`: the summary, the scene file, the stop signal (`null` if none),
/// the flow error if a particle left the field, and the output errors (`[]` if none).
fn write_summary(
    out: &Path,
    scene_path: &Path,
    sim: &Simulation,
    summary: &RunSummary,
    signal: Option<&str>,
    errors: &[OutputError],
) -> Result<PathBuf, OutputError> {
    let path = out.join("summary.json");
    let mut json = summary.to_json();
    json["scene"] = serde_json::Value::String(scene_path.display().to_string());
    json["signal"] = signal.map_or(serde_json::Value::Null, |s| s.into());
    if let Some(e) = &sim.record.left_field {
        json["flow_error"] = serde_json::Value::String(e.to_string());
    }
    json["output_errors"] = errors.iter().map(|e| serde_json::Value::String(e.to_string())).collect();
    let text = serde_json::to_string_pretty(&json).map_err(|e| OutputError::write(&path, e))?;
    write_file(&path, &(text + "\n"))?;
    Ok(path)
}
