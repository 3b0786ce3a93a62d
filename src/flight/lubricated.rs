//! **[ext]** Flight near a wall with the wall-lubrication effect (docs/physics.md §8): the drag is
//! anisotropic there (`λ⊥` normal to the wall, `λ∥` along it) and stiff (the normal relaxation
//! time `τ/λ⊥` falls to `τ h/a`), so the scene's integrator, whose force is one scalar rate, is
//! replaced for such particles by sub-steps of an exponential midpoint scheme written in the
//! wall's frame: each component's linear drag is integrated exactly with its rate frozen over
//! the sub-step (stable at any rate), and each sub-step changes the gap by at most
//! [`GAP_FRACTION`] of itself, so the frozen factor is accurate however thin the film. Particles
//! away from every wall never come here. With the history effect too, the sub-steps carry the
//! memory ([`Carried`]): the memory's force enters each sub-step's balance like the other
//! explicit forces, and the part of it that follows the sub-step's own acceleration as an
//! added inertia.

use super::Kernel;
use super::Motion;
use super::NonLinear;
use super::StepCoefficients;
use crate::effects::{LUBRICATION_RANGE, MemoryKernel, WallExcess, WallTable};
use crate::integrate::{ForceField, Linear, phi12, phi12_lanes};
use crate::numeric::lanes::{DVec3x4, F64x4, LANES, Real, Vector, each};
use crate::walls::{Surface, Wall};
use glam::DVec3;
use std::sync::Arc;

/// Largest change of the lubrication gap in one sub-step, as a fraction of the gap: the wall
/// factors then change by at most about 10 % over a sub-step (`λ⊥ ∝ 1/h` near contact).
pub const GAP_FRACTION: f64 = 0.1;

/// At most this many sub-steps in one flight (a guard; a bead crossing the whole range down to
/// a 1 µm film takes about 100).
const MAX_SUBSTEPS: u32 = 100_000;

/// What the kernel keeps for the effect, per particle kind.
pub(super) struct Lubrication {
    /// The wall terms ([`WallTable::excess`]).
    pub table: Arc<WallTable>,
    /// Each kind's roughness (m).
    pub kind_roughness: Vec<f64>,
    /// Each kind's inertia density far from walls, `ρp + C_M∞ ρ` (kg/m³).
    pub kind_inertia: Vec<f64>,
    /// `ρ` with the added-mass effect (the wall's image series raises the normal inertia by
    /// `(C_M(h) − 1/2) ρ`), 0 without it (kg/m³).
    pub added_density: f64,
}

/// The nearest wall seen through the lubrication: gap `h` (m, the surface gap plus both
/// roughnesses, so `h = h_r` at contact) and its unit normal towards the particle.
fn nearest(walls: &[Wall], x: DVec3, r: f64, kind_roughness: f64) -> Option<(f64, DVec3)> {
    let mut best: Option<(f64, DVec3)> = None;
    for w in walls {
        let g = w.shape.gap(x, r);
        let h = g.gap.max(0.0) + kind_roughness + w.material.roughness;
        if best.is_none_or(|b| h < b.0) {
            best = Some((h, g.normal));
        }
    }
    best
}

/// Whether a particle of radius `r` (m) at lubrication gap `gap` (m) from its nearest wall may
/// come within the effect's range of it in a flight of `h` (s), at `speed` (m/s) and with an
/// acceleration of size `accel` (m/s²): the move is at most `(2|v| + |a| h) h`.
fn may_reach(gap: f64, r: f64, speed: f64, accel: f64, h: f64) -> bool {
    gap - LUBRICATION_RANGE * r < (2.0 * speed + accel * h) * h
}

/// The frozen-coefficient linear acceleration of one state, split along the wall normal `n`:
/// of one particle, or of a lane group of four ([`Kernel::near_wall_lanes`]), with the same
/// operations.
#[derive(Clone, Copy)]
struct Split<V: Vector> {
    /// Explicit normal acceleration (m/s²) and normal drag rate (1/s), fluid normal speed.
    en: V::Real,
    rate_n: V::Real,
    un: V::Real,
    /// Explicit tangential acceleration, tangential rate, fluid tangential velocity.
    et: V,
    rate_t: V::Real,
    ut: V,
    /// The inertia far from walls over the normal inertia, `i∞ / i⊥` (1 without added mass):
    /// a force per unit of `i∞` moves the particle along `n` by this fraction of it.
    normal_share: V::Real,
}

impl<V: Vector> Split<V> {
    /// Exact solution of `v' = e + rate (u − v)` per component over `dt`, from `(x, v)`.
    #[inline(always)]
    fn step(&self, n: V, x: V, v: V, dt: f64) -> (V, V) {
        let (an, at) = self.parts(n, v);
        let (p1n, p2n) = phi12_lanes(self.rate_n * -dt);
        let (p1t, p2t) = phi12_lanes(self.rate_t * -dt);
        let x1 = x + v * dt + n * (an * p2n * dt * dt) + at * (p2t * dt * dt);
        let v1 = v + n * (an * p1n * dt) + at * (p1t * dt);
        (x1, v1)
    }

    /// The acceleration at velocity `v`: its normal component and its tangential part.
    #[inline(always)]
    fn parts(&self, n: V, v: V) -> (V::Real, V) {
        let vn = v.dot(n);
        let vt = v - n * vn;
        (self.en + self.rate_n * (self.un - vn), self.et + (self.ut - vt) * self.rate_t)
    }
}

impl Split<DVec3> {
    /// The same balance with the history force `−c (s + d a)` per unit of the inertia far
    /// from walls (docs/physics.md §10): `s` the memory's part (m/s^{3/2}), fixed, and `d`
    /// (s^½) the part that follows the acceleration `a` itself, an added inertia `c d`, which
    /// the normal direction shares by `i∞ / i⊥`.
    fn with_history(mut self, n: DVec3, c: f64, s: DVec3, d: f64) -> Split<DVec3> {
        let cn = c * self.normal_share;
        let sn = s.dot(n);
        let (gn, gt) = (1.0 / (1.0 + cn * d), 1.0 / (1.0 + c * d));
        self.en = (self.en - cn * sn) * gn;
        self.rate_n *= gn;
        self.et = (self.et - (s - sn * n) * c) * gt;
        self.rate_t *= gt;
        self
    }
}

/// The memory that the sub-steps carry with the history effect (docs/physics.md §10, §8): the
/// modes `F_k`, moved on sub-step by sub-step as [`super::remembered`] moves them over a
/// step, with the acceleration linear in time across each sub-step. A sub-step of the whole
/// step (most flights near a wall but not in its film are one) reads and moves the memory as
/// stored; a shorter one needs the modes one by one, expanded from it once
/// ([`MemoryKernel::expand`]) and folded back at the end ([`Carried::finish`]).
pub(super) struct Carried<'m> {
    /// Weights, rates and short-lag weight of the kernel.
    pub kernel: &'m MemoryKernel,
    /// The memory as stored, the flight's start on entry and its end once finished.
    pub stored: &'m mut [f64],
    /// The modes one by one, once expanded (empty before; unused when the kernel is not
    /// folded, whose memory is stored one by one).
    pub full: Vec<f64>,
    /// The particle's `c` (s^−½).
    pub c: f64,
    /// The coefficients of the whole step and of half of it, computed once per step, for the
    /// memory as stored and for the modes one by one: a flight of a whole step in one sub-step
    /// reads them instead of an exponential per mode.
    pub whole: (&'m StepCoefficients, &'m StepCoefficients),
    pub half: (&'m StepCoefficients, &'m StepCoefficients),
}

impl Carried<'_> {
    /// Whether the memory is still as stored (not expanded) and `co` serves it.
    fn stored_form(&self, co: &StepCoefficients) -> bool {
        self.full.is_empty() && co.serves_stored()
    }

    /// The modes one by one: the memory as stored when the kernel is not folded, else
    /// expanded from it on first use.
    fn modes(&mut self) -> &mut [f64] {
        if self.kernel.fold.is_none() {
            return self.stored;
        }
        if self.full.is_empty() {
            self.full = vec![0.0; 3 * self.kernel.modes()];
            self.kernel.expand(self.stored, &mut self.full);
        }
        &mut self.full
    }

    /// `(Σ w_k F_k, Σ w_k e^{−λ_k h/2} F_k)`, `h` the whole step: the memory's force at a
    /// sub-step's start, and at the middle of a sub-step of the whole step.
    fn now_and_at_half(&mut self) -> (DVec3, DVec3) {
        let half = self.half;
        if self.stored_form(half.0) {
            return half.0.memory_now_and_after(self.stored);
        }
        half.1.memory_now_and_after(self.modes())
    }

    /// The memory's force at `dt` into a sub-step, the modes' response inside it left out:
    /// `Σ w_k e^{−λ_k dt} F_k` (m/s^{3/2}), and the weight `D + Σ w_k dt φ1(−λ_k dt)` (s^½)
    /// with which an acceleration constant over those `dt` adds to it.
    fn ahead(&mut self, dt: f64) -> (DVec3, f64) {
        let kernel = self.kernel;
        let n = kernel.modes();
        let modes = self.modes();
        let (mut s, mut d) = (DVec3::ZERO, kernel.short_weight);
        for (k, (&w, &rate)) in kernel.sum.weights.iter().zip(&kernel.sum.rates).enumerate() {
            let z = -rate * dt;
            let (p1, _) = phi12(z);
            let f = DVec3::new(modes[k], modes[n + k], modes[2 * n + k]);
            s += f * (w * (1.0 + z * p1));
            d += w * dt * p1;
        }
        (s, d)
    }

    /// Moves the modes over a sub-step of `dt` in which the velocity changed by `dv`, taking
    /// the acceleration constant across it: `F_k ← e^{−λ_k dt} F_k + dv φ1(−λ_k dt)`. Not the
    /// sub-step's end-point accelerations: with the frozen stiff drag of a film, the start's
    /// balance pulls the velocity towards a quasi-steady value the sub-step reaches almost at
    /// once, so an acceleration read there is far from the mean and would be remembered as a
    /// jolt at every sub-step; `dv` is what the slip did.
    fn commit(&mut self, dv: DVec3, dt: f64) {
        let whole = self.whole;
        if dt == whole.1.h() {
            // A sub-step of the whole step: its coefficients are the step's.
            if self.stored_form(whole.0) {
                whole.0.move_on_by(self.stored, dv);
            } else {
                whole.1.move_on_by(self.modes(), dv);
            }
            return;
        }
        let kernel = self.kernel;
        let n = kernel.modes();
        let modes = self.modes();
        for (k, &rate) in kernel.sum.rates.iter().enumerate() {
            let z = -rate * dt;
            let (p1, _) = phi12(z);
            for c in 0..3 {
                let f = &mut modes[c * n + k];
                *f = *f * (1.0 + z * p1) + dv[c] * p1;
            }
        }
    }

    /// The memory as stored at the flight's end: the modes folded back if they were expanded.
    fn finish(self) {
        if !self.full.is_empty() {
            self.kernel.fold(&self.full, self.stored);
        }
    }
}

/// What the split force of a particle (or of a lane group) needs of it besides its state.
#[derive(Clone, Copy)]
struct Body<R> {
    /// Radius (m).
    r: R,
    /// The Stokes drag rate, `f(Re) = 1` (1/s): what the wall's excess multiplies.
    stokes_rate: R,
    /// The inertia density far from walls, `ρp + C_M∞ ρ` (kg/m³).
    i_inf: R,
}

/// The split force on a body at velocity `v` with lubrication gap along `n`, from the force
/// field's linearised acceleration `l` there and the wall's excess `ex` at that gap. The
/// Stokes part of the drag grows by the wall's excess, added to the law's `f(Re)`
/// (docs/physics.md §8: `f(Re) + λ − 1`, the film's flow being viscous whatever `Re`).
#[inline(always)]
fn split<V: Vector>(
    added_density: f64,
    body: &Body<V::Real>,
    l: &Linear<V>,
    v: V,
    n: V,
    ex: WallExcess<V::Real>,
) -> Split<V> {
    let i_n = body.i_inf + ex.added_mass * added_density;
    let share = body.i_inf / i_n;
    let vn = v.dot(n);
    // −½ (dm/dh) v_n² / m: the potential flow's energy as the normal added mass changes.
    let image = ex.added_mass_slope / body.r * (-0.5 * added_density) * vn * vn / i_n;
    let en = l.explicit.dot(n) * share + image;
    let un = l.u.dot(n);
    Split {
        en,
        rate_n: (l.inv_tau + body.stokes_rate * ex.normal) * share,
        un,
        et: l.explicit - n * l.explicit.dot(n),
        rate_t: l.inv_tau + body.stokes_rate * ex.parallel,
        ut: l.u - n * un,
        normal_share: share,
    }
}

/// Where a lane of [`Kernel::near_wall_lanes`] ends up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NearWall {
    /// No wall within reach in the step: the scene's integrator's flight stands.
    Away,
    /// Flown in one sub-step, to this state.
    Flown(DVec3, DVec3),
    /// It needs sub-steps (it crosses a tenth of its gap in the step): one at a time.
    Substeps,
}

impl<M: Motion> Kernel<'_, M> {
    /// [`split`] for a particle of kind `k`, radius `r`, at `(x, v)`, with lubrication gap `h`
    /// along `n`.
    fn split(
        &self,
        lub: &Lubrication,
        field: &M::Field<DVec3>,
        (k, r): (usize, f64),
        (x, v): (DVec3, DVec3),
        (h, n): (f64, DVec3),
    ) -> Split<DVec3> {
        let body =
            Body { r, stokes_rate: self.kind_drag_rate[k] / (4.0 * r * r), i_inf: lub.kind_inertia[k] };
        split(lub.added_density, &body, &field.eval(x, v), v, n, lub.table.excess(h / r))
    }

    /// Free flight of a particle of kind `k` and radius `r` over `h` (s) from `(x, v)` when a
    /// wall is within reach of it in the step; `None` when none is (the scene's integrator then
    /// moves it).
    pub(super) fn lubricated_flight(
        &self,
        lub: &Lubrication,
        field: &M::Field<DVec3>,
        (k, r): (usize, f64),
        (x, v): (DVec3, DVec3),
        h: f64,
    ) -> Option<(DVec3, DVec3)> {
        let start = nearest(self.walls, x, r, lub.kind_roughness[k])?;
        // Within reach at its speed alone, the acceleration (a force evaluation) is not needed.
        let within = may_reach(start.0, r, v.length(), 0.0, h)
            || may_reach(start.0, r, v.length(), field.eval(x, v).total(v).length(), h);
        within.then(|| self.substeps(lub, field, (k, r), (x, v), h, start, None))
    }

    /// [`Kernel::lubricated_flight`] of a lane group of four free particles near walls, of
    /// kinds `k` and diameters `d`, from `(x, v)` over `h` (s), under `field` (the lane
    /// group's, [`Kernel::field_lanes`]): the nearest walls and the reach test one lane at a
    /// time, then the flight of those a wall is within reach of in lane form when one sub-step
    /// takes each of them through the whole step (the common case away from the film: the
    /// bead crosses less than a tenth of its gap in a step). Lane for lane the same bits as
    /// [`Kernel::lubricated_flight`]; [`NearWall::Substeps`] for the lanes that need more
    /// sub-steps. Without the effect, every lane is [`NearWall::Substeps`].
    #[inline(always)]
    pub fn near_wall_lanes(
        &self,
        field: &M::Field<DVec3x4>,
        (k, d): ([u16; LANES], F64x4),
        (x, v): ([DVec3; LANES], [DVec3; LANES]),
        h: f64,
    ) -> [NearWall; LANES] {
        let Some(NonLinear::Lubrication(lub)) = &self.nonlinear else {
            return [NearWall::Substeps; LANES];
        };
        let r = d * 0.5;
        let walls =
            each([0, 1, 2, 3], |i| nearest(self.walls, x[i], r.0[i], lub.kind_roughness[k[i] as usize]));
        let (xs, vs) = (DVec3x4::from_array(x), DVec3x4::from_array(v));
        let l0 = field.eval(xs, vs);
        let speed = vs.length_squared().map(f64::sqrt);
        let accel = l0.total(vs).length_squared().map(f64::sqrt);
        let mut fate = [NearWall::Away; LANES];
        let mut any = false;
        for i in 0..LANES {
            let Some((g, n)) = walls[i] else { continue };
            let (r, speed) = (r.0[i], speed.0[i]);
            if may_reach(g, r, speed, 0.0, h) || may_reach(g, r, speed, accel.0[i], h) {
                // One sub-step for the whole step unless the normal speed crosses a tenth of
                // the gap in it ([`Kernel::substeps`]' first choice of its length).
                let one = h > 0.0 && v[i].dot(n).abs() * h <= GAP_FRACTION * g;
                fate[i] = if one { NearWall::Flown(x[i], v[i]) } else { NearWall::Substeps };
                any |= one;
            }
        }
        if !any {
            return fate;
        }
        // The lanes away from walls or left to the sub-steps go along with harmless values.
        let walls = each(walls, |w| w.unwrap_or((1.0, DVec3::Z)));
        let (g, n) = (F64x4(each(walls, |w| w.0)), DVec3x4::from_array(each(walls, |w| w.1)));
        let body = Body {
            r,
            stokes_rate: F64x4(each(k, |k| self.kind_drag_rate[k as usize])) / (r * 4.0 * r),
            i_inf: F64x4(each(k, |k| lub.kind_inertia[k as usize])),
        };
        let s0 = split(lub.added_density, &body, &l0, vs, n, lub.table.excess_lanes(g / r));
        let (xm, vm) = s0.step(n, xs, vs, 0.5 * h);
        // The gap at the midpoint, as [`Kernel::substeps`]' `gap_at(xm).max(1e-3 g)`.
        let to_mid = (xm - xs).dot(n);
        let gm = F64x4(each([0, 1, 2, 3], |i| (g.0[i] + to_mid.0[i]).max(0.0).max(1e-3 * g.0[i])));
        let sm = split(lub.added_density, &body, &field.eval(xm, vm), vm, n, lub.table.excess_lanes(gm / r));
        let (x1, v1) = sm.step(n, xs, vs, h);
        let moved = (x1 - xs).dot(n);
        let (x1, v1) = (x1.to_array(), v1.to_array());
        for i in 0..LANES {
            if let NearWall::Flown(..) = fate[i] {
                // The sub-step's check of its gap change: failed, it is halved, one at a time.
                fate[i] = if moved.0[i].abs() <= GAP_FRACTION * g.0[i] {
                    NearWall::Flown(x1[i], v1[i])
                } else {
                    NearWall::Substeps
                };
            }
        }
        fate
    }

    /// The nearest wall, lubrication gap and normal, when the particle may come within the
    /// effect's range of it in a flight of `h` (s) (its speed and its acceleration's size
    /// `accel`, m/s², bound the move).
    pub(super) fn wall_in_reach(
        &self,
        lub: &Lubrication,
        (k, r): (usize, f64),
        (x, v): (DVec3, DVec3),
        accel: f64,
        h: f64,
    ) -> Option<(f64, DVec3)> {
        let start = nearest(self.walls, x, r, lub.kind_roughness[k])?;
        may_reach(start.0, r, v.length(), accel, h).then_some(start)
    }

    /// The sub-steps of a flight of `h` (s) from `(x, v)` near a wall (`start`, from
    /// [`Kernel::wall_in_reach`]); with `memory`, the history force acts too and its modes are
    /// carried along (each sub-step as [`super::remembered`] takes a whole step, in the wall's
    /// frame, the drag integrated exactly as here).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn substeps(
        &self,
        lub: &Lubrication,
        field: &M::Field<DVec3>,
        (k, r): (usize, f64),
        (x, v): (DVec3, DVec3),
        h: f64,
        start: (f64, DVec3),
        mut memory: Option<Carried>,
    ) -> (DVec3, DVec3) {
        let rough = lub.kind_roughness[k];
        let (mut x, mut v, mut t) = (x, v, 0.0);
        let mut count = 0;
        while t < h && count < MAX_SUBSTEPS {
            // The first sub-step starts where the nearest wall was just found.
            let (g, n) = if count == 0 {
                start
            } else {
                nearest(self.walls, x, r, rough).unwrap_or((f64::INFINITY, DVec3::Z))
            };
            count += 1;
            let rem = h - t;
            let gap_at = |y: DVec3| (g + (y - x).dot(n)).max(0.0);
            let mut s0 = self.split(lub, field, (k, r), (x, v), (g, n));
            // With memory: its force now, and half a step on (what a sub-step of the whole
            // step reads at its middle), in one sweep over the modes.
            let mut at_half = DVec3::ZERO;
            if let Some(m) = &mut memory {
                let now;
                (now, at_half) = m.now_and_at_half();
                s0 = s0.with_history(n, m.c, now, m.kernel.short_weight);
            }
            let vn = v.dot(n).abs();
            let mut dt = if vn * rem > GAP_FRACTION * g { GAP_FRACTION * g / vn } else { rem };
            // Shrink until the gap changes by at most GAP_FRACTION (the force may speed the
            // particle up within the sub-step); the last resort is the guard's share of h.
            let floor = h / MAX_SUBSTEPS as f64;
            let (x1, v1) = loop {
                let (xm, vm) = s0.step(n, x, v, 0.5 * dt);
                let mut sm = self.split(lub, field, (k, r), (xm, vm), (gap_at(xm).max(1e-3 * g), n));
                if let Some(m) = &mut memory {
                    let (s, d) = if 0.5 * dt == m.half.1.h() {
                        (at_half, m.kernel.short_weight + m.half.1.response())
                    } else {
                        m.ahead(0.5 * dt)
                    };
                    sm = sm.with_history(n, m.c, s, d);
                }
                let (x1, v1) = sm.step(n, x, v, dt);
                if (x1 - x).dot(n).abs() <= GAP_FRACTION * g || dt <= floor {
                    break (x1, v1);
                }
                dt = (0.5 * dt).max(floor);
            };
            if let Some(m) = &mut memory {
                m.commit(v1 - v, dt);
            }
            (x, v, t) = (x1, v1, t + dt);
            if dt >= rem {
                break;
            }
        }
        if let Some(m) = memory {
            m.finish();
        }
        (x, v)
    }
}
