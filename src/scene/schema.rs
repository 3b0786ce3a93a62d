//! The scene file's schema (serde). Units and meanings: `docs/scene-format.md`.

use super::accuracy::Accuracy;
use crate::contact::ImpactLocation;
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
    /// Effect name → its table, with the table's place in the file for messages.
    #[serde(default)]
    pub effects: indexmap::IndexMap<String, toml::Spanned<toml::Value>>,
    pub kinds: Vec<KindSpec>,
    #[serde(default)]
    pub walls: Vec<WallSpec>,
    #[serde(default)]
    pub particles: Vec<ParticleSpec>,
    #[serde(default)]
    pub lattice: Vec<LatticeSpec>,
    #[serde(default)]
    pub random_fill: Vec<RandomFillSpec>,
    #[serde(default)]
    pub injectors: Vec<InjectorSpec>,
    #[serde(default)]
    pub outlets: Vec<OutletSpec>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    pub dt: DtSpec,
    pub duration: f64,
    pub output_interval: f64,
    /// Left out: `rk2`, or the accuracy setting's choice with `dt = "auto"`.
    pub integrator: Option<IntegratorKind>,
    /// Only with `dt = "auto"` (default there: balanced).
    pub accuracy: Option<Accuracy>,
    #[serde(default)]
    pub impact_location: ImpactLocation,
}

/// `simulation.dt`: a time step in s, or `"auto"` (chosen from the accuracy setting and the
/// scene's time scales).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DtSpec {
    Seconds(f64),
    Auto,
}

impl<'de> Deserialize<'de> for DtSpec {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = DtSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a time step in s (a number) or \"auto\"")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<DtSpec, E> {
                Ok(DtSpec::Seconds(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<DtSpec, E> {
                if v == "auto" {
                    Ok(DtSpec::Auto)
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Str(v), &self))
                }
            }
        }
        de.deserialize_any(V)
    }
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

/// `fluid.flow`: one flat table whose `type` says which other keys it needs, so that every
/// error keeps its exact key path and line (serde's tagged enums lose both).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlowSpec {
    #[serde(rename = "type", default)]
    pub flow: FlowType,
    pub velocity: Option<[f64; 3]>,
    pub point: Option<[f64; 3]>,
    pub axis: Option<[f64; 3]>,
    pub radius: Option<f64>,
    pub mean_velocity: Option<f64>,
    pub max_velocity: Option<f64>,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FlowType {
    #[default]
    Quiescent,
    Uniform,
    Poiseuille,
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
        BounceSpec { beta: default_beta(), st_critical: default_st_critical(), tangential_restitution: 1.0 }
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

/// One `[[kinds]]` entry; `type` says which material keys it needs (checked in `build`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KindSpec {
    pub name: String,
    #[serde(rename = "type")]
    pub material: KindType,
    pub density: f64,
    pub restitution_max: Option<f64>,
    pub youngs_modulus: Option<f64>,
    pub poisson_ratio: Option<f64>,
    pub surface_tension: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KindType {
    Solid,
    Drop,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub youngs_modulus: Option<f64>,
    pub poisson_ratio: Option<f64>,
    pub restitution_max: Option<f64>,
}

/// One `[[walls]]` entry; `type` says which geometry keys it needs (checked in `build`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    pub name: String,
    #[serde(rename = "type")]
    pub shape: WallType,
    pub point: Option<[f64; 3]>,
    pub normal: Option<[f64; 3]>,
    pub min: Option<[f64; 3]>,
    pub max: Option<[f64; 3]>,
    pub inside: Option<bool>,
    pub base: Option<[f64; 3]>,
    pub axis: Option<[f64; 3]>,
    pub radius: Option<f64>,
    pub length: Option<f64>,
    pub file: Option<String>,
    pub scale: Option<f64>,
    pub translate: Option<[f64; 3]>,
    pub center: Option<[f64; 3]>,
    pub inner_radius: Option<f64>,
    pub outer_radius: Option<f64>,
    pub segments: Option<u32>,
    pub cone_height: Option<f64>,
    #[serde(default)]
    pub material: MaterialSpec,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WallType {
    Plane,
    Box,
    Cylinder,
    Mesh,
    Annulus,
}

impl WallSpec {
    /// Each geometry key, and whether this entry has it.
    pub fn present(&self) -> [(&'static str, bool); 17] {
        [
            ("point", self.point.is_some()),
            ("normal", self.normal.is_some()),
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
            ("inside", self.inside.is_some()),
            ("base", self.base.is_some()),
            ("axis", self.axis.is_some()),
            ("radius", self.radius.is_some()),
            ("length", self.length.is_some()),
            ("file", self.file.is_some()),
            ("scale", self.scale.is_some()),
            ("translate", self.translate.is_some()),
            ("center", self.center.is_some()),
            ("inner_radius", self.inner_radius.is_some()),
            ("outer_radius", self.outer_radius.is_some()),
            ("segments", self.segments.is_some()),
            ("cone_height", self.cone_height.is_some()),
        ]
    }
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

/// One `[[injectors]]` entry.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InjectorSpec {
    pub name: Option<String>,
    pub kind: String,
    pub rate: f64,
    pub region: RegionSpec,
    pub diameter: SizeSpec,
    #[serde(default)]
    pub velocity: [f64; 3],
    pub seed: u64,
    #[serde(default)]
    pub start: f64,
    pub stop: Option<f64>,
}

/// `injectors[i].region`: one flat table whose `type` says which keys it needs.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    #[serde(rename = "type")]
    pub region: RegionType,
    pub center: Option<[f64; 3]>,
    pub normal: Option<[f64; 3]>,
    pub radius: Option<f64>,
    pub min: Option<[f64; 3]>,
    pub max: Option<[f64; 3]>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RegionType {
    Disk,
    Box,
}

/// `injectors[i].diameter`: one flat table whose `distribution` says which keys it needs.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SizeSpec {
    pub distribution: SizeType,
    pub value: Option<f64>,
    pub mean: Option<f64>,
    pub std_dev: Option<f64>,
    pub median: Option<f64>,
    pub sigma: Option<f64>,
    pub min: Option<f64>,
    pub max: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SizeType {
    Fixed,
    Uniform,
    Normal,
    LogNormal,
}

/// One `[[outlets]]` entry.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutletSpec {
    pub name: Option<String>,
    #[serde(rename = "type")]
    pub outlet: OutletType,
    pub point: Option<[f64; 3]>,
    pub normal: Option<[f64; 3]>,
    pub wall: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OutletType {
    Plane,
    Wall,
}
