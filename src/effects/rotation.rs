//! Rotation **[ext]** (docs/physics.md §9): particles carry an angular velocity, which the fluid
//! relaxes towards half its vorticity by the Stokes torque `−8π μ a³ (ω − ½ ∇×u)` (with the
//! drag effect: the same viscous fluid), and which frictional contacts change.

use super::{Effect, Physics};
use crate::fluid::Fluid;
use crate::particles::{Column, Feature, ParticleKind, Particles};
use glam::DVec3;
use serde::Deserialize;
use std::collections::TryReserveError;
use std::sync::Arc;

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
        physics.features.add(Arc::new(self.clone()));
    }
}

/// The spin is a typed column of the store ([`Particles::omega`]): the flight kernel's spin
/// relaxation and the contact rules read it in the hot loop. The step writes its end in
/// `Next::omega`; the store commits it.
impl Feature for Rotation {
    fn name(&self) -> &'static str {
        "rotation"
    }

    /// Particles that no scene file set spinning (made by a program): at rest. The scene
    /// loader turns the column on before it places the particles, which may be given a spin.
    fn start(&self, p: &mut Particles) -> Result<(), TryReserveError> {
        if !p.omega.is_on() {
            p.omega = Column::try_new(1, DVec3::ZERO, p.len())?;
        }
        Ok(())
    }
}
