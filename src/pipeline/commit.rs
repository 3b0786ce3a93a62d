//! Stage 6: the step's results replace the old state; non-finite particles are taken out.

use super::{LostParticle, Scratch};
use crate::particles::{NO_WALL, PairContact, Particles, State};

/// Swaps the scratch columns in, clears the wall of the particles that slid off it (`fell`)
/// and, when an earlier stage saw a non-finite value (`suspect`), removes every particle whose
/// position or velocity is no longer finite, recording it in `lost`. Returns true when
/// particles were removed (indices changed).
pub(crate) fn run(
    p: &mut Particles,
    scratch: &mut Scratch,
    (fell, suspect): (&[u32], bool),
    t1: f64,
    lost: &mut Vec<LostParticle>,
    contacts: &mut Vec<PairContact>,
) -> bool {
    std::mem::swap(&mut p.pos, &mut scratch.next_pos);
    std::mem::swap(&mut p.vel, &mut scratch.next_vel);
    std::mem::swap(&mut p.state, &mut scratch.next_state);
    for &i in fell {
        if p.state[i as usize] == State::Free {
            p.wall[i as usize] = NO_WALL;
        }
    }
    if !suspect {
        return false;
    }
    let keep: Vec<bool> = (0..p.len()).map(|i| p.pos[i].is_finite() && p.vel[i].is_finite()).collect();
    if keep.iter().all(|&k| k) {
        return false;
    }
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
