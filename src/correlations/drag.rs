//! Drag factor and Reynolds number.

use crate::numeric::FixedPower;
use crate::numeric::lanes::Real;

/// Particle Reynolds number `Re = ρ |w| d / μ` (dimensionless).
///
/// `rho` fluid density (kg/m³), `slip_speed` = |v − u| (m/s), `d` diameter (m), `mu` dynamic
/// viscosity (Pa·s). Returns +∞ for `mu = 0` (inviscid fluid, or vacuum with `rho = 0`: 0/0 is
/// taken as 0).
pub fn reynolds_number(rho: f64, slip_speed: f64, d: f64, mu: f64) -> f64 {
    let num = rho * slip_speed * d;
    if num == 0.0 { 0.0 } else { num / mu }
}

/// `Re^0.687`, the Schiller–Naumann exponent, by [`FixedPower`] (tables built at compile time).
static RE_POWER: FixedPower = FixedPower::new(0.687);
/// `(Re²)^0.3435 = Re^0.687`.
static RE2_POWER: FixedPower = FixedPower::new(0.687 / 2.0);

/// Reynolds number above which the drag coefficient is held at its Newton-regime value.
pub const NEWTON_REYNOLDS: f64 = 1000.0;
/// Newton-regime drag coefficient `C_D = 0.44` used above [`NEWTON_REYNOLDS`] **[ext]**.
pub const NEWTON_DRAG_COEFFICIENT: f64 = 0.44;

/// Schiller–Naumann drag factor `f(Re) = 1 + 0.15 Re^0.687` (dimensionless), the ratio of the
/// drag to Stokes drag `3π μ d |w|` (L06 eq. 7; Schiller & Naumann 1933).
///
/// Valid for a rigid sphere up to Re ≈ 1000. **[ext]** Above Re = 1000 the drag coefficient
/// `C_D = 24 f / Re` is held at 0.44 (Newton regime), i.e. `f = 0.44 Re / 24`; the two
/// branches meet within 0.5 % at Re = 1000. `Re^0.687` comes from [`FixedPower`], within
/// 2e-15 of `powf` and several times cheaper.
#[inline]
pub fn drag_factor_schiller_naumann(re: f64) -> f64 {
    if re <= NEWTON_REYNOLDS { 1.0 + 0.15 * RE_POWER.pow(re) } else { NEWTON_DRAG_COEFFICIENT * re / 24.0 }
}

/// [`drag_factor_schiller_naumann`] of `Re²` (dimensionless), without its square root:
/// `1 + 0.15 (Re²)^0.3435`, and the Newton branch above `Re² = 10⁶`. Of one particle (`f64`) or
/// of a lane group ([`crate::numeric::lanes::F64x4`]): a group all below the Newton branch takes the
/// power in lanes, any other goes lane by lane.
#[inline(always)]
pub fn drag_factor_schiller_naumann_of_squared<R: Real>(re2: R) -> R {
    if re2.all(|r| r <= NEWTON_REYNOLDS * NEWTON_REYNOLDS) {
        R::splat(1.0) + re2.pow_fixed(&RE2_POWER) * 0.15
    } else {
        re2.map(|r| {
            if r <= NEWTON_REYNOLDS * NEWTON_REYNOLDS {
                1.0 + 0.15 * RE2_POWER.pow(r)
            } else {
                NEWTON_DRAG_COEFFICIENT * r.sqrt() / 24.0
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schiller_naumann_is_stokes_at_vanishing_reynolds() {
        assert_eq!(drag_factor_schiller_naumann(0.0), 1.0);
    }

    #[test]
    fn newton_branch_joins_schiller_naumann_within_half_a_percent() {
        let below = drag_factor_schiller_naumann(NEWTON_REYNOLDS);
        let above = drag_factor_schiller_naumann(NEWTON_REYNOLDS * (1.0 + 1e-12));
        assert!((below - above).abs() / below < 5e-3, "{below} vs {above}");
    }

    #[test]
    fn factor_of_the_squared_reynolds_number_is_the_factor() {
        for re in [0.0, 1e-9, 0.3, 1.0, 17.5, 999.9, 1000.0, 1000.1, 5e4] {
            let (f, f2) =
                (drag_factor_schiller_naumann(re), drag_factor_schiller_naumann_of_squared(re * re));
            assert!((f - f2).abs() <= 4e-15 * f, "Re = {re}: {f} vs {f2}");
        }
    }

    #[test]
    fn reynolds_number_of_water_drop_matches_hand_value() {
        // 1 mm at 0.1 m/s in water (ρ = 1000, μ = 1e-3): Re = 100.
        assert!((reynolds_number(1000.0, 0.1, 1e-3, 1e-3) - 100.0).abs() < 1e-12);
        assert_eq!(reynolds_number(0.0, 1.0, 1e-3, 0.0), 0.0);
    }
}
