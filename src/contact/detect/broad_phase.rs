//! Stage 3, the broad phase: which particles' straight moves may touch a wall, and which
//! neighbour pairs may touch each other.

use super::neighbours::Neighbours;
use crate::contact::{FastSet, LastingContact};
use crate::particles::{Next, Particles, State};
use crate::walls::{Surface, Wall};
use glam::DVec3;
use rayon::prelude::*;

/// Whether a particle's straight move from `x0` to `x1` may touch a wall other than the one it
/// rests on (walls are few and static; each answers with a closed-form test or a bounding-box
/// overlap). A particle held at a wall does not move.
#[inline(always)]
pub(crate) fn touches_wall(
    walls: &[Wall],
    (x0, x1): (DVec3, DVec3),
    state: State,
    wall: u32,
    d: f64,
) -> bool {
    if state == State::Held {
        return false;
    }
    let r = 0.5 * d;
    walls
        .iter()
        .enumerate()
        .any(|(w, shape)| !(state == State::Resting && wall == w as u32) && shape.shape.may_touch(x0, x1, r))
}

/// Keeps the Verlet list valid for this step's moves (from `p.pos` to `next.pos`; `step_move`
/// is the largest of them) and writes into `candidates` the neighbour pairs whose straight moves
/// come within contact and are not already in a lasting contact.
pub(crate) fn candidate_pairs(
    p: &Particles,
    next: &Next,
    neighbours: &mut Neighbours,
    (step_move, skin_fraction): (f64, f64),
    lasting: &[LastingContact],
    candidates: &mut Vec<[u32; 2]>,
) {
    let next = &next.pos;
    candidates.clear();
    neighbours.update((&p.pos, next), &p.diameter, step_move, skin_fraction);
    if neighbours.pairs.is_empty() {
        return;
    }
    let lasting: FastSet<[u32; 2]> = lasting.iter().map(|c| [c.a, c.b]).collect();
    candidates.par_extend(neighbours.pairs.par_iter().with_min_len(1024).copied().filter(|&[a, b]| {
        let (a, b) = (a as usize, b as usize);
        // Closest approach of the two straight moves.
        let start = p.pos[a] - p.pos[b];
        let change = (next[a] - next[b]) - start;
        let lambda = (-start.dot(change) / change.length_squared()).clamp(0.0, 1.0);
        let closest = if lambda.is_finite() { start + lambda * change } else { start };
        let reach = 0.5 * (p.diameter[a] + p.diameter[b]);
        closest.length() <= reach && !lasting.contains(&[a as u32, b as u32])
    }));
}
