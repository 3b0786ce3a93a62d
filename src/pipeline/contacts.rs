//! Stages 4 and 5: every contact inside the step — with walls and between particles — is
//! located on the particles' curved paths, resolved by the bounce rule in time order, and the
//! rest of the step integrated from the contact point.
//!
//! Particles that may touch each other this step form *islands* (connected by candidate
//! pairs); a particle alone is an island of one. Each island is resolved sequentially, event
//! by event in time order; islands run in parallel and are written back in index order, so
//! the result does not depend on the thread count.

use super::events::kinetic_energy;
use super::{ContactEvent, Ctx, Flight, Motion, Other, Outcome, Segment, fly};
use crate::contact::end_of_step::detect_at_end;
use crate::contact::{ImpactLocation, PairBody, locate_on_path, pair_impact, wall_impact};
use crate::correlations::sphere_volume;
use crate::particles::{NO_WALL, PairContact, Particles, State};
use crate::walls::{Crossing, Surface};
use glam::DVec3;

/// Events resolved per particle of an island in one step before the rest is left to the
/// persistent-contact stage (only a jammed cluster with a huge step reaches it).
const MAX_EVENTS_PER_PARTICLE: usize = 32;

/// One particle's motion through the step, as events reshape it.
pub(crate) struct Track<F> {
    pub i: usize,
    k: usize,
    d: f64,
    field: F,
    pub seg: Segment,
    pub end: Flight,
    /// The wall of a held or resting particle.
    pub wall: u32,
    /// Release time and velocity of a hold at a wall.
    pub release: Option<(f64, DVec3)>,
}

impl<F> Track<F> {
    fn r(&self) -> f64 {
        0.5 * self.d
    }

    /// Held at a wall: immobile until released.
    fn immobile(&self) -> bool {
        self.seg.state == State::Held && self.seg.wall != NO_WALL
    }
}

/// What an island hands back.
pub(crate) struct IslandResult<F> {
    pub tracks: Vec<Track<F>>,
    pub events: Vec<ContactEvent>,
    pub contacts: Vec<PairContact>,
}

impl<'a, M: Motion> Ctx<'a, M> {
    /// The track of particle `i` for the step ending at `t1`, from stage 2's results.
    pub(crate) fn track(
        &self,
        p: &Particles,
        next: (&[DVec3], &[DVec3], &[State]),
        i: usize,
        t0: f64,
    ) -> Track<M::Field<DVec3>> {
        let (k, d) = (p.kind[i] as usize, p.diameter[i]);
        Track {
            i,
            k,
            d,
            field: self.field(k, d),
            seg: Segment {
                t: t0.max(p.release_time[i]),
                x: p.pos[i],
                v: p.vel[i],
                state: p.state[i],
                wall: p.wall[i],
            },
            end: Flight { x: next.0[i], v: next.1[i], state: next.2[i] },
            wall: p.wall[i],
            release: None,
        }
    }

    fn at(&self, tr: &Track<M::Field<DVec3>>, t: f64) -> (DVec3, DVec3) {
        let f = fly(self, &tr.field, tr.r(), &tr.seg, t - tr.seg.t);
        (f.x, f.v)
    }

    fn restart(&self, tr: &mut Track<M::Field<DVec3>>, seg: Segment, t1: f64) {
        tr.seg = seg;
        tr.end = fly(self, &tr.field, tr.r(), &tr.seg, t1 - seg.t);
    }

    /// Inertia in the force balance (kg), ∞ for a particle held at a wall.
    fn inertia(&self, tr: &Track<M::Field<DVec3>>) -> f64 {
        if tr.immobile() { f64::INFINITY } else { self.inertia_of(tr.k, tr.d) }
    }

    /// Inertia (kg) of a particle of kind `k` and diameter `d`: `(ρp + C_M ρ) π d³/6`.
    pub(crate) fn inertia_of(&self, k: usize, d: f64) -> f64 {
        self.inertia_density[k] * sphere_volume(d)
    }

    /// The first wall the track's path reaches before `t1`, and when.
    fn next_wall_event(&self, tr: &Track<M::Field<DVec3>>, t1: f64) -> Option<(usize, f64)> {
        if tr.immobile() {
            return None;
        }
        let (seg, r, h) = (&tr.seg, tr.r(), t1 - tr.seg.t);
        self.walls
            .iter()
            .enumerate()
            .filter(|&(w, _)| !(seg.state == State::Resting && seg.wall == w as u32))
            .filter_map(|(w, wall)| {
                if !wall.shape.may_touch(seg.x, tr.end.x, r) {
                    return None;
                }
                let gap = |x: DVec3| wall.shape.gap(x, r).gap;
                if self.impact_location == ImpactLocation::EndOfStep {
                    let g = wall.shape.gap(tr.end.x, r);
                    return detect_at_end(g.gap, tr.end.v.dot(g.normal), t1).map(|t| (w, t));
                }
                let crossing = wall.shape.sweep(seg.x, tr.end.x, r)?;
                let s = locate_on_path(|s| gap(self.at(tr, seg.t + s).0), h, crossing, gap(tr.end.x), r)?;
                Some((w, seg.t + s))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// When the paths of `a` and `b` first bring them into contact before `t1`.
    fn next_pair_event(
        &self,
        a: &Track<M::Field<DVec3>>,
        b: &Track<M::Field<DVec3>>,
        t1: f64,
    ) -> Option<f64> {
        if a.immobile() && b.immobile() {
            return None;
        }
        // A particle held at a wall is where it is whatever the time: its segment starts at its
        // release, which may be after this step, and must not delay the other's path.
        let start = |tr: &Track<M::Field<DVec3>>| if tr.immobile() { f64::NEG_INFINITY } else { tr.seg.t };
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

    /// Applies the bounce rule of PHYSICS.md §5 to `tr` hitting wall `w` at time `t`.
    fn wall_event(
        &self,
        p: &Particles,
        tr: &mut Track<M::Field<DVec3>>,
        w: usize,
        t: f64,
        t1: f64,
        events: &mut Vec<ContactEvent>,
    ) {
        let wall = &self.walls[w];
        let (x, v) = self.at(tr, t);
        let g = wall.shape.gap(x, tr.r());
        let (xc, n) = (x - g.gap * g.normal, g.normal);
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
        let seg = match impact.outcome {
            Outcome::Bounced => Segment { t, x: xc, v: impact.velocity, state: State::Free, wall: NO_WALL },
            Outcome::Deposited => Segment { t, x: xc, v: impact.velocity, state: State::Resting, wall: w },
            Outcome::Held => {
                let t_release = t + impact.contact_time;
                tr.release = Some((t_release, impact.velocity));
                if t_release >= t1 {
                    Segment { t, x: xc, v: DVec3::ZERO, state: State::Held, wall: w }
                } else {
                    Segment { t: t_release, x: xc, v: impact.velocity, state: State::Free, wall: NO_WALL }
                }
            }
        };
        tr.wall = seg.wall;
        self.restart(tr, seg, t1);
    }

    /// Applies the pair rule to `a` and `b` touching at time `t`; a persistent contact (hold or
    /// no rebound) is returned for the persistent-contact stage.
    #[allow(clippy::too_many_arguments)]
    fn pair_event(
        &self,
        p: &Particles,
        a: &mut Track<M::Field<DVec3>>,
        b: &mut Track<M::Field<DVec3>>,
        t: f64,
        t1: f64,
        events: &mut Vec<ContactEvent>,
    ) -> Option<PairContact> {
        let ((xa, va), (xb, vb)) = (self.at(a, t), self.at(b, t));
        let n = (xb - xa).normalize_or(DVec3::Z);
        let (ma, mb) = (self.inertia(a), self.inertia(b));
        let body = |tr: &Track<M::Field<DVec3>>, m: f64, v: DVec3| PairBody {
            kind: &self.kinds[tr.k],
            d: tr.d,
            inertia: m,
            v,
        };
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
        let state = |tr: &Track<M::Field<DVec3>>| match (imp.outcome, tr.seg.state) {
            (_, State::Resting) => State::Resting,
            (_, State::Held) if tr.immobile() => State::Held,
            (Outcome::Held, _) => State::Held,
            _ => State::Free,
        };
        let (sa, sb) = (state(a), state(b));
        for (tr, x, v, s) in [(&mut *a, xa, imp.va, sa), (&mut *b, xb, imp.vb, sb)] {
            let seg = if tr.immobile() { tr.seg } else { Segment { t, x, v, state: s, wall: tr.seg.wall } };
            self.restart(tr, seg, t1);
        }
        // Tracks are in index order, so `a` is the lower index and `n` points from a to b.
        let tangential = imp.release_relative + imp.eps * imp.normal_speed * n;
        let (ia, ib) = (a.i as u32, b.i as u32);
        match imp.outcome {
            Outcome::Bounced => None,
            Outcome::Deposited => Some(PairContact::resting(ia, ib)),
            Outcome::Held => {
                Some(PairContact::held(ia, ib, t + imp.contact_time, imp.eps * imp.normal_speed, tangential))
            }
        }
    }

    /// Resolves an island: `tracks` sorted by particle index, `pairs` as positions in `tracks`.
    ///
    /// Events wait in a priority queue by time; an event computed before one of its particles
    /// changed course is stale (its version is old) and skipped, and only the changed
    /// particles' events are recomputed — so a dense island costs in proportion to its events.
    pub(crate) fn resolve_island(
        &self,
        p: &Particles,
        mut tracks: Vec<Track<M::Field<DVec3>>>,
        pairs: &[[usize; 2]],
        t1: f64,
    ) -> IslandResult<M::Field<DVec3>> {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        let mut events = Vec::new();
        let mut contacts: Vec<PairContact> = Vec::new();
        let mut settled = vec![false; pairs.len()];
        let mut version = vec![0u32; tracks.len()];
        let mut pairs_of: Vec<Vec<usize>> = vec![Vec::new(); tracks.len()];
        for (q, &[a, b]) in pairs.iter().enumerate() {
            pairs_of[a].push(q);
            pairs_of[b].push(q);
        }
        // (time, kind: 0 wall / 1 pair, index, wall, versions): ordered, so ties resolve the
        // same way on every run.
        type Entry = (Reverse<Time>, u8, usize, usize, u32, u32);
        let mut queue: BinaryHeap<Entry> = BinaryHeap::new();
        let wall_entry = |tracks: &[Track<M::Field<DVec3>>], version: &[u32], k: usize| {
            self.next_wall_event(&tracks[k], t1).map(|(w, t)| (Reverse(Time(t)), 0, k, w, version[k], 0))
        };
        let pair_entry = |tracks: &[Track<M::Field<DVec3>>], version: &[u32], q: usize| {
            let [a, b] = pairs[q];
            self.next_pair_event(&tracks[a], &tracks[b], t1)
                .map(|t| (Reverse(Time(t)), 1, q, 0, version[a], version[b]))
        };
        for k in 0..tracks.len() {
            queue.extend(wall_entry(&tracks, &version, k));
        }
        for q in 0..pairs.len() {
            queue.extend(pair_entry(&tracks, &version, q));
        }
        let mut budget = MAX_EVENTS_PER_PARTICLE * tracks.len();
        while let Some((Reverse(Time(t)), kind, idx, w, va, vb)) = queue.pop() {
            let changed: Vec<usize> = if kind == 0 {
                if version[idx] != va {
                    continue;
                }
                self.wall_event(p, &mut tracks[idx], w, t, t1, &mut events);
                vec![idx]
            } else {
                let [a, b] = pairs[idx];
                if settled[idx] || version[a] != va || version[b] != vb {
                    continue;
                }
                let (lo, hi) = tracks.split_at_mut(b);
                if let Some(c) = self.pair_event(p, &mut lo[a], &mut hi[0], t, t1, &mut events) {
                    settled[idx] = true;
                    contacts.push(c);
                }
                vec![a, b]
            };
            budget -= 1;
            if budget == 0 {
                break;
            }
            for &k in &changed {
                version[k] += 1;
            }
            for &k in &changed {
                queue.extend(wall_entry(&tracks, &version, k));
                for &q in &pairs_of[k] {
                    if !settled[q] {
                        queue.extend(pair_entry(&tracks, &version, q));
                    }
                }
            }
        }
        IslandResult { tracks, events, contacts }
    }
}

/// A time with a total order, for the event queue.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Time(f64);

impl Eq for Time {}

impl PartialOrd for Time {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Time {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// Stages 4 and 5 for the whole step: islands from the broad phase's wall candidates and
/// candidate pairs, resolved in parallel, written back in index order. Returns true when a
/// particle's new state is not finite.
pub(crate) fn run<M: Motion>(
    ctx: &Ctx<M>,
    p: &mut Particles,
    t0: f64,
    t1: f64,
    scratch: &mut super::Scratch,
    events: &mut Vec<ContactEvent>,
    contacts: &mut Vec<PairContact>,
) -> bool {
    use rayon::prelude::*;
    let islands = islands(&scratch.candidates, &scratch.pair_candidates);
    let next = (&scratch.next_pos[..], &scratch.next_vel[..], &scratch.next_state[..]);
    let results: Vec<IslandResult<M::Field<DVec3>>> = islands
        .par_iter()
        .map(|(members, pairs)| {
            let tracks = members.iter().map(|&i| ctx.track(p, next, i, t0)).collect();
            ctx.resolve_island(p, tracks, pairs, t1)
        })
        .collect();
    let mut suspect = false;
    for r in results {
        for tr in r.tracks {
            let i = tr.i;
            let (x, v) = clear_of_walls(ctx, tr.end.x, tr.end.v, tr.r());
            suspect |= !(x.is_finite() && v.is_finite());
            scratch.next_pos[i] = x;
            scratch.next_vel[i] = v;
            scratch.next_state[i] = tr.end.state;
            p.wall[i] = if tr.end.state == State::Free { NO_WALL } else { tr.seg.wall };
            if let Some((t, v)) = tr.release {
                p.release_time[i] = t;
                p.release_vel[i] = v;
            }
        }
        events.extend(r.events);
        contacts.extend(r.contacts);
    }
    suspect
}

/// Pushes a particle that an event left inside a wall (only possible when an island ran out of
/// its event budget, or by round-off) back out, without velocity into the wall.
fn clear_of_walls<M: Motion>(ctx: &Ctx<M>, mut x: DVec3, mut v: DVec3, r: f64) -> (DVec3, DVec3) {
    for wall in ctx.walls {
        (x, v, _) = crate::walls::push_out(&wall.shape, x, v, r);
    }
    (x, v)
}

type Island = (Vec<usize>, Vec<[usize; 2]>);

/// Groups particles connected by candidate pairs (union–find); every wall candidate outside a
/// pair is an island of one. Islands come in order of their lowest particle index, members in
/// index order, pairs as positions among the members (lower first).
fn islands(wall_candidates: &[u32], pairs: &[[u32; 2]]) -> Vec<Island> {
    use super::FastMap;
    let mut parent: FastMap<u32, u32> = FastMap::default();
    fn root(parent: &mut FastMap<u32, u32>, i: u32) -> u32 {
        let mut r = i;
        while let Some(&up) = parent.get(&r) {
            if up == r {
                break;
            }
            r = up;
        }
        parent.insert(i, r);
        r
    }
    for &[a, b] in pairs {
        parent.entry(a).or_insert(a);
        parent.entry(b).or_insert(b);
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        if ra != rb {
            parent.insert(ra.max(rb), ra.min(rb));
        }
    }
    let mut groups: FastMap<u32, Vec<usize>> = FastMap::default();
    let members: Vec<u32> = parent.keys().copied().collect();
    for i in members {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(i as usize);
    }
    let mut out: Vec<Island> = groups
        .into_values()
        .map(|mut m| {
            m.sort_unstable();
            (m, Vec::new())
        })
        .collect();
    out.sort_unstable_by_key(|(m, _)| m[0]);
    let mut island_of: FastMap<usize, usize> = FastMap::default();
    for (k, (m, _)) in out.iter().enumerate() {
        for &i in m {
            island_of.insert(i, k);
        }
    }
    for &[a, b] in pairs {
        let k = island_of[&(a as usize)];
        let m = &out[k].0;
        let pos = |i: u32| m.binary_search(&(i as usize)).expect("member");
        let local = [pos(a), pos(b)];
        out[k].1.push(local);
    }
    for &i in wall_candidates {
        if !island_of.contains_key(&(i as usize)) {
            out.push((vec![i as usize], Vec::new()));
        }
    }
    out.sort_unstable_by_key(|(m, _)| m[0]);
    out
}
