//! Rotation **[ext]** (docs/physics.md §9): particles carry an angular velocity, which the fluid
//! relaxes towards half its vorticity by the Stokes torque `−8π μ a³ (ω − ½ ∇×u)` (with the
//! drag effect: the same viscous fluid), and which frictional contacts change.

use super::{Effect, Physics};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// With this effect every particle has a spin. A scene that gives any friction key
/// (`friction`, `tangential_restitution`, `rolling_friction` of a kind or a wall material) has
/// rotation whether it names the effect or not: friction needs the spin. Without either, spin
/// is neither computed nor written, and the step is the one it was before rotation existed.
/// Scene table: `rotation = {}`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rotation {}

impl Effect for Rotation {
    fn name(&self) -> &'static str {
        "rotation"
    }

    fn apply(&self, _fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        physics.rotation = true;
    }
}
