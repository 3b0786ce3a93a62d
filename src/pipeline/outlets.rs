//! Stage 7 (outflow): outlets take out the particles that leave through them, recording each
//! one's residence time (removal time minus birth time).

use crate::contact::lasting::remove_particles;
use crate::contact::{ContactEvent, LastingContact, Other};
use crate::particles::{NO_WALL, Particles};
use glam::DVec3;
use std::collections::HashSet;

/// Where an outlet is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutletShape {
    /// A plane through `point` (m) with unit `normal` towards the particles' side: a particle
    /// whose centre is strictly behind it at the end of a step has left.
    Plane {
        /// A point of the plane (m).
        point: DVec3,
        /// Unit normal, towards the side the particles live on.
        normal: DVec3,
    },
    /// A wall, by index: a particle that touches it in a step (its contact event is still
    /// written) or is held or resting on it is taken out at the end of that step.
    Wall(u32),
}

/// One particle taken out by an outlet.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Removal {
    /// Its id.
    pub id: u32,
    /// Simulated time of the removal, the end of the step (s).
    pub time: f64,
    /// Time it spent in the simulation (s).
    pub residence_time: f64,
}

/// A scene `[[outlets]]` entry (what it removes is recorded in
/// [`crate::pipeline::Record::removed`]).
#[derive(Debug, Clone)]
pub struct Outlet {
    /// Name in summaries (`outlets[0]` unless the scene names it).
    pub name: String,
    /// Plane or wall.
    pub shape: OutletShape,
}

/// Takes out the particles that left through an outlet in the step ending at `t1`;
/// `step_events` are the contacts of this step. The first outlet (in scene order) that claims
/// a particle records it in its list of `removed`. Returns true when particles were removed
/// (indices changed).
pub(crate) fn run(
    outlets: &[Outlet],
    removed: &mut [Vec<Removal>],
    p: &mut Particles,
    step_events: &[ContactEvent],
    t1: f64,
    lasting: &mut Vec<LastingContact>,
) -> bool {
    if outlets.is_empty() || p.is_empty() {
        return false;
    }
    let mut keep = vec![true; p.len()];
    let mut any = false;
    let q: &Particles = p;
    for (outlet, removed) in outlets.iter().zip(removed.iter_mut()) {
        let touched: HashSet<u32> = match outlet.shape {
            OutletShape::Wall(w) => {
                step_events.iter().filter(|e| e.other == Other::Wall(w)).map(|e| e.id).collect()
            }
            OutletShape::Plane { .. } => HashSet::new(),
        };
        let claims = |i: usize| match outlet.shape {
            OutletShape::Plane { point, normal } => (q.pos[i] - point).dot(normal) < 0.0,
            OutletShape::Wall(w) => (q.wall[i] == w && w != NO_WALL) || touched.contains(&q.id[i]),
        };
        let mut out = Vec::new();
        for (i, k) in keep.iter_mut().enumerate() {
            if *k && claims(i) {
                *k = false;
                any = true;
                out.push(Removal { id: q.id[i], time: t1, residence_time: t1 - q.born[i] });
            }
        }
        removed.extend(out);
    }
    if any {
        remove_particles(p, &keep, lasting);
    }
    any
}
