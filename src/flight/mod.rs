//! The per-particle flight kernel: one particle (or a lane group of four) moved over a stretch
//! of a step under the scene's forces, with no contact in it.
//!
//! - [`Kernel`]: what a step's flight reads — the monomorphised [`Motion`] (integrator, drag
//!   law and flow, picked once per step by [`dispatch`]), each kind's constant acceleration and
//!   drag rate, and the walls a resting particle slides on;
//! - [`Segment`] → [`Kernel::fly`] → [`Flight`]: a stretch of a path, from a start state to
//!   where it ends, for a free particle (integrated), a resting one (slides along its wall) or
//!   a held one (stays);
//! - [`Kernel::free_flight`]: stage 2 of the step for one particle.
//!
//! This room knows no contact rule: the contact room above it asks it where a path goes.

mod lubricated;
mod motion;
mod remembered;
mod spin;

pub use lubricated::NearWall;
pub use motion::{Motion, Mover, StepFlow, WithMotion, dispatch};
pub use remembered::StepCoefficients;

use crate::effects::{MemoryKernel, Physics, history_rate_times_radius};
use crate::fluid::Fluid;
use crate::integrate::{Along, ForceField, Tangential};
use crate::numeric::lanes::{DVec3x4, F64x4, LANES, each};
use crate::particles::{ParticleKind, State};
use crate::walls::{
    CREASE_TOUCHING, Crease, FLAT_CREASE, Surface, Wall, crease, onto_crease, out_of_crease, push_out,
};
use glam::DVec3;

/// Gap (in particle radii) beyond which a sliding particle has lost its wall: it went over a
/// convex edge, or its neighbours lifted it. Below it the particle is put back on the wall. The
/// same hysteresis as for lasting pair contacts, so that a particle in a bed does not leave and
/// land again at every step.
const FALL_AWAY: f64 = 1e-3;

/// What the flight of one step reads: the motion compiled for the scene, and per particle kind
/// the constant acceleration and the drag rate (built once per step, looked up per particle).
pub struct Kernel<'a, M> {
    /// Integrator, drag law and flow, as one type.
    pub motion: &'a M,
    /// The walls (a resting particle slides on one).
    pub walls: &'a [Wall],
    kind_accel: Vec<DVec3>,
    kind_drag_rate: Vec<f64>,
    /// Per kind `G = (1 + C_M) ρ / (ρp + C_M ρ)` (fluid-acceleration effect); read only when
    /// the motion's flow [`Motion::ACCELERATES`].
    kind_fluid_gain: Vec<f64>,
    re_rate: f64,
    /// With an effect that is not one linearised force (wall lubrication, history) only: one
    /// field, so that a scene without them tests one `None` per flight, as before they existed.
    nonlinear: Option<NonLinear<'a>>,
    /// With rotation only (docs/physics.md §9).
    spin: Option<spin::Spin>,
    /// In a field flow on an unstructured grid only (empty otherwise): each particle's
    /// tetrahedron at the start of the step, where its flow lookups walk from
    /// ([`crate::particles::Particles::tet`]).
    tets: &'a [u32],
}

/// The effects the free flight cannot fold into the linearised force. With both, the memory
/// holds the lubrication ([`remembered::Memory::lubrication`]): near a wall the lubricated
/// sub-steps carry the memory.
enum NonLinear<'a> {
    Lubrication(lubricated::Lubrication),
    // Boxed: the memory's per-step coefficients make it several times the other's size.
    Memory(Box<remembered::Memory<'a>>),
}

/// The segment starts with an empty memory (after a contact or a release; docs/physics.md §10): the
/// value of [`Segment::memory`] that names no particle.
pub const NO_MEMORY: u32 = u32::MAX;

impl<'a, M: Motion> Kernel<'a, M> {
    /// The kernel of a step: `motion` from [`dispatch`], the effects' `physics` per kind, an
    /// unsteady flow read at `time` (s).
    pub fn new(
        motion: &'a M,
        physics: &Physics,
        fluid: &Fluid,
        kinds: &[ParticleKind],
        walls: &'a [Wall],
        time: f64,
    ) -> Self {
        let n = physics.kinds.len();
        let mu = fluid.viscosity;
        let table = physics.wall_lubrication.as_ref().filter(|_| physics.drag.is_some());
        let nonlinear = table.map(|table| {
            NonLinear::Lubrication(lubricated::Lubrication {
                table: table.clone(),
                kind_roughness: kinds.iter().map(|k| k.roughness).collect(),
                kind_inertia: physics.kinds.iter().map(|t| t.inertia_density).collect(),
                added_density: if physics.added_mass { fluid.density } else { 0.0 },
            })
        });
        Kernel {
            nonlinear,
            spin: spin::Spin::new(physics, fluid, kinds, time),
            motion,
            walls,
            kind_accel: (0..n).map(|k| physics.body_acceleration(k)).collect(),
            kind_drag_rate: (0..n).map(|k| physics.drag_rate(k, fluid)).collect(),
            kind_fluid_gain: (0..n).map(|k| physics.fluid_acceleration_gain(k, fluid)).collect(),
            re_rate: if mu > 0.0 { fluid.density / mu } else { 0.0 },
            tets: &[],
        }
    }

    /// With a field flow on an unstructured grid: the kernel's flow lookups for particle `i`
    /// walk from `tets[i]`, the tetrahedron that held it at the start of the step. The hint
    /// is not moved along with the integrator's stages: they evaluate the flow within one
    /// step's move of the start (a fraction of a cell at a stable step), a walk of a face or
    /// two, and the kernel's force fields are immutable values shared by the stages (`Copy`,
    /// read by the lane groups and the tracks alike). The end of the step finds the new one.
    pub fn walking_from(mut self, tets: &'a [u32]) -> Self {
        self.tets = tets;
        self
    }

    /// Whether the flow's lookups walk from remembered tetrahedra: the lane groups then give
    /// way to one particle at a time, each with its own start (a field's lookup is per point
    /// anyway, so the lanes bought nothing there).
    #[inline(always)]
    pub fn walks(&self) -> bool {
        M::HINTED && !self.tets.is_empty()
    }

    /// [`Kernel::field`] of particle `i` ([`Segment::memory`]'s index, or [`NO_MEMORY`]),
    /// its flow's lookups walking from its tetrahedron ([`Kernel::walking_from`]).
    #[inline(always)]
    pub fn field_of(&self, k: usize, d: f64, i: u32) -> M::Field<DVec3> {
        let field = self.field(k, d);
        if M::HINTED {
            let tet = self.tets.get(i as usize).copied().unwrap_or(crate::particles::NO_TET);
            M::hinted(field, tet)
        } else {
            field
        }
    }

    /// The force field of a particle of kind `k` and diameter `d` (m).
    #[inline(always)]
    pub fn field(&self, k: usize, d: f64) -> M::Field<DVec3> {
        let gain = if M::ACCELERATES { self.kind_fluid_gain[k] } else { 0.0 };
        self.motion.field(self.kind_accel[k], self.kind_drag_rate[k] / (d * d), self.re_rate * d, gain)
    }

    /// [`Kernel::field`] of a lane group: kinds `k`, diameters `d`.
    #[inline(always)]
    pub fn field_lanes(&self, k: [u16; LANES], d: F64x4) -> M::Field<DVec3x4> {
        let accel = DVec3x4::from_array(each(k, |k| self.kind_accel[k as usize]));
        let drag_rate = F64x4(each(k, |k| self.kind_drag_rate[k as usize]));
        let gain = if M::ACCELERATES {
            F64x4(each(k, |k| self.kind_fluid_gain[k as usize]))
        } else {
            F64x4([0.0; LANES])
        };
        self.motion.field(accel, drag_rate / (d * d), d * self.re_rate, gain)
    }

    /// Whether the scene has the wall-lubrication effect (with drag) and not the history effect:
    /// a particle that may come within its range of a wall then goes through [`Kernel::fly`],
    /// which looks for the wall. (With history, every particle goes through it anyway.)
    pub fn lubricated(&self) -> bool {
        matches!(self.nonlinear, Some(NonLinear::Lubrication(_)))
    }

    /// With the history effect: the kernel flies free particles with their memory, read from
    /// `start` (the memory at the start of the step, [`crate::particles::Particles::memory`]);
    /// `step` is the step's length `t1 − t0` (s), whose per-mode coefficients are computed once
    /// here. Without the effect, the kernel is returned unchanged.
    pub fn remembering(
        mut self,
        physics: &Physics,
        fluid: &Fluid,
        start: &'a [f64],
        kernel: Option<&'a MemoryKernel>,
        step: f64,
    ) -> Self {
        if let Some(kernel) = kernel {
            let lubrication = match self.nonlinear.take() {
                Some(NonLinear::Lubrication(lub)) => {
                    let half = 0.5 * step;
                    Some((lub, (StepCoefficients::stored(kernel, half), StepCoefficients::new(kernel, half))))
                }
                _ => None,
            };
            self.nonlinear = Some(NonLinear::Memory(Box::new(remembered::Memory {
                lubrication,
                kind_rate: physics
                    .kinds
                    .iter()
                    .map(|t| history_rate_times_radius(fluid, t.inertia_density))
                    .collect(),
                step: StepCoefficients::stored(kernel, step),
                whole: StepCoefficients::new(kernel, step),
                kernel,
                start,
            })));
        }
        self
    }

    /// Numbers of memory per particle (3 × stored modes, [`crate::particles::Particles::memory`])
    /// when the kernel flies with memory.
    pub fn memory_width(&self) -> Option<usize> {
        match &self.nonlinear {
            Some(NonLinear::Memory(m)) => Some(3 * m.kernel.stored_modes()),
            _ => None,
        }
    }

    /// [`Kernel::fly`] that also writes the memory at the segment's end into `out` (the
    /// particle's numbers of [`crate::particles::Particles::memory`]): zero unless the particle
    /// flies free (held and resting particles remember nothing). Only with the history effect;
    /// `out` is left alone otherwise.
    pub fn fly_remembering(
        &self,
        field: &M::Field<DVec3>,
        (k, r): (usize, f64),
        seg: &Segment,
        h: f64,
        out: &mut [f64],
    ) -> Flight {
        match (&self.nonlinear, seg.state) {
            (Some(NonLinear::Memory(mem)), State::Free | State::PairHeld) => {
                let (x, v) = self.remembered_flight(mem, field, (k, r), seg, h, Some(out));
                Flight { x, v, state: seg.state }
            }
            _ => {
                out.fill(0.0);
                self.fly(field, (k, r), seg, h)
            }
        }
    }

    /// Moves one segment on by `h` (s) under `field`, for a particle of kind `k` and radius `r`
    /// (m): free flight, sliding along its wall (resting), or nothing (held at a wall). With
    /// wall lubrication, a free particle near a wall flies by [`lubricated`]'s sub-steps.
    #[inline]
    pub fn fly(&self, field: &M::Field<DVec3>, (k, r): (usize, f64), seg: &Segment, h: f64) -> Flight {
        match seg.state {
            State::Held => Flight { x: seg.x, v: seg.v, state: State::Held },
            // A pair-held particle flies; the lasting-contact stage keeps the pair together.
            State::Free | State::PairHeld => {
                let near = match &self.nonlinear {
                    None => None,
                    Some(NonLinear::Lubrication(lub)) => {
                        self.lubricated_flight(lub, field, (k, r), (seg.x, seg.v), h)
                    }
                    Some(NonLinear::Memory(mem)) => {
                        Some(self.remembered_flight(mem, field, (k, r), seg, h, None))
                    }
                };
                let (x, v) = near.unwrap_or_else(|| self.motion.advance(field, seg.x, seg.v, h));
                Flight { x, v, state: seg.state }
            }
            State::Resting => {
                let n = self.walls[seg.wall as usize].shape.gap(seg.x, r).normal;
                // Touching other walls too (a crease of separate walls), it rests against
                // them as well: their contacts are not impacts again at every step.
                let crease = crease(self.walls, seg.wall, seg.x, r);
                if crease.is_empty() {
                    self.slide_on_wall(field, r, seg, h, n)
                } else {
                    self.slide_in_crease(field, r, seg, h, n, &crease)
                }
            }
        }
    }

    /// A resting particle slides along its wall, of normal `n` at the segment's start, under
    /// `field` for `h` (s); it is free once more than [`FALL_AWAY`] from it.
    fn slide_on_wall(&self, field: &M::Field<DVec3>, r: f64, seg: &Segment, h: f64, n: DVec3) -> Flight {
        let wall = &self.walls[seg.wall as usize].shape;
        let slide = Tangential { inner: field, n };
        let (x, v) = self.motion.advance(&slide, seg.x, seg.v - seg.v.dot(n) * n, h);
        let g = wall.gap(x, r);
        if g.gap > FALL_AWAY * r {
            Flight { x, v, state: State::Free }
        } else {
            let n1 = g.normal;
            let (x, v) = (x - g.gap * n1, v - v.dot(n1) * n1);
            // A resting particle ignores contacts with its own wall, so sliding along
            // one face must not take it through another face of that wall (into a box's
            // corner, across a mesh's crease): it stops there.
            let (x, v, _) = push_out(wall, x, v, r);
            Flight { x, v, state: State::Resting }
        }
    }

    /// A resting particle (on its wall, of normal `n`) that also touches the walls of `crease`
    /// at the segment's start: pressed into none of them (moving into one, or moving along it
    /// and pushed into it), it slides on its wall and is kept out of them; pressed into one, it
    /// slides along the crease line of the two and stays on both; pressed into more with no
    /// crease line leading away from the rest (a corner), it stops.
    fn slide_in_crease(
        &self,
        field: &M::Field<DVec3>,
        r: f64,
        seg: &Segment,
        h: f64,
        n: DVec3,
        crease: &Crease,
    ) -> Flight {
        let own = &self.walls[seg.wall as usize].shape;
        let v0 = seg.v - seg.v.dot(n) * n;
        let a0 = Tangential { inner: field, n }.eval(seg.x, v0).total(v0);
        // Beyond round-off: on a crease line both dot products are zero to the last bits.
        let (tol_v, tol_a) = (1e-12 * v0.length(), 1e-9 * a0.length());
        let into = |d: DVec3, m: DVec3| d.dot(m) < -tol_v.max(1e-12 * d.length());
        let pressed = |m: DVec3| {
            let vm = v0.dot(m);
            vm < -tol_v || (vm <= tol_v && a0.dot(m) < -tol_a)
        };
        let lines: Vec<(u32, DVec3)> = crease
            .iter()
            .filter(|&(_, m)| pressed(m))
            .filter_map(|(w, m)| {
                let t = n.cross(m);
                // Nearly one plane: sliding on its own wall keeps it out of the other.
                (t.length() >= FLAT_CREASE).then(|| (w, t.normalize()))
            })
            .collect();
        let keep_out = |x, v| out_of_crease(self.walls, seg.wall, crease, x, v, r);
        if lines.is_empty() && !crease.more {
            let f = self.slide_on_wall(field, r, seg, h, n);
            if f.state == State::Free {
                return f;
            }
            // Sliding away from the other walls, it may be turned back within the step (by its
            // weight) and reach one. Integrated through it and pushed back out afterwards, it
            // kept the speed gained below the crease, which it never descended: an energy gain
            // (docs/stability.md, R2-1). Instead it stops at the first instant it reaches one,
            // found by bisection, its velocity into the walls of the crease lost as in a
            // deposit, for the rest of the step.
            let inside = |f: &Flight| {
                crease
                    .iter()
                    .any(|(w, _)| self.walls[w as usize].shape.gap(f.x, r).gap < -CREASE_TOUCHING * r)
            };
            if f.state == State::Resting && inside(&f) {
                let (mut before, mut after) = (0.0, h);
                for _ in 0..52 {
                    let mid = 0.5 * (before + after);
                    if inside(&self.slide_on_wall(field, r, seg, mid, n)) {
                        after = mid;
                    } else {
                        before = mid;
                    }
                }
                let f = self.slide_on_wall(field, r, seg, before, n);
                let mut v = f.v;
                for (w, _) in crease.iter() {
                    let m = self.walls[w as usize].shape.gap(f.x, r).normal;
                    v -= v.dot(m).min(0.0) * m;
                }
                let (x, v) = keep_out(f.x, v);
                return Flight { x, v, state: State::Resting };
            }
            let (x, v) = keep_out(f.x, f.v);
            return Flight { x, v, state: State::Resting };
        }
        // The crease line whose motion (the velocity along it, or from rest the push along
        // it) goes into none of the other walls touched.
        let line = lines.iter().copied().find(|&(w, t)| {
            let along = v0.dot(t);
            let d = if along.abs() > tol_v { along * t } else { a0.dot(t) * t };
            crease.iter().filter(|&(o, _)| o != w).all(|(_, m)| !into(d, m))
        });
        let Some((w, t)) = line.filter(|_| !crease.more) else {
            // Wedged: at rest where it is.
            return Flight { x: seg.x, v: DVec3::ZERO, state: State::Resting };
        };
        let other = &self.walls[w as usize].shape;
        let (x, v) = self.motion.advance(&Along { inner: field, t }, seg.x, v0.dot(t) * t, h);
        if own.gap(x, r).gap > FALL_AWAY * r {
            return Flight { x, v, state: State::Free };
        }
        let (x, v) = if other.gap(x, r).gap > FALL_AWAY * r {
            // The other wall ended (a column's end, a baffle's rim): on its own wall alone.
            let g = own.gap(x, r);
            (x - g.gap * g.normal, v - v.dot(g.normal) * g.normal)
        } else {
            // Back onto both: the straight line leaves curved walls to second order.
            let (x, t1) = onto_crease(own, other, x, r);
            (x, v.dot(t1) * t1)
        };
        let (x, v) = keep_out(x, v);
        Flight { x, v, state: State::Resting }
    }

    /// Stage 2 for one particle of kind `k` and diameter `d` (m): from `max(t0, t_release)` to
    /// `t1`, starting at `(x, v)` in `state` on `wall`. A particle held at a wall stays.
    #[inline(always)]
    pub fn free_flight(&self, start: Segment, (k, d): (usize, f64), t1: f64) -> Flight {
        self.fly(&self.field_of(k, d, start.memory), (k, 0.5 * d), &start, t1 - start.t)
    }

    /// [`Kernel::free_flight`] writing the memory at `t1` into `out` ([`Kernel::fly_remembering`]).
    pub fn free_flight_remembering(
        &self,
        start: Segment,
        (k, d): (usize, f64),
        t1: f64,
        out: &mut [f64],
    ) -> Flight {
        self.fly_remembering(&self.field_of(k, d, start.memory), (k, 0.5 * d), &start, t1 - start.t, out)
    }

    /// The net acceleration (m/s²) of a particle of kind `k` and diameter `d` at `x` moving at
    /// `v` (the force balance alone, no contact).
    pub fn acceleration(&self, (k, d): (usize, f64), x: DVec3, v: DVec3) -> DVec3 {
        self.field(k, d).eval(x, v).total(v)
    }
}

/// A stretch of one particle's motion inside a step: from time `t` (s), state `(x, v)`, in
/// `state` on `wall` ([`crate::particles::NO_WALL`] when none).
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    /// Start time (s).
    pub t: f64,
    /// Position at `t` (m).
    pub x: DVec3,
    /// Velocity at `t` (m/s).
    pub v: DVec3,
    /// Free, held, pair-held or resting.
    pub state: State,
    /// The wall of a held or resting particle.
    pub wall: u32,
    /// With the history effect: the particle whose memory at the start of the step this
    /// segment continues (its index), or [`NO_MEMORY`] when the segment starts with an empty
    /// memory (after a contact or a release). Unused without the effect.
    pub memory: u32,
}

/// Where a segment ends.
#[derive(Debug, Clone, Copy)]
pub struct Flight {
    /// Position (m).
    pub x: DVec3,
    /// Velocity (m/s).
    pub v: DVec3,
    /// Free, held, pair-held or resting (a resting particle that slid off its wall is free).
    pub state: State,
}
