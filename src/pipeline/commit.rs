//! Stage 6: the step's results replace the old state; non-finite particles are taken out.

use super::{LostParticle, Scratch};
use crate::particles::{NO_WALL, PairContact, Particles, State};
use rayon::prelude::*;

/// Swaps the scratch columns in, clears the wall of particles that became free, and removes
/// any particle whose position or velocity is no longer finite, recording it in `lost`.
/// Returns true when particles were removed (indices changed).
pub(crate) fn run(
    p: &mut Particles,
    scratch: &mut Scratch,
    t1: f64,
    lost: &mut Vec<LostParticle>,
    contacts: &mut Vec<PairContact>,
) -> bool {
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
    if !any_bad {
        return false;
    }
    let keep: Vec<bool> = (0..p.len()).map(|i| p.pos[i].is_finite() && p.vel[i].is_finite()).collect();
    for i in (0..p.len()).filter(|&i| !keep[i]) {
        lost.push(LostParticle { time: t1, id: p.id[i] });
    }
    remove(p, &keep, contacts);
    true
}

/// Keeps the particles with `keep[i]`, in order, and renumbers the pair contacts (dropping
/// those of removed particles).
pub(crate) fn remove(p: &mut Particles, keep: &[bool], contacts: &mut Vec<PairContact>) {
    let mut new_index = vec![u32::MAX; keep.len()];
    let mut n = 0;
    for (i, &k) in keep.iter().enumerate() {
        if k {
            new_index[i] = n;
            n += 1;
        }
    }
    p.retain(keep);
    contacts.retain_mut(|c| {
        let (a, b) = (new_index[c.a as usize], new_index[c.b as usize]);
        (c.a, c.b) = (a, b);
        a != u32::MAX && b != u32::MAX
    });
}
