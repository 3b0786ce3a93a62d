//! Everything about contacts, in one room: which particles may touch, when they touch inside a
//! step, what the bounce rule does then, and the contacts that last.
//!
//! - [`detect`]: the broad phase (wall candidates by closed-form tests, particle pairs from a
//!   Verlet [`Neighbours`] list) and the time of impact on the curved path
//!   ([`locate_on_path`]), or at the end of the step for the accuracy study
//!   ([`ImpactLocation::EndOfStep`]);
//! - [`rules`]: the bounce rule of docs/physics.md §5 for a wall ([`wall_impact`]) and for a pair
//!   of particles ([`pair_impact`], **[ext]**), with the scene's [`BounceRule`];
//! - `in_step`: the contacts inside a step — islands of particles that may touch, each
//!   resolved event by event in time order from a queue, the rest of the step integrated from
//!   each contact point;
//! - [`lasting`]: contacts that outlast an event ([`LastingContact`]: a pair held together, or
//!   resting on each other after an impact below `St_c`), kept by projection;
//! - `release`: the contacts that end (holds whose time is over, resting particles pulled off
//!   their wall);
//! - [`event`]: what a contact was, for the outputs ([`ContactEvent`]).
//!
//! The room sits above the flight kernel ([`crate::flight`]), whose paths it cuts at the
//! contacts, and below the step ([`crate::pipeline`]), which calls its stages in order.

pub mod detect;
pub mod event;
mod in_step;
pub mod lasting;
mod release;
pub mod rules;

pub use detect::{ImpactLocation, Neighbours, locate_on_path};
pub use event::{ContactEvent, Other, Outcome};
pub use lasting::{LastingContact, PairHold, WallContact};
pub use rules::{
    BounceRule, Friction, Impact, PairBody, PairImpact, Spinning, Tangential, pair_impact,
    tangential_impulse, wall_impact,
};

pub(crate) use detect::{candidate_pairs, touches_wall};
pub(crate) use in_step::resolve_in_step;
pub(crate) use lasting::{keep_lasting, release_pairs};
pub(crate) use release::release_at_wall;

use crate::correlations::{sphere_moment_of_inertia, sphere_volume};
use crate::effects::Physics;
use crate::flight::{Kernel, Motion};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use crate::walls::Wall;

/// Hash map of the contact stages: foldhash with a fixed seed — fast on small integer keys, and
/// the same on every run (only lookups are used; no result depends on iteration order).
pub(crate) type FastMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;
/// Hash set of the contact stages (see [`FastMap`]).
pub(crate) type FastSet<K> = std::collections::HashSet<K, foldhash::fast::FixedState>;

/// What the contact stages of a step read: the flight kernel (where paths go), the kinds, the
/// fluid and the bounce rule, and each kind's inertia in the force balance.
pub(crate) struct Ctx<'a, M> {
    pub flight: &'a Kernel<'a, M>,
    pub kinds: &'a [ParticleKind],
    pub fluid: &'a Fluid,
    pub rule: &'a BounceRule,
    pub impact_location: ImpactLocation,
    /// `ρp + C_M ρ` per kind (kg/m³).
    inertia_density: Vec<f64>,
}

impl<'a, M: Motion> Ctx<'a, M> {
    pub fn new(
        flight: &'a Kernel<'a, M>,
        physics: &Physics,
        kinds: &'a [ParticleKind],
        fluid: &'a Fluid,
        rule: &'a BounceRule,
        impact_location: ImpactLocation,
    ) -> Self {
        let inertia_density = physics.kinds.iter().map(|k| k.inertia_density).collect();
        Ctx { flight, kinds, fluid, rule, impact_location, inertia_density }
    }

    /// The walls.
    pub fn walls(&self) -> &'a [Wall] {
        self.flight.walls
    }

    /// Inertia (kg) of a particle of kind `k` and diameter `d`: `(ρp + C_M ρ) π d³/6`.
    pub fn inertia_of(&self, k: usize, d: f64) -> f64 {
        self.inertia_density[k] * sphere_volume(d)
    }

    /// Moment of inertia (kg m²) of a particle of kind `k` and diameter `d`: `(2/5) ρp Vp a²`,
    /// without added mass (a sphere's added mass has no rotational part), for drops as for
    /// solids (docs/physics.md §9).
    pub fn moment_of(&self, k: usize, d: f64) -> f64 {
        sphere_moment_of_inertia(self.kinds[k].density, d)
    }
}
