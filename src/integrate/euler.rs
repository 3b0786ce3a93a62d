//! Forward Euler.

use super::{ForceField, Scheme};
use crate::numeric::lanes::Vector;

/// Forward (explicit) Euler: `x' = x + h v`, `v' = v + h a(x, v)`. Order 1; stable only for
/// `h < 2τ`. Offered for the accuracy study, not for production runs.
#[derive(Debug, Clone, Copy, Default)]
pub struct Euler;

impl Scheme for Euler {
    const ORDER: u32 = 1;
    /// `|1 − λh| < 1`.
    const STABILITY_INTERVAL: f64 = 2.0;
    /// `x' = x + h v`: the step's own acceleration does not move the particle.
    const DISPLACEMENT_SHARE: f64 = 0.0;

    #[inline(always)]
    fn advance<V: Vector, F: ForceField<V>>(self, f: &F, x: V, v: V, h: f64) -> (V, V) {
        let a = f.eval(x, v).total(v);
        (x + v * h, v + a * h)
    }
}
