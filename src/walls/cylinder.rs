//! The inside of a cylinder: a column wall, in closed form.

use super::{Crossing, Drawable, Gap, Solid, Surface};
use glam::{DQuat, DVec3};

/// The lateral surface of a cylinder of `radius` around the axis through `base` along unit
/// `axis`, between `base + lo·axis` and `base + hi·axis`; particles inside. Caps are separate
/// walls (planes, boxes). The rim edges are not modelled: contacts are tested against the
/// infinite cylinder and kept when the centre lies between `lo` and `hi`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// A point on the axis (m).
    pub base: DVec3,
    /// Unit axis direction.
    pub axis: DVec3,
    /// Radius (m).
    pub radius: f64,
    /// Lower end along the axis from `base` (m), may be −∞.
    pub lo: f64,
    /// Upper end along the axis from `base` (m), may be +∞.
    pub hi: f64,
}

impl Cylinder {
    /// Component of `c − base` perpendicular to the axis, and the axial coordinate.
    #[inline]
    fn split(&self, c: DVec3) -> (DVec3, f64) {
        let rel = c - self.base;
        let along = rel.dot(self.axis);
        (rel - along * self.axis, along)
    }
}

impl Surface for Cylinder {
    #[inline]
    fn gap(&self, c: DVec3, r: f64) -> Gap {
        let (perp, along) = self.split(c);
        let rho = perp.length();
        // On the axis every direction is the nearest; pick one perpendicular to the axis.
        let outward = if rho > 0.0 { perp / rho } else { self.axis.any_orthonormal_vector() };
        // Beyond its ends the lateral wall is not there: nothing to touch or rest on.
        let gap = if along < self.lo || along > self.hi { f64::INFINITY } else { self.radius - rho - r };
        Gap { gap, normal: -outward }
    }

    fn sweep(&self, c0: DVec3, c1: DVec3, r: f64) -> Option<Crossing> {
        let (p, _) = self.split(c0);
        let (p1, _) = self.split(c1);
        let q = p1 - p;
        let reach = self.radius - r;
        let (a, b, c) = (q.dot(q), p.dot(q), p.dot(p) - reach * reach);
        let enter = if c >= 0.0 {
            // Touching or overlapping at the start: a contact only if moving outwards.
            if b <= 0.0 {
                return None;
            }
            0.0
        } else {
            // Inside: the positive root of a λ² + 2 b λ + c = 0.
            if a == 0.0 {
                return None;
            }
            let disc = b * b - a * c;
            let lambda = (-b + disc.max(0.0).sqrt()) / a;
            if lambda > 1.0 {
                return None;
            }
            lambda
        };
        let (_, along) = self.split(c0 + enter * (c1 - c0));
        (along >= self.lo && along <= self.hi).then_some(Crossing { enter, exit: 1.0 })
    }

    #[inline]
    fn may_touch(&self, c0: DVec3, c1: DVec3, r: f64) -> bool {
        // The distance from the axis is largest at an end of a straight move.
        let reach = self.radius - r;
        let far = |c: DVec3| self.split(c).0.length_squared() >= reach * reach;
        // A sphere wider than the column touches it anywhere (the lubrication's range, ten
        // radii, is wider than a narrow column: squared, a negative reach would read as far).
        reach <= 0.0 || far(c0) || far(c1)
    }
}

impl Drawable for Cylinder {
    /// A cylinder with both ends finite is bounded: the box around its two end circles, which
    /// reach `radius · √(1 − a_i²)` from the axis along each coordinate `i`. (Unbounded, it has
    /// no box, and a picture is sized from the rest of the scene.)
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        if !(self.lo.is_finite() && self.hi.is_finite()) {
            return None;
        }
        let reach = self.radius * (DVec3::ONE - self.axis * self.axis).max(DVec3::ZERO).sqrt();
        let (a, b) = (self.base + self.lo * self.axis, self.base + self.hi * self.axis);
        Some((a.min(b) - reach, a.max(b) + reach))
    }

    /// An unbounded end stops where the picture's extent does.
    fn solid(&self, center: DVec3, half: f64) -> Solid {
        let mid = (center - self.base).dot(self.axis);
        let lo = if self.lo.is_finite() { self.lo } else { mid - 2.0 * half };
        let hi = if self.hi.is_finite() { self.hi } else { mid + 2.0 * half };
        Solid::Cylinder {
            center: self.base + 0.5 * (lo + hi) * self.axis,
            radius: self.radius,
            length: hi - lo,
            rotation: DQuat::from_rotation_arc(DVec3::Z, self.axis),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_finite_cylinder_is_bounded_by_its_end_circles_and_an_infinite_one_is_not() {
        let column = Cylinder { base: DVec3::ZERO, axis: DVec3::Z, radius: 0.025, lo: 0.0, hi: 0.5 };
        let (lo, hi) = column.bounds().unwrap();
        assert_eq!((lo, hi), (DVec3::new(-0.025, -0.025, 0.0), DVec3::new(0.025, 0.025, 0.5)));
        // Tilted 45° in the x–z plane: the end circles reach r/√2 along x and z, r along y.
        let a = DVec3::new(1.0, 0.0, 1.0).normalize();
        let tilted = Cylinder { base: DVec3::ZERO, axis: a, radius: 1.0, lo: 0.0, hi: 2.0 };
        let (lo, hi) = tilted.bounds().unwrap();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((lo - DVec3::new(-h, -1.0, -h)).abs().max_element() < 1e-12, "{lo}");
        assert!((hi - DVec3::new(2.0 * h + h, 1.0, 2.0 * h + h)).abs().max_element() < 1e-12, "{hi}");
        assert!(Cylinder { hi: f64::INFINITY, ..column }.bounds().is_none());
    }

    #[test]
    fn radial_move_touches_when_centre_reaches_radius_minus_r() {
        let cyl = Cylinder {
            base: DVec3::ZERO,
            axis: DVec3::Z,
            radius: 1.0,
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        };
        let hit = cyl.sweep(DVec3::ZERO, DVec3::new(2.0, 0.0, 5.0), 0.25).unwrap();
        assert!((hit.enter - 0.375).abs() < 1e-14);
        let g = cyl.gap(DVec3::new(0.75, 0.0, 1.0), 0.25);
        assert!(g.gap.abs() < 1e-15 && (g.normal + DVec3::X).length() < 1e-15);
    }

    #[test]
    fn beyond_its_ends_a_finite_cylinder_is_not_there() {
        let cyl = Cylinder { base: DVec3::ZERO, axis: DVec3::Z, radius: 1.0, lo: 0.0, hi: 2.0 };
        assert_eq!(cyl.gap(DVec3::new(5.0, 0.0, 3.0), 0.1).gap, f64::INFINITY);
        assert_eq!(cyl.gap(DVec3::new(5.0, 0.0, -1.0), 0.1).gap, f64::INFINITY);
        assert!(cyl.gap(DVec3::new(5.0, 0.0, 1.0), 0.1).gap < 0.0);
    }

    #[test]
    fn a_sphere_wider_than_the_column_may_touch_it_even_on_the_axis() {
        let cyl = Cylinder { base: DVec3::ZERO, axis: DVec3::Z, radius: 1.0, lo: 0.0, hi: 2.0 };
        let on_axis = DVec3::new(0.0, 0.0, 1.0);
        assert!(!cyl.may_touch(on_axis, on_axis, 0.5));
        assert!(cyl.may_touch(on_axis, on_axis, 1.5));
        assert!(cyl.may_touch(on_axis, on_axis, 3.0));
    }
}
