//! Contact times: Hertz (solids) and the mass–spring analogy (drops).

use super::ADDED_MASS_WALL;
use super::stokes::reduce;
use std::f64::consts::PI;

/// Hertz contact time of a sphere on a flat wall, L06 eq. 3, in s:
///
/// `t = 2.54 ρp^(2/5) [ (1−νp²)/Ep + (1−νw²)/Ew ]^(2/5) d V_imp^(−1/5)`
///
/// `rho_p` particle density (kg/m³), `e_p, nu_p` and `e_w, nu_w` Young's modulus (Pa) and
/// Poisson ratio of particle and wall, `d` diameter (m), `v_imp` impact speed (m/s).
/// Elastic, quasi-static impacts (speeds far below the elastic wave speed). `v_imp = 0` gives +∞.
pub fn hertz_contact_time(rho_p: f64, e_p: f64, nu_p: f64, e_w: f64, nu_w: f64, d: f64, v_imp: f64) -> f64 {
    let compliance = (1.0 - nu_p * nu_p) / e_p + (1.0 - nu_w * nu_w) / e_w;
    2.54 * rho_p.powf(0.4) * compliance.powf(0.4) * d * v_imp.powf(-0.2)
}

/// The fluid correction of L06 eq. 4 (dimensionless), the factor multiplying `t_Hertz`:
///
/// `((ρp + C_Mwall ρ)/ρp)^(2/5) / (1 − 0.85 St^(−0.1))`,  `C_Mwall = 0.73`
///
/// Fitted to data for 17 < St < 10³; it diverges at St = 0.85^10 ≈ 0.197 and is `None` at or
/// below that (there is no physical contact time there; such impacts are below `St_c` anyway).
pub fn immersed_solid_correction(rho_p: f64, rho: f64, st: f64) -> Option<f64> {
    let viscous = 1.0 - 0.85 * st.powf(-0.1);
    (viscous > 0.0).then(|| ((rho_p + ADDED_MASS_WALL * rho) / rho_p).powf(0.4) / viscous)
}

/// Contact time of an immersed solid sphere, L06 eq. 4, in s: [`hertz_contact_time`] times
/// [`immersed_solid_correction`]. Same arguments and units, plus the fluid density `rho`
/// (kg/m³) and the impact Stokes number `st`. `None` for St ≤ 0.197 (see the correction).
#[allow(clippy::too_many_arguments)]
pub fn immersed_solid_contact_time(
    rho_p: f64,
    rho: f64,
    e_p: f64,
    nu_p: f64,
    e_w: f64,
    nu_w: f64,
    d: f64,
    v_imp: f64,
    st: f64,
) -> Option<f64> {
    immersed_solid_correction(rho_p, rho, st)
        .map(|c| c * hertz_contact_time(rho_p, e_p, nu_p, e_w, nu_w, d, v_imp))
}

/// Contact time of a drop on a wall by the mass–spring analogy, L06 eq. 5, in s:
///
/// `t_c = π sqrt(m*/K)`, `m* = (ρp + C_Mwall ρ) π d³/6`, `K = 16π σ / 5`,
/// i.e. `t_c = π sqrt(5/96) sqrt((ρp + C_Mwall ρ) d³ / σ) ≈ 0.717 sqrt((ρp + C_Mwall ρ) d³/σ)`.
///
/// `rho_p`, `rho` drop and fluid density (kg/m³), `d` diameter (m), `sigma` interfacial
/// tension (N/m). Independent of the impact speed; for drops that stay nearly spherical
/// (Weber number of order 1 or below).
pub fn drop_contact_time(rho_p: f64, rho: f64, d: f64, sigma: f64) -> f64 {
    let mass = (rho_p + ADDED_MASS_WALL * rho) * PI * d * d * d / 6.0;
    let stiffness = 16.0 * PI * sigma / 5.0;
    PI * (mass / stiffness).sqrt()
}

/// Hertz contact time of a pair **[ext]** (docs/physics.md §4), in s:
/// `t = 2.87 (m*² / (a* E*² Vn))^(1/5)`, with reduced mass `m*` (kg), reduced radius `a*` (m),
/// effective modulus `1/E* = Σ (1−νi²)/Ei` given as `compliance = 1/E*` (1/Pa), and relative
/// normal speed `vn` (m/s). With `a2 = ∞`, `m2 = ∞` it reduces to L06 eq. 3.
pub fn hertz_pair_contact_time(m_red: f64, a_red: f64, compliance: f64, vn: f64) -> f64 {
    let e_star = 1.0 / compliance;
    2.87 * (m_red * m_red / (a_red * e_star * e_star * vn)).powf(0.2)
}

/// Contact time of two drops **[ext]** (docs/physics.md §4): two springs `K_i = 16π σ_i / 5` in
/// series and the reduced mass, half a period `π sqrt(m*/K)`, in s. `m1, m2` the drops'
/// wall-added-mass-inclusive masses (kg), `sigma1, sigma2` their interfacial tensions (N/m).
pub fn spring_pair_contact_time(m1: f64, m2: f64, sigma1: f64, sigma2: f64) -> f64 {
    let k = reduce(16.0 * PI * sigma1 / 5.0, 16.0 * PI * sigma2 / 5.0);
    PI * (reduce(m1, m2) / k).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drop_contact_time_prefactor_is_0_717() {
        // π sqrt(5/96) = 0.7170…
        let t = drop_contact_time(1.0, 0.0, 1.0, 1.0 / (1.0 + 0.0));
        let prefactor = PI * (5.0_f64 / 96.0).sqrt();
        assert!((t - prefactor).abs() < 1e-14 && (prefactor - 0.717).abs() < 5e-4);
    }

    #[test]
    fn pair_hertz_reduces_to_wall_formula_eq3() {
        let (rho, e, nu, d, v) = (7800.0, 2e11, 0.3, 4e-3, 0.5);
        let a = d / 2.0;
        let m = rho * PI * d * d * d / 6.0;
        let compliance = 2.0 * (1.0 - nu * nu) / e;
        let pair = hertz_pair_contact_time(m, a, compliance, v);
        let wall = hertz_contact_time(rho, e, nu, e, nu, d, v);
        // 2.87 vs 2.54·(π/6)^(2/5)·2^(1/5) = 2.870: same formula to the paper's 3 digits.
        assert!((pair - wall).abs() / wall < 2e-3, "{pair} vs {wall}");
    }

    #[test]
    fn eq4_correction_diverges_below_st_0_197() {
        assert!(immersed_solid_correction(2500.0, 1000.0, 0.19).is_none());
        assert!(immersed_solid_correction(2500.0, 1000.0, 17.0).unwrap() > 1.0);
    }
}
