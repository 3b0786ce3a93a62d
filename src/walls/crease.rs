//! Creases of separate walls: a particle resting on one wall that also touches others (a bead
//! in the corner of a column and a conical baffle, between two planes in a V). The geometry
//! here; the sliding along a crease is the flight kernel's ([`crate::flight`]).

use super::{Surface, Wall};
use glam::DVec3;

/// Gap (fraction of the radius) within which a particle resting on one wall counts as resting
/// against another too: the in-step contact location puts a particle on a wall to 1e-13 of its
/// radius, so a particle that slid into a second wall touches both far within this.
pub const CREASE_TOUCHING: f64 = 1e-9;

/// Below this `|n₁ × n₂|` two touching walls are taken as one plane (a crease flatter than
/// 0.06°, or two walls facing each other): the particle slides on its own wall and is only
/// kept out of the other, as a crease line of such walls is not well defined.
pub const FLAT_CREASE: f64 = 1e-3;

/// The other walls a particle resting on wall `own` touches (at most [`Crease::MAX`]; a third
/// or more is counted in [`Crease::more`]): each wall's index and its normal at the particle.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Crease {
    len: usize,
    walls: [u32; Crease::MAX],
    normals: [DVec3; Crease::MAX],
    /// Further walls touched beyond [`Crease::MAX`] (a particle wedged among four walls).
    pub more: bool,
}

impl Crease {
    /// Walls kept besides the particle's own: two make a corner of three walls.
    pub const MAX: usize = 2;

    /// No other wall touched.
    pub fn is_empty(&self) -> bool {
        self.len == 0 && !self.more
    }

    /// The other walls touched, with their normals (towards the particle).
    pub fn iter(&self) -> impl Iterator<Item = (u32, DVec3)> + '_ {
        self.walls[..self.len].iter().copied().zip(self.normals[..self.len].iter().copied())
    }

    /// Whether wall `w` is one of them.
    pub fn contains(&self, w: u32) -> bool {
        self.walls[..self.len].contains(&w)
    }
}

/// The walls other than `own` that a sphere of radius `r` at `x` touches (gap at most
/// [`CREASE_TOUCHING`] `r`, or overlapping). Each closed-form broad-phase test comes first, so
/// a particle far from every other wall costs one cheap test per wall.
pub fn crease(walls: &[Wall], own: u32, x: DVec3, r: f64) -> Crease {
    let mut c = Crease::default();
    let reach = r * (1.0 + CREASE_TOUCHING);
    for (w, wall) in walls.iter().enumerate() {
        // `may_touch` is false only when the grown sphere is clear: then the gap is positive
        // beyond the tolerance.
        if w as u32 == own || !wall.shape.may_touch(x, x, reach) {
            continue;
        }
        let g = wall.shape.gap(x, r);
        if g.gap <= CREASE_TOUCHING * r {
            if c.len < Crease::MAX {
                (c.walls[c.len], c.normals[c.len]) = (w as u32, g.normal);
                c.len += 1;
            } else {
                c.more = true;
            }
        }
    }
    c
}

/// Puts a sphere of radius `r` at `x` on both `a` and `b` (gaps zero): Newton steps along the
/// two normals, exact in one for planes; a few for curved walls, whose gaps are smooth near a
/// crease. Returns the position and the unit direction of the crease line there.
pub fn onto_crease(a: &impl Surface, b: &impl Surface, mut x: DVec3, r: f64) -> (DVec3, DVec3) {
    for _ in 0..8 {
        let (ga, gb) = (a.gap(x, r), b.gap(x, r));
        let c = ga.normal.dot(gb.normal);
        let det = 1.0 - c * c;
        if det <= FLAT_CREASE * FLAT_CREASE || (ga.gap.abs() <= 1e-14 * r && gb.gap.abs() <= 1e-14 * r) {
            break;
        }
        let alpha = (ga.gap - c * gb.gap) / det;
        let beta = (gb.gap - c * ga.gap) / det;
        x -= alpha * ga.normal + beta * gb.normal;
    }
    let line = a.gap(x, r).normal.cross(b.gap(x, r).normal).normalize_or_zero();
    (x, line)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walls::{Plane, Shape, WallMaterial};

    fn plane(point: DVec3, normal: DVec3) -> Wall {
        Wall {
            name: "p".into(),
            material: WallMaterial::default(),
            shape: Shape::Plane(Plane { point, normal: normal.normalize() }),
        }
    }

    #[test]
    fn a_sphere_in_a_vee_touches_the_other_plane_and_is_put_on_both() {
        let walls =
            [plane(DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0)), plane(DVec3::ZERO, DVec3::new(-1.0, 0.0, 1.0))];
        let r = 1e-3;
        let x = DVec3::new(0.0, 0.3, r * 2f64.sqrt());
        let c = crease(&walls, 0, x, r);
        assert_eq!(c.iter().map(|(w, _)| w).collect::<Vec<_>>(), vec![1]);
        // Lifted off b by 1.4e-6 m (1.4e-3 r): no longer touching it.
        assert!(crease(&walls, 0, x + DVec3::new(-1e-6, 0.0, 1e-6), r).is_empty());
        let (on, line) = onto_crease(&walls[0].shape, &walls[1].shape, x + DVec3::new(3e-5, 0.0, -2e-5), r);
        assert!(walls.iter().all(|w| w.shape.gap(on, r).gap.abs() < 1e-15), "{on:?}");
        assert!((line.cross(DVec3::Y)).length() < 1e-12, "{line:?}");
    }
}
