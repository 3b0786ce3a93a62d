//! What the viewers draw: walls as boxes, cylinders and triangle lists, and a colour per state.
//!
//! Both the MCAP and the rerun writers draw the same solids, so the geometry is decided once
//! here. Infinite walls (planes, unbounded cylinders) cannot be drawn: they become patches
//! sized from the scene — a few times the extent of the particles and the bounded walls — so
//! that they frame the motion without dwarfing it.

use crate::particles::State;
use crate::pipeline::Simulation;
use crate::walls::Drawable;
pub use crate::walls::Solid;
use glam::DVec3;

/// A wall to draw: its name and its solid.
#[derive(Debug, Clone, PartialEq)]
pub struct WallSolid {
    /// The wall's name in the scene.
    pub name: String,
    /// What to draw.
    pub solid: Solid,
}

/// RGBA colour (components in 0..=1) of a particle in `state`: free blue, held orange,
/// resting red — the same in every output and in the README's picture.
pub fn state_color(state: State) -> [f32; 4] {
    match state {
        State::Free => [0.20, 0.50, 1.00, 1.0],
        State::Held | State::PairHeld => [1.00, 0.60, 0.10, 1.0],
        State::Resting => [0.85, 0.15, 0.15, 1.0],
    }
}

/// Walls are drawn see-through so that particles inside a container stay visible.
pub const WALL_COLOR: [f32; 4] = [0.6, 0.6, 0.65, 0.25];

/// The centre and half-extent of what a picture of the scene should show: the particles and
/// the bounded walls.
fn scene_extent(sim: &Simulation) -> (DVec3, f64) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    let mut d_max: f64 = 0.0;
    let p = &sim.world.particles;
    for i in 0..p.len() {
        let r = 0.5 * p.diameter[i];
        lo = lo.min(p.pos[i] - r);
        hi = hi.max(p.pos[i] + r);
        d_max = d_max.max(p.diameter[i]);
    }
    for (min, max) in sim.setup.walls.iter().filter_map(|w| w.shape.bounds()) {
        lo = lo.min(min);
        hi = hi.max(max);
    }
    if !lo.is_finite() || !hi.is_finite() {
        // No particles and no bounded wall: a metre around the origin.
        return (DVec3::ZERO, 0.5);
    }
    let center = 0.5 * (lo + hi);
    // At least ten particle diameters, so a single drop still gets a wall patch around it.
    let half = (0.5 * (hi - lo).max_element()).max(10.0 * d_max).max(1e-3);
    (center, half)
}

/// The solids that represent `sim`'s walls (call it at t = 0: infinite walls are sized from
/// where the particles start).
pub fn wall_solids(sim: &Simulation) -> Vec<WallSolid> {
    let (center, half) = scene_extent(sim);
    sim.setup
        .walls
        .iter()
        .map(|w| WallSolid { name: w.name.clone(), solid: w.shape.solid(center, half) })
        .collect()
}
