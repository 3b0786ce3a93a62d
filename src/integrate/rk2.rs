//! Heun's second-order Runge–Kutta method, L06's integrator.

use super::{ForceField, Scheme};
use crate::numeric::lanes::Vector;

/// Heun's method (the explicit trapezoidal rule), the two-stage Runge–Kutta scheme with
/// tableau `c = (0, 1)`, `b = (1/2, 1/2)`:
///
/// `k1 = f(y)`, `k2 = f(y + h k1)`, `y' = y + h (k1 + k2)/2`, for `y = (x, v)`.
///
/// L06 says only "second-order Runge–Kutta"; Heun's is the textbook RK2 and, like every
/// second-order scheme, exact for motion under a constant force (a ball in vacuum).
#[derive(Debug, Clone, Copy, Default)]
pub struct Rk2;

impl Scheme for Rk2 {
    const ORDER: u32 = 2;
    /// `|1 − z + z²/2| < 1` for `0 < z = λh < 2`.
    const STABILITY_INTERVAL: f64 = 2.0;
    /// `x' = x + h (v + v + h a)/2`.
    const DISPLACEMENT_SHARE: f64 = 0.5;

    #[inline(always)]
    fn advance<V: Vector, F: ForceField<V>>(self, f: &F, x: V, v: V, h: f64) -> (V, V) {
        let a1 = f.eval(x, v).total(v);
        let (x2, v2) = (x + v * h, v + a1 * h);
        let a2 = f.eval(x2, v2).total(v2);
        (x + (v + v2) * (0.5 * h), v + (a1 + a2) * (0.5 * h))
    }
}
