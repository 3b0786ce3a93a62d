//! Stage 6: the step's results replace the old state; non-finite particles are taken out.

use crate::contact::LastingContact;
use crate::contact::lasting::remove_particles;
use crate::particles::{Features, Next, Particles, feature};

/// A particle whose state became non-finite and was taken out of the simulation.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LostParticle {
    /// Simulated time at the end of the step where it was found (s).
    pub time: f64,
    /// Its id.
    pub id: u32,
}

/// Swaps `next` into `p` ([`Particles::commit`]), runs the features' commit and, when an earlier stage saw a non-finite
/// value (`suspect`), removes every particle whose position or velocity is no longer finite,
/// recording it in `lost` at `t1`. Returns true when particles were removed (indices changed).
pub(crate) fn run(
    (p, features): (&mut Particles, &Features),
    next: &mut Next,
    suspect: bool,
    t1: f64,
    lost: &mut Vec<LostParticle>,
    lasting: &mut Vec<LastingContact>,
) -> bool {
    p.commit(next);
    feature::commit(features, p);
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
    remove_particles(p, &keep, lasting);
    true
}
