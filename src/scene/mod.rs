//! Scenes: the TOML file format, its validation and the [`Simulation`] it builds.
//!
//! Loading never panics: a bad file gives a [`SceneError`] that names the file, the key path
//! and the bad value. The format is documented field by field in `docs/scene-format.md`.

pub mod accuracy;
mod build;
mod error;
pub mod estimate;
mod field;
mod fill;
mod flow;
mod flux;
mod overlap;
mod ranges;
mod report;
mod room;
pub mod run_length;
mod schema;
pub mod stiffness;
mod table;
#[cfg(test)]
mod typed_tables_tests;
mod walls;

pub use accuracy::{Accuracy, AutoStep};
pub use error::SceneError;
pub use report::{KindReport, field_report, kind_report, kind_reports, scene_sizes};
pub use run_length::{MAX_FRAMES, MAX_STEPS, TooLong, run_length};

use crate::particles::Particles;
use crate::pipeline::{Setup, Simulation};
use std::path::{Path, PathBuf};

/// A loaded and validated scene, ready to become a [`Simulation`].
#[derive(Debug)]
pub struct Scene {
    /// The file it was read from.
    pub path: PathBuf,
    /// The file's text, kept so outputs can carry their inputs.
    pub source: String,
    /// Simulated duration (s).
    pub duration: f64,
    /// Simulated time between output frames (s).
    pub output_interval: f64,
    /// With `dt = "auto"`: what the accuracy setting chose, and why.
    pub auto_step: Option<AutoStep>,
    /// What the scene fixes: fluid, kinds, walls, effects, rules, time step and integrator,
    /// injectors and outlets.
    pub setup: Setup,
    /// Initial particles.
    pub particles: Particles,
    /// What the run will cost: memory and output bytes, from counts.
    pub estimate: estimate::RunEstimate,
    /// What the estimate's frame count needs, for another output interval.
    pub estimate_inputs: estimate::EstimateInputs,
    /// When a run of it checkpoints (`[checkpoint]`): each `None` when not given.
    pub checkpoint: CheckpointKeys,
}

/// The scene's `[checkpoint]` keys, checked: `every` (s) and `wall_minutes` finite and > 0,
/// `keep` ≥ 1.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CheckpointKeys {
    /// Simulated seconds between checkpoints.
    pub every: Option<f64>,
    /// Wall-clock minutes between checkpoints.
    pub wall_minutes: Option<f64>,
    /// Checkpoints kept.
    pub keep: Option<usize>,
}

/// The largest scene file read (bytes): a scene is a page of TOML; even one listing a million
/// particles one by one is below this. A larger file is a wrong path ([`crate::files`]).
pub const SCENE_FILE_CAP: u64 = 64 << 20;

/// What loading may accept that it refuses by default.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Accept a run of more than [`MAX_FRAMES`] output frames or [`MAX_STEPS`] time steps
    /// (`wetbounce run --allow-long-run`).
    pub allow_long_run: bool,
    /// Accept a run whose estimated memory ([`estimate::RunEstimate::memory_bytes`]) is over
    /// the memory available on this machine (`wetbounce run --allow-large-memory`).
    pub allow_large_memory: bool,
}

impl Scene {
    /// Reads, parses and validates the scene file at `path`. Mesh files are resolved relative
    /// to the scene file's folder.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        Scene::load_with(path, LoadOptions::default())
    }

    /// [`Scene::load`] with `options`.
    pub fn load_with(path: impl AsRef<Path>, options: LoadOptions) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let source = crate::files::read_text(path, SCENE_FILE_CAP, "a scene file").map_err(|problem| {
            let source = match problem {
                crate::files::FileProblem::Io(e) => e,
                other => std::io::Error::other(other.to_string()),
            };
            SceneError::Read { file: path.to_path_buf(), source }
        })?;
        Scene::from_str_with(&source, path, options)
    }

    /// Parses and validates scene text as if read from `path` (used in messages and to find
    /// mesh files).
    pub fn from_str(source: &str, path: &Path) -> Result<Scene, SceneError> {
        Scene::from_str_with(source, path, LoadOptions::default())
    }

    /// [`Scene::from_str`] with `options`.
    pub fn from_str_with(source: &str, path: &Path, options: LoadOptions) -> Result<Scene, SceneError> {
        let file = build::parse(source, path)?;
        let base = path.parent().unwrap_or(Path::new("."));
        build::build(file, base, source, options)
            .map(|mut scene| {
                scene.path = path.to_path_buf();
                scene
            })
            .map_err(|e| SceneError::Invalid {
                file: path.to_path_buf(),
                key: e.key,
                // Numbers quoted from other rooms' messages (effects, meshes) written short too.
                message: error::fmt::shorten_long_numbers(&e.message),
            })
    }

    /// The simulation at time 0. Allocation failures abort, as for any `Vec`; a caller that
    /// must report them uses [`Scene::try_simulation`].
    pub fn simulation(&self) -> Simulation {
        Simulation::new(self.setup.clone(), self.particles.clone())
    }

    /// The simulation at time 0, taking the scene's particles (the scene keeps none, so that a
    /// run does not hold two copies of them), with the history memory reserved first: when the
    /// machine cannot give it, an error naming the scene file and the key that sizes the run,
    /// not an abort.
    pub fn take_simulation(&mut self) -> Result<Simulation, SceneError> {
        let particles = std::mem::take(&mut self.particles);
        Simulation::try_new(self.setup.clone(), particles).map_err(|_| SceneError::Invalid {
            file: self.path.clone(),
            key: self.estimate.key.clone(),
            message: format!(
                "cannot allocate the run's memory, about {} ({})",
                estimate::bytes(self.estimate.memory_bytes()),
                estimate::memory_breakdown(&self.estimate)
            ),
        })
    }
}
