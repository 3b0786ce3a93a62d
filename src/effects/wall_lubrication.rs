//! **[ext]** Wall lubrication: the Stokes-flow drag and added mass of a sphere near a wall
//! (docs/physics.md §8).

use super::{Effect, Physics};
use crate::correlations::{added_mass_normal_and_slope, wall_factor_normal, wall_factor_parallel};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// With this effect, a particle whose lubrication gap `h` to its nearest wall is within
/// [`RANGE`] radii feels the wall (docs/physics.md §8): the drag normal to the wall grows by
/// `λ⊥(h/a) − 1` times Stokes drag, the drag parallel to it by `λ∥(h/a) − 1`, and with the
/// added-mass effect the inertia normal to the wall follows the image series `C_M(h)`. Contact
/// is made at the particle's roughness plus the wall's, where the `e` rule applies (docs/physics.md
/// §3, §8). Scene table: `wall_lubrication = {}`; the roughnesses are material keys.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallLubrication {}

impl Effect for WallLubrication {
    fn name(&self) -> &'static str {
        "wall_lubrication"
    }

    fn apply(&self, _fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        physics.wall_lubrication = true;
    }
}

/// Lubrication gap over radius beyond which the wall is not felt at all. The wall terms are
/// tapered to zero between [`TAPER_START`] and here, so that the force is continuous: at 10
/// radii Brenner's `λ⊥ − 1` is 0.10 and `λ∥ − 1` 0.05, and from 5 radii on the wall adds
/// less than 0.19 to the drag factor.
pub const RANGE: f64 = 10.0;
/// Lubrication gap over radius where the taper to zero begins (see [`RANGE`]).
pub const TAPER_START: f64 = 5.0;

/// The weight of the wall terms at gap ratio `eps = h/a`: 1 up to [`TAPER_START`], 0 from
/// [`RANGE`] on, a smoothstep (continuous with its derivative) in between.
pub fn taper(eps: f64) -> f64 {
    if eps <= TAPER_START {
        1.0
    } else if eps >= RANGE {
        0.0
    } else {
        let s = (RANGE - eps) / (RANGE - TAPER_START);
        s * s * (3.0 - 2.0 * s)
    }
}

/// What a wall at gap ratio `eps = h/a` (`h` the lubrication gap, `a` the radius) adds, all
/// dimensionless: to the drag factor normal to the wall, `(λ⊥ − 1) w`; parallel to it,
/// `(λ∥ − 1) w`; to the normal added-mass coefficient, `(C_M(h) − 1/2) w`, and that term's
/// derivative in `eps` (for the `−½ (dm/dh) v_n²` force that keeps the energy of the potential
/// flow consistent). `w` is [`taper`]. Brenner (1961) and O'Neill (1964) in their fast forms
/// (`correlations::wall_hindrance`, relative error ≤ 3e-5), the image series for `C_M`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallExcess {
    /// `(λ⊥ − 1) w`.
    pub normal: f64,
    /// `(λ∥ − 1) w`.
    pub parallel: f64,
    /// `(C_M(h) − 1/2) w`.
    pub added_mass: f64,
    /// `d/d eps` of `added_mass`.
    pub added_mass_slope: f64,
}

/// [`WallExcess`] at gap ratio `eps > 0`.
pub fn wall_excess(eps: f64) -> WallExcess {
    let w = taper(eps);
    if w == 0.0 {
        return WallExcess { normal: 0.0, parallel: 0.0, added_mass: 0.0, added_mass_slope: 0.0 };
    }
    let (cm, cm_slope) = added_mass_normal_and_slope(eps);
    WallExcess {
        normal: (wall_factor_normal(eps) - 1.0) * w,
        parallel: (wall_factor_parallel(eps) - 1.0) * w,
        added_mass: (cm - 0.5) * w,
        added_mass_slope: cm_slope * w + (cm - 0.5) * taper_slope(eps),
    }
}

/// `d/d eps` of [`taper`].
fn taper_slope(eps: f64) -> f64 {
    if eps <= TAPER_START || eps >= RANGE {
        0.0
    } else {
        let s = (RANGE - eps) / (RANGE - TAPER_START);
        -6.0 * s * (1.0 - s) / (RANGE - TAPER_START)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wall_terms_vanish_beyond_the_range_and_are_continuous_at_its_ends() {
        assert_eq!(wall_excess(RANGE).normal, 0.0);
        assert_eq!(wall_excess(50.0).parallel, 0.0);
        let (a, b) = (wall_excess(TAPER_START - 1e-9), wall_excess(TAPER_START + 1e-9));
        assert!((a.normal - b.normal).abs() < 1e-8);
        assert!((wall_excess(RANGE - 1e-9).normal).abs() < 1e-8);
    }

    #[test]
    fn added_mass_slope_is_the_derivative_of_the_tapered_series() {
        use crate::correlations::added_mass_normal_exact;
        let cm = |e: f64| (added_mass_normal_exact(e) - 0.5) * taper(e);
        for eps in [1e-6, 1e-4, 1e-2, 0.3, 1.0, 1.5, 1.6, 3.0, 6.0, 8.0, 9.9] {
            let d = 1e-5 * eps;
            let fd = (cm(eps + d) - cm(eps - d)) / (2.0 * d);
            let slope = wall_excess(eps).added_mass_slope;
            assert!((slope - fd).abs() <= 1e-6 * fd.abs() + 1e-12, "eps {eps}: {slope} vs {fd}");
        }
    }

    #[test]
    fn near_contact_the_normal_excess_follows_cox_and_brenner_and_added_mass_nears_0_803() {
        let e = wall_excess(1e-4);
        let cox = 1e4 + 0.2 * (1e4f64).ln() + 0.971 - 1.0;
        assert!((e.normal - cox).abs() / cox < 1e-4, "{}", e.normal);
        assert!((e.added_mass + 0.5 - 0.803).abs() < 2e-3, "{}", e.added_mass);
        assert!(e.added_mass_slope < 0.0);
    }
}
