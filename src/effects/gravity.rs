//! Gravity: the particle's weight `ρp Vp g` (docs/physics.md §1).

use super::{Effect, Physics};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// Weight of the particle, `+ρp Vp g`. Scene table: `gravity = {}` (no parameters; the
/// vector is `fluid.gravity`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gravity {}

impl Effect for Gravity {
    fn name(&self) -> &'static str {
        "gravity"
    }

    fn apply(&self, fluid: &Fluid, kinds: &[ParticleKind], physics: &mut Physics) {
        for (terms, kind) in physics.kinds.iter_mut().zip(kinds) {
            terms.force_density += kind.density * fluid.gravity;
        }
    }
}
