//! Terminal velocity: the root of the drag = net weight balance.

use super::{reynolds_number, sphere_volume};
use std::f64::consts::PI;

/// A terminal velocity and the Reynolds number it is reached at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerminalVelocity {
    /// Terminal speed `V_t` (m/s), ≥ 0.
    pub speed: f64,
    /// `Re = ρ V_t d / μ` at that speed.
    pub reynolds: f64,
    /// True when the particle is lighter than the fluid and moves against gravity.
    pub rising: bool,
}

/// Terminal velocity: the root `V` of `3π μ d f(Re) V = Vp |ρp − ρ| |g|` (docs/physics.md §1,
/// the steady state of L06 eq. 7), with `Re = ρ V d / μ`.
///
/// `drag_factor` is `f(Re)` (e.g. [`super::drag_factor_schiller_naumann`], or `|_| 1.0` for
/// Stokes drag), and must be ≥ 1 and non-decreasing, as every drag law here is. Because
/// `f ≥ 1`, the Stokes speed is an upper bound and `0` a lower bound, so a bisection on that
/// bracket converges from the Stokes to the Newton regime, for settling (`ρp > ρ`) and rising
/// (`ρp < ρ`) particles alike, to a relative 1e-14. Units: densities kg/m³, `d` m, `mu` Pa·s,
/// `g` m/s² (magnitude); the speed in m/s. `mu = 0` (no drag) gives an infinite speed.
pub fn terminal_velocity(
    rho_p: f64,
    rho: f64,
    d: f64,
    mu: f64,
    g: f64,
    drag_factor: impl Fn(f64) -> f64,
) -> TerminalVelocity {
    let weight = sphere_volume(d) * (rho_p - rho).abs() * g;
    let stokes_drag_per_speed = 3.0 * PI * mu * d;
    let residual = |v: f64| stokes_drag_per_speed * drag_factor(reynolds_number(rho, v, d, mu)) * v - weight;
    let (mut lo, mut hi) = (0.0_f64, weight / stokes_drag_per_speed);
    if hi.is_finite() && hi > 0.0 {
        // Bisection: ~50 halvings per 15 digits, each a single drag evaluation.
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if residual(mid) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
            if hi - lo <= 1e-15 * hi {
                break;
            }
        }
    }
    let speed = 0.5 * (lo + hi);
    TerminalVelocity { speed, reynolds: reynolds_number(rho, speed, d, mu), rising: rho_p < rho }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::correlations::drag_factor_schiller_naumann;

    #[test]
    fn stokes_law_speed_is_recovered_exactly() {
        // V = (ρp − ρ) g d² / (18 μ)
        let (rp, r, d, mu, g) = (2540.0, 1000.0, 1e-4, 0.1, 9.81);
        let t = terminal_velocity(rp, r, d, mu, g, |_| 1.0);
        let exact = (rp - r) * g * d * d / (18.0 * mu);
        assert!((t.speed - exact).abs() / exact < 1e-13);
    }

    #[test]
    fn newton_regime_large_bead_in_air_matches_cd_0_44() {
        // 10 mm steel ball in air: V = sqrt(4 g d (ρp − ρ) / (3 · 0.44 ρ)).
        let (rp, r, d, mu, g) = (7800.0, 1.2, 1e-2, 1.8e-5, 9.81);
        let t = terminal_velocity(rp, r, d, mu, g, drag_factor_schiller_naumann);
        let exact = (4.0 * g * d * (rp - r) / (3.0 * 0.44 * r)).sqrt();
        assert!(t.reynolds > 1000.0);
        assert!((t.speed - exact).abs() / exact < 1e-10, "{} vs {exact}", t.speed);
    }

    #[test]
    fn rising_drop_is_flagged_rising() {
        let t = terminal_velocity(860.0, 997.0, 2.5e-3, 0.89e-3, 9.81, drag_factor_schiller_naumann);
        assert!(t.rising && t.speed > 0.05 && t.speed < 0.2);
    }
}
