//! Stage 3: which particles' paths may touch a wall.

use super::{Ctx, Motion, Scratch};
use crate::particles::{Particles, State};
use crate::walls::Surface;
use rayon::prelude::*;

/// Collects, in index order, the particles whose straight move from `pos` to `next_pos` may
/// touch a wall other than the one they rest on. Walls are few and static; each answers with
/// a closed-form test or a bounding-box overlap.
pub(crate) fn run<M: Motion>(ctx: &Ctx<M>, p: &Particles, scratch: &mut Scratch) {
    let next = &scratch.next_pos;
    scratch.candidates.clear();
    scratch.candidates.par_extend(
        (0..p.len() as u32)
            .into_par_iter()
            .with_min_len(1024)
            .filter(|&i| {
                let i = i as usize;
                let state = p.state[i];
                if state == State::Held {
                    return false;
                }
                let r = 0.5 * p.diameter[i];
                ctx.walls.iter().enumerate().any(|(w, wall)| {
                    !(state == State::Resting && p.wall[i] == w as u32)
                        && wall.shape.may_touch(p.pos[i], next[i], r)
                })
            }),
    );
}
