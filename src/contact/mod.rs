//! Contact: where inside a step a particle meets a wall, and what the bounce rule does then.
//!
//! - [`locate`]: the time of impact on the particle's curved path inside the step, from the
//!   chord test of [`crate::walls::Surface::sweep`];
//! - [`response`]: the bounce rule of PHYSICS.md §5 (L06 §4) — Stokes number once per contact,
//!   restitution, contact time, and the outcome: held, bounced or deposited;
//! - [`pair`]: the same rule on the relative motion of two particles **[ext]**;
//! - [`end_of_step`]: the alternative, end-of-step detection of wall contacts, for the
//!   accuracy study only.

pub mod end_of_step;
mod locate;
mod pair;
mod response;

pub use end_of_step::ImpactLocation;
pub use locate::locate_on_path;
pub use pair::{PairBody, PairImpact, pair_impact};
pub use response::{BounceRule, Impact, wall_impact};
