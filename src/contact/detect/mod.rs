//! Which particles may touch, and when.
//!
//! - [`touches_wall`] and [`candidate_pairs`]: the broad phase of a step (closed-form wall
//!   tests on each straight move; the pairs of a Verlet [`Neighbours`] list whose straight
//!   moves come within contact);
//! - [`locate_on_path`]: the time of impact on the integrator's curved path, from the chord
//!   test of [`crate::walls::Surface::sweep`];
//! - [`end_of_step`]: the alternative, end-of-step detection of wall contacts, for the
//!   accuracy study only;
//! - `PlacedSpheres`: which particles already placed a new one may overlap (the random fill,
//!   the injectors), binned by size like the neighbour list.

mod broad_phase;
pub mod end_of_step;
mod locate;
pub mod neighbours;
mod placing;

pub use end_of_step::ImpactLocation;
pub use locate::locate_on_path;
pub use neighbours::Neighbours;

pub(crate) use broad_phase::{candidate_pairs, touches_wall};
pub(crate) use placing::PlacedSpheres;
