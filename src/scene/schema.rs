//! The scene file's schema (serde). Units and meanings: `docs/scene-format.md`.

use super::accuracy::Accuracy;
use crate::contact::ImpactLocation;
use crate::integrate::IntegratorKind;
use serde::Deserialize;

pub use super::table::Rest;

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
    /// When a run checkpoints (docs/scene-format.md, `[checkpoint]`).
    #[serde(default)]
    pub checkpoint: CheckpointSpec,
}

/// `[checkpoint]`: `every` simulated seconds, every `wall_minutes` of wall-clock time, the
/// newest `keep` kept. The command line's `--checkpoint-*` options override each.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckpointSpec {
    pub every: Option<f64>,
    pub wall_minutes: Option<f64>,
    pub keep: Option<i64>,
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

/// Every 3-vector key of the scene (positions, velocities, normals, axes, points, corners,
/// gravity, translations, flows): exactly three numbers `[x, y, z]`.
///
/// Not `[f64; 3]`: serde reads a fixed-size array as a tuple, takes its first three elements
/// and returns, and the toml deserializer does not check that the array has ended, so
/// `[0.0, 0.0, 1.0, 99.0, "x", true]` was read as `[0, 0, 1]` and the rest dropped unseen.
/// This type reads the whole array, then checks its length and every element's type, so the
/// error names the key (through `serde_path_to_error`) and says what was given.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Vec3Spec(pub [f64; 3]);

impl<'de> Deserialize<'de> for Vec3Spec {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Vec3Spec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("3 numbers [x, y, z]")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Vec3Spec, A::Error> {
                let mut v = [0.0; 3];
                let mut count = 0usize;
                let mut not_a_number: Option<(usize, String)> = None;
                while let Some(c) = seq.next_element::<Component>()? {
                    match c {
                        Component::Number(x) if count < 3 => v[count] = x,
                        Component::Number(_) => {}
                        Component::Other(what) => {
                            not_a_number.get_or_insert((count, what));
                        }
                    }
                    count += 1;
                }
                let wrong = |detail: String| {
                    serde::de::Error::custom(format!("must be 3 numbers [x, y, z], {detail}"))
                };
                if count != 3 {
                    let s = if count == 1 { "" } else { "s" };
                    return Err(wrong(format!("got {count} value{s}")));
                }
                if let Some((i, what)) = not_a_number {
                    return Err(wrong(format!("but component {i} is {what}")));
                }
                Ok(Vec3Spec(v))
            }
        }
        de.deserialize_seq(V)
    }
}

/// One element of a vector as given: a number (a TOML float or integer), or what it is instead.
enum Component {
    Number(f64),
    Other(String),
}

impl<'de> Deserialize<'de> for Component {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Component;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number")
            }
            fn visit_f64<E>(self, v: f64) -> Result<Component, E> {
                Ok(Component::Number(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Component, E> {
                Ok(Component::Number(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Component, E> {
                Ok(Component::Number(v as f64))
            }
            fn visit_bool<E>(self, v: bool) -> Result<Component, E> {
                Ok(Component::Other(format!("a boolean ({v})")))
            }
            fn visit_str<E>(self, v: &str) -> Result<Component, E> {
                let shown: String = v.chars().take(20).collect();
                let more = if shown.len() < v.len() { "…" } else { "" };
                Ok(Component::Other(format!("a string (\"{}{more}\")", shown.escape_debug())))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Component, A::Error> {
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {}
                Ok(Component::Other("an array".into()))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Component, A::Error> {
                while map.next_entry::<serde::de::IgnoredAny, serde::de::IgnoredAny>()?.is_some() {}
                Ok(Component::Other("a table or a date".into()))
            }
        }
        de.deserialize_any(V)
    }
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
    pub gravity: Vec3Spec,
    #[serde(default)]
    pub flow: FlowSpec,
}

fn default_gravity() -> Vec3Spec {
    Vec3Spec([0.0, 0.0, -9.81])
}

/// `fluid.flow`: its `type` (left out: quiescent) and the keys of that type, read into its
/// struct below once the type is known (`scene::table`).
#[derive(Debug, Clone, Default)]
pub struct FlowSpec {
    pub flow: FlowType,
    pub rest: Rest,
}

/// The flow types: their names in the file. Each one's table is in `FlowType::table`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FlowType {
    #[default]
    Quiescent,
    Uniform,
    Poiseuille,
    Field,
}

/// `type = "quiescent"`: no keys.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuiescentSpec {}

/// `type = "uniform"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UniformSpec {
    pub velocity: Vec3Spec,
}

/// `type = "poiseuille"`: `mean_velocity` or `max_velocity`, not both.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoiseuilleSpec {
    pub point: Vec3Spec,
    /// Left out: +z.
    pub axis: Option<Vec3Spec>,
    pub radius: f64,
    pub mean_velocity: Option<f64>,
    pub max_velocity: Option<f64>,
}

/// `type = "field"`: `file`, or `files` with `times`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSpec {
    /// One VTK file, or a `.pvd` collection of snapshots.
    pub file: Option<String>,
    /// Snapshot files, with `times`.
    pub files: Option<Vec<String>>,
    /// The snapshots' times (s), increasing.
    pub times: Option<Vec<f64>>,
    /// The velocity array's name.
    pub array: Option<String>,
    /// `"point"` or `"cell"` data.
    pub data: Option<DataSpec>,
    /// What the flow is outside the grid.
    pub outside: Option<OutsideSpec>,
    /// The file is a 2-D (r, z) table turned about `axis` through `point`.
    pub axisymmetric: Option<bool>,
    /// With `axisymmetric`: a point of the axis (left out: the origin).
    pub point: Option<Vec3Spec>,
    /// With `axisymmetric`: the axis (left out: +z).
    pub axis: Option<Vec3Spec>,
    /// A series repeats with this period (s).
    pub period: Option<f64>,
}

/// `fluid.flow.data`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DataSpec {
    Point,
    Cell,
}

/// `fluid.flow.outside`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OutsideSpec {
    Error,
    Zero,
    Nearest,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BounceSpec {
    /// β of L06 eq. 2; left out: [`DEFAULT_BETA`]. Only for the `"l06"` rule.
    pub beta: Option<f64>,
    /// `St_c`; left out: [`DEFAULT_ST_CRITICAL`]. Only for the `"l06"` rule.
    pub st_critical: Option<f64>,
    /// `e_t` of the frictionless rule; left out: 1. Refused in a scene with friction keys,
    /// where the materials' `tangential_restitution` (β0) is the tangential rule.
    pub tangential_restitution: Option<f64>,
    /// `"l06"` (ε from L06 eq. 2) or `"e"` (the dry restitution on the impact speed, with wall
    /// lubrication); left out: `"e"` with the `wall_lubrication` effect, `"l06"` without.
    pub rule: Option<RuleSpec>,
    /// `e` of the `"e"` rule; left out: the particle's (or wall's) `restitution_max`.
    pub e: Option<f64>,
}

/// `bounce.rule`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RuleSpec {
    L06,
    E,
}

/// β of L06 eq. 2 when the scene does not give it.
pub const DEFAULT_BETA: f64 = 35.0;
/// The critical Stokes number of L06 when the scene does not give it.
pub const DEFAULT_ST_CRITICAL: f64 = 10.0;

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
    /// Surface roughness `h_r` (m), used by the `wall_lubrication` effect.
    pub roughness: Option<f64>,
    /// Coulomb friction coefficient `μ` **[ext]**.
    pub friction: Option<f64>,
    /// Walton's tangential restitution `β0` **[ext]** (−1 to 1).
    pub tangential_restitution: Option<f64>,
    /// Rolling friction coefficient `μ_r` **[ext]**.
    pub rolling_friction: Option<f64>,
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
    /// Surface roughness of the wall (m), used by the `wall_lubrication` effect.
    pub roughness: Option<f64>,
    /// Coulomb friction coefficient `μ` **[ext]**.
    pub friction: Option<f64>,
    /// Walton's tangential restitution `β0` **[ext]** (−1 to 1).
    pub tangential_restitution: Option<f64>,
    /// Rolling friction coefficient `μ_r` **[ext]**.
    pub rolling_friction: Option<f64>,
}

/// One `[[walls]]` entry: the keys of every wall, its `type`, and the keys of that type, read
/// into its struct below once the type is known (`scene::table`).
#[derive(Debug, Clone)]
pub struct WallSpec {
    pub name: String,
    pub shape: WallType,
    pub material: MaterialSpec,
    pub rest: Rest,
}

/// The wall shapes: their names in the file. Each one's table is in `WallType::table`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WallType {
    Plane,
    Box,
    Cylinder,
    Mesh,
    Annulus,
}

/// `type = "plane"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneSpec {
    pub point: Vec3Spec,
    pub normal: Vec3Spec,
}

/// `type = "box"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    pub min: Vec3Spec,
    pub max: Vec3Spec,
    /// Required; an `Option` so that the message of its absence can say what each value means.
    pub inside: Option<bool>,
}

/// `type = "cylinder"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderSpec {
    pub base: Vec3Spec,
    /// Left out: +z.
    pub axis: Option<Vec3Spec>,
    pub radius: f64,
    /// Left out: infinite both ways.
    pub length: Option<f64>,
}

/// `type = "mesh"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    pub file: String,
    /// Left out: 1.
    pub scale: Option<f64>,
    /// Left out: none.
    pub translate: Option<Vec3Spec>,
}

/// `type = "annulus"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnnulusSpec {
    pub center: Vec3Spec,
    pub normal: Vec3Spec,
    /// Left out: 0 (a disk).
    pub inner_radius: Option<f64>,
    pub outer_radius: f64,
    /// Left out: 0 (flat).
    pub cone_height: Option<f64>,
    /// Left out: 128.
    pub segments: Option<u32>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleSpec {
    pub kind: String,
    pub diameter: f64,
    pub position: Vec3Spec,
    #[serde(default)]
    pub velocity: Vec3Spec,
    /// Initial angular velocity ω (rad/s) **[ext]**: only in a scene with rotation.
    pub angular_velocity: Option<Vec3Spec>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    pub kind: String,
    pub diameter: f64,
    pub min: Vec3Spec,
    pub max: Vec3Spec,
    pub spacing: f64,
    #[serde(default)]
    pub velocity: Vec3Spec,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomFillSpec {
    pub kind: String,
    pub diameter: f64,
    pub min: Vec3Spec,
    pub max: Vec3Spec,
    pub count: u32,
    pub seed: u64,
    #[serde(default)]
    pub velocity: Vec3Spec,
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
    pub velocity: Vec3Spec,
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
    pub center: Option<Vec3Spec>,
    pub normal: Option<Vec3Spec>,
    pub radius: Option<f64>,
    pub min: Option<Vec3Spec>,
    pub max: Option<Vec3Spec>,
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
    pub point: Option<Vec3Spec>,
    pub normal: Option<Vec3Spec>,
    pub wall: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OutletType {
    Plane,
    Wall,
}

/// Reads a `[[walls]]` entry: `name`, `type` and `material` where they stand in the file (so
/// that their errors keep their key path and line); the other keys kept for the type.
impl<'de> Deserialize<'de> for WallSpec {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = WallSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a wall table")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<WallSpec, A::Error> {
                let (mut name, mut shape, mut material) = (None, None, None);
                let mut rest = Rest::default();
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "name" => name = Some(map.next_value()?),
                        "type" => shape = Some(map.next_value()?),
                        "material" => material = Some(map.next_value()?),
                        _ => {
                            let value = map.next_value()?;
                            rest.0.push((key, value));
                        }
                    }
                }
                use serde::de::Error;
                Ok(WallSpec {
                    name: name.ok_or_else(|| A::Error::missing_field("name"))?,
                    shape: shape.ok_or_else(|| A::Error::missing_field("type"))?,
                    material: material.unwrap_or_default(),
                    rest,
                })
            }
        }
        de.deserialize_map(V)
    }
}

/// Reads `fluid.flow`: `type` where it stands in the file; the other keys kept for the type.
impl<'de> Deserialize<'de> for FlowSpec {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = FlowSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a flow table")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<FlowSpec, A::Error> {
                let mut spec = FlowSpec::default();
                while let Some(key) = map.next_key::<String>()? {
                    if key == "type" {
                        spec.flow = map.next_value()?;
                    } else {
                        let value = map.next_value()?;
                        spec.rest.0.push((key, value));
                    }
                }
                Ok(spec)
            }
        }
        de.deserialize_map(V)
    }
}
