//! Stage 3: which particles' paths may touch a wall, and which pairs may touch each other.

use super::neighbours::Neighbours;
use super::{Ctx, Motion, Scratch};
use crate::particles::{NO_WALL, PairContact, Particles, State};
use crate::walls::Surface;
use glam::DVec3;
use rayon::prelude::*;

/// Whether a particle's straight move from `x0` to `x1` may touch a wall other than the one it
/// rests on (walls are few and static; each answers with a closed-form test or a bounding-box
/// overlap). A particle held at a wall does not move.
#[inline(always)]
pub(crate) fn touches_wall<M: Motion>(
    ctx: &Ctx<M>,
    (x0, x1): (DVec3, DVec3),
    state: State,
    wall: u32,
    d: f64,
) -> bool {
    if state == State::Held && wall != NO_WALL {
        return false;
    }
    let r = 0.5 * d;
    ctx.walls
        .iter()
        .enumerate()
        .any(|(w, shape)| !(state == State::Resting && wall == w as u32) && shape.shape.may_touch(x0, x1, r))
}

/// Keeps the Verlet list valid for this step's moves (`step_move`: the largest of them) and collects
/// the neighbour pairs whose straight moves come within contact and are not already in a
/// lasting contact.
pub(crate) fn pairs(
    p: &Particles,
    scratch: &mut Scratch,
    neighbours: &mut Neighbours,
    step_move: f64,
    skin_fraction: f64,
    contacts: &[PairContact],
) {
    let next = &scratch.next_pos;
    scratch.pair_candidates.clear();
    neighbours.update((&p.pos, next), &p.diameter, step_move, skin_fraction);
    if neighbours.pairs.is_empty() {
        return;
    }
    let lasting: super::FastSet<[u32; 2]> = contacts.iter().map(|c| [c.a, c.b]).collect();
    scratch.pair_candidates.par_extend(neighbours.pairs.par_iter().with_min_len(1024).copied().filter(
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
