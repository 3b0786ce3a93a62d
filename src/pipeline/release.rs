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
            // On the wall the velocity is tangent: a normal part left by round-off or by the
            // contact solver would otherwise put a drag force across the wall.
            let vt = *vel - vel.dot(n) * n;
            let a = ctx.field(k, d).eval(x, vt).total(vt);
            // "Points away" beyond round-off: on a side wall gravity is tangent, and the sign
            // of a zero would free and re-deposit the particle at every step.
            if a.dot(n) > 1e-9 * a.length() {
                *state = State::Free;
                *wall = NO_WALL;
            }
        }
    }
}
