//! Coefficient of restitution against the Stokes number.

/// What the bounce rule does at a given Stokes number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Restitution {
    /// `St < St_c`: no rebound; the normal velocity is removed (L06 §4).
    NoRebound,
    /// `St ≥ St_c`: rebound with this coefficient `ε = ε_max exp(−β/St)`.
    Rebound(f64),
}

impl Restitution {
    /// The coefficient, 0 for no rebound.
    pub fn value(self) -> f64 {
        match self {
            Restitution::NoRebound => 0.0,
            Restitution::Rebound(e) => e,
        }
    }
}

/// Restitution `ε = ε_max · exp(−β / St)` (dimensionless), L06 eq. 2, with no rebound below
/// the critical Stokes number `St_c` (L06 §4: measured 10–15; the engine's default is 10).
///
/// `st` Stokes number of the impact (L06 §2), `eps_max` restitution of the particle/wall pair in
/// air, `beta` = 35 in L06. Fitted to drops and solid spheres in air and in liquids over
/// 10 ≲ St ≲ 10⁴; `St = ∞` (vacuum) gives `ε_max`.
pub fn restitution(st: f64, eps_max: f64, beta: f64, st_critical: f64) -> Restitution {
    if st < st_critical { Restitution::NoRebound } else { Restitution::Rebound(eps_max * (-beta / st).exp()) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn st_exactly_at_critical_rebounds() {
        // docs/physics.md §5: "St < St_c: no rebound", so St = St_c rebounds.
        assert!(matches!(restitution(10.0, 1.0, 35.0, 10.0), Restitution::Rebound(_)));
        assert_eq!(restitution(9.999, 1.0, 35.0, 10.0), Restitution::NoRebound);
    }

    #[test]
    fn infinite_stokes_number_gives_eps_max() {
        assert_eq!(restitution(f64::INFINITY, 0.91, 35.0, 10.0).value(), 0.91);
    }
}
