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

/// Runs the fused stages over all particles. Fills `scratch.next_*` and `scratch.candidates`
/// (the particles that may touch a wall, in index order) and returns the largest distance of an
/// end of step from `reference` (∞ without a reference) and the largest move of the step.
pub(crate) fn run<M: Motion>(
    ctx: &Ctx<M>,
    p: &mut Particles,
    t0: f64,
    t1: f64,
    scratch: &mut Scratch,
    reference: &[DVec3],
) -> (f64, f64) {
    let n = p.len();
    scratch.next_pos.resize(n, DVec3::ZERO);
    scratch.next_vel.resize(n, DVec3::ZERO);
    scratch.next_state.resize(n, State::Free);
    let has_reference = reference.len() == n;
    let (pos, kind, diameter, release_time, release_vel) =
        (&p.pos, &p.kind, &p.diameter, &p.release_time, &p.release_vel);
    let chunks: Vec<(Vec<u32>, f64, f64)> = (
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
            let mut candidates = Vec::new();
            let (mut moved, mut step_move) = (0.0f64, 0.0f64);
            for j in 0..state.len() {
                let i = c * CHUNK + j;
                let (x, k, d) = (pos[i], kind[i] as usize, diameter[i]);
                // 1.
                release::particle(
                    ctx,
                    &mut state[j],
                    &mut vel[j],
                    &mut wall[j],
                    (release_time[i], release_vel[i]),
                    x,
                    (k, d),
                    t1,
                );
                // 2.
                let f = free_flight::particle(
                    ctx,
                    (x, vel[j]),
                    (state[j], wall[j]),
                    release_time[i],
                    (k, d),
                    t0,
                    t1,
                );
                (x1[j], v1[j], s1[j]) = (f.x, f.v, f.state);
                // 3. (walls). Squared distances: one square root per step, not two per particle.
                if broad_phase::touches_wall(ctx, (x, f.x), state[j], wall[j], d) {
                    candidates.push(i as u32);
                }
                let from_reference =
                    if has_reference { (f.x - reference[i]).length_squared() } else { f64::INFINITY };
                moved = moved.max(from_reference);
                step_move = step_move.max((f.x - x).length_squared());
            }
            (candidates, moved, step_move)
        })
        .collect();
    scratch.candidates.clear();
    let (mut moved, mut step_move) = (0.0f64, 0.0f64);
    for (list, m, s) in chunks {
        scratch.candidates.extend(list);
        moved = moved.max(m);
        step_move = step_move.max(s);
    }
    (moved.sqrt(), step_move.sqrt())
}
