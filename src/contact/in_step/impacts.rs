//! The bounce rule applied inside the step: a track meets a wall, or two tracks meet; the
//! event is recorded and the tracks go on from the contact point.

use super::super::Ctx;
use super::track::{TOUCHING, Track};
use crate::contact::event::kinetic_energy;
use crate::contact::{ContactEvent, LastingContact, Other, Outcome, PairBody, pair_impact, wall_impact};
use crate::flight::{Motion, NO_MEMORY, Segment};
use crate::particles::{NO_WALL, Particles, State};
use crate::walls::{Surface, contact_part};
use glam::DVec3;

impl<'a, M: Motion> Ctx<'a, M> {
    /// Applies the bounce rule of PHYSICS.md §5 to `tr` hitting wall `w` at time `t`.
    pub(crate) fn wall_event(
        &self,
        p: &Particles,
        tr: &mut Track<M>,
        (w, t): (usize, f64),
        t1: f64,
        events: &mut Vec<ContactEvent>,
    ) {
        let wall = &self.walls()[w];
        let (x, v) = self.at(tr, t);
        // Put on the wall along the nearest part; the bounce is off the part it approaches.
        let near = wall.shape.gap(x, tr.r());
        let xc = x - near.gap * near.normal;
        let n = contact_part(&wall.shape, x, tr.r(), v, TOUCHING * tr.r()).normal;
        let impact = wall_impact(&self.kinds[tr.k], tr.d, &wall.material, self.fluid, self.rule, v, n);
        let m = self.inertia_of(tr.k, tr.d);
        events.push(ContactEvent {
            time: t,
            id: p.id[tr.i],
            other: Other::Wall(w as u32),
            normal_speed: (-v.dot(n)).max(0.0),
            st: impact.st,
            eps: impact.eps,
            contact_time: impact.contact_time,
            outcome: impact.outcome,
            energy_before: kinetic_energy(m, v),
            energy_after: kinetic_energy(m, impact.velocity),
        });
        debug_assert!(
            events.last().is_some_and(ContactEvent::energy_not_gained_if_finite),
            "{:?}",
            events.last()
        );
        let w = w as u32;
        // Every path after a contact starts with an empty memory (PHYSICS.md §10).
        let memory = NO_MEMORY;
        let seg = match impact.outcome {
            Outcome::Bounced => {
                Segment { t, x: xc, v: impact.velocity, state: State::Free, wall: NO_WALL, memory }
            }
            Outcome::Deposited => {
                Segment { t, x: xc, v: impact.velocity, state: State::Resting, wall: w, memory }
            }
            Outcome::Held => {
                let t_release = t + impact.contact_time;
                tr.release = Some((t_release, impact.velocity));
                if t_release >= t1 {
                    Segment { t, x: xc, v: DVec3::ZERO, state: State::Held, wall: w, memory }
                } else {
                    let v = impact.velocity;
                    Segment { t: t_release, x: xc, v, state: State::Free, wall: NO_WALL, memory }
                }
            }
        };
        tr.wall = seg.wall;
        self.restart(tr, seg, t1);
    }

    /// Applies the pair rule to `a` and `b` (`a` the lower index) touching at time `t`; a
    /// lasting contact (hold or no rebound) is returned for the lasting-contact stage.
    pub(crate) fn pair_event(
        &self,
        p: &Particles,
        (a, b): (&mut Track<M>, &mut Track<M>),
        t: f64,
        t1: f64,
        events: &mut Vec<ContactEvent>,
    ) -> Option<LastingContact> {
        let ((xa, va), (xb, vb)) = (self.at(a, t), self.at(b, t));
        let n = (xb - xa).normalize_or(DVec3::Z);
        let (ma, mb) = (self.inertia(a), self.inertia(b));
        let body =
            |tr: &Track<M>, m: f64, v: DVec3| PairBody { kind: &self.kinds[tr.k], d: tr.d, inertia: m, v };
        let imp = pair_impact(&body(a, ma, va), &body(b, mb, vb), n, self.fluid, self.rule);
        // Put them exactly in contact, moving each in proportion to the other's inertia.
        let overlap = a.r() + b.r() - (xb - xa).length();
        let (wa, wb) = (1.0 / ma, 1.0 / mb);
        let (xa, xb) = (xa - n * overlap * wa / (wa + wb), xb + n * overlap * wb / (wa + wb));
        // After a hold, the energy that counts is at release: the common velocity plus the
        // release's relative velocity shared in proportion to the inverse inertias.
        let (va1, vb1) = if imp.outcome == Outcome::Held {
            let s = wa + wb;
            (imp.va + imp.release_relative * (wa / s), imp.vb - imp.release_relative * (wb / s))
        } else {
            (imp.va, imp.vb)
        };
        events.push(ContactEvent {
            time: t,
            id: p.id[a.i],
            other: Other::Particle(p.id[b.i]),
            normal_speed: imp.normal_speed,
            st: imp.st,
            eps: imp.eps,
            contact_time: imp.contact_time,
            outcome: imp.outcome,
            energy_before: kinetic_energy(ma, va) + kinetic_energy(mb, vb),
            energy_after: kinetic_energy(ma, va1) + kinetic_energy(mb, vb1),
        });
        debug_assert!(
            events.last().is_some_and(ContactEvent::energy_not_gained_if_finite),
            "{:?}",
            events.last()
        );
        // A particle on or held at a wall keeps that state; a free one is held with its partner.
        let state = |tr: &Track<M>| match (imp.outcome, tr.seg.state) {
            (_, State::Resting) => State::Resting,
            (_, State::Held) => State::Held,
            (Outcome::Held, _) => State::PairHeld,
            _ => State::Free,
        };
        let (sa, sb) = (state(a), state(b));
        for (tr, x, v, s) in [(&mut *a, xa, imp.va, sa), (&mut *b, xb, imp.vb, sb)] {
            let seg = if tr.immobile() {
                tr.seg
            } else {
                Segment { t, x, v, state: s, wall: tr.seg.wall, memory: NO_MEMORY }
            };
            self.restart(tr, seg, t1);
        }
        // Tracks are in index order, so `a` is the lower index and `n` points from a to b.
        let tangential = imp.release_relative + imp.eps * imp.normal_speed * n;
        let (ia, ib) = (a.i as u32, b.i as u32);
        match imp.outcome {
            Outcome::Bounced => None,
            Outcome::Deposited => Some(LastingContact::resting(ia, ib)),
            Outcome::Held => Some(LastingContact::held(
                ia,
                ib,
                t + imp.contact_time,
                imp.eps * imp.normal_speed,
                tangential,
            )),
        }
    }
}
