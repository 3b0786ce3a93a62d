//! Stages 1, 2 and the wall part of 3, fused into one parallel pass over the particle columns,
//! so that each particle's data is read once per step: for every particle, in order,
//! [`contact::release_at_wall`], [`Kernel::free_flight`] and [`contact::touches_wall`].

use crate::contact;
use crate::effects::LUBRICATION_RANGE;
use crate::flight::{Flight, Kernel, Motion, NO_MEMORY, NearWall, Segment};
use crate::numeric::lane_sums::Avx;
use crate::numeric::lanes::{DVec3x4, F64x4, LANES, each};
use crate::particles::{NO_WALL, Next, Particles, State};
use crate::walls::Surface;
use glam::DVec3;
use multiversion::{
    multiversion,
    target::{TargetFeatures, selected_target},
};
use rayon::prelude::*;

/// Particles per parallel task: large enough to hide the scheduling, small enough to share 2
/// cores evenly for a few thousand particles. Fixed, so results never depend on the threads.
const CHUNK: usize = 512;

/// What the pass found besides the new states.
pub(crate) struct PassResult {
    /// The largest move of the step (m).
    pub step_move: f64,
    /// Some particle's new state may not be finite (commit then checks each one).
    pub suspect: bool,
}

/// Runs the fused stages over all particles from `t0` to `t1`. Stage 1 rewrites, in `p`, the
/// state, velocity and wall of the particles it releases; stages 2 and 3 write every particle's
/// end of step into `next` (position, velocity, state, wall) and the particles that may touch a
/// wall into `wall_candidates`, in index order.
pub(crate) fn run<M: Motion>(
    flight: &Kernel<M>,
    p: &mut Particles,
    (t0, t1): (f64, f64),
    next: &mut Next,
    wall_candidates: &mut Vec<u32>,
) -> PassResult {
    let n = p.len();
    next.resize(n, flight.rotation());
    let width = flight.memory_width();
    if let Some(width) = width {
        next.memory.resize(n * width, 0.0);
    }
    let (pos, kind, diameter, release_time, release_vel) =
        (&p.pos, &p.kind, &p.diameter, &p.release_time, &p.release_vel);
    let columns = (
        p.state.par_chunks_mut(CHUNK),
        p.vel.par_chunks_mut(CHUNK),
        p.wall.par_chunks_mut(CHUNK),
        next.pos.par_chunks_mut(CHUNK),
        next.vel.par_chunks_mut(CHUNK),
        next.state.par_chunks_mut(CHUNK),
        next.wall.par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, (state, vel, wall, x1, v1, s1, w1))| {
            // Every column as a slice of the chunk's length, so the loops have no bounds checks.
            let (base, len) = (c * CHUNK, state.len());
            let range = base..base + len;
            Columns {
                base,
                pos: &pos[range.clone()],
                kind: &kind[range.clone()],
                diameter: &diameter[range.clone()],
                release_time: &release_time[range.clone()],
                release_vel: &release_vel[range.clone()],
                state,
                vel: &mut vel[..len],
                wall: &mut wall[..len],
                x1: &mut x1[..len],
                v1: &mut v1[..len],
                s1: &mut s1[..len],
                w1: &mut w1[..len],
            }
        });
    let chunks: Vec<Chunk> = match width {
        None => columns
            .map(|cols| {
                if !cols.state.iter().all(|&s| s == State::Free) {
                    mixed_chunk(flight, cols, t0, t1, Forgetting)
                } else if flight.lubricated() {
                    // A copy of its own, so that a scene without the effect keeps its loop.
                    free_chunk::<M, true>(flight, cols, t0, t1)
                } else {
                    free_chunk::<M, false>(flight, cols, t0, t1)
                }
            })
            .collect(),
        // With the history effect every particle's memory at t1 is written too.
        Some(width) => columns
            .zip(next.memory.par_chunks_mut(CHUNK * width))
            .map(|(cols, out)| {
                if cols.state.iter().zip(cols.release_time).all(|(&s, &t)| s == State::Free && t <= t0) {
                    remembering_free_chunk(flight, cols, t0, t1, Remembering { out, width })
                } else {
                    mixed_chunk(flight, cols, t0, t1, Remembering { out, width })
                }
            })
            .collect(),
    };
    wall_candidates.clear();
    let mut result = PassResult { step_move: 0.0, suspect: false };
    for chunk in chunks {
        wall_candidates.extend(chunk.candidates);
        result.step_move = result.step_move.max(chunk.step_move);
        result.suspect |= chunk.suspect;
    }
    result.step_move = result.step_move.sqrt();
    result
}

/// Stage 2 for spins, in a scene with rotation only (docs/physics.md §9): every particle's spin
/// relaxed by the fluid's torque over the step (`Kernel::spin_after`), into `next.omega`. A
/// pass of its own, not in the loops above: translation does not depend on spin, and a scene
/// without rotation must keep those loops as they are.
pub(crate) fn spin<M: Motion>(flight: &Kernel<M>, p: &Particles, h: f64, next: &mut Next) {
    let (kind, diameter, pos, omega) = (&p.kind, &p.diameter, &p.pos, p.omega.values());
    next.omega.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
        // The decay factor of the last kind and diameter: particles come in runs of one kind
        // and size (a bed, an injector's stream), and its exponential was a third of this
        // pass (callgrind, the scaling tool's `pairs5-friction`). The same value either way.
        let mut last: Option<((u16, f64), Option<f64>)> = None;
        for (j, o) in out.iter_mut().enumerate() {
            let i = c * CHUNK + j;
            let key = (kind[i], diameter[i]);
            let decay = match last {
                Some((k, decay)) if k == key => decay,
                _ => {
                    let decay = flight.spin_decay((kind[i] as usize, diameter[i]), h);
                    last = Some((key, decay));
                    decay
                }
            };
            *o = decay.map_or(omega[i], |f| flight.spin_relaxed(pos[i], omega[i], f));
        }
    });
}

/// One chunk of the particle columns: the state at the start of the step (read), the part of
/// it that release rewrites, and the end of the step (written).
struct Columns<'a> {
    base: usize,
    pos: &'a [DVec3],
    kind: &'a [u16],
    diameter: &'a [f64],
    release_time: &'a [f64],
    release_vel: &'a [DVec3],
    state: &'a mut [State],
    vel: &'a mut [DVec3],
    wall: &'a mut [u32],
    x1: &'a mut [DVec3],
    v1: &'a mut [DVec3],
    s1: &'a mut [State],
    w1: &'a mut [u32],
}

/// A chunk of free particles only (the bulk of a dilute scene): 1. has nothing to release,
/// 2. is one integrator step, 3. one test per wall. A loop of its own, so that the compiler
/// keeps its few values in registers. Compiled twice, for AVX2 and for any x86-64 (or other
/// target), and picked at run time by `multiversion`: the same operations, so the same bits.
/// Everything it calls in the loops must be inlined (`#[inline(always)]`, no `Iterator`
/// adaptor with a closure, no `<[T; N]>::map`): a call out of the AVX2 copy runs without AVX2
/// and passes its values through memory.
#[multiversion(targets("x86_64+avx2"))]
fn free_chunk<M: Motion, const LUBRICATED: bool>(
    flight: &Kernel<M>,
    mut c: Columns,
    t0: f64,
    t1: f64,
) -> Chunk {
    // Free at the start of the step: released, if ever, before t0.
    debug_assert!(c.release_time.iter().all(|&t| t <= t0));
    // 2. alone first, by lane groups of four particles where that pays (`crate::numeric::lanes`), the
    // few left over one by one: the same operations either way, so the same bits.
    let h = t1 - t0;
    let by_lanes = by_lanes(flight, c.pos.len(), selected_target!());
    let (pos, vel, kind, diameter, x1, v1) = lane_groups(&mut c, by_lanes);
    for (((((x, v), k), d), x1), v1) in pos.iter().zip(vel).zip(kind).zip(diameter).zip(x1).zip(v1) {
        let field = flight.field_lanes(*k, F64x4(*d));
        let (xn, vn) = flight.motion.advance(&field, DVec3x4::from_array(*x), DVec3x4::from_array(*v), h);
        (*x1, *v1) = (xn.to_array(), vn.to_array());
    }
    for j in by_lanes..c.pos.len() {
        let field = flight.field_of(c.kind[j] as usize, c.diameter[j], (c.base + j) as u32);
        (c.x1[j], c.v1[j]) = flight.motion.advance(&field, c.pos[j], c.vel[j], h);
    }
    c.s1.fill(State::Free);
    c.w1.fill(NO_WALL);
    // 3. (walls), and what the step needs to know of the moves.
    let mut out = Chunk::default();
    // Sum of every new coordinate: finite unless one is not (or, harmlessly, unless it
    // overflows), so one test per chunk instead of six per particle.
    let mut sum = 0.0;
    // With wall lubrication, those whose move comes within its range of a wall (the
    // near-wall set of the step, found here in the one pass over the moves) fly again, below;
    // the rest keep the lane group's flight, which is what the kernel would give them too.
    // The range's test is the wider: a move clear of it is clear of the walls too.
    // Room for every particle of the chunk at once (a chunk holds at most `CHUNK`): grown push by
    // push, its reallocations and copies took about 5 instructions per particle-step of
    // `bench_paper_lubrication` (callgrind). Only with the effect: a `Vec` without pushes does
    // not allocate.
    let mut near: Vec<usize> = if LUBRICATED { Vec::with_capacity(c.pos.len()) } else { Vec::new() };
    for j in 0..c.pos.len() {
        if LUBRICATED {
            let reach = 0.5 * c.diameter[j] * (1.0 + LUBRICATION_RANGE);
            let mut within = false;
            for w in flight.walls {
                if w.shape.may_touch(c.pos[j], c.x1[j], reach) {
                    within = true;
                    break;
                }
            }
            if within {
                near.push(j);
                continue;
            }
            let (x, xn, vn) = (c.pos[j], c.x1[j], c.v1[j]);
            sum += (xn + vn).element_sum();
            out.step_move = out.step_move.max((xn - x).length_squared());
            continue;
        }
        sum += moved(flight, &c, j, &mut out);
    }
    if LUBRICATED && !near.is_empty() {
        // A flow whose lookups walk from each particle's own cell takes them one at a time, as
        // it takes the others ([`Kernel::walks`]).
        let by_lanes = if flight.walks() { 0 } else { near.len() / LANES * LANES };
        for js in near[..by_lanes].as_chunks::<LANES>().0 {
            let (k, d) = (each(*js, |j| c.kind[j]), F64x4(each(*js, |j| c.diameter[j])));
            let field = flight.field_lanes(k, d);
            let start = (each(*js, |j| c.pos[j]), each(*js, |j| c.vel[j]));
            let fates = flight.near_wall_lanes(&field, (k, d), start, t1 - t0);
            for (&j, fate) in js.iter().zip(fates) {
                match fate {
                    NearWall::Away => {}
                    NearWall::Flown(x, v) => (c.x1[j], c.v1[j]) = (x, v),
                    NearWall::Substeps => refly(flight, &mut c, j, (t0, t1)),
                }
            }
        }
        for &j in &near[by_lanes..] {
            refly(flight, &mut c, j, (t0, t1));
        }
        for &j in &near {
            sum += moved(flight, &c, j, &mut out);
        }
        // The near-wall candidates came after the others: index order again.
        out.candidates.sort_unstable();
    }
    out.suspect = !sum.is_finite();
    out
}

/// [`free_chunk`] with the history effect: a chunk of free particles, released (if ever) before
/// `t0`, each flying the whole step from its own memory and writing its memory at `t1`, by lane
/// groups of four where that pays ([`Kernel::remembered_lanes`]), the rest one at a time (those
/// left over, and those the lanes leave to wall lubrication's sub-steps): the same operations
/// either way, so the same bits.
#[multiversion(targets("x86_64+avx2+fma"))]
fn remembering_free_chunk<M: Motion>(
    flight: &Kernel<M>,
    mut c: Columns,
    t0: f64,
    t1: f64,
    rec: Remembering,
) -> Chunk {
    let (h, width) = (t1 - t0, rec.width);
    let by_lanes = by_lanes(flight, c.pos.len(), selected_target!());
    // The two sweeps over each bead's modes in 256-bit vectors with FMA in the AVX2 copy.
    let avx = Avx::of(selected_target!());
    let mut alone: Vec<usize> = Vec::new();
    // Lane groups as arrays of four, as in `free_chunk`: indexing by `first + i` cost a bounds
    // check per column and lane, 36 instructions per bead of 1012 (callgrind, docs/performance.md).
    let base = c.base;
    let (pos, vel, kind, diameter, x1, v1) = lane_groups(&mut c, by_lanes);
    let outs = rec.out[..by_lanes * width].chunks_exact_mut(LANES * width);
    let groups = pos.iter().zip(vel).zip(kind).zip(diameter).zip(x1.iter_mut().zip(v1)).zip(outs);
    for (g, (((((x, v), k), d), (x1, v1)), out)) in groups.enumerate() {
        let first = g * LANES;
        let (k, d) = (*k, F64x4(*d));
        let field = flight.field_lanes(k, d);
        let starts = (DVec3x4::from_array(*x), DVec3x4::from_array(*v));
        match flight.remembered_lanes(&field, (k, d), starts, (base + first, h), out, avx) {
            Some((flown, xn, vn)) => {
                let (xn, vn) = (xn.to_array(), vn.to_array());
                for i in 0..LANES {
                    if flown[i] {
                        (x1[i], v1[i]) = (xn[i], vn[i]);
                    } else {
                        alone.push(first + i);
                    }
                }
            }
            None => alone.extend(first..first + LANES),
        }
    }
    alone.extend(by_lanes..c.pos.len());
    for j in alone {
        let start = Segment {
            t: t0,
            x: c.pos[j],
            v: c.vel[j],
            state: State::Free,
            wall: NO_WALL,
            memory: (c.base + j) as u32,
        };
        let out = &mut rec.out[j * width..(j + 1) * width];
        let f = flight.free_flight_remembering(start, (c.kind[j] as usize, c.diameter[j]), t1, out);
        (c.x1[j], c.v1[j]) = (f.x, f.v);
    }
    c.s1.fill(State::Free);
    c.w1.fill(NO_WALL);
    // 3. (walls)
    let mut out = Chunk::default();
    let mut sum = 0.0;
    for j in 0..c.pos.len() {
        sum += moved(flight, &c, j, &mut out);
    }
    out.suspect = !sum.is_finite();
    out
}

/// A chunk's first `n` particles (`n` a multiple of four) as lane groups: the start's
/// positions, velocities, kinds and diameters, and the ends to write, as arrays of four (no
/// bounds check per column and lane in the loops over them).
#[inline(always)]
fn lane_groups<'c>(c: &'c mut Columns, n: usize) -> LaneGroups<'c> {
    (
        c.pos[..n].as_chunks::<LANES>().0,
        c.vel[..n].as_chunks::<LANES>().0,
        c.kind[..n].as_chunks::<LANES>().0,
        c.diameter[..n].as_chunks::<LANES>().0,
        c.x1[..n].as_chunks_mut::<LANES>().0,
        c.v1[..n].as_chunks_mut::<LANES>().0,
    )
}

/// What [`lane_groups`] gives: positions, velocities, kinds, diameters; end positions and
/// velocities.
type LaneGroups<'c> = (
    &'c [[DVec3; LANES]],
    &'c [[DVec3; LANES]],
    &'c [[u16; LANES]],
    &'c [[f64; LANES]],
    &'c mut [[DVec3; LANES]],
    &'c mut [[DVec3; LANES]],
);

/// How many of a chunk's `n` particles go by lane groups, in a copy compiled for `target`: as
/// many whole groups as there are where lane groups pay, none where they do not. They pay for
/// every law where one vector instruction holds a whole group (AVX2), and otherwise for the
/// laws that say so; not in a flow whose lookups walk from each particle's cell.
#[inline(always)]
fn by_lanes<M: Motion>(flight: &Kernel<M>, n: usize, target: TargetFeatures) -> usize {
    let wide = matches!(target.suggested_simd_width::<f64>(), Some(w) if w >= LANES);
    if (M::LANE_GROUPS || wide) && !flight.walks() { n / LANES * LANES } else { 0 }
}

/// Stage 3 (walls) for free particle `j` of a chunk, flown: it becomes a wall candidate when
/// its move may touch a wall, and its move counts for the step's largest. Returns the sum of
/// its new coordinates (finite unless one is not).
#[inline(always)]
fn moved<M: Motion>(flight: &Kernel<M>, c: &Columns, j: usize, out: &mut Chunk) -> f64 {
    let (x, xn, vn, r) = (c.pos[j], c.x1[j], c.v1[j], 0.5 * c.diameter[j]);
    // `contact::touches_wall` for a free particle, written out: calling it here (with
    // the state a constant) made this loop half as fast. A plain loop, not `any`, whose
    // closure is a call of its own in the AVX2 copy of this function (also half as fast).
    for w in flight.walls {
        if w.shape.may_touch(x, xn, r) {
            out.candidates.push((c.base + j) as u32);
            break;
        }
    }
    // Squared: one square root per step, not one per particle.
    out.step_move = out.step_move.max((xn - x).length_squared());
    (xn + vn).element_sum()
}

/// Stage 2 again for free particle `j` of a chunk, whose move (straight, from the start to the
/// free flight's end) comes within the lubrication range of a wall, with the sphere grown by
/// that range: [`Kernel::free_flight`] flies it by the lubricated sub-steps when a wall is
/// within reach, and otherwise as the lane groups did. The range is ten radii, where the wall's
/// terms have tapered to zero with their slope, so a path that bends back into the range within
/// one step (by less than `|a| h²/8`) meets a wall term of the order of that bend squared.
/// Outside [`free_chunk`]'s inlined loops: it runs only in scenes with the effect.
#[inline(never)]
fn refly<M: Motion>(flight: &Kernel<M>, c: &mut Columns, j: usize, (t0, t1): (f64, f64)) {
    let start =
        Segment { t: t0, x: c.pos[j], v: c.vel[j], state: State::Free, wall: NO_WALL, memory: NO_MEMORY };
    let f = flight.free_flight(start, (c.kind[j] as usize, c.diameter[j]), t1);
    (c.x1[j], c.v1[j]) = (f.x, f.v);
}

/// How [`mixed_chunk`] flies a particle: without memory, or writing its memory at the end of
/// the step (the history effect). A type, so that the loop without memory is compiled as if
/// the effect did not exist.
trait Recorder {
    fn fly<M: Motion>(
        &mut self,
        flight: &Kernel<M>,
        start: Segment,
        kd: (usize, f64),
        t1: f64,
        j: usize,
    ) -> Flight;
}

/// Flies without memory.
struct Forgetting;

impl Recorder for Forgetting {
    #[inline(always)]
    fn fly<M: Motion>(
        &mut self,
        flight: &Kernel<M>,
        start: Segment,
        kd: (usize, f64),
        t1: f64,
        _: usize,
    ) -> Flight {
        flight.free_flight(start, kd, t1)
    }
}

/// Flies with memory, writing particle `j`'s memory at `t1` into its `width` numbers of `out`.
struct Remembering<'a> {
    out: &'a mut [f64],
    width: usize,
}

impl Recorder for Remembering<'_> {
    #[inline(always)]
    fn fly<M: Motion>(
        &mut self,
        flight: &Kernel<M>,
        start: Segment,
        kd: (usize, f64),
        t1: f64,
        j: usize,
    ) -> Flight {
        flight.free_flight_remembering(start, kd, t1, &mut self.out[j * self.width..(j + 1) * self.width])
    }
}

/// Any chunk: stages 1, 2 and 3 (walls) for particles in every state.
fn mixed_chunk<M: Motion, R: Recorder>(
    flight: &Kernel<M>,
    c: Columns,
    t0: f64,
    t1: f64,
    mut rec: R,
) -> Chunk {
    let mut out = Chunk::default();
    let mut sum = 0.0;
    for j in 0..c.pos.len() {
        let (x, k, d) = (c.pos[j], c.kind[j] as usize, c.diameter[j]);
        // 1. (walls): rewrites where the path starts.
        let memory = (c.base + j) as u32;
        let start = Segment {
            t: t0.max(c.release_time[j]),
            x,
            v: c.vel[j],
            state: c.state[j],
            wall: c.wall[j],
            memory,
        };
        let start = contact::release_at_wall(flight, start, c.release_vel[j], (k, d), t1);
        (c.state[j], c.vel[j], c.wall[j]) = (start.state, start.v, start.wall);
        // 2.
        let f = rec.fly(flight, start, (k, d), t1, j);
        (c.x1[j], c.v1[j], c.s1[j]) = (f.x, f.v, f.state);
        // A resting particle that slid off its wall has none.
        c.w1[j] = if f.state == State::Free { NO_WALL } else { start.wall };
        sum += (f.x + f.v).element_sum();
        // 3. (walls)
        if contact::touches_wall(flight.walls, (x, f.x), start.state, start.wall, d) {
            out.candidates.push((c.base + j) as u32);
        }
        out.step_move = out.step_move.max((f.x - x).length_squared());
    }
    out.suspect = !sum.is_finite();
    out
}

/// One chunk's share of [`PassResult`] (squared distances) and its wall candidates.
#[derive(Default)]
struct Chunk {
    candidates: Vec<u32>,
    step_move: f64,
    suspect: bool,
}
