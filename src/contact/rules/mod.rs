//! The bounce rule of docs/physics.md §5 (L06 §4): the Stokes number once per contact, the
//! restitution, the contact time and the outcome — held, bounced or deposited — for a particle
//! on a wall ([`wall`]) and for two particles ([`pair`], **[ext]**); with friction, the
//! tangential impulse and the spin of Walton's model ([`friction`], **[ext]**).

pub mod friction;
mod pair;
mod wall;

pub use friction::{Friction, Spinning, Tangential, tangential_impulse};
pub use pair::{PairBody, PairImpact, pair_impact};
pub use wall::{BounceRule, Impact, wall_impact};
