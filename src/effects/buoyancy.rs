//! Buoyancy: the displaced fluid's weight `−ρ Vp g` (docs/physics.md §1).

use super::{Effect, Physics};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// Archimedes' force `−ρ Vp g`; with [`super::Gravity`] the net weight is `Vp (ρp − ρ) g`.
/// Scene table: `buoyancy = {}`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Buoyancy {}

impl Effect for Buoyancy {
    fn name(&self) -> &'static str {
        "buoyancy"
    }

    fn apply(&self, fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        for terms in &mut physics.kinds {
            terms.force_density -= fluid.density * fluid.gravity;
        }
    }
}
