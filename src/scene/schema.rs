//! The scene file's schema (serde). Units and meanings: `docs/scene-format.md`.

use crate::integrate::IntegratorKind;
use serde::Deserialize;

/// A whole scene file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub simulation: SimulationSpec,
    pub fluid: FluidSpec,
    #[serde(default)]
    pub bounce: BounceSpec,
    #[serde(default)]
    pub effects: toml::Table,
    pub kinds: Vec<KindSpec>,
    #[serde(default)]
    pub walls: Vec<WallSpec>,
    #[serde(default)]
    pub particles: Vec<ParticleSpec>,
    #[serde(default)]
    pub lattice: Vec<LatticeSpec>,
    #[serde(default)]
    pub random_fill: Vec<RandomFillSpec>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    pub dt: f64,
    pub duration: f64,
    pub output_interval: f64,
    #[serde(default = "default_integrator")]
    pub integrator: IntegratorKind,
}

fn default_integrator() -> IntegratorKind {
    IntegratorKind::Rk2
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSpec {
    pub density: f64,
    pub viscosity: f64,
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    #[serde(default)]
    pub flow: FlowSpec,
}

fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum FlowSpec {
    #[default]
    Quiescent,
    Uniform {
        velocity: [f64; 3],
    },
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BounceSpec {
    #[serde(default = "default_beta")]
    pub beta: f64,
    #[serde(default = "default_st_critical")]
    pub st_critical: f64,
    #[serde(default = "one")]
    pub tangential_restitution: f64,
}

impl Default for BounceSpec {
    fn default() -> Self {
        BounceSpec {
            beta: default_beta(),
            st_critical: default_st_critical(),
            tangential_restitution: 1.0,
        }
    }
}

fn default_beta() -> f64 {
    35.0
}
fn default_st_critical() -> f64 {
    10.0
}
fn one() -> f64 {
    1.0
}

#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum KindSpec {
    Solid {
        name: String,
        density: f64,
        #[serde(default = "one")]
        restitution_max: f64,
        youngs_modulus: f64,
        poisson_ratio: f64,
    },
    Drop {
        name: String,
        density: f64,
        restitution_max: f64,
        surface_tension: f64,
    },
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub youngs_modulus: Option<f64>,
    pub poisson_ratio: Option<f64>,
    pub restitution_max: Option<f64>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum WallSpec {
    Plane {
        name: String,
        point: [f64; 3],
        normal: [f64; 3],
        #[serde(default)]
        material: MaterialSpec,
    },
    Box {
        name: String,
        min: [f64; 3],
        max: [f64; 3],
        inside: bool,
        #[serde(default)]
        material: MaterialSpec,
    },
    Cylinder {
        name: String,
        base: [f64; 3],
        #[serde(default = "default_axis")]
        axis: [f64; 3],
        radius: f64,
        length: Option<f64>,
        #[serde(default)]
        material: MaterialSpec,
    },
    Mesh {
        name: String,
        file: String,
        #[serde(default = "one")]
        scale: f64,
        #[serde(default)]
        translate: [f64; 3],
        #[serde(default)]
        material: MaterialSpec,
    },
}

fn default_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleSpec {
    pub kind: String,
    pub diameter: f64,
    pub position: [f64; 3],
    #[serde(default)]
    pub velocity: [f64; 3],
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    pub kind: String,
    pub diameter: f64,
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub spacing: f64,
    #[serde(default)]
    pub velocity: [f64; 3],
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomFillSpec {
    pub kind: String,
    pub diameter: f64,
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub count: u32,
    pub seed: u64,
    #[serde(default)]
    pub velocity: [f64; 3],
}
