//! Stage 2: free flight of every particle over its part of the step.

use super::{Ctx, Flight, Motion, Segment, fly};
use crate::particles::State;
use glam::DVec3;

/// Integrates a free or resting particle from `max(t0, release time)` to `t1`; a particle held
/// at a wall stays where it is.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn particle<M: Motion>(
    ctx: &Ctx<M>,
    (x, v): (DVec3, DVec3),
    (state, wall): (State, u32),
    t_release: f64,
    (k, d): (usize, f64),
    t0: f64,
    t1: f64,
) -> Flight {
    let start = t0.max(t_release);
    let seg = Segment { t: start, x, v, state, wall };
    fly(ctx, &ctx.field(k, d), 0.5 * d, &seg, t1 - start)
}
