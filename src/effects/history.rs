//! **[ext]** The Basset–Boussinesq history force (docs/physics.md §10), with a bounded memory per
//! particle: its kernel `1/√t` as a sum of decaying exponentials (the exponential-mode form of
//! Parmar, Balachandar & Haselbacher 2018), each one an extra state per particle.

use super::{Effect, EffectError, Physics};
use crate::correlations::ExponentialSum;
use crate::fluid::Fluid;
use crate::particles::{Column, Feature, ParticleKind, Particles, feature::reset_at_walls};
use serde::Deserialize;
use std::collections::TryReserveError;
use std::sync::Arc;

/// The shortest lag the exponential sum resolves, as a fraction of the window: lags below it
/// are lumped into one instantaneous term ([`MemoryKernel::short_weight`]). Ten decades below
/// the window; the scene loader checks that it stays below Δt/1000 (a window of at most 10⁷ Δt).
pub const SHORTEST_LAG: f64 = 1e-10;

/// The history effect. Scene table: `history = {}`, or `history = { window = 1.0,
/// tolerance = 1e-4 }`: the memory kernel `1/√t` is matched within `tolerance` (relative) for
/// lags from `1e-10 window` to `window` (s); beyond the window the sum falls slowly below
/// `1/√t`, so older accelerations are under-weighted, then forgotten. Memory: 37 modes
/// (888 bytes) per particle with the defaults.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct History {
    /// How far back the memory is exact within `tolerance` (s); default 1 s.
    #[serde(default = "default_window")]
    pub window: f64,
    /// Relative error of the memory kernel on the window (dimensionless); default 1e-4.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
}

fn default_window() -> f64 {
    1.0
}

fn default_tolerance() -> f64 {
    1e-4
}

/// The tolerances accepted: below 1e-10 the sum would need hundreds of modes per particle,
/// above 0.1 it is no longer the Basset kernel.
pub const TOLERANCE_RANGE: (f64, f64) = (1e-10, 0.1);

impl History {
    /// Checks the window is finite and > 0 and the tolerance within [`TOLERANCE_RANGE`]. (The
    /// window against Δt is checked by the scene loader, which knows Δt.)
    pub fn validated(self) -> Result<Self, EffectError> {
        if !(self.window.is_finite() && self.window > 0.0) {
            return Err(EffectError::new(
                "window",
                format!("must be finite and > 0 (s), got {}", self.window),
            ));
        }
        let (lo, hi) = TOLERANCE_RANGE;
        if !(self.tolerance.is_finite() && (lo..=hi).contains(&self.tolerance)) {
            let message = format!("must be between {lo:e} and {hi} (relative error), got {}", self.tolerance);
            return Err(EffectError::new("tolerance", message));
        }
        Ok(self)
    }
}

impl Effect for History {
    fn name(&self) -> &'static str {
        "history"
    }

    fn apply(&self, _fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        let kernel = MemoryKernel::new(self.window, self.tolerance);
        physics.features.add(Arc::new(Memory { modes: kernel.modes() }));
        physics.history = Some(kernel);
    }
}

/// The memory of the history force as a feature: a typed column of the store
/// ([`Particles::memory`], 3 × `modes` numbers per particle) that the flight kernel reads in the
/// hot loop and writes the end of in `Next::memory` (the particle pass, and stage 4 for the
/// paths a contact restarted); the store commits it.
#[derive(Debug, Clone)]
struct Memory {
    modes: usize,
}

impl Feature for Memory {
    fn name(&self) -> &'static str {
        "history"
    }

    /// One memory per particle, allocated only when a run starts: a scene that is only
    /// checked never holds it. A new particle remembers nothing, as if it had moved at its
    /// velocity forever.
    fn start(&self, p: &mut Particles) -> Result<(), TryReserveError> {
        if !p.memory.is_on() {
            p.memory = Column::try_new(3 * self.modes, 0.0, p.len())?;
        }
        Ok(())
    }

    /// A particle held at a wall or resting on one remembers nothing: its flight after the
    /// release starts a new memory (docs/physics.md §10, "impact, hold and release").
    fn commit(&self, p: &mut Particles) {
        let width = p.memory.width();
        reset_at_walls(&p.state, p.memory.values_mut(), width, 0.0);
    }
}

/// The history kernel as the flight integrates it: `1/√t ≈ Σ_k w_k e^{−λ_k t} + D δ(t)`.
///
/// The sum is `ExponentialSum::inverse_sqrt` on `[SHORTEST_LAG · window, window]`; below its
/// shortest lag the sum saturates while `1/√t` does not, and the missing area `D` is put back
/// as an instantaneous term (an added mass `c D` in units of the particle's inertia), which is
/// exact for every acceleration that does not change over the shortest lag.
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryKernel {
    /// Window (s).
    pub window: f64,
    /// Relative error of the sum on the window.
    pub tolerance: f64,
    /// The sum: weights `w_k` (s^−½) and rates `λ_k` (1/s).
    pub sum: ExponentialSum,
    /// `D = ∫_0^T (1/√t − Σ w_k e^{−λ_k t}) dt` (s^½), at `T = 10⁴ ×` the shortest lag, where
    /// the sum has long joined `1/√t`.
    pub short_weight: f64,
}

impl MemoryKernel {
    /// The kernel for a window (s, > 0) and a tolerance within [`TOLERANCE_RANGE`].
    pub fn new(window: f64, tolerance: f64) -> Self {
        let shortest = SHORTEST_LAG * window;
        let sum = ExponentialSum::inverse_sqrt(shortest, window, tolerance);
        let t = 1e4 * shortest;
        let area: f64 = sum.weights.iter().zip(&sum.rates).map(|(w, l)| w * -(-l * t).exp_m1() / l).sum();
        MemoryKernel { window, tolerance, short_weight: 2.0 * t.sqrt() - area, sum }
    }

    /// Number of modes, the states kept per particle and per component.
    pub fn modes(&self) -> usize {
        self.sum.len()
    }

    /// Memory per particle (bytes): one `DVec3` per mode.
    pub fn bytes_per_particle(&self) -> usize {
        self.modes() * std::mem::size_of::<glam::DVec3>()
    }
}

/// `c = K_H / (m_eff a)` per unit `1/a`: the history force's rate on a sphere of radius `a`,
/// `c / a` in s^−½, for a kind of inertia density `inertia_density` (kg/m³, `ρp + C_M ρ`) in
/// `fluid`: `K_H / m_eff = 6 a² sqrt(π ρ μ) / (inertia_density · 4π a³/3) = (9/2) sqrt(ρ μ / π) /
/// (inertia_density · a)` (docs/physics.md §10).
pub fn history_rate_times_radius(fluid: &Fluid, inertia_density: f64) -> f64 {
    4.5 * (fluid.density * fluid.viscosity / std::f64::consts::PI).sqrt() / inertia_density
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernel_with_its_short_term_matches_the_area_under_one_over_root_t() {
        let k = MemoryKernel::new(1.0, 1e-4);
        let shortest = SHORTEST_LAG;
        // ∫_0^T of the kernel is 2√T within the tolerance for every T well above the
        // shortest lag, thanks to D.
        for t in [1e2 * shortest, 1e3 * shortest, 1e-6, 1e-3, 0.1, 1.0] {
            let area: f64 =
                k.sum.weights.iter().zip(&k.sum.rates).map(|(w, l)| w * -(-l * t).exp_m1() / l).sum();
            let rel = (area + k.short_weight - 2.0 * t.sqrt()).abs() / (2.0 * t.sqrt());
            assert!(rel < 2e-4, "T = {t}: {rel}");
        }
        assert!(k.short_weight > 0.0 && k.short_weight < 2.0 * (1e4 * shortest).sqrt());
    }

    #[test]
    fn default_kernel_has_37_modes_of_24_bytes_each() {
        let k = MemoryKernel::new(1.0, 1e-4);
        assert_eq!(k.modes(), 37);
        assert_eq!(k.bytes_per_particle(), 24 * k.modes());
    }

    #[test]
    fn bad_window_and_tolerance_are_refused_naming_the_key() {
        let bad = |window, tolerance| History { window, tolerance }.validated().unwrap_err().key;
        assert_eq!(bad(0.0, 1e-4), "window");
        assert_eq!(bad(f64::NAN, 1e-4), "window");
        assert_eq!(bad(1.0, 0.5), "tolerance");
        assert_eq!(bad(1.0, 0.0), "tolerance");
    }
}
