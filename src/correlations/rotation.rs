//! Rotation of a sphere **[ext]** (docs/physics.md §9): its moment of inertia and the Stokes torque
//! of the fluid on it.

/// Moment of inertia of a uniform sphere of density `rho_p` (kg/m³) and diameter `d` (m) about
/// a diameter, `I = (2/5) m a² = ρp π d⁵ / 60` (kg m²). Rigid-body mechanics (any textbook,
/// e.g. Landau & Lifshitz, *Mechanics* §32). Valid for a solid sphere of uniform density; for a
/// drop it assumes rigid-body rotation of the drop (see docs/physics.md, rotation).
pub fn sphere_moment_of_inertia(rho_p: f64, d: f64) -> f64 {
    std::f64::consts::PI * rho_p * d.powi(5) / 60.0
}

/// Stokes torque (N m) on a sphere of radius `a` (m) spinning at `omega_rel` (rad/s) relative to
/// half the fluid's vorticity, in a fluid of viscosity `mu` (Pa s):
/// `T = −8π μ a³ (ω − ½ ∇×u)` (Kirchhoff; Happel & Brenner, *Low Reynolds number
/// hydrodynamics* (1965), eq. 5-3.14; Lamb, *Hydrodynamics* §334). Valid at a rotational
/// Reynolds number `ρ |ω| a² / μ ≪ 1`; no finite-Re correction is applied.
pub fn rotational_stokes_torque(mu: f64, a: f64, omega_rel: glam::DVec3) -> glam::DVec3 {
    -8.0 * std::f64::consts::PI * mu * a * a * a * omega_rel
}

/// Spin relaxation rate times d² (m²/s) of a uniform sphere of density `rho_p` in a fluid of
/// viscosity `mu`: `8π μ a³ / I = 15 μ / (ρp a²) = 60 μ / (ρp d²)`, so `1/τ_ω = rate / d²`.
/// From [`rotational_stokes_torque`] and [`sphere_moment_of_inertia`]; the added mass of a
/// sphere in potential flow has no rotational part, so `ρp` alone carries the inertia.
pub fn spin_relaxation_rate_d2(mu: f64, rho_p: f64) -> f64 {
    60.0 * mu / rho_p
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn torque_over_inertia_is_the_relaxation_rate() {
        let (mu, rho, d) = (1e-3, 2500.0, 2e-3);
        let omega = DVec3::new(0.0, 0.0, 10.0);
        let alpha = rotational_stokes_torque(mu, 0.5 * d, omega) / sphere_moment_of_inertia(rho, d);
        let rate = spin_relaxation_rate_d2(mu, rho) / (d * d);
        assert!((alpha.z + rate * 10.0).abs() < 1e-12 * rate * 10.0, "{alpha} {rate}");
        // I = 2/5 m a².
        let m = rho * std::f64::consts::PI * d * d * d / 6.0;
        assert!((sphere_moment_of_inertia(rho, d) - 0.4 * m * 0.25 * d * d).abs() < 1e-25);
    }
}
