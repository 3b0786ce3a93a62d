//! Stage 5: lasting contacts between particles **[ext]** (docs/physics.md §5, pairs): a held pair
//! moves together at its centre-of-mass velocity; a pair that met below `St_c` may not
//! approach again. Both are kept by projection, Gauss–Seidel over the contacts in index order
//! (deterministic), with the walls the particles touch.

use super::Ctx;
use super::rules::Friction;
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
    /// With friction **[ext]**: the tangential force (N, on `a`) and the rolling-resistance
    /// torque (N m, on `a`) the contact carried in the last step, the warm start of its friction
    /// rows as `force` is of its normal one.
    pub friction: Option<(DVec3, DVec3)>,
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
#[derive(Debug, Clone, Copy, PartialEq)]
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

/// One wall a moving particle touches, in the velocity sweeps: the particle's place among the
/// involved, the wall's normal towards it, and the impulse accumulated so far (N s).
struct WallRow {
    k: usize,
    /// The warm start's key: the wall's index and part.
    wall: (u32, crate::walls::Part),
    n: DVec3,
    impulse: f64,
    /// With friction: its rows (the wall is `b`).
    friction: Option<FrictionRows>,
}

/// One pair in the velocity sweeps: the two particles' places among the involved, the normal
/// from `a` to `b`, and the impulse pushing them apart accumulated so far (N s).
struct PairRow {
    a: usize,
    b: usize,
    n: DVec3,
    impulse: f64,
    /// With friction, for a resting pair (a hold is a bond and has none).
    friction: Option<FrictionRows>,
}

/// The friction rows of one contact **[ext]** (docs/physics.md §9): Coulomb friction on the contact
/// point's slip and rolling resistance on the relative rolling, each an impulse accumulated over
/// the sweeps (N s, and N m s, on `a`) and kept inside its cone: `|J_t| ≤ μ N`,
/// `|L_r| ≤ μ_r R N`, `N` the contact's accumulated normal impulse plus `support`.
struct FrictionRows {
    f: Friction,
    /// Normal impulse (N s) the flight kernel already gave a particle resting on this wall: it
    /// slid along the wall, its push into the wall removed there, not by a row of this solver.
    support: f64,
    /// Lever arm of the rolling resistance, the reduced radius (m).
    arm: f64,
    tangent: DVec3,
    rolling: DVec3,
}

/// The state of the friction sweeps: each involved particle's spin, inverse moment of inertia
/// and radius.
struct Spins {
    omega: Vec<DVec3>,
    inv_moment: Vec<f64>,
    radius: Vec<f64>,
}

impl FrictionRows {
    fn new(f: Friction, support: f64, arm: f64, warm: Option<(DVec3, DVec3)>, n: DVec3, h: f64) -> Self {
        let (tangent, rolling) = match warm {
            // The last step's force, turned into this step's tangent plane (the normal moved).
            Some((t, r)) => ((t - t.dot(n) * n) * h, (r - r.dot(n) * n) * h),
            None => (DVec3::ZERO, DVec3::ZERO),
        };
        FrictionRows { f, support, arm, tangent, rolling }
    }

    /// One Gauss–Seidel update of the friction and rolling rows of the contact between `a` and
    /// `b` (`b = None`: a wall) with normal `n` from `a` to `b` and accumulated normal impulse
    /// `normal`; returns the largest velocity change it made (m/s).
    fn sweep(
        &mut self,
        (vel, s): (&mut [DVec3], &mut Spins),
        (a, wa): (usize, f64),
        b: Option<(usize, f64)>,
        n: DVec3,
        normal: f64,
    ) -> f64 {
        let load = (normal + self.support).max(0.0);
        let (ra, ia) = (s.radius[a], s.inv_moment[a]);
        let (vb, ob, rb, ib, wb) = match b {
            Some((b, wb)) => (vel[b], s.omega[b], s.radius[b], s.inv_moment[b], wb),
            None => (DVec3::ZERO, DVec3::ZERO, 0.0, 0.0, 0.0),
        };
        // Coulomb: the impulse that stops the slip, inside the cone.
        let u = (vel[a] + s.omega[a].cross(ra * n)) - (vb + ob.cross(-rb * n));
        let slip = u - u.dot(n) * n;
        let c = wa + wb + ra * ra * ia + rb * rb * ib;
        let mut worst: f64 = 0.0;
        if c > 0.0 {
            let new = clamp_length(self.tangent - slip / c, self.f.mu * load);
            let dj = new - self.tangent;
            self.tangent = new;
            vel[a] += dj * wa;
            s.omega[a] += (ra * n).cross(dj) * ia;
            if let Some((b, wb)) = b {
                vel[b] -= dj * wb;
                s.omega[b] += (rb * n).cross(dj) * ib;
            }
            worst = worst.max(dj.length() * c);
        }
        // Rolling resistance: the angular impulse that stops the relative rolling, inside its
        // cone (a torque up to μ_r R N).
        if self.f.rolling > 0.0 && ia + ib > 0.0 {
            let w = s.omega[a] - b.map_or(DVec3::ZERO, |(b, _)| s.omega[b]);
            let rolling = w - w.dot(n) * n;
            let new = clamp_length(self.rolling - rolling / (ia + ib), self.f.rolling * self.arm * load);
            let dl = new - self.rolling;
            self.rolling = new;
            s.omega[a] += dl * ia;
            if let Some((b, _)) = b {
                s.omega[b] -= dl * ib;
            }
            worst = worst.max(dl.length() * (ia + ib) * self.arm);
        }
        worst
    }
}

/// `v` shortened to length `limit` when longer.
fn clamp_length(v: DVec3, limit: f64) -> DVec3 {
    let l2 = v.length_squared();
    if l2 > limit * limit { v * (limit / l2.sqrt()) } else { v }
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
/// With friction: a bed at rest is the point of friction, so the sweeps go on until no
/// velocity changes by more than 1e-4 `g Δt`, up to 100 sweeps.
const FRICTION_VELOCITY_SWEEPS: usize = 100;
const FRICTION_VELOCITY_TOLERANCE: f64 = 1e-4;

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
pub(crate) fn keep_lasting<M: Motion>(
    ctx: &Ctx<M>,
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
        if contacts.is_empty() {
            break;
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
    if friction {
        // With friction a particle resting alone on a wall is held by it too: the kernel slid
        // it without friction, the rows below add it.
        involved.extend((0..p.len()).filter(|&i| state[i] == State::Resting));
        involved.sort_unstable();
        involved.dedup();
    }
    if involved.is_empty() {
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
    solve_velocities(ctx, p, (x, v, state), spins, contacts, &involved, &w, h);
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
            if round > 0 && overlapping.is_empty() {
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
            project_positions(ctx, p, x, &all, &moved, &w);
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
///
/// With friction (`spins`: the spin column and each particle's wall), every contact and wall
/// row also has its friction rows ([`FrictionRows`]), updated right after its normal row, and
/// warm-started like it.
#[allow(clippy::too_many_arguments)]
fn solve_velocities<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    (x, v, state): (&[DVec3], &mut [DVec3], &[State]),
    spins: Option<(&mut [DVec3], &[u32], &mut Vec<WallContact>)>,
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
    let (omega, wall_of, mut wall_contacts) = match spins {
        Some((omega, wall_of, last)) => (Some(omega), Some(wall_of), Some(last)),
        None => (None, None, None),
    };
    let mut spin = omega.as_ref().map(|omega| Spins {
        omega: involved.iter().map(|&i| omega[i]).collect(),
        inv_moment: involved
            .iter()
            .zip(&inv)
            .map(
                |(&i, &w)| if w > 0.0 { 1.0 / ctx.moment_of(p.kind[i] as usize, p.diameter[i]) } else { 0.0 },
            )
            .collect(),
        radius: involved.iter().map(|&i| 0.5 * p.diameter[i]).collect(),
    });
    let mut walls: Vec<WallRow> = Vec::new();
    for (k, &i) in involved.iter().enumerate().filter(|&(k, _)| inv[k] > 0.0) {
        let r = 0.5 * p.diameter[i];
        // A sphere grown by twice the tolerance: clear of it, no part is within the tolerance.
        let near = |wall: &&crate::walls::Wall| wall.shape.may_touch(x[i], x[i], r * (1.0 + 2.0 * TOLERANCE));
        // With friction, a particle resting on a wall slid on it in the flight kernel, which took
        // out its push into the wall: that push, `m max(0, −a·n) h`, is the wall's normal
        // impulse on it, and bounds its friction.
        let resting_on = wall_of.filter(|_| state[i] == State::Resting).map(|walls| walls[i] as usize);
        for (wi, wall) in ctx.walls().iter().enumerate().filter(|(_, w)| near(w)) {
            wall.shape.touching(x[i], r, TOLERANCE * r, |part, g| {
                let key = (wi as u32, part);
                // With friction, the last step's forces at this wall (none: a new contact).
                let warm = wall_contacts.as_ref().and_then(|last| {
                    let found = last.binary_search_by(|c| (c.id, c.wall).cmp(&(p.id[i], key)));
                    found.ok().map(|at| last[at])
                });
                let friction = spin.as_ref().map(|_| {
                    let kind = &ctx.kinds[p.kind[i] as usize];
                    let support = if resting_on == Some(wi) {
                        let a = ctx.flight.acceleration((p.kind[i] as usize, p.diameter[i]), x[i], v[i]);
                        (-a.dot(g.normal)).max(0.0) * h / inv[k]
                    } else {
                        0.0
                    };
                    let f = Friction::between(&kind.friction, &wall.material.friction);
                    FrictionRows::new(f, support, r, warm.map(|c| c.friction), -g.normal, h)
                });
                let impulse = warm.map_or(0.0, |c| (c.force * h).max(0.0));
                walls.push(WallRow { k, wall: key, n: g.normal, impulse, friction })
            });
        }
    }
    let mut rows: Vec<PairRow> = contacts
        .iter()
        .map(|c| {
            let n = (x[c.b as usize] - x[c.a as usize]).normalize_or(DVec3::Z);
            let warm = if c.hold.is_none() { (c.force * h).max(0.0) } else { 0.0 };
            let friction = spin.as_ref().filter(|_| c.hold.is_none()).map(|_| {
                let (ka, kb) =
                    (&ctx.kinds[p.kind[c.a as usize] as usize], &ctx.kinds[p.kind[c.b as usize] as usize]);
                let (ra, rb) = (0.5 * p.diameter[c.a as usize], 0.5 * p.diameter[c.b as usize]);
                let f = Friction::between(&ka.friction, &kb.friction);
                FrictionRows::new(f, 0.0, ra * rb / (ra + rb), c.friction, -n, h)
            });
            PairRow { a: local(c.a), b: local(c.b), n, impulse: warm, friction }
        })
        .collect();
    // Warm start: the last step's wall forces, as `FrictionRows::sweep` applies them (the wall
    // is `b`, the normal from the particle to it `−n`).
    for WallRow { k, n, impulse: j, friction, .. } in &walls {
        vel[*k] += *n * *j * inv[*k];
        if let (Some(fr), Some(s)) = (friction, spin.as_mut()) {
            let (rt, rr) = (fr.tangent, fr.rolling);
            vel[*k] += rt * inv[*k];
            s.omega[*k] += (s.radius[*k] * -*n).cross(rt) * s.inv_moment[*k] + rr * s.inv_moment[*k];
        }
    }
    for PairRow { a, b, n, impulse: j, friction } in &rows {
        let (a, b, n, j) = (*a, *b, *n, *j);
        vel[a] -= n * j * inv[a];
        vel[b] += n * j * inv[b];
        // The last step's friction as well: on `a` (contact point at `+r_a n`), its opposite on
        // `b` (at `−r_b n`), as `FrictionRows::sweep` applies it.
        if let (Some(fr), Some(s)) = (friction, spin.as_mut()) {
            let (rt, rr) = (fr.tangent, fr.rolling);
            vel[a] += rt * inv[a];
            vel[b] -= rt * inv[b];
            s.omega[a] += (s.radius[a] * n).cross(rt) * s.inv_moment[a] + rr * s.inv_moment[a];
            s.omega[b] += (s.radius[b] * n).cross(rt) * s.inv_moment[b] - rr * s.inv_moment[b];
        }
    }
    let (sweeps, tolerance) = if spin.is_some() {
        (FRICTION_VELOCITY_SWEEPS, FRICTION_VELOCITY_TOLERANCE * ctx.fluid.gravity.length() * h)
    } else {
        (VELOCITY_SWEEPS, VELOCITY_TOLERANCE * ctx.fluid.gravity.length() * h)
    };
    for _ in 0..sweeps {
        let mut worst: f64 = 0.0;
        for WallRow { k, n, impulse: acc, friction, .. } in walls.iter_mut() {
            let new = (*acc - vel[*k].dot(*n) / inv[*k]).max(0.0);
            let dv = (new - *acc) * inv[*k];
            vel[*k] += *n * dv;
            *acc = new;
            worst = worst.max(dv.abs());
            if let (Some(fr), Some(s)) = (friction.as_mut(), spin.as_mut()) {
                // The wall is `b`: the normal from the particle to it is `−n`.
                worst = worst.max(fr.sweep((&mut vel, s), (*k, inv[*k]), None, -*n, *acc));
            }
        }
        for (c, PairRow { a, b, n, impulse: acc, friction }) in contacts.iter().zip(rows.iter_mut()) {
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
                if let (Some(fr), Some(s)) = (friction.as_mut(), spin.as_mut()) {
                    worst = worst.max(fr.sweep((&mut vel, s), (a, wa), Some((b, wb)), n, *acc));
                }
            }
        }
        if worst <= tolerance {
            break;
        }
    }
    for (k, &i) in involved.iter().enumerate() {
        v[i] = vel[k];
    }
    if let (Some(omega), Some(s)) = (omega, spin) {
        for (k, &i) in involved.iter().enumerate() {
            omega[i] = s.omega[k];
        }
    }
    for (c, row) in contacts.iter_mut().zip(rows) {
        c.force = row.impulse / h;
        c.friction = row.friction.map(|f| (f.tangent / h, f.rolling / h));
    }
    if let Some(last) = wall_contacts.as_mut() {
        last.clear();
        last.extend(walls.iter().map(|row| WallContact {
            id: p.id[involved[row.k]],
            wall: row.wall,
            force: row.impulse / h,
            friction:
                row.friction.as_ref().map_or((DVec3::ZERO, DVec3::ZERO), |f| (f.tangent / h, f.rolling / h)),
        }));
        last.sort_unstable_by_key(|c| (c.id, c.wall));
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
