//! What a stateful feature is to the particle store: the one mechanism through which a feature
//! that keeps per-particle state (spin, the history memory, a field's cell hints, or a new one:
//! a drop's deformation, its temperature) declares that state and is called at the step's
//! boundaries. The model is the LAMMPS `fix`: its columns grow and shrink with the particles
//! (`grow_arrays`/`copy_arrays`: here [`Particles::push`] and [`Particles::retain`], for every
//! column of every feature), and it has hooks at fixed points of the step (`end_of_step`, …).
//!
//! - a feature is registered once, by adding itself to [`Features`] (an effect does it in its
//!   `apply`; the scene loader for a field's cell hints);
//! - its columns are either a typed column of [`Particles`] that the flight kernel reads in the
//!   hot loop (spin, memory, cell hints: `Column<DVec3>`, `Column<u32>`), or one of its own,
//!   made by [`Particles::add_column`] (`f64`s, any width) — which needs no line outside the
//!   feature's file;
//! - the store pushes, retains and commits every column; the feature's hooks say what happens
//!   to its values, each called with the whole store (a hook runs once per step, not once per
//!   particle: a scene without the feature pays nothing).
//!
//! How a feature changes a particle's *flight* is not a hook here: the flight kernel is compiled
//! for the scene's physics, and its overrides (the lubricated sub-steps, the remembered flight,
//! the spin's relaxation) are values of the kernel (`flight::Kernel`), so that a scene without
//! them tests one `None` per flight.

use super::{Next, Particles, State};
use std::collections::TryReserveError;
use std::fmt::Debug;
use std::sync::Arc;

/// A contact of the step, as a feature's [`Feature::after_contact`] sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch {
    /// Index of the particle (in the step's order, before commit).
    pub index: usize,
    /// Time of the contact (s).
    pub time: f64,
    /// Normal approach speed `V∞` (m/s).
    pub normal_speed: f64,
    /// Stokes number of the impact.
    pub st: f64,
    /// Restitution applied (0 for a deposit).
    pub eps: f64,
    /// Against a wall (true) or another particle.
    pub wall: bool,
}

/// A stateful feature: its columns and its hooks. Every hook has a default that does nothing;
/// a feature overrides those it needs.
pub trait Feature: Debug + Send + Sync {
    /// The feature's name (the effect's, in the scene file).
    fn name(&self) -> &'static str;

    /// When a run starts (`Simulation::new`): turns its columns on for the particles there
    /// are — a typed column of [`Particles`], or its own by [`Particles::add_column`]. A
    /// machine that cannot give them is an error, not an abort.
    fn start(&self, _p: &mut Particles) -> Result<(), TryReserveError> {
        Ok(())
    }

    /// After the contacts of the step (stage 5½), before commit: the end-of-step values of its
    /// columns, from the particles at the start of the step (`p`) and at its end (`next`), over
    /// a step of `h` (s). Its own columns' end-of-step values start as a copy of their
    /// start-of-step values ([`Next::column_mut`]).
    fn end_of_step(&self, _p: &mut Particles, _next: &mut Next, _h: f64) {}

    /// After [`Feature::end_of_step`], once per contact of the step, in the events' order.
    fn after_contact(&self, _touch: &Touch, _next: &mut Next) {}

    /// After commit swapped the step's end into `p`, before outlets and injectors.
    fn commit(&self, _p: &mut Particles) {}
}

/// The scene's stateful features, in registration order. Two lists are equal when they name
/// the same features in the same order.
#[derive(Debug, Clone, Default)]
pub struct Features(Vec<Arc<dyn Feature>>);

impl Features {
    /// Registers `feature`, once: a second feature of the same name is not added.
    pub fn add(&mut self, feature: Arc<dyn Feature>) {
        if !self.0.iter().any(|f| f.name() == feature.name()) {
            self.0.push(feature);
        }
    }

    /// Puts `feature` in the place of the registered feature of its name (or registers it):
    /// a feature whose column's width is known only later (the history memory, once the time
    /// step is).
    pub fn replace(&mut self, feature: Arc<dyn Feature>) {
        match self.0.iter_mut().find(|f| f.name() == feature.name()) {
            Some(f) => *f = feature,
            None => self.0.push(feature),
        }
    }

    /// The features, in registration order.
    pub fn iter(&self) -> impl Iterator<Item = &dyn Feature> {
        self.0.iter().map(|f| f.as_ref())
    }

    /// Whether a feature of this name is registered.
    pub fn has(&self, name: &str) -> bool {
        self.0.iter().any(|f| f.name() == name)
    }

    /// Whether any feature is registered.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl PartialEq for Features {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len() && self.iter().zip(other.iter()).all(|(a, b)| a.name() == b.name())
    }
}

/// Runs every feature's [`Feature::start`] on `p`.
pub fn start_all(features: &Features, p: &mut Particles) -> Result<(), TryReserveError> {
    for f in features.iter() {
        f.start(p)?;
    }
    Ok(())
}

/// Stage 5½: the features' own columns' end-of-step values start as their start-of-step
/// values, then every feature's [`Feature::end_of_step`] and, for each of the step's contacts,
/// its [`Feature::after_contact`].
pub fn end_of_step(features: &Features, p: &mut Particles, next: &mut Next, h: f64, touches: &[Touch]) {
    if features.is_empty() {
        return;
    }
    next.columns.resize_with(p.columns.len(), Vec::new);
    for ((_, start), end) in p.columns.iter().zip(&mut next.columns) {
        end.clear();
        end.extend_from_slice(start.values());
    }
    for f in features.iter() {
        f.end_of_step(p, next, h);
    }
    for touch in touches {
        for f in features.iter() {
            f.after_contact(touch, next);
        }
    }
}

/// After commit: every feature's [`Feature::commit`].
pub fn commit(features: &Features, p: &mut Particles) {
    for f in features.iter() {
        f.commit(p);
    }
}

/// Zeroes the `width` values of every particle held at a wall or resting on one: what the
/// history memory's commit does (a contact ends the memory, docs/physics.md §10), and what any
/// feature whose state a wall contact resets can call.
pub fn reset_at_walls<T: Copy>(state: &[State], values: &mut [T], width: usize, zero: T) {
    if width == 0 {
        return;
    }
    for (s, m) in state.iter().zip(values.chunks_exact_mut(width)) {
        if matches!(s, State::Held | State::Resting) {
            m.fill(zero);
        }
    }
}
