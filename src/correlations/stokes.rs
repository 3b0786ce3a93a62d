//! Stokes number and relaxation time.

use super::ADDED_MASS_FAR;

/// Impact Stokes number `St = (ρp + C_M∞ ρ) V∞ d / (9 μ)` (dimensionless), L06 §2.
///
/// `rho_p`, `rho` particle and fluid density (kg/m³), `v_inf` normal approach speed before the
/// particle feels the wall (m/s), `d` diameter (m), `mu` viscosity (Pa·s), `C_M∞ = 1/2`.
/// Valid for any approach speed ≥ 0; returns +∞ for `mu = 0` (vacuum or inviscid fluid, where
/// nothing damps the impact).
pub fn stokes_number(rho_p: f64, rho: f64, v_inf: f64, d: f64, mu: f64) -> f64 {
    let num = (rho_p + ADDED_MASS_FAR * rho) * v_inf * d;
    if num == 0.0 { 0.0 } else { num / (9.0 * mu) }
}

/// Pair Stokes number **[ext]** (docs/physics.md §2): `St = m* Vn / (6π μ a*²)` with the reduced,
/// added-mass-inclusive mass `m* = m1 m2 / (m1 + m2)` (kg) and reduced radius
/// `a* = a1 a2 / (a1 + a2)` (m); `vn` relative normal approach speed (m/s).
///
/// For a wall (`m2, a2 → ∞`, pass `f64::INFINITY`) this is exactly [`stokes_number`].
pub fn pair_stokes_number(m1: f64, m2: f64, a1: f64, a2: f64, vn: f64, mu: f64) -> f64 {
    let m_red = reduce(m1, m2);
    let a_red = reduce(a1, a2);
    let num = m_red * vn;
    if num == 0.0 { 0.0 } else { num / (6.0 * std::f64::consts::PI * mu * a_red * a_red) }
}

/// `x y / (x + y)`, with `y = ∞` giving `x` (a wall in a pair formula).
pub(crate) fn reduce(x: f64, y: f64) -> f64 {
    if y.is_infinite() {
        x
    } else if x.is_infinite() {
        y
    } else {
        x * y / (x + y)
    }
}

/// Relaxation time `t_r = (ρp + C_M ρ) d² / (18 μ f(Re))` in s, L06 eq. 6.
///
/// `c_m` is the added-mass coefficient in the inertia (1/2 in L06; 0 without added mass),
/// `drag_factor` the `f(Re)` of the drag law (1 for Stokes drag). Returns +∞ for `mu = 0`.
pub fn relaxation_time(rho_p: f64, rho: f64, c_m: f64, d: f64, mu: f64, drag_factor: f64) -> f64 {
    (rho_p + c_m * rho) * d * d / (18.0 * mu * drag_factor)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::correlations::sphere_volume;

    #[test]
    fn pair_stokes_number_reduces_to_wall_formula() {
        let (rho_p, rho, d, mu, v) = (860.0, 997.0, 2.75e-3, 0.89e-3, 0.12);
        let m = (rho_p + ADDED_MASS_FAR * rho) * sphere_volume(d);
        let pair = pair_stokes_number(m, f64::INFINITY, d / 2.0, f64::INFINITY, v, mu);
        let wall = stokes_number(rho_p, rho, v, d, mu);
        assert!((pair - wall).abs() / wall < 1e-13, "{pair} vs {wall}");
    }

    #[test]
    fn stokes_number_in_vacuum_is_infinite() {
        assert_eq!(stokes_number(2500.0, 0.0, 1.0, 1e-3, 0.0), f64::INFINITY);
        assert_eq!(stokes_number(2500.0, 0.0, 0.0, 1e-3, 0.0), 0.0);
    }
}
