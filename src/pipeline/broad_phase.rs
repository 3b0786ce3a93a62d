//! Stage 3: which particles' paths may touch a wall, and which pairs may touch each other.

use super::{Ctx, Motion, Scratch};
use crate::particles::{NO_WALL, PairContact, Particles, State};
use crate::walls::Surface;
use rayon::prelude::*;
use std::collections::HashSet;

/// Collects, in index order, the particles whose straight move from `pos` to `next_pos` may
/// touch a wall other than the one they rest on (walls are few and static; each answers with a
/// closed-form test or a bounding-box overlap), and the neighbour pairs whose straight moves
/// come within contact and are not already in a lasting contact.
pub(crate) fn run<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    scratch: &mut Scratch,
    neighbour_pairs: &[[u32; 2]],
    contacts: &[PairContact],
) {
    let next = &scratch.next_pos;
    scratch.candidates.clear();
    scratch.candidates.par_extend((0..p.len() as u32).into_par_iter().with_min_len(1024).filter(|&i| {
        let i = i as usize;
        let state = p.state[i];
        if state == State::Held && p.wall[i] != NO_WALL {
            return false;
        }
        let r = 0.5 * p.diameter[i];
        ctx.walls.iter().enumerate().any(|(w, wall)| {
            !(state == State::Resting && p.wall[i] == w as u32) && wall.shape.may_touch(p.pos[i], next[i], r)
        })
    }));
    scratch.pair_candidates.clear();
    if neighbour_pairs.is_empty() {
        return;
    }
    let lasting: HashSet<[u32; 2]> = contacts.iter().map(|c| [c.a, c.b]).collect();
    scratch.pair_candidates.par_extend(neighbour_pairs.par_iter().with_min_len(1024).copied().filter(
        |&[a, b]| {
            let (a, b) = (a as usize, b as usize);
            // Closest approach of the two straight moves.
            let start = p.pos[a] - p.pos[b];
            let change = (next[a] - next[b]) - start;
            let lambda = (-start.dot(change) / change.length_squared()).clamp(0.0, 1.0);
            let closest = if lambda.is_finite() { start + lambda * change } else { start };
            let reach = 0.5 * (p.diameter[a] + p.diameter[b]);
            closest.length() <= reach && !lasting.contains(&[a as u32, b as u32])
        },
    ));
}
