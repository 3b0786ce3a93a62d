//! Stage 5's velocities: sequential impulses (projected Gauss–Seidel) on the particles of the
//! lasting contacts and the walls they touch, in four steps — build the rows, warm-start them,
//! sweep, write back ([`solve`]) — with every impulse applied through [`Bodies`] and [`Spins`].

use super::{Ctx, LastingContact, TOLERANCE, WallContact, places};
use crate::contact::rules::Friction;
use crate::flight::Motion;
use crate::particles::{Particles, State};
use crate::walls::Surface;
use glam::DVec3;

/// Velocity sweeps per step, at most; they stop early once no sweep changes a velocity by
/// more than `VELOCITY_TOLERANCE` times what gravity adds in the step, `g Δt`.
const VELOCITY_SWEEPS: usize = 30;
const VELOCITY_TOLERANCE: f64 = 1e-2;
/// With friction: a bed at rest is the point of friction, so the sweeps go on until no
/// velocity changes by more than 1e-4 `g Δt`, up to 100 sweeps.
const FRICTION_VELOCITY_SWEEPS: usize = 100;
const FRICTION_VELOCITY_TOLERANCE: f64 = 1e-4;

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

/// The friction rows of one contact **[ext]** (docs/physics.md §9): Coulomb friction on the
/// contact point's slip and rolling resistance on the relative rolling, each an impulse
/// accumulated over the sweeps (N s, and N m s, on `a`) and kept inside its cone:
/// `|J_t| ≤ μ N`, `|L_r| ≤ μ_r R N`, `N` the contact's accumulated normal impulse plus `support`.
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

/// The involved particles in the sweeps: compact copies of their velocities and inverse
/// inertias (0 for a particle held at a wall), by place among the involved.
struct Bodies {
    vel: Vec<DVec3>,
    inv: Vec<f64>,
}

/// With friction, the involved particles' spins, inverse moments of inertia and radii.
struct Spins {
    omega: Vec<DVec3>,
    inv_moment: Vec<f64>,
    radius: Vec<f64>,
}

// The impulses, applied here only. Each form keeps the order of its operations: the same
// impulse written another way rounds differently, and outputs are to stay byte for byte.
impl Bodies {
    /// A linear impulse `j` (N s) on body `k`.
    #[inline]
    fn push(&mut self, k: usize, j: DVec3) {
        self.vel[k] += j * self.inv[k];
    }

    /// An impulse `j` (N s) along the unit `n` on body `k`; returns the speed it gave (m/s).
    #[inline]
    fn push_along(&mut self, k: usize, n: DVec3, j: f64) -> f64 {
        let dv = j * self.inv[k];
        self.vel[k] += n * dv;
        dv
    }

    /// A hold is a bond: bodies `a` and `b` take their common velocity (momentum kept);
    /// returns how far apart their velocities were (m/s).
    #[inline]
    fn bond(&mut self, a: usize, b: usize) -> f64 {
        let (wa, wb) = (self.inv[a], self.inv[b]);
        let u = self.vel[b] - self.vel[a];
        self.vel[a] += u * wa / (wa + wb);
        self.vel[b] -= u * wb / (wa + wb);
        u.length()
    }
}

impl Spins {
    /// The spin an impulse `j` (N s) at `arm` (m, from the centre) gives body `k`.
    #[inline]
    fn turn(&mut self, k: usize, arm: DVec3, j: DVec3) {
        self.omega[k] += arm.cross(j) * self.inv_moment[k];
    }

    /// An angular impulse `l` (N m s) on body `k`.
    #[inline]
    fn twist(&mut self, k: usize, l: DVec3) {
        self.omega[k] += l * self.inv_moment[k];
    }

    /// Both at once, as the warm start applies the last step's friction.
    #[inline]
    fn turn_and_twist(&mut self, k: usize, arm: DVec3, j: DVec3, l: DVec3) {
        self.omega[k] += arm.cross(j) * self.inv_moment[k] + l * self.inv_moment[k];
    }
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
        (v, s): (&mut Bodies, &mut Spins),
        a: usize,
        b: Option<usize>,
        n: DVec3,
        normal: f64,
    ) -> f64 {
        let load = (normal + self.support).max(0.0);
        let (wa, ra, ia) = (v.inv[a], s.radius[a], s.inv_moment[a]);
        let (vb, ob, rb, ib, wb) = match b {
            Some(b) => (v.vel[b], s.omega[b], s.radius[b], s.inv_moment[b], v.inv[b]),
            None => (DVec3::ZERO, DVec3::ZERO, 0.0, 0.0, 0.0),
        };
        // Coulomb: the impulse that stops the slip, inside the cone.
        let u = (v.vel[a] + s.omega[a].cross(ra * n)) - (vb + ob.cross(-rb * n));
        let slip = u - u.dot(n) * n;
        let c = wa + wb + ra * ra * ia + rb * rb * ib;
        let mut worst: f64 = 0.0;
        if c > 0.0 {
            let new = clamp_length(self.tangent - slip / c, self.f.mu * load);
            let dj = new - self.tangent;
            self.tangent = new;
            v.push(a, dj);
            s.turn(a, ra * n, dj);
            if let Some(b) = b {
                v.push(b, -dj);
                s.turn(b, rb * n, dj);
            }
            worst = worst.max(dj.length() * c);
        }
        // Rolling resistance: the angular impulse that stops the relative rolling, inside its
        // cone (a torque up to μ_r R N).
        if self.f.rolling > 0.0 && ia + ib > 0.0 {
            let w = s.omega[a] - b.map_or(DVec3::ZERO, |b| s.omega[b]);
            let rolling = w - w.dot(n) * n;
            let new = clamp_length(self.rolling - rolling / (ia + ib), self.f.rolling * self.arm * load);
            let dl = new - self.rolling;
            self.rolling = new;
            s.twist(a, dl);
            if let Some(b) = b {
                s.twist(b, -dl);
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

/// The end of the step's positions, velocities and states, read by the rows.
type EndOfStep<'a> = (&'a [DVec3], &'a mut [DVec3], &'a [State]);

/// Sequential impulses (projected Gauss–Seidel) on the velocities of the particles involved:
/// a hold makes the pair move together; a resting contact, and the walls they touch, may not
/// approach. Each non-penetration impulse is *accumulated* over the sweeps and kept ≥ 0, so an
/// impulse that an early sweep gave in excess is taken back by a later one — rather than left
/// as a velocity that throws the pair apart, which is what kept a bed jittering at ~`g Δt`.
/// A pair's impulse starts from the force it carried in the last step (warm start), and the
/// force found is kept for the next.
///
/// `involved`: the particles of the contacts (ascending), `w`: their inverse inertias. With
/// friction (`spins`: the spin column, each particle's wall and the walls' last forces),
/// every contact and wall row also has its friction rows ([`FrictionRows`]), updated right
/// after its normal row, and warm-started like it.
pub(super) fn solve<M: Motion>(
    (ctx, agree): (&Ctx<M>, &dyn crate::agree::Agree),
    p: &Particles,
    (x, v, state): EndOfStep,
    spins: Option<(&mut [DVec3], &[u32], &mut Vec<WallContact>)>,
    contacts: &mut [LastingContact],
    (involved, w): (&[usize], &impl Fn(usize) -> f64),
    h: f64,
) {
    let (omega, wall_of, wall_contacts) = match spins {
        Some((omega, wall_of, last)) => (Some(omega), Some(wall_of), Some(last)),
        None => (None, None, None),
    };
    // 1. Build the rows, on compact copies of the involved particles.
    let mut bodies = Bodies {
        vel: involved.iter().map(|&i| v[i]).collect(),
        inv: involved.iter().map(|&i| w(i)).collect(),
    };
    let mut spin = omega.as_ref().map(|omega| Spins {
        omega: involved.iter().map(|&i| omega[i]).collect(),
        inv_moment: involved
            .iter()
            .zip(&bodies.inv)
            .map(
                |(&i, &w)| if w > 0.0 { 1.0 / ctx.moment_of(p.kind[i] as usize, p.diameter[i]) } else { 0.0 },
            )
            .collect(),
        radius: involved.iter().map(|&i| 0.5 * p.diameter[i]).collect(),
    });
    let last = wall_contacts.as_deref().map(Vec::as_slice);
    let resting_on = |i: usize| wall_of.filter(|_| state[i] == State::Resting).map(|walls| walls[i] as usize);
    let mut walls = wall_rows(ctx, p, (x, &*v), involved, &bodies.inv, (spin.is_some(), resting_on, last), h);
    let mut rows = pair_rows(ctx, p, x, contacts, involved, spin.is_some(), h);
    // 2. Warm start.
    warm_start(&mut bodies, spin.as_mut(), &walls, &rows);
    // 3. Sweep.
    let tolerance = if spin.is_some() { FRICTION_VELOCITY_TOLERANCE } else { VELOCITY_TOLERANCE };
    let sweeps = if spin.is_some() { FRICTION_VELOCITY_SWEEPS } else { VELOCITY_SWEEPS };
    let tolerance = tolerance * ctx.fluid.gravity.length() * h;
    for _ in 0..sweeps {
        if agree.max(sweep(&mut bodies, spin.as_mut(), contacts, &mut walls, &mut rows)) <= tolerance {
            break;
        }
    }
    // 4. Write back: velocities and spins, and the forces found, the next step's warm start.
    for (k, &i) in involved.iter().enumerate() {
        v[i] = bodies.vel[k];
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
    if let Some(last) = wall_contacts {
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

/// The rows of the walls each moving involved particle touches (within the tolerance), each
/// part its own row, warm-started from `last` (the walls' forces of the last step, by particle
/// id, wall and part) with friction. `friction`: whether the scene has it; `resting_on(i)`:
/// the wall particle `i` rests on, with friction.
fn wall_rows<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    (x, v): (&[DVec3], &[DVec3]),
    involved: &[usize],
    inv: &[f64],
    (friction, resting_on, last): (bool, impl Fn(usize) -> Option<usize>, Option<&[WallContact]>),
    h: f64,
) -> Vec<WallRow> {
    let mut walls: Vec<WallRow> = Vec::new();
    for (k, &i) in involved.iter().enumerate().filter(|&(k, _)| inv[k] > 0.0) {
        let r = 0.5 * p.diameter[i];
        // A sphere grown by twice the tolerance: clear of it, no part is within the tolerance.
        let near = |wall: &&crate::walls::Wall| wall.shape.may_touch(x[i], x[i], r * (1.0 + 2.0 * TOLERANCE));
        // With friction, a particle resting on a wall slid on it in the flight kernel, which took
        // out its push into the wall: that push, `m max(0, −a·n) h`, is the wall's normal
        // impulse on it, and bounds its friction.
        let resting_on = resting_on(i);
        for (wi, wall) in ctx.walls().iter().enumerate().filter(|(_, w)| near(w)) {
            wall.shape.touching(x[i], r, TOLERANCE * r, |part, g| {
                let key = (wi as u32, part);
                // With friction, the last step's forces at this wall (none: a new contact).
                let warm = last.and_then(|last| {
                    let found = last.binary_search_by(|c| (c.id, c.wall).cmp(&(p.id[i], key)));
                    found.ok().map(|at| last[at])
                });
                let friction = friction.then(|| {
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
    walls
}

/// The rows of the lasting contacts, by the particles' places among the involved, each
/// warm-started from the force it carried in the last step (a hold, a bond, from none).
fn pair_rows<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    x: &[DVec3],
    contacts: &[LastingContact],
    involved: &[usize],
    friction: bool,
    h: f64,
) -> Vec<PairRow> {
    // A lookup table: a binary search per contact end cost more than the sweeps.
    let place = places(p.len(), involved);
    let local = |i: u32| place.of(i as usize);
    contacts
        .iter()
        .map(|c| {
            let n = (x[c.b as usize] - x[c.a as usize]).normalize_or(DVec3::Z);
            let warm = if c.hold.is_none() { (c.force * h).max(0.0) } else { 0.0 };
            let friction = (friction && c.hold.is_none()).then(|| {
                let (ka, kb) =
                    (&ctx.kinds[p.kind[c.a as usize] as usize], &ctx.kinds[p.kind[c.b as usize] as usize]);
                let (ra, rb) = (0.5 * p.diameter[c.a as usize], 0.5 * p.diameter[c.b as usize]);
                let f = Friction::between(&ka.friction, &kb.friction);
                FrictionRows::new(f, 0.0, ra * rb / (ra + rb), c.friction, -n, h)
            });
            PairRow { a: local(c.a), b: local(c.b), n, impulse: warm, friction }
        })
        .collect()
}

/// The last step's forces applied, as the sweeps apply them: at a wall, the wall is `b` and
/// the normal from the particle to it `−n`; in a pair, the friction acts on `a` at `+r_a n`
/// and its opposite on `b` at `−r_b n`.
fn warm_start(bodies: &mut Bodies, mut spin: Option<&mut Spins>, walls: &[WallRow], rows: &[PairRow]) {
    for &WallRow { k, n, impulse: j, ref friction, .. } in walls {
        bodies.push(k, n * j);
        if let (Some(fr), Some(s)) = (friction, spin.as_deref_mut()) {
            bodies.push(k, fr.tangent);
            s.turn_and_twist(k, s.radius[k] * -n, fr.tangent, fr.rolling);
        }
    }
    for &PairRow { a, b, n, impulse: j, ref friction } in rows {
        bodies.push(a, -(n * j));
        bodies.push(b, n * j);
        if let (Some(fr), Some(s)) = (friction, spin.as_deref_mut()) {
            bodies.push(a, fr.tangent);
            bodies.push(b, -fr.tangent);
            s.turn_and_twist(a, s.radius[a] * n, fr.tangent, fr.rolling);
            s.turn_and_twist(b, s.radius[b] * n, fr.tangent, -fr.rolling);
        }
    }
}

/// One Gauss–Seidel sweep over the wall rows, then the pair rows (each friction row right
/// after its normal row); returns the largest velocity change it made (m/s).
fn sweep(
    bodies: &mut Bodies,
    mut spin: Option<&mut Spins>,
    contacts: &[LastingContact],
    walls: &mut [WallRow],
    rows: &mut [PairRow],
) -> f64 {
    let mut worst: f64 = 0.0;
    for WallRow { k, n, impulse: acc, friction, .. } in walls.iter_mut() {
        let (k, n) = (*k, *n);
        let new = (*acc - bodies.vel[k].dot(n) / bodies.inv[k]).max(0.0);
        let dv = bodies.push_along(k, n, new - *acc);
        *acc = new;
        worst = worst.max(dv.abs());
        if let (Some(fr), Some(s)) = (friction.as_mut(), spin.as_deref_mut()) {
            // The wall is `b`: the normal from the particle to it is `−n`.
            worst = worst.max(fr.sweep((bodies, s), k, None, -n, *acc));
        }
    }
    for (c, PairRow { a, b, n, impulse: acc, friction }) in contacts.iter().zip(rows.iter_mut()) {
        let (a, b, n) = (*a, *b, *n);
        let (wa, wb) = (bodies.inv[a], bodies.inv[b]);
        if wa + wb == 0.0 {
            continue;
        }
        if c.hold.is_some() {
            worst = worst.max(bodies.bond(a, b));
        } else {
            let new = (*acc - (bodies.vel[b] - bodies.vel[a]).dot(n) / (wa + wb)).max(0.0);
            let dj = new - *acc;
            bodies.push(a, -(n * dj));
            bodies.push(b, n * dj);
            *acc = new;
            worst = worst.max(dj * (wa + wb)).max(-dj * (wa + wb));
            if let (Some(fr), Some(s)) = (friction.as_mut(), spin.as_deref_mut()) {
                worst = worst.max(fr.sweep((bodies, s), a, Some(b), n, *acc));
            }
        }
    }
    worst
}
