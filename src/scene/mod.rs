//! Scenes: the TOML file format, its validation and the [`Simulation`] it builds.
//!
//! Loading never panics: a bad file gives a [`SceneError`] that names the file, the key path
//! and the bad value. The format is documented field by field in `docs/scene-format.md`.

pub mod accuracy;
mod build;
mod error;
mod fill;
mod flux;
mod report;
mod schema;
pub mod stiffness;

pub use accuracy::{Accuracy, AutoStep};
pub use error::SceneError;
pub use report::{KindReport, kind_report, kind_reports, scene_sizes};

use crate::contact::{BounceRule, ImpactLocation};
use crate::effects::Physics;
use crate::fluid::Fluid;
use crate::integrate::IntegratorKind;
use crate::particles::{ParticleKind, Particles};
use crate::pipeline::Simulation;
use crate::pipeline::inject::Injector;
use crate::pipeline::outlets::Outlet;
use crate::walls::Wall;
use std::path::{Path, PathBuf};

/// A loaded and validated scene, ready to become a [`Simulation`].
#[derive(Debug)]
pub struct Scene {
    /// The file it was read from.
    pub path: PathBuf,
    /// The file's text, kept so outputs can carry their inputs.
    pub source: String,
    /// Time step `Δt` (s).
    pub dt: f64,
    /// Simulated duration (s).
    pub duration: f64,
    /// Simulated time between output frames (s).
    pub output_interval: f64,
    /// Time integrator.
    pub integrator: IntegratorKind,
    /// Where wall contacts are placed in time (`simulation.impact_location`).
    pub impact_location: ImpactLocation,
    /// With `dt = "auto"`: what the accuracy setting chose, and why.
    pub auto_step: Option<AutoStep>,
    /// Carrier fluid.
    pub fluid: Fluid,
    /// Particle kinds.
    pub kinds: Vec<ParticleKind>,
    /// Walls.
    pub walls: Vec<Wall>,
    /// The effects' physics.
    pub physics: Physics,
    /// Bounce parameters.
    pub rule: BounceRule,
    /// Initial particles.
    pub particles: Particles,
    /// Injectors (`[[injectors]]`), nothing injected yet.
    pub injectors: Vec<Injector>,
    /// Outlets (`[[outlets]]`).
    pub outlets: Vec<Outlet>,
}

impl Scene {
    /// Reads, parses and validates the scene file at `path`. Mesh files are resolved relative
    /// to the scene file's folder.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let source = std::fs::read_to_string(path)
            .map_err(|source| SceneError::Read { file: path.to_path_buf(), source })?;
        Scene::from_str(&source, path)
    }

    /// Parses and validates scene text as if read from `path` (used in messages and to find
    /// mesh files).
    pub fn from_str(source: &str, path: &Path) -> Result<Scene, SceneError> {
        let file = build::parse(source, path)?;
        let base = path.parent().unwrap_or(Path::new("."));
        build::build(file, base, source)
            .map(|mut scene| {
                scene.path = path.to_path_buf();
                scene
            })
            .map_err(|e| SceneError::Invalid { file: path.to_path_buf(), key: e.key, message: e.message })
    }

    /// The simulation at time 0.
    pub fn simulation(&self) -> Simulation {
        let mut sim = Simulation::new(
            self.particles.clone(),
            self.kinds.clone(),
            self.walls.clone(),
            self.fluid.clone(),
            self.physics.clone(),
            self.rule,
            self.integrator,
            self.dt,
        );
        sim.impact_location = self.impact_location;
        sim.injectors = self.injectors.clone();
        sim.outlets = self.outlets.clone();
        sim
    }
}
