//! The spin of a particle between contacts **[ext]** (docs/physics.md §9): relaxed by the fluid's
//! Stokes torque towards half the flow's vorticity. Not in the free-flight loop: translation
//! does not depend on spin (no lift force), so spin is its own pass, and a scene without
//! rotation never runs it.

use super::Kernel;
use crate::correlations::spin_relaxation_rate_d2;
use crate::effects::Physics;
use crate::fluid::{Flow, Fluid};
use crate::particles::ParticleKind;
use glam::DVec3;

/// What the spin relaxation reads: per kind `60 μ / ρp` (m²/s; 0 without the drag effect: no
/// viscous fluid, no torque), and the flow for its vorticity.
#[derive(Debug, Clone)]
pub(crate) struct Spin {
    kind_rate: Vec<f64>,
    flow: Flow,
    /// The time (s) at which an unsteady flow's vorticity is read: the middle of the step, as
    /// for its velocity.
    time: f64,
}

impl Spin {
    pub fn new(physics: &Physics, fluid: &Fluid, kinds: &[ParticleKind], time: f64) -> Option<Spin> {
        physics.rotation.then(|| Spin {
            kind_rate: kinds
                .iter()
                .map(|k| {
                    if physics.drag.is_some() {
                        spin_relaxation_rate_d2(fluid.viscosity, k.density)
                    } else {
                        0.0
                    }
                })
                .collect(),
            flow: fluid.flow.clone(),
            time,
        })
    }
}

impl<M> Kernel<'_, M> {
    /// Whether particles spin in this scene (the rotation effect, or friction).
    #[inline]
    pub fn rotation(&self) -> bool {
        self.spin.is_some()
    }

    /// The spin of a particle of kind `k` and diameter `d` (m), at `x`, after `h` (s) from
    /// `omega` (rad/s): `Ω + (ω − Ω) e^{−h/τ_ω}`, `Ω = ½ ∇×u` at `x` and `1/τ_ω = 60 μ/(ρp d²)`
    /// — the exact solution of `I dω/dt = −8π μ a³ (ω − Ω)` for `Ω` held at its value at the
    /// start of the stretch. Unchanged without rotation or without a viscous fluid.
    #[inline]
    pub fn spin_after(&self, kd: (usize, f64), x: DVec3, omega: DVec3, h: f64) -> DVec3 {
        match self.spin_decay(kd, h) {
            Some(decay) => self.spin_relaxed(x, omega, decay),
            None => omega,
        }
    }

    /// The factor `e^{−h/τ_ω}` of [`Kernel::spin_after`] for kind `k` and diameter `d` (m) over
    /// `h` (s); `None` when the spin does not change (no rotation, no viscous fluid, `h ≤ 0`).
    /// Apart from the position, so that a pass over many particles of one kind and size
    /// computes the exponential once.
    #[inline]
    pub fn spin_decay(&self, (k, d): (usize, f64), h: f64) -> Option<f64> {
        let spin = self.spin.as_ref()?;
        let rate = spin.kind_rate[k] / (d * d);
        (rate != 0.0 && h > 0.0).then(|| (-rate * h).exp())
    }

    /// `Ω + (ω − Ω) decay` at `x` ([`Kernel::spin_after`] with its factor already computed).
    #[inline]
    pub fn spin_relaxed(&self, x: DVec3, omega: DVec3, decay: f64) -> DVec3 {
        let Some(spin) = &self.spin else { return omega };
        let target = spin.flow.half_vorticity(x, spin.time);
        target + (omega - target) * decay
    }
}
