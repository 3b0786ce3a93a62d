//! Stage 5: lasting contacts between particles **[ext]** (docs/physics.md §5, pairs): a held pair
//! moves together at its centre-of-mass velocity; a pair that met below `St_c` may not
//! approach again. Both are kept by projection, Gauss–Seidel over the contacts in index order
//! (deterministic), with the walls the particles touch.

mod velocities;

use super::Ctx;
use crate::agree::Agree;
use crate::flight::Motion;
use crate::particles::{Next, Particles, State};
use crate::walls::{Surface, push_out};
use glam::DVec3;
use rayon::prelude::*;

/// A lasting contact between particles `a < b` (indices): after an impact below `St_c`
/// (resting: they may not approach) or during a hold (they move together) **[ext]**.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LastingContact {
    /// Lower particle index.
    pub a: u32,
    /// Higher particle index.
    pub b: u32,
    /// `Some` during a hold.
    pub hold: Option<PairHold>,
    /// Normal force the contact carried in the last step (N, pushing the pair apart): the
    /// projection starts from it (warm start), so a bed carrying its own weight converges in a
    /// few sweeps instead of one sweep per layer.
    pub force: f64,
    /// With friction **[ext]**: the tangential force (N, on `a`) and the rolling-resistance
    /// torque (N m, on `a`) the contact carried in the last step, the warm start of its friction
    /// rows as `force` is of its normal one.
    pub friction: Option<(DVec3, DVec3)>,
}

/// The release of a held pair.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PairHold {
    /// When the hold ends (s).
    pub release_time: f64,
    /// Relative normal speed at release `ε Vn` (m/s), separating.
    pub normal_speed: f64,
    /// Relative tangential velocity `v_a − v_b` at release, `e_t` times that at impact (m/s).
    pub tangential: DVec3,
}

impl LastingContact {
    /// A resting contact.
    pub fn resting(a: u32, b: u32) -> Self {
        LastingContact { a, b, hold: None, force: 0.0, friction: None }
    }

    /// A hold until `release_time`.
    pub fn held(a: u32, b: u32, release_time: f64, normal_speed: f64, tangential: DVec3) -> Self {
        LastingContact {
            a,
            b,
            hold: Some(PairHold { release_time, normal_speed, tangential }),
            force: 0.0,
            friction: None,
        }
    }
}

/// The forces a wall carried on a particle in the last step, with friction **[ext]**: the warm
/// start of its rows in the next step, as [`LastingContact::force`] and
/// [`LastingContact::friction`] are of a pair's. Kept by particle id (not index: outlets and
/// commit renumber particles), wall and part; sorted by that key.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WallContact {
    /// The particle's id.
    pub id: u32,
    /// The wall's index and the part of it touched.
    pub wall: (u32, crate::walls::Part),
    /// Normal force (N, pushing the particle off the wall).
    pub force: f64,
    /// Tangential force and rolling-resistance torque on the particle (N, N m).
    pub friction: (DVec3, DVec3),
}

/// Keeps the particles with `keep[i]` in `p`, in order, and renumbers the lasting contacts
/// (dropping those of removed particles).
pub fn remove_particles(p: &mut Particles, keep: &[bool], lasting: &mut Vec<LastingContact>) {
    let mut new_index = vec![u32::MAX; keep.len()];
    let mut n = 0;
    for (i, &k) in keep.iter().enumerate() {
        if k {
            new_index[i] = n;
            n += 1;
        }
    }
    p.retain(keep);
    lasting.retain_mut(|c| {
        let (a, b) = (new_index[c.a as usize], new_index[c.b as usize]);
        (c.a, c.b) = (a, b);
        a != u32::MAX && b != u32::MAX
    });
}

/// Gap beyond which a resting pair has separated (relative to the sum of radii): hysteresis,
/// so that neighbours at rest do not break and re-make their contact every step.
const SEPARATED: f64 = 1e-3;
/// Position sweeps per step, at most; they stop early once every contact holds to
/// `TOLERANCE` of the sum of radii.
const SWEEPS: usize = 20;
/// Rounds of (find overlapping neighbours, project) per step.
const ROUNDS: usize = 2;
const TOLERANCE: f64 = 1e-3;
/// The neighbour pairs that overlap by more than `TOLERANCE` of their reach (the sum of the
/// radii, `reach_of`) and are not in `known`, as new resting contacts.
fn new_overlaps(
    neighbour_pairs: &[[u32; 2]],
    x: &[DVec3],
    reach_of: &impl Fn(u32, u32) -> f64,
    known: &crate::contact::FastSet<[u32; 2]>,
) -> Vec<LastingContact> {
    neighbour_pairs
        .iter()
        .filter(|&&[a, b]| {
            (x[b as usize] - x[a as usize]).length() < reach_of(a, b) * (1.0 - TOLERANCE)
                && !known.contains(&[a, b])
        })
        .map(|&[a, b]| LastingContact::resting(a, b))
        .collect()
}

/// Keeps every lasting contact at the end of the step (writes `next.pos` and `next.vel`).
/// A neighbour pair found overlapping — left so by the events (a particle knocked off its course
/// into a neighbour that was not a candidate), or by this projection pushing a particle into a
/// neighbour — becomes a resting contact, and the projection runs again. Positions are
/// projected first (without touching velocities, so that correcting a drift adds no kinetic
/// energy), then velocities (`solve_velocities`). `h` is the step (s). Returns true when a
/// particle's new state is not finite.
///
/// Every decision that spans all contacts (whether a round or a sweep is needed) is asked of
/// `agree`: on ranks of one run, all of them take the same rounds and sweeps as one process.
#[allow(clippy::too_many_arguments)]
pub(crate) fn keep_lasting<M: Motion>(
    ctx: &Ctx<M>,
    agree: &dyn Agree,
    p: &Particles,
    next: &mut Next,
    contacts: &mut Vec<LastingContact>,
    neighbour_pairs: &[[u32; 2]],
    wall_contacts: &mut Vec<WallContact>,
    h: f64,
) -> bool {
    let friction = ctx.rule.friction;
    let (x, v, state) = (&mut next.pos, &mut next.vel, &next.state);
    let reach_of = |a: u32, b: u32| 0.5 * (p.diameter[a as usize] + p.diameter[b as usize]);
    contacts.retain(|c| {
        c.hold.is_some()
            || (x[c.b as usize] - x[c.a as usize]).length() < reach_of(c.a, c.b) * (1.0 + SEPARATED)
    });
    // Inverse inertia; 0 for a particle held at a wall (immobile).
    let w = |i: usize| {
        if state[i] == State::Held { 0.0 } else { 1.0 / ctx.inertia_of(p.kind[i] as usize, p.diameter[i]) }
    };
    let mut involved: Vec<usize> = Vec::new();
    let mut known: crate::contact::FastSet<[u32; 2]> = contacts.iter().map(|c| [c.a, c.b]).collect();
    for round in 0..ROUNDS {
        let before = contacts.len();
        let found = new_overlaps(neighbour_pairs, x, &reach_of, &known);
        known.extend(found.iter().map(|c| [c.a, c.b]));
        contacts.extend(found);
        if !agree.any(!contacts.is_empty()) {
            break;
        }
        if !agree.any(contacts.len() != before) && round > 0 {
            break;
        }
        // Bottom-up along gravity: a sweep then carries the support of the walls up through a
        // stack in one pass, instead of one layer per sweep.
        let up = -ctx.fluid.gravity.normalize_or(DVec3::NEG_Z);
        let height = |c: &LastingContact| x[c.a as usize].dot(up).min(x[c.b as usize].dot(up));
        contacts.sort_by(|c, d| height(c).total_cmp(&height(d)).then((c.a, c.b).cmp(&(d.a, d.b))));
        // Ascending and unique: by marking when contacts are many (sorting 10⁵ indices cost
        // more than a pass over the particles), by sorting when they are few.
        if 16 * contacts.len() >= p.len() {
            let mut mark = vec![false; p.len()];
            for c in contacts.iter() {
                (mark[c.a as usize], mark[c.b as usize]) = (true, true);
            }
            involved = (0..p.len()).filter(|&i| mark[i]).collect();
        } else {
            involved = contacts.iter().flat_map(|c| [c.a as usize, c.b as usize]).collect();
            involved.sort_unstable();
            involved.dedup();
        }
        project_positions(ctx, agree, p, x, contacts, &involved, &w);
        // Walls are hard: whatever the sweeps left, no particle ends inside one.
        // (`may_touch` first: the closed-form broad phase answers for most, and it is false
        // only when the gap is positive, where `push_out` does nothing.)
        for &i in involved.iter().filter(|&&i| w(i) > 0.0) {
            let r = 0.5 * p.diameter[i];
            for wall in ctx.walls() {
                if wall.shape.may_touch(x[i], x[i], r) {
                    (x[i], v[i], _) = push_out(&wall.shape, x[i], v[i], r);
                }
            }
        }
    }
    if friction {
        // With friction a particle resting alone on a wall is held by it too: the kernel slid
        // it without friction, the rows below add it. A pass over every particle, every step:
        // in parallel (in order), or it was a fifth of a 10⁶-bead step on 16 threads.
        involved.par_extend((0..p.len()).into_par_iter().filter(|&i| state[i] == State::Resting));
        involved.sort_unstable();
        involved.dedup();
    }
    if !agree.any(!involved.is_empty()) {
        wall_contacts.clear();
        return false;
    }
    // With friction a bed is to come to rest: the flight moved each particle by the whole
    // step's acceleration, the velocities below take part of it back, and so the positions
    // follow (a particle held at rest ends the step where it began). Left to the position
    // projection, which stops at `TOLERANCE`, the bed sank into itself by `h² g/2` a step and
    // was pushed out unevenly: contacts opened by `SEPARATED` and their beads fell back, at
    // millimetres per second, dozens of times a second in a 300-bead bed.
    let flown: Vec<DVec3> = if friction { involved.iter().map(|&i| v[i]).collect() } else { Vec::new() };
    let spins = friction.then_some((&mut next.omega[..], &next.wall[..], wall_contacts));
    velocities::solve((ctx, agree), p, (x, v, state), spins, contacts, (&involved, &w), h);
    for (&i, &flown) in involved.iter().zip(&flown) {
        x[i] += (M::DISPLACEMENT_SHARE * h) * (v[i] - flown);
    }
    if friction {
        // That displacement came after the projection: a bead whose velocity the sweeps changed
        // (a fast collision with ε_max = 1 in air) moved by up to `h |Δv|/2` into a wall or a
        // neighbour it had no contact with, which left pairs overlapping by 2.5 % of d and walls
        // by 2.6 % of r in a 300-bead pour (issue 25). Project again, with the neighbours now
        // overlapping (for this projection only: the next step finds their contact as an
        // impact), and keep the walls hard as above. Positions only, so a bed at rest stays
        // at rest. (Without friction nothing moved: no second pass.)
        // Rounds as above: a projection may push a bead into a further neighbour.
        let mut all: Vec<LastingContact> = Vec::new();
        let mut moved: Vec<usize> = Vec::new();
        for round in 0..ROUNDS + 1 {
            let overlapping = new_overlaps(neighbour_pairs, x, &reach_of, &known);
            if round > 0 && !agree.any(!overlapping.is_empty()) {
                break;
            }
            if round == 0 {
                all.extend_from_slice(contacts);
                moved.clone_from(&involved);
            }
            known.extend(overlapping.iter().map(|c| [c.a, c.b]));
            moved.extend(overlapping.iter().flat_map(|c| [c.a as usize, c.b as usize]));
            moved.sort_unstable();
            moved.dedup();
            all.extend(overlapping);
            project_positions(ctx, agree, p, x, &all, &moved, &w);
        }
        for &i in moved.iter().filter(|&&i| w(i) > 0.0) {
            let r = 0.5 * p.diameter[i];
            for wall in ctx.walls() {
                if wall.shape.may_touch(x[i], x[i], r) {
                    (x[i], v[i], _) = push_out(&wall.shape, x[i], v[i], r);
                }
            }
        }
    }
    involved.iter().any(|&i| !(x[i].is_finite() && v[i].is_finite()))
}

/// Gauss–Seidel sweeps on positions over the walls of the particles involved, then the
/// contacts: a resting contact may not overlap, a hold keeps the pair touching.
fn project_positions<M: Motion>(
    ctx: &Ctx<M>,
    agree: &dyn Agree,
    p: &Particles,
    x: &mut [DVec3],
    contacts: &[LastingContact],
    involved: &[usize],
    w: &impl Fn(usize) -> f64,
) {
    let reach = |c: &LastingContact| 0.5 * (p.diameter[c.a as usize] + p.diameter[c.b as usize]);
    // Inverse inertias looked up, not recomputed at every sweep.
    let place = places(p.len(), involved);
    let inv: Vec<f64> = involved.iter().map(|&i| w(i)).collect();
    let w = |i: usize| inv[place.of(i)];
    for _ in 0..SWEEPS {
        let mut worst: f64 = 0.0;
        for &i in involved.iter().filter(|&&i| w(i) > 0.0) {
            let r = 0.5 * p.diameter[i];
            for wall in ctx.walls() {
                // False only when the gap is positive (then there is nothing to do).
                if !wall.shape.may_touch(x[i], x[i], r) {
                    continue;
                }
                let g = wall.shape.gap(x[i], r);
                if g.gap < 0.0 {
                    x[i] -= g.gap * g.normal;
                    worst = worst.max(-g.gap / r);
                }
            }
        }
        for c in contacts.iter() {
            let (a, b) = (c.a as usize, c.b as usize);
            let (wa, wb) = (w(a), w(b));
            if wa + wb == 0.0 {
                continue;
            }
            let r = reach(c);
            let delta = x[b] - x[a];
            let dist = delta.length();
            let n = if dist > 0.0 { delta / dist } else { DVec3::Z };
            let error = dist - r;
            // A hold is a bond (both ways); a resting contact only pushes apart.
            let push = if c.hold.is_some() { error } else { error.min(0.0) };
            if push != 0.0 {
                worst = worst.max(push.abs() / r);
                x[a] += n * push * wa / (wa + wb);
                x[b] -= n * push * wb / (wa + wb);
            }
        }
        if agree.max(worst) < TOLERANCE {
            break;
        }
    }
}

/// The place of a particle in `involved` (ascending): a table over all `n` particles when many
/// are involved (a binary search per contact end cost more than the sweeps), a search when few
/// are (the table would cost a pass over all particles).
enum Places<'a> {
    Table(Vec<u32>),
    Search(&'a [usize]),
}

impl Places<'_> {
    #[inline]
    fn of(&self, i: usize) -> usize {
        match self {
            Places::Table(t) => t[i] as usize,
            Places::Search(involved) => involved.binary_search(&i).expect("involved"),
        }
    }
}

fn places(n: usize, involved: &[usize]) -> Places<'_> {
    if 16 * involved.len() < n {
        return Places::Search(involved);
    }
    let mut place = vec![u32::MAX; n];
    for (k, &i) in involved.iter().enumerate() {
        place[i] = k as u32;
    }
    Places::Table(place)
}

/// Stage 1 for pairs: a held pair whose hold ends before `t1` gets its release velocities
/// (relative normal speed `ε Vn` apart, tangential `e_t` times that at impact, momentum
/// conserved); its particles are free again unless still held by another pair.
pub(crate) fn release_pairs<M: Motion>(
    ctx: &Ctx<M>,
    p: &mut Particles,
    contacts: &mut Vec<LastingContact>,
    t1: f64,
) {
    let mut released = Vec::new();
    contacts.retain(|c| match c.hold {
        Some(h) if h.release_time < t1 => {
            released.push(*c);
            false
        }
        _ => true,
    });
    for c in released {
        let hold = c.hold.expect("held");
        let (a, b) = (c.a as usize, c.b as usize);
        let inertia = |i: usize| {
            if p.state[i] == State::Held {
                f64::INFINITY
            } else {
                ctx.inertia_of(p.kind[i] as usize, p.diameter[i])
            }
        };
        let (wa, wb) = (1.0 / inertia(a), 1.0 / inertia(b));
        if wa + wb == 0.0 {
            continue;
        }
        let n = (p.pos[b] - p.pos[a]).normalize_or(DVec3::Z);
        let target = -hold.normal_speed * n + hold.tangential - hold.tangential.dot(n) * n;
        let j = (target - (p.vel[a] - p.vel[b])) / (wa + wb);
        p.vel[a] += wa * j;
        p.vel[b] -= wb * j;
        for i in [a, b] {
            let still_held =
                contacts.iter().any(|o| o.hold.is_some() && (o.a as usize == i || o.b as usize == i));
            if p.state[i] == State::PairHeld && !still_held {
                p.state[i] = State::Free;
            }
        }
    }
}
