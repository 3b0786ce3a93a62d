//! Stage 3: which particles' paths may touch a wall, and which pairs may touch each other.

use super::neighbours::Neighbours;
use super::{Ctx, Motion, Scratch};
use crate::particles::{NO_WALL, PairContact, Particles, State};
use crate::walls::Surface;
use rayon::prelude::*;
use std::collections::HashSet;

/// Collects, in index order, the particles whose straight move from `pos` to `next_pos` may
/// touch a wall other than the one they rest on (walls are few and static; each answers with a
/// closed-form test or a bounding-box overlap); in the same pass measures how far particles
/// moved, keeps the Verlet list valid (`neighbours`, when pairs collide), and collects the
/// neighbour pairs whose straight moves come within contact and are not already in a lasting
/// contact.
pub(crate) fn run<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    scratch: &mut Scratch,
    neighbours: Option<&mut Neighbours>,
    skin_fraction: f64,
    contacts: &[PairContact],
) {
    let next = &scratch.next_pos;
    let reference = neighbours.as_ref().map_or(&[][..], |nb| nb.reference());
    let has_reference = reference.len() == p.len();
    // One pass: wall candidates, and the largest moves for the Verlet list.
    let (candidates, moved, step_move) = (0..p.len())
        .into_par_iter()
        .with_min_len(2048)
        .fold(
            || (Vec::new(), 0.0f64, 0.0f64),
            |(mut list, moved, step), i| {
                // Squared distances: one square root per step instead of two per particle.
                let from_reference =
                    if has_reference { (next[i] - reference[i]).length_squared() } else { f64::INFINITY };
                let step_i = (next[i] - p.pos[i]).length_squared();
                let state = p.state[i];
                let immobile = state == State::Held && p.wall[i] != NO_WALL;
                let r = 0.5 * p.diameter[i];
                let touches = !immobile
                    && ctx.walls.iter().enumerate().any(|(w, wall)| {
                        !(state == State::Resting && p.wall[i] == w as u32)
                            && wall.shape.may_touch(p.pos[i], next[i], r)
                    });
                if touches {
                    list.push(i as u32);
                }
                (list, moved.max(from_reference), step.max(step_i))
            },
        )
        .reduce(
            || (Vec::new(), 0.0, 0.0),
            |(mut a, ma, sa), (b, mb, sb)| {
                a.extend(b);
                (a, ma.max(mb), sa.max(sb))
            },
        );
    scratch.candidates = candidates;
    let (moved, step_move) = (moved.sqrt(), step_move.sqrt());
    scratch.pair_candidates.clear();
    let Some(neighbours) = neighbours else { return };
    neighbours.update(&p.pos, &p.diameter, moved, step_move, skin_fraction);
    if neighbours.pairs.is_empty() {
        return;
    }
    let lasting: HashSet<[u32; 2]> = contacts.iter().map(|c| [c.a, c.b]).collect();
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
