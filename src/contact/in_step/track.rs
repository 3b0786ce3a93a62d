//! One particle's path through the step, as contacts reshape it, and when two paths (or a
//! path and a wall) first meet.

use super::super::Ctx;
use crate::contact::detect::end_of_step::detect_at_end;
use crate::contact::{ImpactLocation, locate_on_path};
use crate::flight::{Flight, Motion, NO_MEMORY, Segment};
use crate::particles::{Next, Particles, State};
use crate::walls::{Crease, Crossing, Surface, crease, parts_slid_along};
use glam::DVec3;

/// Gap (fraction of the radius) within which a part of a wall counts as touched at the start of
/// a path: far above the impact location's round-off (1e-13 of the radius), far below a real
/// gap.
pub(crate) const TOUCHING: f64 = 1e-9;

/// One particle's motion through the step: the segment since its last contact, and where that
/// segment ends at the end of the step.
pub(crate) struct Track<M: Motion> {
    /// Particle index.
    pub i: usize,
    pub k: usize,
    pub d: f64,
    pub field: M::Field<DVec3>,
    pub seg: Segment,
    pub end: Flight,
    /// The wall of a held or resting particle.
    pub wall: u32,
    /// Release time and velocity of a hold at a wall begun in the step.
    pub release: Option<(f64, DVec3)>,
    /// With rotation: the spin (rad/s) at time `spin_t` (s), from where the particle was then,
    /// `spin_x` (m) — the start of the step, or the last contact — relaxed from there by
    /// `Kernel::spin_after`.
    pub spin: DVec3,
    pub spin_t: f64,
    pub spin_x: DVec3,
}

impl<M: Motion> Track<M> {
    pub fn r(&self) -> f64 {
        0.5 * self.d
    }

    /// Held at a wall: immobile until released.
    pub fn immobile(&self) -> bool {
        self.seg.state == State::Held
    }
}

impl<'a, M: Motion> Ctx<'a, M> {
    /// The track of particle `i` for the step from `t0`, from stage 2's results `next`.
    pub(crate) fn track(&self, p: &Particles, next: &Next, i: usize, t0: f64) -> Track<M> {
        let (k, d) = (p.kind[i] as usize, p.diameter[i]);
        Track {
            i,
            k,
            d,
            field: self.flight.field(k, d),
            seg: Segment {
                t: t0.max(p.release_time[i]),
                x: p.pos[i],
                v: p.vel[i],
                state: p.state[i],
                wall: p.wall[i],
                // Released in this step: the path starts at the release, with an empty memory.
                memory: if p.release_time[i] > t0 { NO_MEMORY } else { i as u32 },
            },
            end: Flight { x: next.pos[i], v: next.vel[i], state: next.state[i] },
            wall: p.wall[i],
            release: None,
            spin: if self.flight.rotation() { p.omega.values()[i] } else { DVec3::ZERO },
            spin_t: t0,
            spin_x: p.pos[i],
        }
    }

    /// The spin of `tr` at time `t` (rad/s); zero without rotation.
    pub(crate) fn spin_at(&self, tr: &Track<M>, t: f64) -> DVec3 {
        self.flight.spin_after((tr.k, tr.d), tr.spin_x, tr.spin, t - tr.spin_t)
    }

    /// The spin of `tr` is `omega` from time `t` at `x` (a contact changed it).
    pub(crate) fn set_spin(tr: &mut Track<M>, omega: DVec3, t: f64, x: DVec3) {
        (tr.spin, tr.spin_t, tr.spin_x) = (omega, t, x);
    }

    /// Position and velocity of `tr` at time `t` on its current segment.
    pub(crate) fn at(&self, tr: &Track<M>, t: f64) -> (DVec3, DVec3) {
        let f = self.flight.fly(&tr.field, (tr.k, tr.r()), &tr.seg, t - tr.seg.t);
        (f.x, f.v)
    }

    /// Starts `tr` on a new segment `seg` and flies it to the end of the step, `t1`.
    pub(crate) fn restart(&self, tr: &mut Track<M>, seg: Segment, t1: f64) {
        tr.seg = seg;
        tr.end = self.flight.fly(&tr.field, (tr.k, tr.r()), &tr.seg, t1 - seg.t);
    }

    /// Inertia in the force balance (kg), ∞ for a particle held at a wall.
    pub(crate) fn inertia(&self, tr: &Track<M>) -> f64 {
        if tr.immobile() { f64::INFINITY } else { self.inertia_of(tr.k, tr.d) }
    }

    /// The first wall the track's path reaches before `t1`, and when.
    pub(crate) fn next_wall_event(&self, tr: &Track<M>, t1: f64) -> Option<(usize, f64)> {
        if tr.immobile() {
            return None;
        }
        let (seg, r, h) = (&tr.seg, tr.r(), t1 - tr.seg.t);
        // A resting particle rests against its wall and the others of its crease: the flight
        // kernel keeps it out of them.
        let crease = if seg.state == State::Resting {
            crease(self.walls(), seg.wall, seg.x, r)
        } else {
            Crease::default()
        };
        self.walls()
            .iter()
            .enumerate()
            .filter(|&(w, _)| {
                !(seg.state == State::Resting && (seg.wall == w as u32 || crease.contains(w as u32)))
            })
            .filter_map(|(w, wall)| {
                if !wall.shape.may_touch(seg.x, tr.end.x, r) {
                    return None;
                }
                if self.impact_location == ImpactLocation::EndOfStep {
                    let g = wall.shape.gap(tr.end.x, r);
                    return detect_at_end(g.gap, tr.end.v.dot(g.normal), t1).map(|t| (w, t));
                }
                let crossing = wall.shape.sweep(seg.x, tr.end.x, r)?;
                // The parts touched at the start and slid along are not where this contact is:
                // their zero gap would hide the part approached.
                let skip = if wall.shape.gap(seg.x, r).gap <= TOUCHING * r {
                    parts_slid_along(&wall.shape, (seg.x, tr.end.x), r, seg.v, TOUCHING * r)
                } else {
                    Vec::new()
                };
                let gap = |x: DVec3| wall.shape.gap_without(x, r, &skip).gap;
                let s = locate_on_path(|s| gap(self.at(tr, seg.t + s).0), h, crossing, gap(tr.end.x), r)?;
                Some((w, seg.t + s))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// When the paths of `a` and `b` first bring them into contact before `t1`.
    pub(crate) fn next_pair_event(&self, a: &Track<M>, b: &Track<M>, t1: f64) -> Option<f64> {
        if a.immobile() && b.immobile() {
            return None;
        }
        // A particle held at a wall is where it is whatever the time: its segment starts at its
        // release, which may be after this step, and must not delay the other's path.
        let start = |tr: &Track<M>| if tr.immobile() { f64::NEG_INFINITY } else { tr.seg.t };
        let t = start(a).max(start(b));
        if t >= t1 {
            return None;
        }
        let reach = a.r() + b.r();
        let p = self.at(a, t).0 - self.at(b, t).0;
        let q = (a.end.x - b.end.x) - p;
        let (qa, qb, qc) = (q.dot(q), p.dot(q), p.dot(p) - reach * reach);
        let crossing = if qc <= 0.0 {
            (qb < 0.0).then_some(Crossing { enter: 0.0, exit: 1.0 })?
        } else {
            let disc = qb * qb - qa * qc;
            if qb >= 0.0 || disc < 0.0 || qa == 0.0 {
                return None;
            }
            let enter = (-qb - disc.sqrt()) / qa;
            if enter > 1.0 {
                return None;
            }
            Crossing { enter, exit: ((-qb + disc.sqrt()) / qa).min(1.0) }
        };
        let gap = |s: f64| (self.at(a, t + s).0 - self.at(b, t + s).0).length() - reach;
        let end_gap = (a.end.x - b.end.x).length() - reach;
        locate_on_path(gap, t1 - t, crossing, end_gap, reach).map(|s| t + s)
    }
}
