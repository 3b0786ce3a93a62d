//! Infinite plane.

use super::{Crossing, Gap, Surface, ends_touch, linear_crossing};
use glam::DVec3;

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
