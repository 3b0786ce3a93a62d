//! Stage 2: free flight of every particle over its part of the step.

use super::{Ctx, Motion, Scratch, Segment, fly};
use crate::particles::{Particles, State};
use glam::DVec3;
use rayon::prelude::*;

/// Integrates every free or resting particle from `max(t0, release time)` to `t1`, into the
/// scratch columns `next_*`; held particles stay where they are.
pub(crate) fn run<M: Motion>(ctx: &Ctx<M>, p: &Particles, t0: f64, t1: f64, scratch: &mut Scratch) {
    let n = p.len();
    scratch.next_pos.resize(n, DVec3::ZERO);
    scratch.next_vel.resize(n, DVec3::ZERO);
    scratch.next_state.resize(n, State::Free);
    (
        &mut scratch.next_pos,
        &mut scratch.next_vel,
        &mut scratch.next_state,
        (&p.pos, &p.vel, &p.state, &p.wall, &p.release_time, &p.kind, &p.diameter),
    )
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(x1, v1, s1, (&x, &v, &state, &wall, &t_release, &k, &d))| {
            let start = t0.max(t_release);
            let seg = Segment { t: start, x, v, state, wall };
            let f = fly(ctx, &ctx.field(k as usize, d), 0.5 * d, &seg, t1 - start);
            (*x1, *v1, *s1) = (f.x, f.v, f.state);
        });
}
