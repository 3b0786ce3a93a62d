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
use super::StepCoefficients;
use crate::effects::{LUBRICATION_RANGE, MemoryKernel, WallTable};
use crate::integrate::{ForceField, phi12};
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

/// The frozen-coefficient linear acceleration of one state, split along the wall normal `n`.
#[derive(Clone, Copy)]
struct Split {
    /// Explicit normal acceleration (m/s²) and normal drag rate (1/s), fluid normal speed.
    en: f64,
    rate_n: f64,
    un: f64,
    /// Explicit tangential acceleration, tangential rate, fluid tangential velocity.
    et: DVec3,
    rate_t: f64,
    ut: DVec3,
    /// The inertia far from walls over the normal inertia, `i∞ / i⊥` (1 without added mass):
    /// a force per unit of `i∞` moves the particle along `n` by this fraction of it.
    normal_share: f64,
}

impl Split {
    /// Exact solution of `v' = e + rate (u − v)` per component over `dt`, from `(x, v)`.
    fn step(&self, n: DVec3, x: DVec3, v: DVec3, dt: f64) -> (DVec3, DVec3) {
        let (an, at) = self.parts(n, v);
        let (p1n, p2n) = phi12(-self.rate_n * dt);
        let (p1t, p2t) = phi12(-self.rate_t * dt);
        let x1 = x + v * dt + n * (an * p2n * dt * dt) + at * (p2t * dt * dt);
        let v1 = v + n * (an * p1n * dt) + at * (p1t * dt);
        (x1, v1)
    }

    /// The acceleration at velocity `v`: its normal component and its tangential part.
    fn parts(&self, n: DVec3, v: DVec3) -> (f64, DVec3) {
        let vn = v.dot(n);
        let vt = v - vn * n;
        (self.en + self.rate_n * (self.un - vn), self.et + (self.ut - vt) * self.rate_t)
    }

    /// The same balance with the history force `−c (s + d a)` per unit of the inertia far
    /// from walls (docs/physics.md §10): `s` the memory's part (m/s^{3/2}), fixed, and `d`
    /// (s^½) the part that follows the acceleration `a` itself, an added inertia `c d`, which
    /// the normal direction shares by `i∞ / i⊥`.
    fn with_history(mut self, n: DVec3, c: f64, s: DVec3, d: f64) -> Split {
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
/// step, with the acceleration linear in time across each sub-step.
pub(super) struct Carried<'m> {
    /// Weights, rates and short-lag weight of the kernel.
    pub kernel: &'m MemoryKernel,
    /// The modes, at the start of the flight on entry and at its end on return (by
    /// component, as [`crate::particles::Particles::memory`] holds them).
    pub modes: &'m mut [f64],
    /// The particle's `c` (s^−½).
    pub c: f64,
    /// The coefficients of the whole step and of half of it, computed once per step: a flight
    /// of a whole step in one sub-step (most of those near a wall but not in its film) reads
    /// them instead of an exponential per mode.
    pub whole: &'m StepCoefficients,
    pub half: &'m StepCoefficients,
}

impl Carried<'_> {
    /// The memory's force at `dt` into a sub-step, the modes' response inside it left out:
    /// `Σ w_k e^{−λ_k dt} F_k` (m/s^{3/2}), and the weight `D + Σ w_k dt φ1(−λ_k dt)` (s^½)
    /// with which an acceleration constant over those `dt` adds to it.
    fn ahead(&self, dt: f64) -> (DVec3, f64) {
        let n = self.kernel.modes();
        let (mut s, mut d) = (DVec3::ZERO, self.kernel.short_weight);
        for (k, (&w, &rate)) in self.kernel.sum.weights.iter().zip(&self.kernel.sum.rates).enumerate() {
            let z = -rate * dt;
            let (p1, _) = phi12(z);
            let f = DVec3::new(self.modes[k], self.modes[n + k], self.modes[2 * n + k]);
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
        if dt == self.whole.h() {
            // A sub-step of the whole step: its coefficients are the step's.
            self.whole.move_on_by(self.modes, dv);
            return;
        }
        let n = self.kernel.modes();
        for (k, &rate) in self.kernel.sum.rates.iter().enumerate() {
            let z = -rate * dt;
            let (p1, _) = phi12(z);
            for c in 0..3 {
                let f = &mut self.modes[c * n + k];
                *f = *f * (1.0 + z * p1) + dv[c] * p1;
            }
        }
    }
}

impl<M: Motion> Kernel<'_, M> {
    /// The split force on a particle of kind `k`, radius `r`, at `(x, v)`, with lubrication gap
    /// `h` along `n`. The Stokes part of the drag grows by the wall's excess, added to the law's
    /// `f(Re)` (docs/physics.md §8: `f(Re) + λ − 1`, the film's flow being viscous whatever `Re`).
    fn split(
        &self,
        lub: &Lubrication,
        field: &M::Field<DVec3>,
        (k, r): (usize, f64),
        (x, v): (DVec3, DVec3),
        (h, n): (f64, DVec3),
    ) -> Split {
        let l = field.eval(x, v);
        let ex = lub.table.excess(h / r);
        let stokes_rate = self.kind_drag_rate[k] / (4.0 * r * r);
        let i_inf = lub.kind_inertia[k];
        let i_n = i_inf + lub.added_density * ex.added_mass;
        let vn = v.dot(n);
        // −½ (dm/dh) v_n² / m: the potential flow's energy as the normal added mass changes.
        let image = -0.5 * lub.added_density * (ex.added_mass_slope / r) * vn * vn / i_n;
        let en = l.explicit.dot(n) * (i_inf / i_n) + image;
        let un = l.u.dot(n);
        Split {
            en,
            rate_n: (l.inv_tau + stokes_rate * ex.normal) * (i_inf / i_n),
            un,
            et: l.explicit - l.explicit.dot(n) * n,
            rate_t: l.inv_tau + stokes_rate * ex.parallel,
            ut: l.u - un * n,
            normal_share: i_inf / i_n,
        }
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
            if let Some(m) = &memory {
                let now;
                (now, at_half) = m.half.memory_now_and_after(m.modes, &m.kernel.sum.weights);
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
                if let Some(m) = &memory {
                    let (s, d) = if 0.5 * dt == m.half.h() {
                        (at_half, m.kernel.short_weight + m.half.response())
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
        (x, v)
    }
}
