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
pub fn scene_extent(sim: &Simulation) -> (DVec3, f64) {
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

/// Sides of the polygon that stands for a cylinder's circle in [`triangulate`]: the chord's
/// distance from the arc is `r (1 − cos(π/48))`, 0.2 % of the radius.
pub const CYLINDER_SIDES: u32 = 48;

/// The triangles of a solid's surface, as vertices and index triples, wound so that the normals
/// point out of a box. A box gives its 6 faces (12 triangles), a cylinder its lateral surface
/// only — the wall particles move inside, open at both ends — as [`CYLINDER_SIDES`] quads, a
/// mesh its own triangles.
pub fn triangulate(solid: &Solid) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    match solid {
        Solid::Cuboid { center, size, rotation } => {
            let h = 0.5 * *size;
            // Corner k has x = +h.x when bit 0 is set, y when bit 1, z when bit 2.
            let vertices = (0..8)
                .map(|k| {
                    let s = DVec3::new(
                        if k & 1 == 0 { -1.0 } else { 1.0 },
                        if k & 2 == 0 { -1.0 } else { 1.0 },
                        if k & 4 == 0 { -1.0 } else { 1.0 },
                    );
                    *center + *rotation * (s * h)
                })
                .collect();
            // Each face as a quad, counter-clockwise seen from outside.
            let quads: [[u32; 4]; 6] = [
                [0, 2, 3, 1], // −z
                [4, 5, 7, 6], // +z
                [0, 1, 5, 4], // −y
                [2, 6, 7, 3], // +y
                [0, 4, 6, 2], // −x
                [1, 3, 7, 5], // +x
            ];
            let indices = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
            (vertices, indices)
        }
        Solid::Cylinder { center, radius, length, rotation } => {
            let n = CYLINDER_SIDES;
            let mut vertices = Vec::with_capacity(2 * n as usize);
            for k in 0..n {
                let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
                let rim = DVec3::new(radius * a.cos(), radius * a.sin(), 0.0);
                for z in [-0.5 * length, 0.5 * length] {
                    vertices.push(*center + *rotation * (rim + DVec3::new(0.0, 0.0, z)));
                }
            }
            let indices = (0..n)
                .flat_map(|k| {
                    let (b0, t0) = (2 * k, 2 * k + 1);
                    let (b1, t1) = (2 * ((k + 1) % n), 2 * ((k + 1) % n) + 1);
                    [[b0, b1, t1], [b0, t1, t0]]
                })
                .collect();
            (vertices, indices)
        }
        Solid::Triangles { vertices, indices } => (vertices.clone(), indices.clone()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    /// The signed volume enclosed by a closed triangle surface (positive when its normals point
    /// out), by the divergence theorem.
    fn volume(vertices: &[DVec3], indices: &[[u32; 3]]) -> f64 {
        indices
            .iter()
            .map(|t| {
                vertices[t[0] as usize].dot(vertices[t[1] as usize].cross(vertices[t[2] as usize])) / 6.0
            })
            .sum()
    }

    #[test]
    fn a_box_is_twelve_outward_triangles_enclosing_its_volume() {
        let rotation = DQuat::from_rotation_arc(DVec3::Z, DVec3::new(1.0, 2.0, 3.0).normalize());
        let solid =
            Solid::Cuboid { center: DVec3::new(1.0, -2.0, 0.5), size: DVec3::new(2.0, 3.0, 0.5), rotation };
        let (v, t) = triangulate(&solid);
        assert_eq!((v.len(), t.len()), (8, 12));
        assert!((volume(&v, &t) - 3.0).abs() < 1e-12, "{}", volume(&v, &t));
    }

    #[test]
    fn a_cylinder_is_its_lateral_surface_on_its_axis() {
        let axis = DVec3::new(0.0, 1.0, 1.0).normalize();
        let center = DVec3::new(0.1, 0.2, 0.3);
        let rotation = DQuat::from_rotation_arc(DVec3::Z, axis);
        let (v, t) = triangulate(&Solid::Cylinder { center, radius: 0.5, length: 2.0, rotation });
        assert_eq!((v.len(), t.len()), (2 * CYLINDER_SIDES as usize, 2 * CYLINDER_SIDES as usize));
        for p in &v {
            let along = (*p - center).dot(axis);
            let radial = (*p - center - along * axis).length();
            assert!((along.abs() - 1.0).abs() < 1e-12 && (radial - 0.5).abs() < 1e-12, "{p}");
        }
        assert!(t.iter().flatten().all(|&i| (i as usize) < v.len()));
    }
}
