//! **[ext]** Wall lubrication: the Stokes-flow drag and added mass of a sphere near a wall
//! (docs/physics.md §8).

use super::{Effect, Physics};
use crate::correlations::{added_mass_normal_and_slope, wall_factor_normal, wall_factor_parallel};
use crate::fluid::Fluid;
use crate::numeric::lanes::{F64x4, Real, each};
use crate::particles::ParticleKind;
use serde::Deserialize;
use std::sync::Arc;

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
        physics.wall_lubrication = Some(Arc::new(WallTable::new()));
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
/// Of one gap, or of a lane group of four ([`WallTable::excess_lanes`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallExcess<R = f64> {
    /// `(λ⊥ − 1) w`.
    pub normal: R,
    /// `(λ∥ − 1) w`.
    pub parallel: R,
    /// `(C_M(h) − 1/2) w`.
    pub added_mass: R,
    /// `d/d eps` of `added_mass`.
    pub added_mass_slope: R,
}

impl WallExcess {
    /// Nothing: beyond the range.
    const NONE: WallExcess =
        WallExcess { normal: 0.0, parallel: 0.0, added_mass: 0.0, added_mass_slope: 0.0 };
}

/// [`WallExcess`] at gap ratio `eps > 0`.
pub fn wall_excess(eps: f64) -> WallExcess {
    let w = taper(eps);
    if w == 0.0 {
        return WallExcess::NONE;
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

/// Gap ratio from which [`WallTable`] interpolates (below it, in the film, the wall terms are
/// evaluated in their fast closed forms, whose steep `1/ε` and `ln ε` a table would need many
/// more nodes for).
const TABLE_FROM: f64 = 0.5;
/// Intervals of [`WallTable`]'s grid.
const TABLE_INTERVALS: usize = 1024;

/// The wall terms of [`wall_excess`] between [`TABLE_FROM`] and [`RANGE`], tabulated once per
/// scene: the four untapered functions `λ⊥ − 1`, `λ∥ − 1`, `C_M − 1/2` and `dC_M/dε` on a
/// uniform grid of `s = 1/(1 + ε)`, where each is smooth, interpolated by the cubic through the
/// four nearest nodes, then tapered. Evaluating the closed forms (a logarithm, the added mass's
/// image sum and its slope) was two thirds of a near-wall particle's flight, and a particle
/// away from the film evaluates them twice per step. Error against [`wall_excess`] (test
/// `the_table_is_the_closed_forms_to_1e_11`): below 1e-11 relative for the drag factors and
/// the added mass, a millionth of the fast forms' own error against the exact series; below
/// 2e-8 for the added mass's slope, whose closed form itself steps by 1e-8 where its tail stops
/// (`ε` = 1.58), a term of `(dm/dh) v_n²` that the cubic smooths.
#[derive(Debug, Clone, PartialEq)]
pub struct WallTable {
    /// `s` of node 0 (one interval below `1/(1 + RANGE)`: every cubic has its four nodes).
    s0: f64,
    /// Intervals per unit of `s`.
    per_s: f64,
    /// The four functions at every node.
    nodes: Vec<[f64; 4]>,
}

impl WallTable {
    /// The table, from the closed forms (about 10⁶ instructions, once per scene).
    pub fn new() -> Self {
        let (lo, hi) = (1.0 / (1.0 + RANGE), 1.0 / (1.0 + TABLE_FROM));
        let ds = (hi - lo) / TABLE_INTERVALS as f64;
        let s0 = lo - ds;
        let nodes = (0..TABLE_INTERVALS + 3)
            .map(|i| {
                let eps = 1.0 / (s0 + i as f64 * ds) - 1.0;
                let (cm, cm_slope) = added_mass_normal_and_slope(eps);
                [wall_factor_normal(eps) - 1.0, wall_factor_parallel(eps) - 1.0, cm - 0.5, cm_slope]
            })
            .collect();
        WallTable { s0, per_s: 1.0 / ds, nodes }
    }

    /// [`wall_excess`] at gap ratio `eps > 0`, interpolated from [`TABLE_FROM`] on.
    #[inline]
    pub fn excess(&self, eps: f64) -> WallExcess {
        if eps < TABLE_FROM {
            return wall_excess(eps);
        }
        let (i, t) = self.locate(eps);
        let rows = &self.nodes[i - 1..i + 3];
        let f = interpolate(lagrange(t - i as f64), |m, c| rows[m][c]);
        tapered(f, taper(eps), taper_slope(eps))
    }

    /// [`WallTable::excess`] of a lane group, lane for lane the same bits: in lane form when
    /// every gap is in the table (the common case: the film is a small part of the range).
    #[inline(always)]
    pub fn excess_lanes(&self, eps: F64x4) -> WallExcess<F64x4> {
        if !eps.all(|e| e >= TABLE_FROM) {
            let e = each(eps.0, |e| self.excess(e));
            return WallExcess {
                normal: F64x4(each(e, |e| e.normal)),
                parallel: F64x4(each(e, |e| e.parallel)),
                added_mass: F64x4(each(e, |e| e.added_mass)),
                added_mass_slope: F64x4(each(e, |e| e.added_mass_slope)),
            };
        }
        let found = each(eps.0, |e| self.locate(e));
        let rows = each(found, |(i, _)| &self.nodes[i - 1..i + 3]);
        let weights = lagrange(F64x4(each(found, |(i, t)| t - i as f64)));
        let f = interpolate(weights, |m, c| F64x4(each(rows, |row| row[m][c])));
        tapered(f, eps.map(taper), eps.map(taper_slope))
    }

    /// The interval `i` of gap ratio `eps` (its nodes `i − 1 … i + 2`) and the position `t` on
    /// the grid (`t − i` within the interval).
    #[inline(always)]
    fn locate(&self, eps: f64) -> (usize, f64) {
        let t = (1.0 / (1.0 + eps) - self.s0) * self.per_s;
        // Nodes i − 1 … i + 2 around t (> 1 in the table: the cast is the floor), i ≥ 1 and
        // i + 2 within the table at both ends.
        (((t as usize).clamp(1, TABLE_INTERVALS)), t)
    }
}

/// The Lagrange weights of the nodes at −1, 0, 1, 2 of an interval at `u` within it
/// (`u` ∈ [0, 1)), for the cubic through them. Of one value or a lane group, with the same
/// operations.
#[inline(always)]
fn lagrange<R: Real>(u: R) -> [R; 4] {
    let (um, up, u2) = (u + R::splat(1.0), u - R::splat(1.0), u - R::splat(2.0));
    const SIXTH: f64 = 1.0 / 6.0;
    [
        (R::splat(0.0) - u) * up * u2 * SIXTH,
        um * up * u2 * 0.5,
        (R::splat(0.0) - um) * u * u2 * 0.5,
        um * u * up * SIXTH,
    ]
}

/// The four functions from the `weights` of the four nodes of an interval (`node(m, c)`: node
/// `m` of those four, function `c`). Of one value or a lane group, with the same operations.
#[inline(always)]
fn interpolate<R: Real>(weights: [R; 4], node: impl Fn(usize, usize) -> R) -> [R; 4] {
    let mut f = [R::splat(0.0); 4];
    for (m, weight) in weights.into_iter().enumerate() {
        for (c, f) in f.iter_mut().enumerate() {
            *f = *f + weight * node(m, c);
        }
    }
    f
}

/// The tabulated functions `[λ⊥ − 1, λ∥ − 1, C_M − 1/2, dC_M/dε]` tapered by `w` (slope
/// `w_slope`): zero where `w` is (the functions are finite and the slope's sum is then `+0`).
#[inline(always)]
fn tapered<R: Real>(f: [R; 4], w: R, w_slope: R) -> WallExcess<R> {
    let [normal, parallel, cm, cm_slope] = f;
    WallExcess {
        normal: normal * w,
        parallel: parallel * w,
        added_mass: cm * w,
        added_mass_slope: cm_slope * w + cm * w_slope,
    }
}

impl Default for WallTable {
    fn default() -> Self {
        Self::new()
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
    fn the_table_is_the_closed_forms_to_1e_11() {
        let table = WallTable::new();
        let (mut values, mut slope): (f64, f64) = (0.0, 0.0);
        for i in 0..=200_000 {
            // From below the table's start to past the range, the taper's corners included.
            let eps = 0.4 + 10.0 * i as f64 / 200_000.0;
            let (a, b) = (table.excess(eps), wall_excess(eps));
            for (x, y) in [(a.normal, b.normal), (a.parallel, b.parallel), (a.added_mass, b.added_mass)] {
                values = values.max((x - y).abs() / y.abs().max(1e-300));
            }
            slope = slope
                .max((a.added_mass_slope - b.added_mass_slope).abs() / b.added_mass_slope.abs().max(1e-6));
        }
        assert!(values < 1e-11 && slope < 2e-8, "{values:e} {slope:e}");
        assert_eq!(table.excess(0.3), wall_excess(0.3));
        assert_eq!(table.excess(RANGE).normal, 0.0);
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
