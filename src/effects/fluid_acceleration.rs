//! **[ext]** The fluid-acceleration force of a non-uniform or unsteady flow (docs/physics.md §7.1):
//! `ρ Vp (1 + C_M) Du/Dt`, `Du/Dt = ∂u/∂t + (u·∇)u` the fluid's acceleration at the particle.

use super::{Effect, Physics};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// The fluid-acceleration effect. Scene table: `fluid_acceleration = {}`.
///
/// The force on the sphere from the undisturbed flow's pressure gradient and viscous stress is
/// `ρ Vp Du/Dt` (the buoyancy `−ρ Vp g` apart; Maxey & Riley 1983, eq. 4.1, the term
/// `m_F Du/Dt`); with added mass, the fluid accelerated with the particle adds
/// `C_M ρ Vp (Du/Dt − dv/dt)`, whose `Du/Dt` is the fluid's material acceleration (Auton, Hunt &
/// Prud'homme 1988, eq. 5.12, for a sphere in a weakly non-uniform rotational flow; Maxey &
/// Riley's `d/dt` along the particle's path differs from it only at higher order). With the
/// `−C_M ρ Vp dv/dt` already in the inertia ([`super::AddedMass`]), the balance reads
///
/// ```text
/// (ρp + C_M ρ) Vp dv/dt = … + (1 + C_M) ρ Vp Du/Dt
/// ```
///
/// so the acceleration per unit effective inertia is `G Du/Dt`, `G = (1 + C_M) ρ / (ρp + C_M ρ)`
/// ([`fluid_acceleration_gain`]): `G = ρ/ρp` without added mass (the undisturbed-flow term
/// alone), `G = 1` for a neutrally buoyant particle with or without it, which then follows the
/// fluid exactly.
///
/// `Du/Dt` is zero in every analytic flow the engine offers (quiescent, uniform, Poiseuille:
/// steady, and Poiseuille's `(u·∇)u = 0`), so the effect is accepted there and costs nothing.
/// In a field it is evaluated with the drag, at every stage of the integrator
/// ([`crate::fluid::field::Accelerating`]).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidAcceleration {}

impl Effect for FluidAcceleration {
    fn name(&self) -> &'static str {
        "fluid_acceleration"
    }

    fn apply(&self, _fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        physics.fluid_acceleration = true;
    }
}

/// `G = (1 + C_M) ρ / (ρp + C_M ρ)` (dimensionless): the particle's acceleration per unit fluid
/// acceleration `Du/Dt` from the fluid-stress and added-mass forces, for a fluid of density `ρ`
/// (kg/m³), an added-mass coefficient `C_M` (0 without added mass) and the particle's inertia
/// density `ρp + C_M ρ` (kg/m³). Maxey & Riley (1983) eq. 4.1 with the added-mass term of Auton,
/// Hunt & Prud'homme (1988) eq. 5.12. Range: any `ρ ≥ 0`, `C_M ≥ 0`, inertia density > 0.
pub fn fluid_acceleration_gain(fluid_density: f64, added_mass_coefficient: f64, inertia_density: f64) -> f64 {
    (1.0 + added_mass_coefficient) * fluid_density / inertia_density
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_neutrally_buoyant_particle_has_gain_one_with_or_without_added_mass() {
        assert_eq!(fluid_acceleration_gain(1000.0, 0.0, 1000.0), 1.0);
        assert_eq!(fluid_acceleration_gain(1000.0, 0.5, 1500.0), 1.0);
        // A glass bead in water with added mass: 1.5 · 1000 / (2500 + 500).
        assert_eq!(fluid_acceleration_gain(1000.0, 0.5, 3000.0), 0.5);
        // A bubble-light particle: up to 1 + 1/C_M = 3.
        assert!((fluid_acceleration_gain(1000.0, 0.5, 500.0 + 1e-9) - 3.0).abs() < 1e-9);
    }
}
