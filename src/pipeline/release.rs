//! Stage 1: contacts that end at the start of the step.

use super::{Ctx, Motion};
use crate::integrate::ForceField;
use crate::particles::{NO_WALL, State};
use crate::walls::Surface;
use glam::DVec3;

/// Releases a particle held at a wall whose release time falls before `t1` (its free flight
/// then starts at the release time, see [`super::free_flight`]), and frees a resting particle
/// whose net force points away from its wall (PHYSICS.md §5.2). A pair's hold ends in
/// [`super::persistent::release`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn particle<M: Motion>(
    ctx: &Ctx<M>,
    state: &mut State,
    vel: &mut DVec3,
    wall: &mut u32,
    (t_release, v_release): (f64, DVec3),
    x: DVec3,
    (k, d): (usize, f64),
    t1: f64,
) {
    match *state {
        State::Free => {}
        State::Held if *wall != NO_WALL => {
            if t_release < t1 {
                *state = State::Free;
                *vel = v_release;
                *wall = NO_WALL;
            }
        }
        State::Held => {}
        State::Resting => {
            let n = ctx.walls[*wall as usize].shape.gap(x, 0.5 * d).normal;
            let a = ctx.field(k, d).eval(x, *vel).total(*vel);
            if a.dot(n) > 0.0 {
                *state = State::Free;
                *wall = NO_WALL;
            }
        }
    }
}
