//! Stiffness of the drag: how fast the drag force grows with the slip speed.

use super::drag::{NEWTON_DRAG_COEFFICIENT, NEWTON_REYNOLDS};

/// Schiller–Naumann stiffness factor `d(Re f(Re))/dRe = f + Re f'(Re)` (dimensionless).
///
/// The drag force is `3π μ d f(Re) w` along the slip `w` (L06 eq. 7); its derivative with respect
/// to the slip speed is `3π μ d (f + Re f')`, so an explicit integrator sees the relaxation rate
/// `(f + Re f') / τ_Stokes` along the slip, larger than the rate `f / τ_Stokes` that sets the
/// relaxation time of L06 eq. 6 (the two transverse directions see `f / τ_Stokes`). With
/// `f = 1 + 0.15 Re^0.687`: `1 + 0.15 · 1.687 Re^0.687`; **[ext]** in the Newton regime above
/// Re = 1000, `f = 0.44 Re/24` and the factor is `2 f`. Increasing in `Re`, so its value at a
/// bound on the slip speed bounds it below that speed.
pub fn schiller_naumann_stiffness_factor(re: f64) -> f64 {
    if re <= NEWTON_REYNOLDS {
        1.0 + 0.15 * 1.687 * re.powf(0.687)
    } else {
        2.0 * NEWTON_DRAG_COEFFICIENT * re / 24.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::correlations::drag_factor_schiller_naumann;

    #[test]
    fn stiffness_factor_is_the_derivative_of_re_times_f() {
        for re in [0.01, 1.0, 50.0, 400.0, 999.0, 2000.0, 1e5] {
            let h = 1e-6 * re;
            let force = |r: f64| r * drag_factor_schiller_naumann(r);
            let numeric = (force(re + h) - force(re - h)) / (2.0 * h);
            let exact = schiller_naumann_stiffness_factor(re);
            assert!((numeric - exact).abs() < 1e-6 * exact, "Re {re}: {numeric} vs {exact}");
        }
    }
}
