//! Infinite plane.

use super::{Crossing, Drawable, Gap, Solid, Surface, ends_touch, linear_crossing};
use glam::{DQuat, DVec3};

/// The plane through `point` with unit `normal`; particles live on the side `normal` points to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// A point of the plane (m).
    pub point: DVec3,
    /// Unit normal, towards the particles.
    pub normal: DVec3,
}

impl Surface for Plane {
    #[inline]
    fn gap(&self, c: DVec3, r: f64) -> Gap {
        Gap { gap: (c - self.point).dot(self.normal) - r, normal: self.normal }
    }

    #[inline]
    fn sweep(&self, c0: DVec3, c1: DVec3, r: f64) -> Option<Crossing> {
        linear_crossing(self.gap(c0, r).gap, self.gap(c1, r).gap)
    }

    #[inline]
    fn may_touch(&self, c0: DVec3, c1: DVec3, r: f64) -> bool {
        ends_touch(self, c0, c1, r)
    }
}

impl Drawable for Plane {
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        None
    }

    /// A thin square slab centred under the picture, on the wall's far side.
    fn solid(&self, center: DVec3, half: f64) -> Solid {
        let foot = center - (center - self.point).dot(self.normal) * self.normal;
        let reach = 2.0 * half.max((center - foot).length());
        let thickness = 1e-3 * reach;
        Solid::Cuboid {
            center: foot - 0.5 * thickness * self.normal,
            size: DVec3::new(reach * 2.0, reach * 2.0, thickness),
            rotation: DQuat::from_rotation_arc(DVec3::Z, self.normal),
        }
    }
}
