//! What the viewers draw: walls as boxes, cylinders and triangle lists, and a colour per state.
//!
//! Both the MCAP and the rerun writers draw the same solids, so the geometry is decided once
//! here. Infinite walls (planes, unbounded cylinders) cannot be drawn: they become patches
//! sized from the scene — a few times the extent of the particles and the bounded walls — so
//! that they frame the motion without dwarfing it.

use crate::particles::State;
use crate::pipeline::Simulation;
use crate::walls::Shape;
use glam::{DQuat, DVec3};

/// A drawable solid, in scene coordinates (m).
#[derive(Debug, Clone, PartialEq)]
pub enum Solid {
    /// A box: centre, full size along its local axes, and the rotation of those axes.
    Cuboid {
        /// Centre (m).
        center: DVec3,
        /// Full edge lengths along the local x, y, z axes (m).
        size: DVec3,
        /// Rotation from the local axes to the scene's.
        rotation: DQuat,
    },
    /// A cylinder whose local axis is +Z (Foxglove's and rerun's convention), rotated onto the
    /// wall's axis.
    Cylinder {
        /// Centre (m).
        center: DVec3,
        /// Radius (m).
        radius: f64,
        /// Length along the axis (m).
        length: f64,
        /// Rotation taking +Z onto the cylinder's axis.
        rotation: DQuat,
    },
    /// A triangle mesh: vertices and index triples.
    Triangles {
        /// Vertices (m).
        vertices: Vec<DVec3>,
        /// Triangles as vertex indices.
        indices: Vec<[u32; 3]>,
    },
}

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
        State::Held => [1.00, 0.60, 0.10, 1.0],
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
    let p = &sim.particles;
    for i in 0..p.len() {
        let r = 0.5 * p.diameter[i];
        lo = lo.min(p.pos[i] - r);
        hi = hi.max(p.pos[i] + r);
        d_max = d_max.max(p.diameter[i]);
    }
    for w in &sim.walls {
        match &w.shape {
            Shape::Cuboid(b) => {
                lo = lo.min(b.min);
                hi = hi.max(b.max);
            }
            Shape::Mesh(m) => {
                for v in m.mesh.vertices() {
                    lo = lo.min(*v);
                    hi = hi.max(*v);
                }
            }
            Shape::Plane(_) | Shape::Cylinder(_) => {}
        }
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
    sim.walls
        .iter()
        .map(|w| {
            let solid = match &w.shape {
                Shape::Plane(p) => {
                    // A thin square slab centred under the scene, on the wall's far side.
                    let foot = center - (center - p.point).dot(p.normal) * p.normal;
                    let reach = 2.0 * half.max((center - foot).length());
                    let thickness = 1e-3 * reach;
                    Solid::Cuboid {
                        center: foot - 0.5 * thickness * p.normal,
                        size: DVec3::new(reach * 2.0, reach * 2.0, thickness),
                        rotation: DQuat::from_rotation_arc(DVec3::Z, p.normal),
                    }
                }
                Shape::Cuboid(b) => Solid::Cuboid {
                    center: 0.5 * (b.min + b.max),
                    size: b.max - b.min,
                    rotation: DQuat::IDENTITY,
                },
                Shape::Cylinder(c) => {
                    // An unbounded end stops where the scene's extent does.
                    let mid = (center - c.base).dot(c.axis);
                    let lo = if c.lo.is_finite() { c.lo } else { mid - 2.0 * half };
                    let hi = if c.hi.is_finite() { c.hi } else { mid + 2.0 * half };
                    Solid::Cylinder {
                        center: c.base + 0.5 * (lo + hi) * c.axis,
                        radius: c.radius,
                        length: hi - lo,
                        rotation: DQuat::from_rotation_arc(DVec3::Z, c.axis),
                    }
                }
                Shape::Mesh(m) => Solid::Triangles {
                    vertices: m.mesh.vertices().to_vec(),
                    indices: m.mesh.indices().to_vec(),
                },
            };
            WallSolid { name: w.name.clone(), solid }
        })
        .collect()
}
