//! Four particles at once: the free-flight arithmetic written once, generically over
//! [`Vector`], runs either on one particle (`glam::DVec3`, `f64`) or on four ([`DVec3x4`],
//! [`F64x4`]) whose `x`, `y` and `z` sit in columns of four lanes, so that one vector
//! instruction does the work of four particles.
//!
//! The lanes are plain arrays rather than a SIMD crate's types (`wide`, `ultraviolet`), which
//! fix their instruction set at compile time: written as loops over four lanes they compile to
//! whatever the calling function may use (SSE2 everywhere, AVX2 where
//! [`crate::pipeline`] dispatches to it at run time). Every lane does exactly the operations of
//! the scalar code, in the same order (and Rust never fuses a multiply and an add by itself), so
//! a particle's result is bit for bit the same whichever path stepped it; the tests of
//! `integrate` check that.

use super::FixedPower;
use glam::DVec3;
use std::ops::{Add, Div, Mul, Sub};

/// Particles per lane group.
pub const LANES: usize = 4;

/// `f` of each of four values: `<[T; 4]>::map`, but always inlined, so that the lanes compile
/// with the instruction set of the function they end up in (`std`'s `map` is a call of its own
/// there, and the lane group goes through memory).
#[inline(always)]
pub fn each<T, U>(a: [T; LANES], f: impl Fn(T) -> U) -> [U; LANES] {
    let [a0, a1, a2, a3] = a;
    [f(a0), f(a1), f(a2), f(a3)]
}

/// What reals and vectors per lane have in common: a value per lane that adds, subtracts and
/// scales by one `f64`.
pub trait Lanes:
    Copy + Send + Sync + 'static + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self>
{
}

impl<T: Copy + Send + Sync + 'static + Add<Output = T> + Sub<Output = T> + Mul<f64, Output = T>> Lanes for T {}

/// A real number per lane.
pub trait Real: Lanes + Mul<Output = Self> + Div<Output = Self> {
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    /// `f` of every lane (for what has no lane form: a branch, a library function).
    fn map(self, f: impl Fn(f64) -> f64) -> Self;
    /// `f` of every lane, for a function of two results.
    fn map2(self, f: impl Fn(f64) -> (f64, f64)) -> (Self, Self);
    /// Whether `f` holds in every lane.
    fn all(self, f: impl Fn(f64) -> bool) -> bool;
    /// `x^p` in every lane ([`FixedPower::pow`], or its lane form).
    fn pow_fixed(self, p: &FixedPower) -> Self;
}

/// A 3-vector per lane.
pub trait Vector:
    Lanes + Mul<<Self as Vector>::Real, Output = Self> + Div<<Self as Vector>::Real, Output = Self>
{
    /// The matching real number per lane.
    type Real: Real;
    /// The zero vector.
    const ZERO: Self;
    /// `v` in every lane.
    fn splat(v: DVec3) -> Self;
    /// `x² + y² + z²`, in glam's order.
    fn length_squared(self) -> Self::Real;
    /// `x x' + y y' + z z'`, in glam's order.
    fn dot(self, o: Self) -> Self::Real;
    /// `f` of every lane.
    fn map_points(self, f: impl Fn(DVec3) -> DVec3) -> Self;
    /// `f` of a single point or of a lane group, by [`PointMap::one`] or [`PointMap::four`].
    fn map_by(self, f: &impl PointMap) -> Self;
}

/// A function of points with a lane form of its own (a structured field's lookup). A trait
/// rather than two closures, so that its methods can be always inlined: the lane form then
/// compiles with the instruction set of the loop it ends up in (a closure that large is called
/// out of line, with the baseline's).
pub trait PointMap {
    /// The value at one point.
    fn one(&self, x: DVec3) -> DVec3;
    /// The values at a lane group of points, lane for lane [`PointMap::one`]'s.
    fn four(&self, x: DVec3x4) -> DVec3x4;
}

/// Four `f64` lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct F64x4(pub [f64; LANES]);

impl F64x4 {
    /// Lane-wise `f(a, b)`.
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        let (a, b) = (self.0, o.0);
        F64x4([f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2]), f(a[3], b[3])])
    }
}

impl Add for F64x4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.zip(o, |a, b| a + b)
    }
}

impl Sub for F64x4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.zip(o, |a, b| a - b)
    }
}

impl Mul for F64x4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self.zip(o, |a, b| a * b)
    }
}

impl Div for F64x4 {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.zip(o, |a, b| a / b)
    }
}

impl Mul<f64> for F64x4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: f64) -> Self {
        self * F64x4([s; LANES])
    }
}

impl Real for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        f(self)
    }
    #[inline(always)]
    fn map2(self, f: impl Fn(f64) -> (f64, f64)) -> (Self, Self) {
        f(self)
    }
    #[inline(always)]
    fn all(self, f: impl Fn(f64) -> bool) -> bool {
        f(self)
    }
    #[inline(always)]
    fn pow_fixed(self, p: &FixedPower) -> Self {
        p.pow(self)
    }
}

impl Real for F64x4 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        F64x4([x; LANES])
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        F64x4(each(self.0, f))
    }
    #[inline(always)]
    fn map2(self, f: impl Fn(f64) -> (f64, f64)) -> (Self, Self) {
        let r = each(self.0, f);
        (F64x4(each(r, |r| r.0)), F64x4(each(r, |r| r.1)))
    }
    #[inline(always)]
    fn all(self, f: impl Fn(f64) -> bool) -> bool {
        let [a, b, c, d] = self.0;
        f(a) & f(b) & f(c) & f(d)
    }
    #[inline(always)]
    fn pow_fixed(self, p: &FixedPower) -> Self {
        p.pow_lanes(self)
    }
}

/// Four 3-vectors, as a column of four lanes per coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DVec3x4 {
    /// The `x` of each lane.
    pub x: F64x4,
    /// The `y` of each lane.
    pub y: F64x4,
    /// The `z` of each lane.
    pub z: F64x4,
}

impl DVec3x4 {
    /// The four vectors `a` as lanes.
    #[inline(always)]
    pub fn from_array(a: [DVec3; LANES]) -> Self {
        DVec3x4 { x: F64x4(each(a, |v| v.x)), y: F64x4(each(a, |v| v.y)), z: F64x4(each(a, |v| v.z)) }
    }

    /// The lanes as four vectors.
    #[inline(always)]
    pub fn to_array(self) -> [DVec3; LANES] {
        let (x, y, z) = (self.x.0, self.y.0, self.z.0);
        each([0, 1, 2, 3], |i| DVec3::new(x[i], y[i], z[i]))
    }
}

impl Add for DVec3x4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        DVec3x4 { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl Sub for DVec3x4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        DVec3x4 { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl Mul<f64> for DVec3x4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: f64) -> Self {
        DVec3x4 { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

impl Mul<F64x4> for DVec3x4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: F64x4) -> Self {
        DVec3x4 { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

impl Div<F64x4> for DVec3x4 {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: F64x4) -> Self {
        DVec3x4 { x: self.x / s, y: self.y / s, z: self.z / s }
    }
}

impl Vector for DVec3 {
    type Real = f64;
    const ZERO: Self = DVec3::ZERO;
    #[inline(always)]
    fn splat(v: DVec3) -> Self {
        v
    }
    #[inline(always)]
    fn length_squared(self) -> f64 {
        DVec3::length_squared(self)
    }
    #[inline(always)]
    fn dot(self, o: Self) -> f64 {
        DVec3::dot(self, o)
    }
    #[inline(always)]
    fn map_points(self, f: impl Fn(DVec3) -> DVec3) -> Self {
        f(self)
    }
    #[inline(always)]
    fn map_by(self, f: &impl PointMap) -> Self {
        f.one(self)
    }
}

impl Vector for DVec3x4 {
    type Real = F64x4;
    const ZERO: Self = DVec3x4 { x: F64x4([0.0; LANES]), y: F64x4([0.0; LANES]), z: F64x4([0.0; LANES]) };
    #[inline(always)]
    fn splat(v: DVec3) -> Self {
        DVec3x4 { x: F64x4([v.x; LANES]), y: F64x4([v.y; LANES]), z: F64x4([v.z; LANES]) }
    }
    #[inline(always)]
    fn length_squared(self) -> F64x4 {
        // glam's `dot`: (x x + y y) + z z.
        self.x * self.x + self.y * self.y + self.z * self.z
    }
    #[inline(always)]
    fn dot(self, o: Self) -> F64x4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    fn map_points(self, f: impl Fn(DVec3) -> DVec3) -> Self {
        DVec3x4::from_array(each(self.to_array(), f))
    }
    #[inline(always)]
    fn map_by(self, f: &impl PointMap) -> Self {
        f.four(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_round_trip_and_match_the_scalar_operations_bit_for_bit() {
        let a = [DVec3::new(1.0, -2.0, 3.5), DVec3::new(0.1, 0.2, 0.3), DVec3::ZERO, DVec3::splat(1e-300)];
        let b = [DVec3::new(-7.0, 2.5, 1e9), DVec3::splat(1.0 / 3.0), DVec3::X, DVec3::new(3.0, 4.0, 5.0)];
        let (va, vb) = (DVec3x4::from_array(a), DVec3x4::from_array(b));
        assert_eq!(va.to_array(), a);
        let s = F64x4([0.5, -1.0, 3.0, 1e-3]);
        let got = ((va + vb) * 0.7 - vb * s).to_array();
        let divided = (va / s).to_array();
        let lengths = (va - vb).length_squared().0;
        for i in 0..LANES {
            assert_eq!(got[i], (a[i] + b[i]) * 0.7 - b[i] * s.0[i]);
            assert_eq!(divided[i], a[i] / s.0[i]);
            assert_eq!(lengths[i], (a[i] - b[i]).length_squared());
            assert_eq!(va.dot(vb).0[i], a[i].dot(b[i]));
        }
    }
}
