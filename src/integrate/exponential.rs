//! Exponential integrator: the linear drag part is integrated exactly.

use super::{ForceField, Linear, Scheme};
use crate::numeric::lanes::{Real, Vector};

/// Exponential midpoint scheme. With the coefficients of [`Linear`] frozen, the equation
/// `dv/dt = a + λ(u − v)` has the exact solution (`z = −λh`)
///
/// `v(h) = v + A h φ1(z)`, `x(h) = x + v h + A h² φ2(z)`, `A = a + λ(u − v)`,
///
/// with `φ1(z) = (eᶻ − 1)/z`, `φ2(z) = (eᶻ − 1 − z)/z²`. The coefficients are taken at the
/// midpoint state predicted by a half step, so the scheme is second order when the drag factor
/// or the flow vary, exact for Stokes drag in a uniform flow whatever `h`, and unconditionally
/// stable: a step much longer than the relaxation time lands on the terminal velocity
/// (OpenFOAM's "analytical" scheme; docs/architecture.md).
#[derive(Debug, Clone, Copy, Default)]
pub struct Exponential;

/// `φ1(z) = (eᶻ − 1)/z` and `φ2(z) = (eᶻ − 1 − z)/z²`, accurate to round-off for all `z ≤ 0`.
#[inline]
pub(crate) fn phi12(z: f64) -> (f64, f64) {
    if z.abs() < 0.1 { phi12_series(z) } else { phi12_closed(z) }
}

/// `INV_FACTORIAL[i] = 1/(i + 1)!`: the Taylor coefficients of `φ1` (from index 0) and `φ2`
/// (from index 1).
const INV_FACTORIAL: [f64; 11] = {
    let mut c = [1.0; 11];
    let mut j = 1;
    while j < 11 {
        c[j] = c[j - 1] / (j + 1) as f64;
        j += 1;
    }
    c
};

/// Taylor series `φk(z) = Σ_{j<10} z^j / (j + k)!`, by Horner's rule on constant coefficients
/// (no division: it is most of the cost of the film's sub-steps, two pairs per sub-step); ten
/// terms reach 1e-17 at |z| = 0.1, where the closed form starts losing digits to cancellation.
#[inline]
fn phi12_series(z: f64) -> (f64, f64) {
    series(z)
}

/// [`phi12_series`] of one value or of a lane group, with the same operations per lane.
#[inline(always)]
fn series<R: Real>(z: R) -> (R, R) {
    let (mut phi1, mut phi2) = (R::splat(INV_FACTORIAL[9]), R::splat(INV_FACTORIAL[10]));
    for j in (0..9).rev() {
        phi1 = phi1 * z + R::splat(INV_FACTORIAL[j]);
        phi2 = phi2 * z + R::splat(INV_FACTORIAL[j + 1]);
    }
    (phi1, phi2)
}

/// [`phi12`] of each lane, the same bits: the series in lane form when every lane takes it
/// (the common case near a wall away from its film, where `|z|` is far below 0.1), else
/// lane by lane.
#[inline(always)]
pub(crate) fn phi12_lanes<R: Real>(z: R) -> (R, R) {
    if z.all(|z| z.abs() < 0.1) { series(z) } else { z.map2(phi12) }
}

#[inline]
fn phi12_closed(z: f64) -> (f64, f64) {
    let em1 = z.exp_m1();
    (em1 / z, (em1 - z) / (z * z))
}

#[inline]
fn frozen_step<V: Vector>(l: &Linear<V>, x: V, v: V, h: f64) -> (V, V) {
    let a = l.total(v);
    let (phi1, phi2) = l.inv_tau.map2(|rate| phi12(-rate * h));
    (x + v * h + a * (phi2 * (h * h)), v + a * (phi1 * h))
}

impl Scheme for Exponential {
    const ORDER: u32 = 2;
    /// The decay `e^(−λh)` is exact, below 1 for every step.
    const STABILITY_INTERVAL: f64 = f64::INFINITY;
    /// `φ2/φ1`, which is ½ for a step short against the relaxation time and tends to 1 for a
    /// long one. ½ is taken: in a bed of particles that relax within the step, the contacts
    /// gain up to half a step of settling as overlap, which the position projection removes.
    const DISPLACEMENT_SHARE: f64 = 0.5;

    #[inline(always)]
    fn advance<V: Vector, F: ForceField<V>>(self, f: &F, x: V, v: V, h: f64) -> (V, V) {
        let l0 = f.eval(x, v);
        let (xm, vm) = frozen_step(&l0, x, v, 0.5 * h);
        let lm = f.eval(xm, vm);
        frozen_step(&lm, x, v, h)
    }
}

#[cfg(test)]
mod tests {
    use super::{phi12, phi12_closed, phi12_series};

    #[test]
    fn series_and_closed_form_agree_where_the_scheme_switches() {
        let (s1, s2) = phi12_series(-0.1);
        let (c1, c2) = phi12_closed(-0.1);
        assert!((s1 - c1).abs() < 1e-15 && (s2 - c2).abs() < 1e-14, "{s1} {c1} {s2} {c2}");
        assert_eq!(phi12(0.0), (1.0, 0.5));
    }

    #[test]
    fn horners_series_matches_the_term_by_term_sum_within_two_ulps() {
        // Against 30 terms summed one by one (the form this replaced), where the
        // truncation is far below round-off: within two ulps.
        for z in [-0.1, -0.05, -1e-2, -1e-3, -1e-6, 0.0, 1e-3, 0.05] {
            let (mut t1, mut t2, mut s1, mut s2) = (1.0f64, 0.5f64, 0.0f64, 0.0f64);
            for j in 0..30 {
                s1 += t1;
                s2 += t2;
                t1 *= z / (j as f64 + 2.0);
                t2 *= z / (j as f64 + 3.0);
            }
            let (p1, p2) = phi12_series(z);
            assert!(
                (p1 - s1).abs() <= 4e-16 * s1 && (p2 - s2).abs() <= 4e-16 * s2,
                "{z}: {p1} {s1} {p2} {s2}"
            );
        }
    }

    #[test]
    fn phi_functions_tend_to_their_stiff_limits() {
        let z = -1e6;
        let (p1, p2) = phi12(z);
        assert!((p1 - 1e-6).abs() < 1e-18 && (p2 - (1e6 - 1.0) / 1e12).abs() < 1e-18);
    }
}
