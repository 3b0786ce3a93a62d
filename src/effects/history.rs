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
/// `1/√t`, so older accelerations are under-weighted, then forgotten. Memory: 37 modes with
/// the defaults, stored as 28 (672 bytes) per particle at Δt = 8.77 µs ([`Fold`]).
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
        physics.features.add(Arc::new(Memory { numbers: 3 * kernel.stored_modes() }));
        physics.history = Some(kernel);
    }
}

/// Once the scene's time step `dt` (s) is known: the history kernel of `physics` (if any)
/// holds its fast modes folded for that step ([`MemoryKernel::fold_for_step`]), and the
/// memory feature's column is as wide as the memory it then stores.
pub fn fold_history_for_step(physics: &mut Physics, dt: f64) {
    if let Some(kernel) = &mut physics.history {
        kernel.fold_for_step(dt);
        physics.features.replace(Arc::new(Memory { numbers: 3 * kernel.stored_modes() }));
    }
}

/// The memory of the history force as a feature: a typed column of the store
/// ([`Particles::memory`], 3 × [`MemoryKernel::stored_modes`] numbers per particle) that the flight kernel reads in the
/// hot loop and writes the end of in `Next::memory` (the particle pass, and stage 4 for the
/// paths a contact restarted); the store commits it.
#[derive(Debug, Clone)]
struct Memory {
    /// Numbers per particle: 3 × [`MemoryKernel::stored_modes`].
    numbers: usize,
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
            p.memory = Column::try_new(self.numbers, 0.0, p.len())?;
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
    /// Once folded for a time step ([`MemoryKernel::fold_for_step`]): the modes that forget
    /// their start within one step, stored as two numbers per component.
    pub fold: Option<Fold>,
}

/// A mode forgets its start within a step of `dt` when `λ dt` is at least this: `e^{−40}` is
/// 4·10⁻¹⁸. Such modes are the ones a kernel folded for `dt` holds as `(A, B)` ([`Fold`]).
pub const FORGETS_IN_A_STEP: f64 = 40.0;

/// The stored form of a folded memory serves a segment of `h` when its slowest fast mode has
/// `λ h` at least this (`e^{−37}` is 8.5·10⁻¹⁷, below the round-off of the numbers it
/// multiplies): the whole steps, and a step shortened by less than 7 % to land on an output.
pub const FORGOTTEN_IN_A_SEGMENT: f64 = 37.0;

/// The fast modes of a kernel folded for a time step `dt`: those with `λ_k dt ≥ 40`, the last
/// of the sum (its rates rise along it), less as few as make the numbers stored per component
/// a multiple of four (the lane groups' width). A mode that forgets its start within the
/// segment it flies holds, at the segment's end, `F_k = A/λ_k − B/λ_k²` exactly (to
/// `e^{−λ_k h}`) when the acceleration is linear across it, with `A` the acceleration at the
/// end and `B` its slope: `h φ1(−λh) = 1/λ` and `h φ2(−λh) = 1/λ − 1/(λ² h)` there. So the memory
/// stores `A` and `B` in place of those modes (per component: the slow modes one by one, then
/// `A`, then `B`), and a whole step reads them as two modes of weights `Σ w_k/λ_k` and
/// `−Σ w_k/λ_k²` that forget their start (docs/physics.md §10.1). A segment the stored form does
/// not serve (a contact's, a film's sub-steps) expands them, `F_k = (A − B/λ_k)/λ_k`, and folds
/// its end back by the two moments `Σ w_k F_k` and `Σ w_k F_k/λ_k` (the first exact: it is all
/// a following whole step reads of them).
#[derive(Debug, Clone, PartialEq)]
pub struct Fold {
    /// The modes kept one by one: the first `slow` of the sum.
    pub slow: usize,
    /// `Σ w_k/λ_k` (s^½) over the fast modes: the weight of `A`.
    pub q1: f64,
    /// `Σ w_k/λ_k²` (s^{3/2}) over the fast modes: minus the weight of `B`.
    pub q2: f64,
    /// The slowest fast mode's rate (1/s).
    pub slowest: f64,
    /// `(A, B)` from the moments `(Σ w_k F_k, Σ w_k F_k/λ_k)`: the inverse of
    /// `[[q1, −q2], [q2, −q3]]`, `q3 = Σ w_k/λ_k³`.
    fit: [[f64; 2]; 2],
    /// `1/λ_k` and `w_k/λ_k` of the fast modes.
    inverse_rate: Vec<f64>,
    weight_over_rate: Vec<f64>,
}

impl MemoryKernel {
    /// The kernel for a window (s, > 0) and a tolerance within [`TOLERANCE_RANGE`].
    pub fn new(window: f64, tolerance: f64) -> Self {
        let shortest = SHORTEST_LAG * window;
        let sum = ExponentialSum::inverse_sqrt(shortest, window, tolerance);
        let t = 1e4 * shortest;
        let area: f64 = sum.weights.iter().zip(&sum.rates).map(|(w, l)| w * -(-l * t).exp_m1() / l).sum();
        MemoryKernel { window, tolerance, short_weight: 2.0 * t.sqrt() - area, sum, fold: None }
    }

    /// Number of modes of the sum.
    pub fn modes(&self) -> usize {
        self.sum.len()
    }

    /// Numbers stored per particle and per component: the modes, or, folded, the slow ones
    /// and `A`, `B` ([`Fold`]).
    pub fn stored_modes(&self) -> usize {
        self.fold.as_ref().map_or(self.modes(), |f| f.slow + 2)
    }

    /// Memory per particle (bytes): three numbers per stored mode.
    pub fn bytes_per_particle(&self) -> usize {
        self.stored_modes() * std::mem::size_of::<glam::DVec3>()
    }

    /// Folds the modes that forget their start within a step of `dt` (s) ([`Fold`]); none when
    /// fewer than three would fold (two numbers would then replace as many or more).
    pub fn fold_for_step(&mut self, dt: f64) {
        self.fold = None;
        let n = self.modes();
        let rates = &self.sum.rates;
        // Index 0 is the lumped slow tail; the rates rise from index 1 on.
        let mut fast = rates[1..].iter().rev().take_while(|&&l| l * dt >= FORGETS_IN_A_STEP).count();
        while fast >= 3 && !(n - fast + 2).is_multiple_of(4) {
            fast -= 1;
        }
        if fast < 3 {
            return;
        }
        let slow = n - fast;
        let q = |p: i32| -> f64 {
            let fast_modes = self.sum.weights[slow..].iter().zip(&rates[slow..]);
            fast_modes.map(|(w, l)| w / l.powi(p)).sum()
        };
        let (q1, q2, q3) = (q(1), q(2), q(3));
        // [[q1, −q2], [q2, −q3]]⁻¹; its determinant q2² − q1 q3 < 0 (Cauchy–Schwarz, the rates
        // differ).
        let det = q2 * q2 - q1 * q3;
        let fit = [[-q3 / det, q2 / det], [-q2 / det, q1 / det]];
        let inverse_rate: Vec<f64> = rates[slow..].iter().map(|l| 1.0 / l).collect();
        let weights = &self.sum.weights[slow..];
        let weight_over_rate = weights.iter().zip(&inverse_rate).map(|(w, i)| w * i).collect();
        self.fold = Some(Fold { slow, q1, q2, slowest: rates[slow], fit, inverse_rate, weight_over_rate });
    }

    /// The modes one by one (`full`, 3 × [`MemoryKernel::modes`] by component) from the memory
    /// as stored (`stored`, 3 × [`MemoryKernel::stored_modes`]).
    pub fn expand(&self, stored: &[f64], full: &mut [f64]) {
        let Some(f) = &self.fold else {
            full.copy_from_slice(stored);
            return;
        };
        let (n, w) = (self.modes(), f.slow + 2);
        for (s, o) in stored.chunks_exact(w).zip(full.chunks_exact_mut(n)) {
            o[..f.slow].copy_from_slice(&s[..f.slow]);
            let (a, b) = (s[f.slow], s[f.slow + 1]);
            for (o, &i) in o[f.slow..].iter_mut().zip(&f.inverse_rate) {
                *o = (a - b * i) * i;
            }
        }
    }

    /// The memory as stored from the modes one by one: [`MemoryKernel::expand`]'s inverse,
    /// exact for modes of the form `(A − B/λ_k)/λ_k`, the two moments of [`Fold`] otherwise.
    pub fn fold(&self, full: &[f64], stored: &mut [f64]) {
        let Some(f) = &self.fold else {
            stored.copy_from_slice(full);
            return;
        };
        let (n, w) = (self.modes(), f.slow + 2);
        for (o, s) in stored.chunks_exact_mut(w).zip(full.chunks_exact(n)) {
            o[..f.slow].copy_from_slice(&s[..f.slow]);
            let (mut m0, mut m1) = (0.0, 0.0);
            let fast = s[f.slow..].iter().zip(&self.sum.weights[f.slow..]).zip(&f.weight_over_rate);
            for ((&x, &w), &wi) in fast {
                m0 += w * x;
                m1 += wi * x;
            }
            o[f.slow] = f.fit[0][0] * m0 + f.fit[0][1] * m1;
            o[f.slow + 1] = f.fit[1][0] * m0 + f.fit[1][1] * m1;
        }
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

    /// The bench scenes' step.
    const BENCH_DT: f64 = 8.77e-6;

    fn folded(dt: f64) -> MemoryKernel {
        let mut k = MemoryKernel::new(1.0, 1e-4);
        k.fold_for_step(dt);
        k
    }

    #[test]
    fn folded_for_the_bench_step_the_default_kernel_stores_28_modes_a_multiple_of_four() {
        let k = folded(BENCH_DT);
        let f = k.fold.as_ref().expect("folded");
        assert_eq!((k.modes(), f.slow, k.stored_modes()), (37, 26, 28));
        assert_eq!(k.bytes_per_particle(), 28 * 24);
        assert!(k.sum.rates[f.slow..].iter().all(|&l| l * BENCH_DT >= FORGETS_IN_A_STEP));
        assert_eq!(f.slowest, k.sum.rates[f.slow]);
        // One more mode would forget its start too, but the stored numbers would be 27.
        assert!(k.sum.rates[f.slow - 1] * BENCH_DT >= FORGETS_IN_A_STEP);
        assert!(k.sum.rates[f.slow - 2] * BENCH_DT < FORGETS_IN_A_STEP);
        // A step so short that fewer than three modes forget it: nothing folds.
        let k = folded(1e-9);
        assert_eq!((k.fold.is_none(), k.stored_modes()), (true, 37));
    }

    /// Numbers of every sign and of the sizes a bead's memory has (`A` in m/s², `B` = slope).
    fn some_stored(k: &MemoryKernel) -> Vec<f64> {
        let w = k.stored_modes();
        (0..3 * w)
            .map(|i| match i % w {
                j if j == w - 2 => 9.81 * (1.0 - 0.3 * (i / w) as f64),
                j if j == w - 1 => -4.0e5 * (1.0 + (i / w) as f64),
                j => 1e-3 * ((j * 7919 % 997) as f64 - 498.0),
            })
            .collect()
    }

    #[test]
    fn a_memory_of_the_folded_form_expands_and_folds_back_to_itself() {
        let k = folded(BENCH_DT);
        let stored = some_stored(&k);
        let mut full = vec![0.0; 3 * k.modes()];
        k.expand(&stored, &mut full);
        let mut back = vec![0.0; stored.len()];
        k.fold(&full, &mut back);
        let w = k.stored_modes();
        for (i, (a, b)) in stored.iter().zip(&back).enumerate() {
            let tol = if i % w < w - 2 { 0.0 } else { 1e-11 * a.abs() };
            assert!((a - b).abs() <= tol, "number {i}: {a} folded back to {b}");
        }
    }

    #[test]
    fn folding_keeps_what_a_whole_step_reads_of_the_fast_modes_whatever_they_hold() {
        let k = folded(BENCH_DT);
        let f = k.fold.as_ref().expect("folded");
        let n = k.modes();
        // Modes of no particular form (a film's sub-steps, a contact's short segment).
        let full: Vec<f64> = (0..3 * n).map(|i| ((i * 104729 % 1009) as f64 - 500.0) * 1e-4).collect();
        let mut stored = vec![0.0; 3 * k.stored_modes()];
        k.fold(&full, &mut stored);
        for c in 0..3 {
            let s = &stored[c * (f.slow + 2)..(c + 1) * (f.slow + 2)];
            let fast = &full[c * n + f.slow..(c + 1) * n];
            let exact: f64 = fast.iter().zip(&k.sum.weights[f.slow..]).map(|(x, w)| w * x).sum();
            let read = f.q1 * s[f.slow] - f.q2 * s[f.slow + 1];
            assert!((read - exact).abs() <= 1e-12 * exact.abs(), "component {c}: {read} vs {exact}");
            assert_eq!(&s[..f.slow], &full[c * n..c * n + f.slow]);
        }
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
