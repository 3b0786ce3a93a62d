//! Forward Euler.

use super::{ForceField, Scheme};
use glam::DVec3;

/// Forward (explicit) Euler: `x' = x + h v`, `v' = v + h a(x, v)`. Order 1; stable only for
/// `h < 2τ`. Offered for the accuracy study, not for production runs.
#[derive(Debug, Clone, Copy, Default)]
pub struct Euler;

impl Scheme for Euler {
    const ORDER: u32 = 1;
    /// `|1 − λh| < 1`.
    const STABILITY_INTERVAL: f64 = 2.0;

    #[inline(always)]
    fn advance<F: ForceField>(self, f: &F, x: DVec3, v: DVec3, h: f64) -> (DVec3, DVec3) {
        let a = f.eval(x, v).total(v);
        (x + h * v, v + h * a)
    }
}
