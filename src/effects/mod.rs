//! The physical effects a scene can name, one file each (docs/physics.md §1 and §5).
//!
//! An effect does not run in the hot loop: it *builds* the scene's [`Physics`] once, by adding
//! its term to each particle kind's inertia and force (per unit particle volume), by choosing the
//! drag law, or by switching on the hold at contact. The integrators then evaluate one
//! linearised force ([`crate::integrate::Linear`]) per particle, compiled for the drag law and
//! flow the scene has, so an effect the scene does not name costs nothing.
//!
//! The registry is one table of names and builders (`REGISTRY`, read by [`build_effect`]): a
//! new effect is its file and one line there.

mod added_mass;
mod buoyancy;
mod cell_hints;
mod contact_time;
mod drag;
mod fluid_acceleration;
mod gravity;
mod history;
mod rotation;
mod wall_lubrication;

pub use added_mass::AddedMass;
pub use buoyancy::Buoyancy;
pub use cell_hints::CellHints;
pub use contact_time::ContactTime;
pub use drag::{Drag, DragLaw, DragLawKind, NoDrag, SchillerNaumann, Stokes};
pub use fluid_acceleration::{FluidAcceleration, fluid_acceleration_gain};
pub use gravity::Gravity;
pub use history::{
    FORGETS_IN_A_STEP, FORGOTTEN_IN_A_SEGMENT, Fold, History, MemoryKernel, SHORTEST_LAG,
    fold_history_for_step, history_rate_times_radius,
};
pub use rotation::Rotation;
pub use wall_lubrication::{
    RANGE as LUBRICATION_RANGE, WallExcess, WallLubrication, WallTable, taper, wall_excess,
};

use crate::fluid::Fluid;
use crate::particles::{Features, ParticleKind};
use glam::DVec3;
use std::sync::Arc;

/// How an effect is built from its own table of the scene file.
type Build = fn(toml::Value) -> Result<Box<dyn Effect>, EffectError>;

/// The effect registry: each name a scene's `[effects]` table accepts, listed once, in the
/// order the docs list them, with how its effect is built.
const REGISTRY: &[(&str, Build)] = &[
    ("gravity", |t| Ok(Box::new(parse::<Gravity>(t)?))),
    ("buoyancy", |t| Ok(Box::new(parse::<Buoyancy>(t)?))),
    ("drag", |t| Ok(Box::new(parse::<Drag>(t)?))),
    ("added_mass", |t| Ok(Box::new(parse::<AddedMass>(t)?.validated()?))),
    ("contact_time", |t| Ok(Box::new(parse::<ContactTime>(t)?))),
    ("wall_lubrication", |t| Ok(Box::new(parse::<WallLubrication>(t)?))),
    ("history", |t| Ok(Box::new(parse::<History>(t)?.validated()?))),
    ("rotation", |t| Ok(Box::new(parse::<Rotation>(t)?))),
    ("fluid_acceleration", |t| Ok(Box::new(parse::<FluidAcceleration>(t)?))),
];

/// The names a scene's `[effects]` table accepts, in the order the docs list them.
pub fn effect_names() -> impl Iterator<Item = &'static str> {
    REGISTRY.iter().map(|&(name, _)| name)
}

/// One physical effect: adds its part to the scene's [`Physics`].
pub trait Effect: std::fmt::Debug + Send + Sync {
    /// The name the scene file uses.
    fn name(&self) -> &'static str;
    /// Adds this effect's term to `physics`, for a scene with these `kinds` in this `fluid`.
    fn apply(&self, fluid: &Fluid, kinds: &[ParticleKind], physics: &mut Physics);
    /// Checks the table against the scene's kinds (a kind named by the effect must exist);
    /// the scene loader adds the file and `effects.<name>`.
    fn check(&self, _kinds: &[ParticleKind]) -> Result<(), EffectError> {
        Ok(())
    }
}

/// The error of [`build_effect`]; the scene loader adds the file and `effects.<name>`.
#[derive(Debug, Clone, PartialEq)]
pub struct EffectError {
    /// Key path inside the effect's table (empty for the table itself).
    pub key: String,
    /// What is wrong, with the bad value.
    pub message: String,
}

impl EffectError {
    /// An error about `key` of the effect's table.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        EffectError { key: key.into(), message: message.into() }
    }
}

/// Builds the effect `name` from its own table of the scene file ([`REGISTRY`]); an unknown
/// name is an error that lists the valid ones.
pub fn build_effect(name: &str, table: toml::Value) -> Result<Box<dyn Effect>, EffectError> {
    let Some(&(_, build)) = REGISTRY.iter().find(|&&(n, _)| n == name) else {
        let names: Vec<&str> = effect_names().collect();
        return Err(EffectError::new(
            "",
            format!("unknown effect \"{name}\"; valid effects are: {}", names.join(", ")),
        ));
    };
    build(table)
}

/// An effect's table, deserialised with the path of a bad key.
fn parse<T: serde::de::DeserializeOwned>(table: toml::Value) -> Result<T, EffectError> {
    serde_path_to_error::deserialize(table).map_err(|e| {
        let key = e.path().to_string();
        EffectError::new(if key == "." { String::new() } else { key }, e.inner().message())
    })
}

/// What one particle kind's inertia and steady forces are, per unit particle volume.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KindTerms {
    /// Inertia per unit volume (kg/m³): `ρp`, plus `C_M ρ` with added mass.
    pub inertia_density: f64,
    /// Force per unit volume that does not depend on the particle's motion (N/m³):
    /// `ρp g` with gravity, `−ρ g` with buoyancy.
    pub force_density: DVec3,
}

/// What the scene's effects make of its physics; built once, read in the hot loop.
#[derive(Debug, Clone, PartialEq)]
pub struct Physics {
    /// One entry per particle kind, indexed like the kinds.
    pub kinds: Vec<KindTerms>,
    /// The drag law, or `None` without the drag effect.
    pub drag: Option<DragLawKind>,
    /// Added-mass coefficient in the inertia (0 without the added-mass effect).
    pub added_mass_coefficient: f64,
    /// With the added-mass effect: the fluid's inertia is in the particle's (so wall
    /// lubrication's near-wall added mass is too, docs/physics.md §8).
    pub added_mass: bool,
    /// With the contact-time effect: particles are held at the wall for `t_c`
    /// (docs/physics.md §5.3).
    pub hold_at_contact: bool,
    /// Which kinds the contact-time effect holds, indexed like the kinds (empty without it).
    pub held_kinds: Vec<bool>,
    /// With the wall-lubrication effect **[ext]**: the drag and added mass near a wall
    /// (docs/physics.md §8), evaluated by the flight kernel for particles near a wall only,
    /// from its terms tabulated away from the film ([`WallTable`]); `None` without it.
    pub wall_lubrication: Option<std::sync::Arc<WallTable>>,
    /// With the history effect **[ext]**: the memory kernel of the Basset–Boussinesq force
    /// (docs/physics.md §10), integrated by the flight kernel with one memory per particle.
    pub history: Option<MemoryKernel>,
    /// With rotation **[ext]** (the effect, or any friction key in the scene): particles spin,
    /// the fluid's torque relaxes the spin, contacts with friction change it (docs/physics.md §9).
    pub rotation: bool,
    /// With the fluid-acceleration effect **[ext]**: the force `(1 + C_M) ρ Vp Du/Dt` of a
    /// non-uniform or unsteady flow (docs/physics.md §7.1), evaluated with the drag in a field flow
    /// (zero, and not evaluated, in the analytic flows).
    pub fluid_acceleration: bool,
    /// The stateful features (docs/architecture.md, "Features that own their state"): the
    /// effects that keep per-particle state register here in `apply` (rotation, history), and
    /// [`Physics::build`] registers a field's cell hints.
    pub features: Features,
    /// Names of the effects, in the order they were applied.
    pub effect_names: Vec<&'static str>,
}

impl Physics {
    /// Applies `effects` in order to a scene with these `kinds` in this `fluid`.
    pub fn build(fluid: &Fluid, kinds: &[ParticleKind], effects: &[Box<dyn Effect>]) -> Self {
        let mut physics = Physics {
            kinds: kinds
                .iter()
                .map(|k| KindTerms { inertia_density: k.density, force_density: DVec3::ZERO })
                .collect(),
            drag: None,
            added_mass_coefficient: 0.0,
            added_mass: false,
            hold_at_contact: false,
            held_kinds: Vec::new(),
            wall_lubrication: None,
            history: None,
            rotation: false,
            fluid_acceleration: false,
            features: Features::default(),
            effect_names: Vec::new(),
        };
        for effect in effects {
            effect.apply(fluid, kinds, &mut physics);
            physics.effect_names.push(effect.name());
        }
        if let Some(field) = fluid.flow.shared_field()
            && field.0.walks()
        {
            physics.features.add(Arc::new(CellHints::new(field.clone())));
        }
        physics
    }

    /// The constant part of kind `k`'s acceleration (m/s²): force density over inertia density.
    pub fn body_acceleration(&self, k: usize) -> DVec3 {
        self.kinds[k].force_density / self.kinds[k].inertia_density
    }

    /// `G = (1 + C_M) ρ / (ρp + C_M ρ)` of kind `k`: its acceleration per unit fluid
    /// acceleration `Du/Dt` ([`fluid_acceleration_gain`]); 0 without the fluid-acceleration effect.
    pub fn fluid_acceleration_gain(&self, k: usize, fluid: &Fluid) -> f64 {
        if self.fluid_acceleration {
            fluid_acceleration_gain(fluid.density, self.added_mass_coefficient, self.kinds[k].inertia_density)
        } else {
            0.0
        }
    }

    /// Stokes relaxation rate of kind `k` times d² (m²/s): `18 μ / (ρp + C_M ρ)`, so that a
    /// particle of diameter `d` has `1/τ = rate · f(Re) / d²` (L06 eq. 6). 0 without drag.
    pub fn drag_rate(&self, k: usize, fluid: &Fluid) -> f64 {
        if self.drag.is_some() { 18.0 * fluid.viscosity / self.kinds[k].inertia_density } else { 0.0 }
    }
}
