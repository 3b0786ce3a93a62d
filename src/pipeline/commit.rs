//! Stage 6: the step's results replace the old state; non-finite particles are taken out.

use super::{LostParticle, Scratch};
use crate::particles::{NO_WALL, Particles, State};
use rayon::prelude::*;

/// Swaps the scratch columns in, clears the wall of particles that became free, and removes
/// any particle whose position or velocity is no longer finite, recording it in `lost`.
pub(crate) fn run(p: &mut Particles, scratch: &mut Scratch, t1: f64, lost: &mut Vec<LostParticle>) {
    std::mem::swap(&mut p.pos, &mut scratch.next_pos);
    std::mem::swap(&mut p.vel, &mut scratch.next_vel);
    std::mem::swap(&mut p.state, &mut scratch.next_state);
    let any_bad = (&p.state, &mut p.wall, &p.pos, &p.vel)
        .into_par_iter()
        .with_min_len(4096)
        .map(|(&s, wall, x, v)| {
            if s == State::Free {
                *wall = NO_WALL;
            }
            !(x.is_finite() && v.is_finite())
        })
        .reduce(|| false, |a, b| a || b);
    if any_bad {
        // Rare: walk from the end so swap_remove does not skip a particle.
        for i in (0..p.len()).rev() {
            if !(p.pos[i].is_finite() && p.vel[i].is_finite()) {
                lost.push(LostParticle {
                    time: t1,
                    id: p.id[i],
                });
                p.swap_remove(i);
            }
        }
    }
}
