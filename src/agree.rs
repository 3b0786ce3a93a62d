//! What the ranks of one run must agree on inside a step (docs/distributed.md).
//!
//! A run split over MPI ranks steps each rank's particles with the single-process step. Its
//! particles are whole *clusters* — particles that may touch before the next re-clustering —
//! so no contact crosses a rank, and almost every decision of the step is local. A few are not:
//! the Gauss–Seidel sweeps of the lasting contacts stop when *every* contact holds, and that
//! "every" spans the ranks; a sweep more or less changes the last bits of a bed that converged
//! first. The step asks these questions through [`Agree`]: one process answers them itself
//! ([`Alone`], the identity), ranks answer them together. The step also tells the ranks how far
//! its particles flew ([`Agree::flown`]), so that the run can check its clusters stayed apart.
//!
//! The trait lives here, below the contact stages that call it, and knows nothing of MPI.

use glam::DVec3;

/// The questions a step asks every rank of its run. The defaults are one process's answers.
pub trait Agree {
    /// The largest `x` over the ranks.
    fn max(&self, x: f64) -> f64 {
        x
    }

    /// Whether `b` holds on any rank.
    fn any(&self, b: bool) -> bool {
        b
    }

    /// After the free flight (stage 2): the largest move of the step (m), and where each
    /// particle starts and where the free flight took it by the end of the step, in index order.
    fn flown(&self, _step_move: f64, _paths: (&[DVec3], &[DVec3])) {}
}

/// One process: every answer is its own.
#[derive(Debug, Clone, Copy, Default)]
pub struct Alone;

impl Agree for Alone {}
