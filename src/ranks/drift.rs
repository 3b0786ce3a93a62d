//! How far a rank's particles moved since their clusters were found: what a step tells the
//! ranks of its free flight ([`Agreeing`]), and the references kept through removals.

use super::comm::Comm;
use crate::agree::Agree;
use glam::DVec3;
use std::cell::Cell;

/// What a step asks the ranks, and what it tells them of its moves.
pub(super) struct Agreeing<'a> {
    pub comm: &'a dyn Comm,
    pub reference: &'a [DVec3],
    /// A bound on every particle's distance from its reference at the start of the step (m).
    pub drift: f64,
    pub half_skin: f64,
    /// The step's largest free-flight move, and how far the farthest particle may have gone
    /// from its reference by the end of the step (m), over the ranks.
    pub flown: Cell<(f64, f64)>,
}

impl Agree for Agreeing<'_> {
    fn max(&self, x: f64) -> f64 {
        self.comm.max(x)
    }

    fn any(&self, b: bool) -> bool {
        self.comm.any(b)
    }

    fn flown(&self, step_move: f64, (start, end): (&[DVec3], &[DVec3])) {
        let moved = self.comm.max(step_move);
        // A path stays within its move of its start (twice, for a curved one). The bound costs
        // nothing; only when it is spent is each particle measured.
        let mut reach = self.drift + 2.0 * moved;
        if reach >= self.half_skin {
            let mut farthest = 0.0f64;
            for ((s, e), r) in start.iter().zip(end).zip(self.reference) {
                farthest = farthest.max((*s - *r).length() + 2.0 * (*e - *s).length());
            }
            reach = self.comm.max(farthest);
        }
        self.flown.set((moved, reach));
    }
}

/// The references (`ids_then`, `reference`) of the particles `ids` still here: removals only,
/// every list in id order.
pub(super) fn realign(ids: &[u32], (ids_then, reference): (&[u32], &[DVec3])) -> (Vec<DVec3>, Vec<u32>) {
    let mut kept = Vec::with_capacity(ids.len());
    let mut k = 0;
    for &id in ids {
        while ids_then[k] != id {
            k += 1;
        }
        kept.push(reference[k]);
    }
    (kept, ids.to_vec())
}
