//! What the viewers draw for a wall: a box, a cylinder or a list of triangles, in scene
//! coordinates. Each shape says which ([`super::Drawable`]), so the MCAP and rerun writers draw
//! the same solids.

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
