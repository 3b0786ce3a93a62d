//! Stages 1, 2 and the wall part of 3, fused into one parallel pass over the particle columns,
//! so that each particle's data is read once per step: for every particle, in order,
//! [`release::particle`], [`free_flight::particle`] and [`broad_phase::touches_wall`].

use super::{Ctx, Motion, Scratch, broad_phase, free_flight, release};
use crate::particles::{Particles, State};
use glam::DVec3;
use rayon::prelude::*;

/// Particles per parallel task: large enough to hide the scheduling, small enough to share 2
/// cores evenly for a few thousand particles. Fixed, so results never depend on the threads.
const CHUNK: usize = 1024;

/// What the pass found besides the new states.
pub(crate) struct PassResult {
    /// The largest distance of an end of step from the Verlet reference (∞ without one).
    pub moved: f64,
    /// The largest move of the step.
    pub step_move: f64,
    /// Particles that slid off their wall in free flight (their wall is cleared at commit).
    pub fell: Vec<u32>,
    /// Some particle's new state may not be finite (commit then checks each one).
    pub suspect: bool,
}

/// Runs the fused stages over all particles. Fills `scratch.next_*` and `scratch.candidates`
/// (the particles that may touch a wall, in index order).
pub(crate) fn run<M: Motion>(
    ctx: &Ctx<M>,
    p: &mut Particles,
    t0: f64,
    t1: f64,
    scratch: &mut Scratch,
    reference: &[DVec3],
) -> PassResult {
    let n = p.len();
    scratch.next_pos.resize(n, DVec3::ZERO);
    scratch.next_vel.resize(n, DVec3::ZERO);
    scratch.next_state.resize(n, State::Free);
    let has_reference = reference.len() == n;
    let (pos, kind, diameter, release_time, release_vel) =
        (&p.pos, &p.kind, &p.diameter, &p.release_time, &p.release_vel);
    let chunks: Vec<Chunk> = (
        p.state.par_chunks_mut(CHUNK),
        p.vel.par_chunks_mut(CHUNK),
        p.wall.par_chunks_mut(CHUNK),
        scratch.next_pos.par_chunks_mut(CHUNK),
        scratch.next_vel.par_chunks_mut(CHUNK),
        scratch.next_state.par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .enumerate()
        .map(|(c, (state, vel, wall, x1, v1, s1))| {
            // Every column as a slice of the chunk's length, so the loop has no bounds checks.
            let (base, len) = (c * CHUNK, state.len());
            let range = base..base + len;
            let (pos, kind, diameter) = (&pos[range.clone()], &kind[range.clone()], &diameter[range.clone()]);
            let (release_time, release_vel) = (&release_time[range.clone()], &release_vel[range.clone()]);
            let reference = if has_reference { &reference[range] } else { &[] };
            let (vel, wall, x1, v1, s1) =
                (&mut vel[..len], &mut wall[..len], &mut x1[..len], &mut v1[..len], &mut s1[..len]);
            let mut out = Chunk::default();
            // Sum of every new coordinate: finite unless one is not (or, harmlessly, unless it
            // overflows), so one test per chunk instead of six per particle.
            let mut sum = 0.0;
            for j in 0..len {
                let (x, k, d) = (pos[j], kind[j] as usize, diameter[j]);
                // 1.
                release::particle(
                    ctx,
                    &mut state[j],
                    &mut vel[j],
                    &mut wall[j],
                    (release_time[j], release_vel[j]),
                    x,
                    (k, d),
                    t1,
                );
                // 2.
                let f = free_flight::particle(
                    ctx,
                    (x, vel[j]),
                    (state[j], wall[j]),
                    release_time[j],
                    (k, d),
                    t0,
                    t1,
                );
                (x1[j], v1[j], s1[j]) = (f.x, f.v, f.state);
                sum += (f.x + f.v).element_sum();
                if f.state == State::Free && state[j] == State::Resting {
                    out.fell.push((base + j) as u32);
                }
                // 3. (walls). Squared distances: one square root per step, not two per particle.
                if broad_phase::touches_wall(ctx, (x, f.x), state[j], wall[j], d) {
                    out.candidates.push((base + j) as u32);
                }
                let from_reference =
                    if has_reference { (f.x - reference[j]).length_squared() } else { f64::INFINITY };
                out.moved = out.moved.max(from_reference);
                out.step_move = out.step_move.max((f.x - x).length_squared());
            }
            out.suspect = !sum.is_finite();
            out
        })
        .collect();
    scratch.candidates.clear();
    let mut result = PassResult { moved: 0.0, step_move: 0.0, fell: Vec::new(), suspect: false };
    for chunk in chunks {
        scratch.candidates.extend(chunk.candidates);
        result.fell.extend(chunk.fell);
        result.moved = result.moved.max(chunk.moved);
        result.step_move = result.step_move.max(chunk.step_move);
        result.suspect |= chunk.suspect;
    }
    (result.moved, result.step_move) = (result.moved.sqrt(), result.step_move.sqrt());
    result
}

/// One chunk's share of [`PassResult`] (squared distances) and its wall candidates.
#[derive(Default)]
struct Chunk {
    candidates: Vec<u32>,
    fell: Vec<u32>,
    moved: f64,
    step_move: f64,
    suspect: bool,
}
