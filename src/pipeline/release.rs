//! Stage 1: contacts that end at the start of the step.

use super::{Ctx, Motion};
use crate::integrate::ForceField;
use crate::particles::{NO_WALL, Particles, State};
use crate::walls::Surface;
use rayon::prelude::*;

/// Releases held particles whose release time falls before `t1` (their free flight then
/// starts at the release time, see [`super::free_flight`]), and frees resting particles whose
/// net force points away from their wall (PHYSICS.md §5.2).
pub(crate) fn run<M: Motion>(ctx: &Ctx<M>, p: &mut Particles, t1: f64) {
    (&mut p.state, &mut p.vel, &mut p.wall, &p.release_time, &p.release_vel, &p.pos, &p.kind, &p.diameter)
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(state, vel, wall, &t_release, &v_release, &x, &k, &d)| match *state {
            State::Free => {}
            // Held at a wall; a pair's hold ends in `persistent::release`.
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
                let a = ctx.field(k as usize, d).eval(x, *vel).total(*vel);
                if a.dot(n) > 0.0 {
                    *state = State::Free;
                    *wall = NO_WALL;
                }
            }
        });
}
