//! Added mass: the fluid set in motion with the particle (docs/physics.md §1).

use super::{Effect, Physics};
use crate::correlations::ADDED_MASS_FAR;
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// Adds `C_M ρ Vp` to the particle's inertia (L06 eq. 7, `C_M = C_M∞ = 1/2` by default).
///
/// The fluid-acceleration terms `ρ Vp (1 + C_M) Du/Dt` **[ext]** vanish for every flow the
/// engine offers, so no force is added: quiescent and uniform flows are steady and uniform, and
/// laminar Poiseuille flow is steady and unidirectional with `u` varying only across its axis,
/// so its convective acceleration `(u·∇)u` is zero too.
/// Scene table: `added_mass = {}` or `added_mass = { coefficient = 0.5 }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AddedMass {
    /// Added-mass coefficient `C_M` (dimensionless, ≥ 0); default 1/2, a sphere far from walls.
    #[serde(default = "default_coefficient")]
    pub coefficient: f64,
}

fn default_coefficient() -> f64 {
    ADDED_MASS_FAR
}

impl AddedMass {
    /// Checks the coefficient is finite and ≥ 0.
    pub fn validated(self) -> Result<Self, super::EffectError> {
        if self.coefficient.is_finite() && self.coefficient >= 0.0 {
            Ok(self)
        } else {
            let message = format!("must be finite and >= 0, got {}", self.coefficient);
            Err(super::EffectError::new("coefficient", message))
        }
    }
}

impl Effect for AddedMass {
    fn name(&self) -> &'static str {
        "added_mass"
    }

    fn apply(&self, fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        for terms in &mut physics.kinds {
            terms.inertia_density += self.coefficient * fluid.density;
        }
        physics.added_mass_coefficient = self.coefficient;
        physics.added_mass = true;
    }
}
