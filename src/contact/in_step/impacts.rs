//! The bounce rule applied inside the step: a track meets a wall, or two tracks meet; the
//! event is recorded and the tracks go on from the contact point.

use super::super::Ctx;
use super::track::{TOUCHING, Track};
use crate::contact::event::kinetic_energy;
use crate::contact::rules::friction::contact_velocity;
use crate::contact::{
    ContactEvent, Friction, LastingContact, Other, Outcome, PairBody, Spinning, pair_impact,
    tangential_impulse, wall_impact,
};
use crate::flight::{Motion, NO_MEMORY, Segment};
use crate::particles::{NO_WALL, Particles, State};
use crate::walls::{CREASE_TOUCHING, Surface, contact_part};
use glam::DVec3;

impl<'a, M: Motion> Ctx<'a, M> {
    /// Applies the bounce rule of docs/physics.md §5 to `tr` hitting wall `w` at time `t`.
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
        let mut impact = wall_impact(&self.kinds[tr.k], tr.d, &wall.material, self.fluid, self.rule, v, n);
        let m = self.inertia_of(tr.k, tr.d);
        let omega = self.spin_at(tr, t);
        let moment = self.moment_of(tr.k, tr.d);
        let body = Spinning { inv_mass: 1.0 / m, inv_moment: 1.0 / moment, radius: tr.r(), v, omega };
        let vn = (-v.dot(n)).max(0.0);
        // The wall is `b`, so the normal from the particle to it is `−n`.
        let slip = {
            let u = contact_velocity(&body, &Spinning::WALL, -n);
            u - u.dot(n) * n
        };
        let mut omega_after = omega;
        if self.rule.friction {
            // Walton's tangential impulse on top of the rule's normal one (its `e_t` is 1).
            let f = Friction::between(&self.kinds[tr.k].friction, &wall.material.friction);
            let tangential = tangential_impulse(&body, &Spinning::WALL, -n, vn, impact.eps, &f);
            let [(_, spin), _] = tangential.apply(&body, &Spinning::WALL, -n);
            impact.velocity += tangential.impulse / m;
            omega_after = spin;
        }
        let rotational = |w: DVec3| if self.flight.rotation() { kinetic_energy(moment, w) } else { 0.0 };
        events.push(ContactEvent {
            time: t,
            id: p.id[tr.i],
            other: Other::Wall(w as u32),
            normal_speed: vn,
            tangential_speed: slip.length(),
            incidence_angle: (v - v.dot(n) * n).length().atan2(vn),
            st: impact.st,
            eps: impact.eps,
            contact_time: impact.contact_time,
            outcome: impact.outcome,
            energy_before: kinetic_energy(m, v) + rotational(omega),
            energy_after: kinetic_energy(m, impact.velocity) + rotational(omega_after),
        });
        debug_assert!(
            events.last().is_some_and(ContactEvent::energy_not_gained_if_finite),
            "{:?}",
            events.last()
        );
        if self.flight.rotation() {
            Self::set_spin(tr, omega_after, t, xc);
        }
        let w = w as u32;
        // Every path after a contact starts with an empty memory (docs/physics.md §10).
        let memory = NO_MEMORY;
        let seg = match impact.outcome {
            // A particle resting on another wall that rebounds along it or into it (a bead
            // sliding on a floor into a side wall, or down a cone into a column wall) has not
            // left it: it slides on, rather than landing on it again at once.
            Outcome::Bounced if self.stays_on_its_wall(tr, w, xc, impact.velocity) => {
                let own = tr.seg.wall;
                Segment { t, x: xc, v: impact.velocity, state: State::Resting, wall: own, memory }
            }
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

    /// Whether `tr`, resting on a wall other than `w` and rebounding off `w` at `x` with
    /// velocity `v`, does not leave its own wall (`v` along it or into it, to round-off).
    fn stays_on_its_wall(&self, tr: &Track<M>, w: u32, x: DVec3, v: DVec3) -> bool {
        if tr.seg.state != State::Resting || tr.seg.wall == w {
            return false;
        }
        let own = &self.walls()[tr.seg.wall as usize].shape;
        let g = own.gap(x, tr.r());
        g.gap <= CREASE_TOUCHING * tr.r() && v.dot(g.normal) <= 1e-12 * v.length()
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
        let mut imp = pair_impact(&body(a, ma, va), &body(b, mb, vb), n, self.fluid, self.rule);
        // Put them exactly in contact, moving each in proportion to the other's inertia.
        let overlap = a.r() + b.r() - (xb - xa).length();
        let (wa, wb) = (1.0 / ma, 1.0 / mb);
        let (xa, xb) = (xa - n * overlap * wa / (wa + wb), xb + n * overlap * wb / (wa + wb));
        let (oa, ob) = (self.spin_at(a, t), self.spin_at(b, t));
        let moment = |tr: &Track<M>| if tr.immobile() { f64::INFINITY } else { self.moment_of(tr.k, tr.d) };
        let (ia, ib) = (moment(a), moment(b));
        let spinning = |tr: &Track<M>, w: f64, i: f64, v: DVec3, omega: DVec3| Spinning {
            inv_mass: w,
            inv_moment: 1.0 / i,
            radius: tr.r(),
            v,
            omega,
        };
        let (sa, sb) = (spinning(a, wa, ia, va, oa), spinning(b, wb, ib, vb, ob));
        let slip = {
            let u = contact_velocity(&sa, &sb, n);
            u - u.dot(n) * n
        };
        let (mut oa1, mut ob1) = (oa, ob);
        if self.rule.friction {
            // Walton's tangential impulse on top of the rule's normal one (its `e_t` is 1): on
            // the velocities after the impact, or, for a hold, on the relative velocity given
            // at release (the common velocity does not change).
            let f = Friction::between(&self.kinds[a.k].friction, &self.kinds[b.k].friction);
            let tangential = tangential_impulse(&sa, &sb, n, imp.normal_speed, imp.eps, &f);
            let j = tangential.impulse;
            [(_, oa1), (_, ob1)] = tangential.apply(&sa, &sb, n);
            if imp.outcome == Outcome::Held {
                imp.release_relative += j * (wa + wb);
            } else {
                imp.va += j * wa;
                imp.vb -= j * wb;
            }
        }
        // After a hold, the energy that counts is at release: the common velocity plus the
        // release's relative velocity shared in proportion to the inverse inertias.
        let (va1, vb1) = if imp.outcome == Outcome::Held {
            let s = wa + wb;
            (imp.va + imp.release_relative * (wa / s), imp.vb - imp.release_relative * (wb / s))
        } else {
            (imp.va, imp.vb)
        };
        let rotational = |i: f64, w: DVec3| if self.flight.rotation() { kinetic_energy(i, w) } else { 0.0 };
        let u = va - vb;
        events.push(ContactEvent {
            time: t,
            id: p.id[a.i],
            other: Other::Particle(p.id[b.i]),
            normal_speed: imp.normal_speed,
            tangential_speed: slip.length(),
            incidence_angle: (u - u.dot(n) * n).length().atan2(imp.normal_speed),
            st: imp.st,
            eps: imp.eps,
            contact_time: imp.contact_time,
            outcome: imp.outcome,
            energy_before: kinetic_energy(ma, va)
                + kinetic_energy(mb, vb)
                + rotational(ia, oa)
                + rotational(ib, ob),
            energy_after: kinetic_energy(ma, va1)
                + kinetic_energy(mb, vb1)
                + rotational(ia, oa1)
                + rotational(ib, ob1),
        });
        debug_assert!(
            events.last().is_some_and(ContactEvent::energy_not_gained_if_finite),
            "{:?}",
            events.last()
        );
        if self.flight.rotation() {
            if !a.immobile() {
                Self::set_spin(a, oa1, t, xa);
            }
            if !b.immobile() {
                Self::set_spin(b, ob1, t, xb);
            }
        }
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
