//! The classical fourth-order Runge–Kutta method.

use super::{ForceField, Scheme};
use crate::numeric::lanes::Vector;

/// Classical RK4 on `y = (x, v)`, `y' = (v, a(x, v))`. Order 4; explicit, so stable only for
/// `h` below about 2.8 τ.
#[derive(Debug, Clone, Copy, Default)]
pub struct Rk4;

impl Scheme for Rk4 {
    const ORDER: u32 = 4;
    /// `|1 − z + z²/2 − z³/6 + z⁴/24| < 1` for `0 < z = λh < 2.7853`.
    const STABILITY_INTERVAL: f64 = 2.785_293_563_405_282;
    /// Exact under a constant acceleration: `x' = x + h v + h² a/2`.
    const DISPLACEMENT_SHARE: f64 = 0.5;

    #[inline(always)]
    fn advance<V: Vector, F: ForceField<V>>(self, f: &F, x: V, v: V, h: f64) -> (V, V) {
        let half = 0.5 * h;
        let (k1x, k1v) = (v, f.eval(x, v).total(v));
        let (x2, v2) = (x + k1x * half, v + k1v * half);
        let (k2x, k2v) = (v2, f.eval(x2, v2).total(v2));
        let (x3, v3) = (x + k2x * half, v + k2v * half);
        let (k3x, k3v) = (v3, f.eval(x3, v3).total(v3));
        let (x4, v4) = (x + k3x * h, v + k3v * h);
        let (k4x, k4v) = (v4, f.eval(x4, v4).total(v4));
        let sixth = h / 6.0;
        (x + (k1x + k2x * 2.0 + k3x * 2.0 + k4x) * sixth, v + (k1v + k2v * 2.0 + k3v * 2.0 + k4v) * sixth)
    }
}
