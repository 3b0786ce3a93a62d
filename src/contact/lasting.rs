//! Stage 5b: lasting contacts between particles **[ext]** (PHYSICS.md §5, pairs): a held pair
//! moves together at its centre-of-mass velocity; a pair that met below `St_c` may not
//! approach again. Both are kept by projection, Gauss–Seidel over the contacts in index order
//! (deterministic), with the walls the particles touch.

use super::Ctx;
use crate::flight::Motion;
use crate::particles::{Next, Particles, State};
use crate::walls::{Surface, push_out};
use glam::DVec3;

/// A lasting contact between particles `a < b` (indices): after an impact below `St_c`
/// (resting: they may not approach) or during a hold (they move together) **[ext]**.
#[derive(Debug, Clone, Copy, PartialEq)]
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
}

/// The release of a held pair.
#[derive(Debug, Clone, Copy, PartialEq)]
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
        LastingContact { a, b, hold: None, force: 0.0 }
    }

    /// A hold until `release_time`.
    pub fn held(a: u32, b: u32, release_time: f64, normal_speed: f64, tangential: DVec3) -> Self {
        LastingContact { a, b, hold: Some(PairHold { release_time, normal_speed, tangential }), force: 0.0 }
    }
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

/// One wall a moving particle touches, in the velocity sweeps: the particle's place among the
/// involved, the wall's normal towards it, and the impulse accumulated so far (N s).
struct WallRow {
    k: usize,
    n: DVec3,
    impulse: f64,
}

/// One pair in the velocity sweeps: the two particles' places among the involved, the normal
/// from `a` to `b`, and the impulse pushing them apart accumulated so far (N s).
struct PairRow {
    a: usize,
    b: usize,
    n: DVec3,
    impulse: f64,
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
/// Velocity sweeps per step, at most; they stop early once no sweep changes a velocity by
/// more than `VELOCITY_TOLERANCE` times what gravity adds in the step, `g Δt`.
const VELOCITY_SWEEPS: usize = 30;
const VELOCITY_TOLERANCE: f64 = 1e-2;

/// Keeps every lasting contact at the end of the step (writes `next.pos` and `next.vel`).
/// A neighbour pair found overlapping — left so by the events (a particle knocked off its course
/// into a neighbour that was not a candidate), or by this projection pushing a particle into a
/// neighbour — becomes a resting contact, and the projection runs again. Positions are
/// projected first (without touching velocities, so that correcting a drift adds no kinetic
/// energy), then velocities (`solve_velocities`). `h` is the step (s). Returns true when a
/// particle's new state is not finite.
pub(crate) fn keep_lasting<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    next: &mut Next,
    contacts: &mut Vec<LastingContact>,
    neighbour_pairs: &[[u32; 2]],
    h: f64,
) -> bool {
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
        let found: Vec<LastingContact> = neighbour_pairs
            .iter()
            .filter(|&&[a, b]| {
                (x[b as usize] - x[a as usize]).length() < reach_of(a, b) * (1.0 - TOLERANCE)
                    && !known.contains(&[a, b])
            })
            .map(|&[a, b]| LastingContact::resting(a, b))
            .collect();
        known.extend(found.iter().map(|c| [c.a, c.b]));
        contacts.extend(found);
        if contacts.is_empty() {
            return false;
        }
        if contacts.len() == before && round > 0 {
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
        project_positions(ctx, p, x, contacts, &involved, &w);
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
    solve_velocities(ctx, p, x, v, contacts, &involved, &w, h);
    involved.iter().any(|&i| !(x[i].is_finite() && v[i].is_finite()))
}

/// Gauss–Seidel sweeps on positions over the walls of the particles involved, then the
/// contacts: a resting contact may not overlap, a hold keeps the pair touching.
fn project_positions<M: Motion>(
    ctx: &Ctx<M>,
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
        if worst < TOLERANCE {
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

/// Sequential impulses (projected Gauss–Seidel) on the velocities of the particles involved:
/// a hold makes the pair move together; a resting contact, and the walls they touch, may not
/// approach. Each non-penetration impulse is *accumulated* over the sweeps and kept ≥ 0, so an
/// impulse that an early sweep gave in excess is taken back by a later one — rather than left
/// as a velocity that throws the pair apart, which is what kept a bed jittering at ~`g Δt`.
/// A pair's impulse starts from the force it carried in the last step (warm start), and the
/// force found is kept for the next.
#[allow(clippy::too_many_arguments)]
fn solve_velocities<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    x: &[DVec3],
    v: &mut [DVec3],
    contacts: &mut [LastingContact],
    involved: &[usize],
    w: &impl Fn(usize) -> f64,
    h: f64,
) {
    // The sweeps work on compact copies: the involved particles' velocities and inverse
    // inertias, contacts by position in `involved`.
    // A lookup table: a binary search per contact end cost more than the sweeps.
    let place = places(p.len(), involved);
    let local = |i: u32| place.of(i as usize);
    let inv: Vec<f64> = involved.iter().map(|&i| w(i)).collect();
    let mut vel: Vec<DVec3> = involved.iter().map(|&i| v[i]).collect();
    let mut walls: Vec<WallRow> = Vec::new();
    for (k, &i) in involved.iter().enumerate().filter(|&(k, _)| inv[k] > 0.0) {
        let r = 0.5 * p.diameter[i];
        // A sphere grown by twice the tolerance: clear of it, no part is within the tolerance.
        let near = |wall: &&crate::walls::Wall| wall.shape.may_touch(x[i], x[i], r * (1.0 + 2.0 * TOLERANCE));
        for wall in ctx.walls().iter().filter(near) {
            wall.shape.touching(x[i], r, TOLERANCE * r, |_, g| {
                walls.push(WallRow { k, n: g.normal, impulse: 0.0 })
            });
        }
    }
    let mut rows: Vec<PairRow> = contacts
        .iter()
        .map(|c| {
            let n = (x[c.b as usize] - x[c.a as usize]).normalize_or(DVec3::Z);
            let warm = if c.hold.is_none() { (c.force * h).max(0.0) } else { 0.0 };
            PairRow { a: local(c.a), b: local(c.b), n, impulse: warm }
        })
        .collect();
    for &PairRow { a, b, n, impulse: j } in &rows {
        vel[a] -= n * j * inv[a];
        vel[b] += n * j * inv[b];
    }
    let tolerance = VELOCITY_TOLERANCE * ctx.fluid.gravity.length() * h;
    for _ in 0..VELOCITY_SWEEPS {
        let mut worst: f64 = 0.0;
        for WallRow { k, n, impulse: acc } in walls.iter_mut() {
            let new = (*acc - vel[*k].dot(*n) / inv[*k]).max(0.0);
            let dv = (new - *acc) * inv[*k];
            vel[*k] += *n * dv;
            *acc = new;
            worst = worst.max(dv.abs());
        }
        for (c, PairRow { a, b, n, impulse: acc }) in contacts.iter().zip(rows.iter_mut()) {
            let (a, b, n) = (*a, *b, *n);
            let (wa, wb) = (inv[a], inv[b]);
            if wa + wb == 0.0 {
                continue;
            }
            if c.hold.is_some() {
                let u = vel[b] - vel[a];
                vel[a] += u * wa / (wa + wb);
                vel[b] -= u * wb / (wa + wb);
                worst = worst.max(u.length());
            } else {
                let new = (*acc - (vel[b] - vel[a]).dot(n) / (wa + wb)).max(0.0);
                let dj = new - *acc;
                vel[a] -= n * dj * wa;
                vel[b] += n * dj * wb;
                *acc = new;
                worst = worst.max(dj * (wa + wb)).max(-dj * (wa + wb));
            }
        }
        if worst <= tolerance {
            break;
        }
    }
    for (k, &i) in involved.iter().enumerate() {
        v[i] = vel[k];
    }
    for (c, row) in contacts.iter_mut().zip(rows) {
        c.force = row.impulse / h;
    }
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
