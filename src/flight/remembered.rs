//! **[ext]** Free flight with the history force (docs/physics.md §10): the Basset–Boussinesq memory
//! integral with its kernel a sum of exponentials, each mode one state per particle.
//!
//! With the slip `w = v − u` and the modes `F_k(t) = ∫ e^{−λ_k (t − s)} (dw/ds) ds`, the force
//! per unit inertia is `a_H = −c (Σ_k w_k F_k + D dw/dt)`, `c = K_H / m_eff` (s^−½). Over a
//! segment of length `h` the particle's acceleration is taken linear in time, from `a0` at its
//! start to `a1` at its end (the trapezoidal rule), and the rate of change of the slip is taken
//! as that acceleration (exact in quiescent and uniform flow). Then each mode moves on exactly,
//!
//! `F_k(h) = e^{−λ_k h} F_k(0) + a0 h φ1(−λ_k h) + (a1 − a0) h φ2(−λ_k h)`,
//!
//! and the force balance at the end is linear in `a1` once the drag rate is frozen at a
//! predicted end state: one solve, no iteration. `a0` needs no solve: the modes at the start
//! are known. The fast modes (`λ_k h ≫ 1`) follow the acceleration within the segment; the
//! slow ones carry the old accelerations. The scheme is second order on smooth motions and
//! A-stable in the drag (as `λ h → ∞` the velocity lands on the fluid's plus the terminal
//! slip), whatever the scene's integrator: with history, free flight is this scheme.
//!
//! The modes that forget their start within a step are stored folded, as the acceleration at
//! the end of the step and its slope ([`crate::effects::Fold`]): a whole step reads and writes
//! the memory as stored ([`StepCoefficients::stored`]); any other segment expands it, flies the
//! modes one by one, and folds its end back.

use super::lubricated::{Carried, Lubrication};
use super::{Kernel, Motion, NO_MEMORY, NonLinear, Segment};
use crate::effects::{FORGOTTEN_IN_A_SEGMENT, MemoryKernel};
use crate::integrate::{ForceField, Linear, phi12};
use crate::numeric::lane_sums::{
    Avx, component_sums, component_sums_of_four, component_update, component_update_of_four,
};
use crate::numeric::lanes::{DVec3x4, F64x4, LANES, Real, Vector, each};
use glam::DVec3;
use multiversion::{multiversion, target::selected_target};

/// What the kernel keeps for the history effect.
pub(super) struct Memory<'a> {
    /// The memory kernel (weights, rates, short-lag term).
    pub kernel: &'a MemoryKernel,
    /// Per kind, `c a` (m s^−½): [`crate::effects::history_rate_times_radius`].
    pub kind_rate: Vec<f64>,
    /// The memory of every particle at the start of the step, `3 × kernel.stored_modes()`
    /// numbers per particle, by component ([`crate::particles::Particles::memory`]).
    pub start: &'a [f64],
    /// The coefficients of a whole step (most segments are one) for the memory as stored
    /// ([`StepCoefficients::stored`]).
    pub step: StepCoefficients,
    /// The coefficients of a whole step for the modes one by one ([`StepCoefficients::new`]):
    /// the flights the stored form does not serve expand the memory.
    pub whole: StepCoefficients,
    /// With wall lubrication too: near a wall, the flight is its sub-steps, carrying the memory;
    /// with the coefficients of half a step, which a sub-step of a whole step reads at its
    /// middle, for the memory as stored and for the modes one by one.
    pub lubrication: Option<(Lubrication, (StepCoefficients, StepCoefficients))>,
}

/// The per-mode coefficients of a segment of length `h`, the same for every particle:
/// the weights `w_k`, `e^{−λ_k h}`, `h φ1(−λ_k h)`, `h φ2(−λ_k h)`, `w_k e^{−λ_k h}`, and
/// the sums `Σ w_k h φ1`, `Σ w_k h φ2` (s^½). Either for the modes one by one
/// ([`StepCoefficients::new`]), or for the memory as stored ([`StepCoefficients::stored`]),
/// whose last two modes are then a folded kernel's `A` and `B` ([`crate::effects::Fold`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StepCoefficients {
    h: f64,
    /// Whether these apply to the memory as stored (folded or not).
    stored: bool,
    weight: Vec<f64>,
    decay: Vec<f64>,
    phi1: Vec<f64>,
    phi2: Vec<f64>,
    weight_decayed: Vec<f64>,
    sum1: f64,
    sum2: f64,
}

impl StepCoefficients {
    /// The coefficients of `kernel`'s modes one by one for a segment of `h` (s).
    pub fn new(kernel: &MemoryKernel, h: f64) -> Self {
        Self::of_modes(kernel, kernel.modes(), h, kernel.fold.is_none())
    }

    /// The coefficients for the memory as stored over a segment of `h` (s): with a folded
    /// kernel whose fast modes forget their start within `h`, the slow modes one by one, then
    /// `A` (weight `q1`, moved on to `a0 + (a1 − a0)`) and `B` (weight `−q2`, moved on to
    /// `(a1 − a0)/h`), neither remembering its start; otherwise [`StepCoefficients::new`], which
    /// serves the stored memory only when the kernel is not folded.
    pub fn stored(kernel: &MemoryKernel, h: f64) -> Self {
        let Some(fold) = kernel.fold.as_ref().filter(|f| f.slowest * h >= FORGOTTEN_IN_A_SEGMENT) else {
            return Self::new(kernel, h);
        };
        let mut c = Self::of_modes(kernel, fold.slow, h, true);
        c.push(fold.q1, 0.0, 1.0, 1.0);
        c.push(-fold.q2, 0.0, 0.0, 1.0 / h);
        c
    }

    /// The coefficients of `kernel`'s first `n` modes over `h`.
    fn of_modes(kernel: &MemoryKernel, n: usize, h: f64, stored: bool) -> Self {
        let mut c = StepCoefficients {
            h,
            stored,
            weight: Vec::with_capacity(n + 2),
            decay: Vec::with_capacity(n + 2),
            phi1: Vec::with_capacity(n + 2),
            phi2: Vec::with_capacity(n + 2),
            weight_decayed: Vec::with_capacity(n + 2),
            sum1: 0.0,
            sum2: 0.0,
        };
        for (&w, &rate) in kernel.sum.weights[..n].iter().zip(&kernel.sum.rates[..n]) {
            let z = -rate * h;
            let (p1, p2) = phi12(z);
            // e^z = 1 + z φ1(z): no second exponential.
            c.push(w, 1.0 + z * p1, h * p1, h * p2);
        }
        c
    }

    /// Appends a mode of weight `w`, decay `e`, and `h φ1`, `h φ2`.
    fn push(&mut self, w: f64, e: f64, p1: f64, p2: f64) {
        self.weight.push(w);
        self.decay.push(e);
        self.phi1.push(p1);
        self.phi2.push(p2);
        self.weight_decayed.push(w * e);
        self.sum1 += w * p1;
        self.sum2 += w * p2;
    }

    /// Whether these serve the memory as stored ([`StepCoefficients::stored`]).
    pub(super) fn serves_stored(&self) -> bool {
        self.stored
    }

    /// The segment length `h` (s) these coefficients are for.
    pub(super) fn h(&self) -> f64 {
        self.h
    }

    /// `(Σ_k w_k F_k, Σ_k w_k e^{−λ_k h} F_k)` over a particle's modes `f` (by component).
    pub(super) fn memory_now_and_after(&self, f: &[f64]) -> (DVec3, DVec3) {
        mode_sums(f, &self.weight, &self.weight_decayed)
    }

    /// `Σ_k w_k h φ1(−λ_k h)` (s^½): how an acceleration constant over `h` adds to the memory.
    pub(super) fn response(&self) -> f64 {
        self.sum1
    }

    /// Moves the modes `f` (by component) over `h` in which the velocity changed by `dv`, the
    /// acceleration constant: `F_k ← e^{−λ_k h} F_k + (dv/h) h φ1(−λ_k h)`.
    pub(super) fn move_on_by(&self, f: &mut [f64], dv: DVec3) {
        let n = f.len() / 3;
        for (c, part) in f.chunks_exact_mut(n).enumerate() {
            let a = dv[c] / self.h;
            let (e, p1) = (&self.decay[..n], &self.phi1[..n]);
            for i in 0..n {
                part[i] = part[i] * e[i] + a * p1[i];
            }
        }
    }
}

/// `(Σ_k a_k F_k, Σ_k b_k F_k)` over a particle's modes `f` (its numbers of the memory): the
/// three components in one pass by lane groups of four ([`component_sums`]), the sums kept per
/// lane and added in a fixed order, so the result is the same on every target.
#[multiversion(targets("x86_64+avx2+fma"))]
fn mode_sums(f: &[f64], a: &[f64], b: &[f64]) -> (DVec3, DVec3) {
    let (sa, sb) = component_sums(f, (a, b), Avx::of(selected_target!()));
    (DVec3::from_array(sa), DVec3::from_array(sb))
}

/// The modes at the end of a segment, into `out`: `F_k(h) = e^{−λ_k h} F_k(0) + a0 h φ1 +
/// (a1 − a0) h φ2`, from `start` (empty for a memory that starts empty).
#[multiversion(targets("x86_64+avx2+fma"))]
fn modes_moved_on(co: &StepCoefficients, start: &[f64], a0: DVec3, da: DVec3, out: &mut [f64]) {
    let (e, p1, p2) = (&co.decay[..], &co.phi1[..], &co.phi2[..]);
    let avx = Avx::of(selected_target!());
    component_update(out, (start, e), (a0.to_array(), p1), (da.to_array(), p2), avx);
}

impl<M: Motion> Kernel<'_, M> {
    /// Free flight with memory of a particle of kind `k` and radius `r` over `h` (s) from the
    /// start of `seg`; with `out`, the memory at the end is written there.
    pub(super) fn remembered_flight(
        &self,
        mem: &Memory,
        field: &M::Field<DVec3>,
        (k, r): (usize, f64),
        seg: &Segment,
        h: f64,
        out: Option<&mut [f64]>,
    ) -> (DVec3, DVec3) {
        let kernel = mem.kernel;
        let width = 3 * kernel.stored_modes();
        let start: &[f64] = if seg.memory == NO_MEMORY {
            &[]
        } else {
            let i = seg.memory as usize * width;
            &mem.start[i..i + width]
        };
        let (x0, v0) = (seg.x, seg.v);
        let l0 = field.eval(x0, v0);
        let c = mem.kind_rate[k] / r;
        let near = match &mem.lubrication {
            Some((lub, half)) => self
                .wall_in_reach(lub, (k, r), (x0, v0), l0.total(v0).length(), h)
                .map(|wall| (lub, half, wall)),
            None => None,
        };
        if near.is_none() && h == mem.step.h && mem.step.stored {
            // A whole step away from walls: on the memory as stored.
            let co = &mem.step;
            let sums =
                if start.is_empty() { (DVec3::ZERO, DVec3::ZERO) } else { co.memory_now_and_after(start) };
            let end = segment_end(field, (x0, v0), &l0, sums, c, (kernel.short_weight, co));
            if let Some(out) = out {
                modes_moved_on(co, start, end.a0, end.a1 - end.a0, out);
            }
            return (end.x1, end.v1);
        }
        if let Some((lub, half, wall)) = near {
            // Near a wall: the lubricated sub-steps, with the memory carried along (in `out`, or
            // in a scratch copy when the caller keeps no memory).
            let mut scratch = Vec::new();
            let stored = match out {
                Some(out) => out,
                None => {
                    scratch.resize(width, 0.0);
                    &mut scratch[..]
                }
            };
            if start.is_empty() {
                stored.fill(0.0);
            } else {
                stored.copy_from_slice(start);
            }
            let (whole, half) = ((&mem.step, &mem.whole), (&half.0, &half.1));
            let carried = Carried { kernel, stored, full: Vec::new(), c, whole, half };
            return self.substeps(lub, field, (k, r), (x0, v0), h, wall, Some(carried));
        }
        // Otherwise the modes one by one: expanded from the memory as stored, and the end folded
        // back into it.
        let n = 3 * kernel.modes();
        let mut modes = vec![0.0; 2 * n];
        let (begin, end_modes) = modes.split_at_mut(n);
        if !start.is_empty() {
            kernel.expand(start, begin);
        }
        let owned;
        let co = if h == mem.whole.h {
            &mem.whole
        } else {
            owned = StepCoefficients::new(kernel, h);
            &owned
        };
        let begin: &[f64] = if start.is_empty() { &[] } else { begin };
        // Σ w_k F_k(0) and Σ w_k e^{−λ_k h} F_k(0): the old accelerations' force now and at h.
        let sums = if begin.is_empty() { (DVec3::ZERO, DVec3::ZERO) } else { co.memory_now_and_after(begin) };
        let end = segment_end(field, (x0, v0), &l0, sums, c, (kernel.short_weight, co));
        if let Some(out) = out {
            modes_moved_on(co, begin, end.a0, end.a1 - end.a0, end_modes);
            kernel.fold(end_modes, out);
        }
        (end.x1, end.v1)
    }

    /// [`Kernel::remembered_flight`] of a lane group of four free particles, `first` to
    /// `first + 3`, each flying the whole step of `h` (s) from its memory at the start of the
    /// step, and writing its memory at the end into its `width` numbers of `out`: the same
    /// operations lane by lane, so the same bits. Returns which lanes it flew and where they
    /// end. A lane within the wall lubrication's reach of a wall is left to the sub-steps, one
    /// at a time (not flown, its memory not written), and so is the whole group when `h` is not
    /// the step's (`None`). Always inlined, so that its lanes compile with the instruction set of
    /// the loop that calls it (and the ends are lanes, not an array of options, which went
    /// through memory by parts, `perf annotate`); `avx` says whether that loop's two sweeps over the
    /// modes may take AVX with FMA.
    #[inline(always)]
    pub fn remembered_lanes(
        &self,
        field: &M::Field<DVec3x4>,
        (k, d): ([u16; LANES], F64x4),
        (x0, v0): (DVec3x4, DVec3x4),
        (first, h): (usize, f64),
        out: &mut [f64],
        avx: Avx,
    ) -> Option<([bool; LANES], DVec3x4, DVec3x4)> {
        let Some(NonLinear::Memory(mem)) = &self.nonlinear else { return None };
        let co = &mem.step;
        if h != co.h || !co.stored {
            return None;
        }
        let width = 3 * mem.kernel.stored_modes();
        let r = d * 0.5;
        let l0 = field.eval(x0, v0);
        let mut flown = [true; LANES];
        if let Some((lub, _)) = &mem.lubrication {
            let accel = l0.total(v0).length_squared().map(f64::sqrt);
            let (x, v) = (x0.to_array(), v0.to_array());
            for i in 0..LANES {
                let (k, r) = (k[i] as usize, r.0[i]);
                flown[i] = self.wall_in_reach(lub, (k, r), (x[i], v[i]), accel.0[i], h).is_none();
            }
            if !flown.contains(&true) {
                return None;
            }
        }
        let starts = &mem.start[first * width..(first + LANES) * width];
        // The sums come as lanes, and the update takes them as lanes: the four beads' numbers
        // are not moved about between the sweeps and the lane group's balance.
        let (now, later) = component_sums_of_four(starts, (&co.weight, &co.weight_decayed), avx);
        let now = DVec3x4 { x: F64x4(now[0]), y: F64x4(now[1]), z: F64x4(now[2]) };
        let later = DVec3x4 { x: F64x4(later[0]), y: F64x4(later[1]), z: F64x4(later[2]) };
        let c = F64x4(each(k, |k| mem.kind_rate[k as usize])) / r;
        let end = segment_end(field, (x0, v0), &l0, (now, later), c, (mem.kernel.short_weight, co));
        let (a0, da) = (end.a0, end.a1 - end.a0);
        let (a0, da) = ([a0.x.0, a0.y.0, a0.z.0], [da.x.0, da.y.0, da.z.0]);
        let (e, p1, p2) = (&co.decay[..], &co.phi1[..], &co.phi2[..]);
        component_update_of_four(out, (starts, e), (a0, p1), (da, p2), flown, avx);
        Some((flown, end.x1, end.v1))
    }
}

/// Where a free flight with memory ends over a segment, for one particle or a lane group.
struct SegmentEnd<V> {
    /// The acceleration at the start (m/s²).
    a0: V,
    /// The acceleration at the end (m/s²).
    a1: V,
    /// The position at the end (m).
    x1: V,
    /// The velocity at the end (m/s).
    v1: V,
}

/// The force balance of a segment from `(x0, v0)`, where the force is `l0`, with the old
/// accelerations' force `(now, later)` (`Σ w_k F_k(0)` and `Σ w_k e^{−λ_k h} F_k(0)`), the
/// history rate `c` (s^−½), and the kernel's short-lag weight and the segment's coefficients
/// `co`: `a0` needs no solve, the drag rate and the fluid velocity are taken at a predicted end
/// (second order needs them to O(h²)), and the rest of the end's balance is linear in `a1`.
/// Written once for one particle and for four lanes, so both give the same bits.
#[inline(always)]
fn segment_end<V: Vector, F: ForceField<V>>(
    field: &F,
    (x0, v0): (V, V),
    l0: &Linear<V>,
    (now, later): (V, V),
    c: V::Real,
    (short_weight, co): (f64, &StepCoefficients),
) -> SegmentEnd<V> {
    let h = co.h;
    let inertia = V::Real::splat(1.0) + c * short_weight;
    let a0 = (l0.total(v0) - now * c) / inertia;
    let l1 = field.eval(x0 + v0 * h + a0 * (0.5 * h * h), v0 + a0 * h);
    let rate = l1.inv_tau;
    let rhs = l1.explicit + (l1.u - v0 - a0 * (0.5 * h)) * rate - later * c - a0 * (c * (co.sum1 - co.sum2));
    let a1 = rhs / (inertia + c * co.sum2 + rate * 0.5 * h);
    let v1 = v0 + (a0 + a1) * (0.5 * h);
    let x1 = x0 + v0 * h + (a0 * (1.0 / 3.0) + a1 * (1.0 / 6.0)) * (h * h);
    SegmentEnd { a0, a1, x1, v1 }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 8.77e-6;

    fn folded() -> MemoryKernel {
        let mut k = MemoryKernel::new(1.0, 1e-4);
        k.fold_for_step(DT);
        k
    }

    fn close(a: f64, b: f64, rel: f64, what: &str) {
        assert!((a - b).abs() <= rel * a.abs().max(b.abs()), "{what}: {a} vs {b}");
    }

    /// A mode that forgets its start within a whole step ends it as `(A − B/λ)/λ`, `A` the
    /// acceleration at the end and `B` its slope, whatever it held: what the fold stores.
    #[test]
    fn fast_modes_end_a_whole_step_as_the_acceleration_and_its_slope() {
        let k = folded();
        let f = k.fold.as_ref().expect("folded");
        let co = StepCoefficients::new(&k, DT);
        let (a0, da) = (DVec3::new(9.81, -3.0, 0.5), DVec3::new(-2.0, 0.25, 1e-3));
        let n = k.modes();
        let start: Vec<f64> = (0..3 * n).map(|i| 1e3 * ((i % 5) as f64 - 2.0)).collect();
        let mut end = vec![0.0; 3 * n];
        modes_moved_on(&co, &start, a0, da, &mut end);
        for c in 0..3 {
            let (a, b) = ((a0 + da)[c], da[c] / DT);
            for (j, &l) in k.sum.rates.iter().enumerate().skip(f.slow) {
                close(end[c * n + j], (a - b / l) / l, 1e-14, &format!("component {c}, mode {j}"));
            }
        }
    }

    /// The stored form of a folded memory reads and moves it as the modes one by one do: the
    /// same forces now and at the step's end, the same response to the step's own acceleration,
    /// and the same memory at the end, to round-off.
    #[test]
    fn the_stored_form_reads_and_moves_the_memory_as_the_modes_one_by_one() {
        let k = folded();
        let (stored_co, full_co) = (StepCoefficients::stored(&k, DT), StepCoefficients::new(&k, DT));
        assert!(stored_co.stored && !full_co.stored);
        assert_eq!(stored_co.weight.len(), k.stored_modes());
        let w = k.stored_modes();
        let stored: Vec<f64> = (0..3 * w)
            .map(|i| match i % w {
                j if j == w - 2 => 9.81 + i as f64,
                j if j == w - 1 => 3e4 * (i as f64 - 40.0),
                j => 1e-3 * ((j * 31 % 17) as f64 - 8.0),
            })
            .collect();
        let mut full = vec![0.0; 3 * k.modes()];
        k.expand(&stored, &mut full);
        let (now_s, later_s) = stored_co.memory_now_and_after(&stored);
        let (now_f, later_f) = full_co.memory_now_and_after(&full);
        for c in 0..3 {
            close(now_s[c], now_f[c], 1e-13, "now");
            close(later_s[c], later_f[c], 1e-13, "at the step's end");
        }
        close(stored_co.sum1, full_co.sum1, 1e-14, "Σ w h φ1");
        close(stored_co.sum2, full_co.sum2, 1e-14, "Σ w h φ2");
        let (a0, da) = (DVec3::new(1.0, -9.81, 0.2), DVec3::new(0.5, 0.05, -0.3));
        let mut end_stored = vec![0.0; stored.len()];
        modes_moved_on(&stored_co, &stored, a0, da, &mut end_stored);
        let mut end_full = vec![0.0; full.len()];
        modes_moved_on(&full_co, &full, a0, da, &mut end_full);
        let mut folded_back = vec![0.0; stored.len()];
        k.fold(&end_full, &mut folded_back);
        for (i, (a, b)) in end_stored.iter().zip(&folded_back).enumerate() {
            // `B` is a small part of each fast mode (B/λ against A): the fit gives it to fewer
            // digits, the modes themselves (below) to round-off.
            let rel = if i % w == w - 1 { 1e-9 } else { 1e-13 };
            close(*a, *b, rel, &format!("stored number {i}"));
        }
        let mut expanded = vec![0.0; full.len()];
        k.expand(&end_stored, &mut expanded);
        let n = k.modes();
        for (i, (a, b)) in expanded.iter().zip(&end_full).enumerate() {
            let c = i / n;
            let size = end_full[c * n..(c + 1) * n].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!((a - b).abs() <= 1e-13 * size, "mode {i}: {a} vs {b}");
        }
        // A step too short for the fast modes to forget their start: the modes one by one.
        assert!(!StepCoefficients::stored(&k, 0.3 * DT).stored);
        assert!(StepCoefficients::stored(&k, 0.35 * DT).stored);
    }
}
