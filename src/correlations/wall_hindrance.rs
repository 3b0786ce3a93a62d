//! **[ext]** Stokes-flow wall factors of a sphere near a plane wall (docs/physics.md §8): the drag
//! factors for motion normal (`λ⊥`) and parallel (`λ∥`) to the wall and the added mass of a
//! sphere moving normal to it.
//!
//! Every factor is a function of the dimensionless surface gap `ε = h/a` (`h` the gap between
//! the sphere surface and the wall, `a` the radius). Each comes twice: an exact evaluation of
//! the bispherical-coordinate solution (a series summed until its terms are negligible, for
//! tests and tables) and a fast closed form for the hot loop whose relative error against the
//! exact one is measured by a test and stated in its doc comment.
//!
//! Constants checked here against the exact series (tests below):
//! - Cox & Brenner's small-gap constant 0.971 of `λ⊥`: the series gives
//!   [`NORMAL_GAP_CONSTANT`] = 0.9712799, and the next term is `−(1/21) ε ln ε`;
//! - the small-gap constant of `λ∥`: O'Neill's (1964) exact solution gives
//!   [`PARALLEL_GAP_CONSTANT`] = 0.9542937, O'Neill & Stewartson's (1967) 0.9543; Goldman, Cox
//!   & Brenner's (1967) 0.9588 is 0.0045 too high as a limit (it is a fit to finite-gap values),
//!   and the next term is `−(64/375) ε ln ε`;
//! - the added-mass coefficient at contact, `(3ζ(3) − 2)/2 = 0.8030854`.

use std::f64::consts::SQRT_2;

/// Constant term `C⊥` of the small-gap expansion of the normal factor,
/// `λ⊥ = 1/ε − (1/5) ln ε + C⊥ − (1/21) ε ln ε + O(ε)` (Cox & Brenner 1967, who give 0.971).
///
/// Value from a least-squares fit of `λ⊥ − 1/ε + (1/5) ln ε` over `ε ∈ [1e-7, 1e-3]` with the
/// exact series [`brenner_normal_exact`]; stable to the 8 digits given across fit windows.
pub const NORMAL_GAP_CONSTANT: f64 = 0.971_279_93;

/// Constant term `C∥` of the small-gap expansion of the parallel factor,
/// `λ∥ = −(8/15) ln ε + C∥ − (64/375) ε ln ε + O(ε)` (O'Neill & Stewartson 1967 give 0.9543;
/// Goldman, Cox & Brenner 1967 quote 0.9588).
///
/// Value from a fit of `λ∥ + (8/15) ln ε` over `ε ∈ [1e-8, 1e-5]` with the exact solution
/// [`oneill_parallel_exact`]; the fit also returns −0.17067 for the `ε ln ε` coefficient
/// (`64/375 = 0.170667`).
pub const PARALLEL_GAP_CONSTANT: f64 = 0.954_293_7;

/// Added-mass coefficient of a sphere touching a plane wall, moving normal to it:
/// `C_M(0) = 1/2 + (3/2)(ζ(3) − 1) = (3ζ(3) − 2)/2 = 0.80308535…` (image series, see
/// [`added_mass_normal_exact`]). L06 uses 0.73 (after Kok 1995) in its contact time; that value
/// stays in [`super::ADDED_MASS_WALL`].
pub const ADDED_MASS_CONTACT: f64 = 0.803_085_354_739_391_4;

/// `sinh x − x` for `x ≥ 0`, without cancellation for small `x`.
fn sinh_minus_x(x: f64) -> f64 {
    if x < 1.0 {
        let x2 = x * x;
        let mut term = x * x2 / 6.0;
        let mut sum = term;
        let mut k = 2.0;
        while term > 1e-18 * sum {
            term *= x2 / (2.0 * k * (2.0 * k + 1.0));
            sum += term;
            k += 1.0;
        }
        sum
    } else {
        x.sinh() - x
    }
}

/// `x coth x − 1` for `x ≥ 0`, without cancellation for small `x`.
fn x_coth_x_minus_1(x: f64) -> f64 {
    if x < 0.25 {
        // Taylor series Σ_{k≥1} 2^{2k} B_{2k} x^{2k} / (2k)!; the first omitted term is
        // below 1e-19 of the sum at x = 0.25.
        const C: [f64; 7] = [
            1.0 / 3.0,
            -1.0 / 45.0,
            2.0 / 945.0,
            -1.0 / 4725.0,
            2.0 / 93555.0,
            -1382.0 / 638_512_875.0,
            4.0 / 18_243_225.0,
        ];
        let x2 = x * x;
        C.iter().rev().fold(0.0, |acc, c| acc * x2 + c) * x2
    } else {
        x / x.tanh() - 1.0
    }
}

/// `coth x − 1 = 2 / (e^{2x} − 1)`, with no loss of digits at large `x`.
fn coth_minus_1(x: f64) -> f64 {
    2.0 / (2.0 * x).exp_m1()
}

/// Neumaier-compensated running sum (the series below add up to 10⁵ terms).
#[derive(Default)]
struct Sum {
    sum: f64,
    comp: f64,
}

impl Sum {
    fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.comp += (self.sum - t) + x;
        } else {
            self.comp += (x - t) + self.sum;
        }
        self.sum = t;
    }

    fn value(&self) -> f64 {
        self.sum + self.comp
    }
}

/// Bispherical parameter `α = arccosh(1 + ε)` and `sinh α = sqrt(ε (2 + ε))`, both to full
/// relative precision for small `ε` (where `acosh(1.0 + ε)` would lose the digits of `ε`).
fn bispherical_alpha(gap: f64) -> (f64, f64) {
    let sinh_a = (gap * (2.0 + gap)).sqrt();
    ((gap + sinh_a).ln_1p(), sinh_a)
}

/// Normal wall factor `λ⊥(ε)` of a sphere moving normal to a plane wall, exact: the series of
/// Brenner (1961), Chem. Eng. Sci. 16, 242–251 (docs/physics.md §8). The Stokes drag is
/// `λ⊥ · 6π μ a v`.
///
/// With `ε = h/a` (surface gap over radius, dimensionless) and `α = arccosh(1 + ε)`,
///
/// `λ⊥ = (4/3) sinh α Σ_{n≥1} n(n+1)/((2n−1)(2n+3)) · [ (2 sinh((2n+1)α) + (2n+1) sinh 2α) /
/// (4 sinh²((n+½)α) − (2n+1)² sinh² α) − 1 ]`.
///
/// Each bracket is evaluated as `(2(1 − e^{−kα}) + k sinh 2α + k² sinh² α) / ((2 sinh(kα/2) −
/// k sinh α)(2 sinh(kα/2) + k sinh α))` with `k = 2n + 1`, the difference factor from
/// `sinh x − x` series, so that neither cancellation at small `nα` nor overflow at large `nα`
/// costs digits. The series is summed (compensated) until `nα > 40` and the terms fall below
/// 1e-18 of the sum: about `25/α ≈ 18/√ε` terms, 1.8·10⁴ at `ε = 1e-6`. Agrees with a
/// 40-digit evaluation to 1e-14 relative at `ε = 1e-4 … 1e3` (test). Valid for every `ε > 0`;
/// above `ε = 1e12` it returns the method-of-reflections form `1/(1 − (9/8)s + (1/2)s³)`,
/// `s = 1/(1 + ε)`, exact there to 1e-48. Returns +∞ for `ε ≤ 0` (contact).
pub fn brenner_normal_exact(gap: f64) -> f64 {
    if gap <= 0.0 {
        return f64::INFINITY;
    }
    if gap >= 1e12 {
        let s = 1.0 / (1.0 + gap);
        return 1.0 / (1.0 - 1.125 * s + 0.5 * s * s * s);
    }
    let (alpha, sinh_a) = bispherical_alpha(gap);
    let sinh_2a = 2.0 * sinh_a * (1.0 + gap);
    let sinhm_a = sinh_minus_x(alpha);
    let mut sum = Sum::default();
    let mut n = 1.0_f64;
    loop {
        let k = 2.0 * n + 1.0;
        let q = 0.5 * k * alpha;
        let num = -2.0 * (-k * alpha).exp_m1() + k * sinh_2a + k * k * sinh_a * sinh_a;
        let bracket = if q < 300.0 {
            num / ((2.0 * sinh_minus_x(q) - k * sinhm_a) * (2.0 * q.sinh() + k * sinh_a))
        } else {
            // Numerator and denominator scaled by e^{−kα}.
            let p = -(-k * alpha).exp_m1();
            let r = k * sinh_a * (-q).exp();
            num * (-k * alpha).exp() / ((p - r) * (p + r))
        };
        let term = n * (n + 1.0) / ((2.0 * n - 1.0) * (2.0 * n + 3.0)) * bracket;
        sum.add(term);
        if q > 20.0 && term < 1e-18 * sum.value() {
            break;
        }
        n += 1.0;
    }
    4.0 / 3.0 * sinh_a * sum.value()
}

/// Coefficients of the fitted correction of [`wall_factor_normal`].
const NORMAL_FIT: [f64; 5] = [
    0.130_784_802_537_015,
    -0.159_255_153_618_723,
    0.466_396_194_769_743,
    -0.752_833_660_422_011,
    0.469_058_692_293_484,
];

/// Normal wall factor `λ⊥(ε)`, fast form for the hot loop **[ext]**: the Cox & Brenner (1967)
/// small-gap terms and Brenner's (1961) far field joined by a fitted polynomial in
/// `s = a/(h + a) = 1/(1 + ε)`:
///
/// `λ⊥ ≈ 1/ε + (1/5) ln(1 + 1/ε) + 1 − (3/40) s + (C⊥ − 37/40) s² + s² (1 − s) Σ_{j=0}^{4} c_j s^j`
///
/// with `C⊥` = [`NORMAL_GAP_CONSTANT`]. It has the exact limits on both sides: `a/h + (1/5)
/// ln(a/h) + C⊥` at contact (Cox & Brenner 1967) and `1 + (9/8) s` far away (Brenner 1961;
/// Lorentz). The `c_j` are a minimax (Lawson-weighted least-squares) fit of the relative error
/// to [`brenner_normal_exact`] on 4001 points of `ε ∈ [1e-8, 1e8]`.
///
/// **Accuracy**: maximum relative error against the exact series **1.97e-5** (near `ε = 0.5`)
/// on a dense log grid of `ε` from 1e-6 to 1e3 (200 points per decade); below 2e-5 also on
/// `[1e-10, 1e-6]` and `[1e3, 1e14]`, and tending to 0 as `ε → 0` and `ε → ∞`, where the form
/// has the exact limits. Measured by the test
/// `normal_fast_form_within_2e_5_of_brenner_series_for_all_gaps` (`cargo test --lib
/// correlations::wall_hindrance`). Dimensionless; returns +∞ for `ε ≤ 0`.
pub fn wall_factor_normal(gap: f64) -> f64 {
    if gap <= 0.0 {
        return f64::INFINITY;
    }
    let inv = 1.0 / gap;
    let s = 1.0 / (1.0 + gap);
    let poly = NORMAL_FIT.iter().rev().fold(0.0, |acc, c| acc * s + c);
    inv + 0.2 * inv.ln_1p() + 1.0 - 0.075 * s
        + (NORMAL_GAP_CONSTANT - 0.925) * s * s
        + s * s * (1.0 - s) * poly
}

/// Parallel wall factor `λ∥(ε)` of a sphere translating parallel to a plane wall without
/// rotating, exact: O'Neill (1964), Mathematika 11, 67–74, in the notation of Goldman, Cox &
/// Brenner (1967), Chem. Eng. Sci. 22, 637–651 (their `F*_t`). The drag is `λ∥ · 6π μ a v`.
///
/// With `α = arccosh(1 + ε)` and `k_n = (n+½) coth((n+½)α) − coth α`, the coefficients
/// `A_n` (n ≥ 1) solve the tridiagonal system
///
/// `(n−1)/(2n−1) a_n A_{n−1} − [n a_n + (n+1) b_n]/(2n+1) A_n + (n+2)/(2n+3) b_n A_{n+1}
///  = √2 [2 coth((n+½)α) − coth((n−½)α) − coth((n+3/2)α)]`,
///
/// `a_n = (2n−1) k_{n−1} − (2n−3) k_n`, `b_n = (2n+5) k_n − (2n+3) k_{n+1}`; then
/// `E_n = 2√2 e^{−(n+½)α}/sinh((n+½)α) + k_n [(n−1)n/(2n−1) A_{n−1} − (n+1)(n+2)/(2n+3) A_{n+1}]`,
/// `C_n = −2 k_n [(n−1)/(2n−1) A_{n−1} − A_n + (n+2)/(2n+3) A_{n+1}]` (`C_0 = 0`) and
///
/// `λ∥ = (√2/6) sinh α Σ_{n≥0} (E_n + n(n+1) C_n)`.
///
/// The system is truncated at `N = 50/α + 20` (`A_{N+1} = 0`; doubling `N` changes the result
/// by less than 1e-14, test) and solved by the Thomas algorithm; `k_n` and the `coth` differences are formed from
/// `x coth x − 1` and `coth x − 1` so that small `α` and large `nα` lose no digits. Checks
/// (tests): Faxén's far field to 2e-7 at `ε = 9.07` and 6e-5 at `ε = 2.76` (where Faxén's
/// truncation error is of that size), and the small-gap limit `−(8/15) ln ε + 0.9543`. Valid
/// for all `ε > 0` (cost O(1/√ε) time and memory: 3.5·10⁵ unknowns at `ε = 1e-8`); above
/// `ε = 1e10` it returns [`faxen_parallel`], exact there to 1e-60. Returns +∞ for `ε ≤ 0`.
pub fn oneill_parallel_exact(gap: f64) -> f64 {
    if gap <= 0.0 {
        return f64::INFINITY;
    }
    if gap >= 1e10 {
        return faxen_parallel(gap);
    }
    let (alpha, _) = bispherical_alpha(gap);
    oneill_parallel_truncated(gap, (50.0 / alpha).ceil() as usize + 20)
}

/// O'Neill's solution with the tridiagonal system truncated at `nmax` unknowns.
fn oneill_parallel_truncated(gap: f64, nmax: usize) -> f64 {
    let (alpha, sinh_a) = bispherical_alpha(gap);
    let h_a = x_coth_x_minus_1(alpha);
    // k_n = [ (n+½)α coth((n+½)α) − α coth α ] / α, n = 0 ..= nmax + 1.
    let k: Vec<f64> =
        (0..=nmax + 1).map(|n| (x_coth_x_minus_1((n as f64 + 0.5) * alpha) - h_a) / alpha).collect();
    // Forward sweep of the Thomas algorithm for A_1 ..= A_N.
    let mut cp = vec![0.0; nmax + 1];
    let mut dp = vec![0.0; nmax + 1];
    for i in 1..=nmax {
        let n = i as f64;
        let a_n = (2.0 * n - 1.0) * k[i - 1] - (2.0 * n - 3.0) * k[i];
        let b_n = (2.0 * n + 5.0) * k[i] - (2.0 * n + 3.0) * k[i + 1];
        let sub = a_n * (n - 1.0) / (2.0 * n - 1.0);
        let diag = -(a_n * n + b_n * (n + 1.0)) / (2.0 * n + 1.0);
        let sup = b_n * (n + 2.0) / (2.0 * n + 3.0);
        // 2 coth x_n − coth x_{n−1} − coth x_{n+1}, the constant parts cancelling exactly.
        let rhs = SQRT_2
            * (2.0 * coth_minus_1((n + 0.5) * alpha)
                - coth_minus_1((n - 0.5) * alpha)
                - coth_minus_1((n + 1.5) * alpha));
        let m = diag - sub * cp[i - 1];
        cp[i] = if i < nmax { sup / m } else { 0.0 };
        dp[i] = (rhs - sub * dp[i - 1]) / m;
    }
    let mut a = vec![0.0; nmax + 2];
    for i in (1..=nmax).rev() {
        a[i] = dp[i] - cp[i] * a[i + 1];
    }
    let mut sum = Sum::default();
    for n in 0..nmax {
        let nf = n as f64;
        let a_prev = if n >= 1 { a[n - 1] } else { 0.0 };
        // 2√2 e^{−(n+½)α} / sinh((n+½)α) = 4√2 / (e^{(2n+1)α} − 1).
        let e_n = 4.0 * SQRT_2 / ((2.0 * nf + 1.0) * alpha).exp_m1()
            + k[n]
                * ((nf - 1.0) * nf / (2.0 * nf - 1.0) * a_prev
                    - (nf + 1.0) * (nf + 2.0) / (2.0 * nf + 3.0) * a[n + 1]);
        let c_n = if n >= 1 {
            -2.0 * k[n]
                * ((nf - 1.0) / (2.0 * nf - 1.0) * a_prev - a[n] + (nf + 2.0) / (2.0 * nf + 3.0) * a[n + 1])
        } else {
            0.0
        };
        sum.add(e_n + nf * (nf + 1.0) * c_n);
    }
    SQRT_2 / 6.0 * sinh_a * sum.value()
}

/// Faxén's far-field parallel factor (method of reflections; Faxén 1923, as given by Happel &
/// Brenner 1965, Low Reynolds Number Hydrodynamics, ch. 7): `λ∥ ≈ 1 / (1 − (9/16)s + (1/8)s³ − (45/256)s⁴ − (1/16)s⁵)`,
/// `s = a/(h + a) = 1/(1 + ε)` (docs/physics.md §8). Dimensionless.
///
/// Against [`oneill_parallel_exact`]: relative error 2e-7 at `ε = 9`, 6e-5 at `ε = 2.76`, 1e-3
/// at `ε = 1.35`, 1 % at `ε = 0.54`, 4 % at `ε = 0.13`; it stays finite at contact (3.08)
/// where the true factor diverges. Use [`wall_factor_parallel`] at gaps below ~3 radii.
pub fn faxen_parallel(gap: f64) -> f64 {
    let s = 1.0 / (1.0 + gap);
    let s2 = s * s;
    1.0 / (1.0 - 9.0 / 16.0 * s + s * s2 / 8.0 - 45.0 / 256.0 * s2 * s2 - s2 * s2 * s / 16.0)
}

/// Coefficients of the fitted correction of [`wall_factor_parallel`]: four for the polynomial
/// and the last for the `ln(1 + 1/ε)` term.
const PARALLEL_FIT: [f64; 5] = [
    0.132_830_567_876_350,
    -0.219_262_282_391_752,
    0.123_136_256_466_484,
    -0.150_275_223_739_010,
    0.148_031_161_098_480,
];

/// Parallel wall factor `λ∥(ε)` (translation parallel to the wall, no rotation), fast form for
/// the hot loop **[ext]**: one formula over all gaps (no switch), joining the near-wall
/// asymptote `−(8/15) ln ε + C∥` (O'Neill & Stewartson 1967) and the far field `1 + (9/16) s`
/// (Faxén) through a fitted correction in `s = 1/(1 + ε)` and `L = ln(1 + 1/ε)`:
///
/// `λ∥ ≈ (8/15) L + 1 + (7/240) s + (C∥ − 247/240) s² + s² (1 − s) (Σ_{j=0}^{3} p_j s^j + q L)`
///
/// with `C∥` = [`PARALLEL_GAP_CONSTANT`] (0.9543, checked against O'Neill's exact solution; not
/// Goldman, Cox & Brenner's 0.9588). The `p_j`, `q` are a minimax (Lawson-weighted
/// least-squares) fit of the relative error to [`oneill_parallel_exact`] on 2001 points of
/// `ε ∈ [1e-8, 1e8]`; the `(1 − s) L` basis function carries the `ε ln ε` term of the
/// small-gap expansion.
///
/// **Accuracy**: maximum relative error against the exact solution **2.6e-5** on a log grid of
/// `ε` from 1e-6 to 1e3 (200 points per decade; the maximum is near `ε = 8e-3`), smaller
/// outside it (exact limits on both sides). Asserted on 100 points per decade by
/// `parallel_fast_form_within_3e_5_of_oneill_for_all_gaps`; the 200-point figure is printed by
/// `cargo test --lib correlations::wall_hindrance -- --ignored --nocapture`. Dimensionless;
/// +∞ for `ε ≤ 0`.
pub fn wall_factor_parallel(gap: f64) -> f64 {
    if gap <= 0.0 {
        return f64::INFINITY;
    }
    let s = 1.0 / (1.0 + gap);
    let l = (1.0 / gap).ln_1p();
    let [p0, p1, p2, p3, q] = PARALLEL_FIT;
    let poly = p0 + s * (p1 + s * (p2 + s * p3)) + q * l;
    8.0 / 15.0 * l
        + 1.0
        + 7.0 / 240.0 * s
        + (PARALLEL_GAP_CONSTANT - 247.0 / 240.0) * s * s
        + s * s * (1.0 - s) * poly
}

/// Added-mass coefficient `C_M(ε)` of a sphere moving normal to a plane wall in potential flow,
/// exact image series of potential flow (docs/physics.md §8; a sphere and its mirror image, the
/// classical two-sphere problem):
///
/// `C_M = 1/2 + (3/2) Σ_{n≥2} (sinh α / sinh nα)³`, `α = arccosh(1 + ε)`,
///
/// from `1/2 + (3/16) s³` far away (`s = 1/(1 + ε)`) to [`ADDED_MASS_CONTACT`] =
/// `(3ζ(3) − 2)/2 ≈ 0.80309` at contact. The added mass is `C_M ρ Vp` (kg). Summed until
/// `nα > 40` and the terms are below 1e-18 of the sum (about `40/α` terms); relative accuracy
/// ~1e-15. Valid for `ε ≥ 0` (`ε = 0` returns the contact value; above `ε = 1e6` the one-image
/// form `1/2 + (3/16) s³`, exact there to 1e-36).
pub fn added_mass_normal_exact(gap: f64) -> f64 {
    if gap <= 0.0 {
        return ADDED_MASS_CONTACT;
    }
    if gap >= 1e6 {
        let s = 1.0 / (1.0 + gap);
        return 0.5 + 0.1875 * s * s * s;
    }
    let (alpha, sinh_a) = bispherical_alpha(gap);
    let mut sum = Sum::default();
    let mut n = 2.0_f64;
    loop {
        let x = n * alpha;
        let r = sinh_a / x.sinh();
        let t = r * r * r;
        sum.add(t);
        if x > 40.0 && t < 1e-18 * sum.value() {
            break;
        }
        n += 1.0;
    }
    0.5 + 1.5 * sum.value()
}

/// Added-mass coefficient `C_M(ε)` for motion normal to a wall, fast form for the hot loop
/// **[ext]**: the image series of [`added_mass_normal_exact`] summed exactly for `n = 2 … 12`
/// (`sinh nα / sinh α = U_{n−1}(1 + ε)`, Chebyshev polynomials of the second kind, by their
/// three-term recurrence: no hyperbolic functions), plus its tail by the midpoint
/// Euler–Maclaurin rule, `Σ_{n>12} f(n) ≈ ∫_{12.5}^∞ f + f′(12.5)/24` with
/// `∫_u^∞ csch³ = ½ csch u coth u − ½ ln coth(u/2)`.
///
/// **Accuracy**: relative error **3.5e-8** at most (near `ε = 1e-6`) on a log grid of `ε` from
/// 1e-10 to 1e7 (200 points per decade), 2.5e-8 at contact; asserted (< 4e-8) on 40 points per
/// decade from 1e-8 to 1e7 by `added_mass_fast_form_within_4e_8_of_series`. Dimensionless;
/// negative gaps are treated as contact.
pub fn added_mass_normal(gap: f64) -> f64 {
    added_mass_normal_and_slope(gap).0
}

/// Largest gap ratio at which [`added_mass_normal`] adds its tail: `α · 12.5 < 20`, i.e.
/// `ε < cosh 1.6 − 1`. Beyond it the tail is below 1e-25 of the sum, and `α` (a logarithm)
/// need not be computed at all.
const ADDED_MASS_TAIL_GAP: f64 = 1.577_464_471_194_885_3;

/// [`added_mass_normal`] and its derivative `dC_M/dε`, in one pass: the derivative of the
/// sum for `n = 2 … 12` from the recurrence's own derivative (`U′_{n+1} = 2U_n + 2x U′_n −
/// U′_{n−1}`, each term contributing `−3 U′/U⁴`), and the tail's by a central difference in
/// `α` (relative step 1e-6, so about 1e-10 of the tail; `dα/dε = 1/sinh α`). The value is
/// computed by the same operations as without the derivative. The slope is −∞ at contact
/// (`C_M ≈ C_M(0) − c ε ln(1/ε)`), which the force balance never asks for (contact is at the
/// roughness, `ε > 0`).
pub fn added_mass_normal_and_slope(gap: f64) -> (f64, f64) {
    const N: usize = 12;
    let gap = gap.max(0.0);
    if gap >= 1e6 {
        let s = 1.0 / (1.0 + gap);
        return (0.5 + 0.1875 * s * s * s, -0.5625 * s * s * s * s);
    }
    let x = 1.0 + gap;
    let (mut u_prev, mut u) = (1.0, 2.0 * x);
    let (mut du_prev, mut du) = (0.0, 2.0);
    let (mut sum, mut slope) = (0.0, 0.0);
    // Beyond the tail's gap the terms fall by `(2x)³` or more each: once one is below 1e-17
    // of the sum (and its slope's of the slope), the rest change neither in the last digit.
    let early = gap >= ADDED_MASS_TAIL_GAP;
    for _ in 2..=N {
        let u2 = u * u;
        let (term, dterm) = (1.0 / (u2 * u), 3.0 * du / (u2 * u2));
        sum += term;
        slope -= dterm;
        if early && term < 1e-17 * sum && dterm < -1e-17 * slope {
            break;
        }
        let next = 2.0 * x * u - u_prev;
        let dnext = 2.0 * u + 2.0 * x * du - du_prev;
        (u_prev, u, du_prev, du) = (u, next, du, dnext);
    }
    let y = N as f64 + 0.5;
    // The Euler–Maclaurin tail at `α`, with `sinh α` given (the value's own is from the gap).
    let tail = |alpha: f64, sinh_a: f64| {
        let v = alpha * y;
        let (sh, ch) = (v.sinh(), v.cosh());
        let tail_integral = 0.5 * ch / (sh * sh) + 0.5 * (0.5 * v).tanh().ln();
        let s3 = sinh_a * sinh_a * sinh_a;
        let derivative = -3.0 * alpha * ch * s3 / (sh * sh * sh * sh);
        s3 / alpha * tail_integral + derivative / 24.0
    };
    if gap == 0.0 {
        // Σ_{n>N} 1/n³ by the same rule.
        sum += 0.5 / (y * y) - 0.125 / (y * y * y * y);
        slope = f64::NEG_INFINITY;
    } else if gap < ADDED_MASS_TAIL_GAP {
        let (alpha, sinh_a) = bispherical_alpha(gap);
        if alpha * y < 20.0 {
            sum += tail(alpha, sinh_a);
            let d = 1e-6 * alpha;
            let (a1, a0) = (alpha + d, alpha - d);
            slope += (tail(a1, a1.sinh()) - tail(a0, a0.sinh())) / ((a1 - a0) * sinh_a);
        }
    }
    (0.5 + 1.5 * sum, 1.5 * slope)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Apéry's constant ζ(3).
    const ZETA_3: f64 = 1.202_056_903_159_594_2;

    /// `n` log-spaced gaps per decade from `10^lo` to `10^hi`.
    fn log_grid(lo: f64, hi: f64, per_decade: usize) -> impl Iterator<Item = f64> {
        let n = ((hi - lo) * per_decade as f64).round() as usize;
        (0..=n).map(move |i| 10f64.powf(lo + (hi - lo) * i as f64 / n as f64))
    }

    fn max_rel_error(
        grid: impl Iterator<Item = f64>,
        f: impl Fn(f64) -> f64,
        g: impl Fn(f64) -> f64,
    ) -> (f64, f64) {
        grid.map(|x| ((f(x) / g(x) - 1.0).abs(), x)).fold((0.0, 0.0), |m, e| if e.0 > m.0 { e } else { m })
    }

    #[test]
    fn brenner_series_matches_40_digit_evaluation() {
        // Brenner's series summed with mpmath at 40 digits (scratch script, not in the repo).
        for (gap, exact) in [
            (1e-4, 10_002.813_408_565_09),
            (1e-3, 1002.3533268805824),
            (0.1, 11.459157203409557),
            (0.543_080_634_815_243_7, 3.0360643803143205), // α = 1: Brenner's table, 3.036
            (1.0, 2.1255355667600402),
            (10.0, 1.113503233905708),
            (1000.0, 1.0011251401434815),
        ] {
            let got = brenner_normal_exact(gap);
            assert!((got / exact - 1.0).abs() < 1e-14, "ε = {gap}: {got} vs {exact}");
        }
    }

    #[test]
    fn brenner_series_far_field_is_one_plus_nine_eighths_s() {
        for gap in [1e4, 1e6, 1e9, 1e11, 1e13] {
            let s = 1.0 / (1.0 + gap);
            let far = 1.0 / (1.0 - 1.125 * s + 0.5 * s * s * s);
            assert!((brenner_normal_exact(gap) / far - 1.0).abs() < 1e-14, "ε = {gap}");
        }
    }

    #[test]
    fn cox_brenner_constant_is_0_97128() {
        // λ⊥ − 1/ε + (1/5) ln ε + (1/21) ε ln ε → C⊥; the remainder is O(ε).
        for gap in [1e-8, 1e-7, 1e-6] {
            let c = brenner_normal_exact(gap) - 1.0 / gap + 0.2 * gap.ln() + gap * gap.ln() / 21.0;
            assert!((c - NORMAL_GAP_CONSTANT).abs() < 1e-6, "ε = {gap}: {c}");
        }
        // Cox & Brenner's 0.971 is this constant to its three digits.
        assert!((NORMAL_GAP_CONSTANT - 0.971).abs() < 5e-4);
    }

    #[test]
    fn normal_fast_form_within_2e_5_of_brenner_series_for_all_gaps() {
        let (err, at) = max_rel_error(log_grid(-6.0, 3.0, 200), wall_factor_normal, brenner_normal_exact);
        assert!(err < 2.0e-5, "max relative error {err:e} at ε = {at}");
        let (err, at) = max_rel_error(
            log_grid(-10.0, -6.0, 10).chain(log_grid(3.0, 14.0, 10)),
            wall_factor_normal,
            brenner_normal_exact,
        );
        assert!(err < 2.0e-5, "outside the fit window: {err:e} at ε = {at}");
        assert_eq!(wall_factor_normal(0.0), f64::INFINITY);
    }

    #[test]
    fn oneill_parallel_matches_faxen_far_from_the_wall() {
        // Faxén's truncation error is O(s⁶): 1e-6 at s = 0.1, 4e-4 at s = 0.27.
        assert!((oneill_parallel_exact(9.0677) / faxen_parallel(9.0677) - 1.0).abs() < 1e-6);
        assert!((oneill_parallel_exact(2.7622) / faxen_parallel(2.7622) - 1.0).abs() < 1e-4);
        assert!((oneill_parallel_exact(1e6) / faxen_parallel(1e6) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn oneill_parallel_truncation_is_converged() {
        for gap in [1e-5, 1e-3, 0.1, 1.0, 100.0] {
            let alpha = bispherical_alpha(gap).0;
            let n = (50.0 / alpha).ceil() as usize + 20;
            let (once, twice) = (oneill_parallel_truncated(gap, n), oneill_parallel_truncated(gap, 2 * n));
            assert!((once / twice - 1.0).abs() < 1e-14, "ε = {gap}: {once} vs {twice}");
        }
    }

    #[test]
    fn parallel_constant_is_oneill_stewartson_0_9543_not_0_9588() {
        for gap in [1e-8, 1e-7, 1e-6] {
            let c = oneill_parallel_exact(gap) + (8.0 / 15.0 + 64.0 / 375.0 * gap) * gap.ln();
            assert!((c - PARALLEL_GAP_CONSTANT).abs() < 2e-6, "ε = {gap}: {c}");
            assert!((c - 0.9543).abs() < 1e-5, "O'Neill & Stewartson's 0.9543, ε = {gap}: {c}");
            assert!((c - 0.9588).abs() > 4e-3, "Goldman, Cox & Brenner's 0.9588, ε = {gap}: {c}");
        }
    }

    #[test]
    fn parallel_fast_form_within_3e_5_of_oneill_for_all_gaps() {
        let (err, at) = max_rel_error(log_grid(-6.0, 3.0, 100), wall_factor_parallel, oneill_parallel_exact);
        assert!(err < 3.0e-5, "max relative error {err:e} at ε = {at}");
        let (err, at) = max_rel_error(
            log_grid(-7.0, -6.0, 5).chain(log_grid(3.0, 12.0, 5)),
            wall_factor_parallel,
            oneill_parallel_exact,
        );
        assert!(err < 3.0e-5, "outside the fit window: {err:e} at ε = {at}");
    }

    #[test]
    fn added_mass_at_contact_is_three_zeta_3_minus_2_over_2() {
        assert!((ADDED_MASS_CONTACT - (3.0 * ZETA_3 - 2.0) / 2.0).abs() < 1e-15);
        assert!((ADDED_MASS_CONTACT - 0.803).abs() < 1e-4);
        // The series approaches the limit like ε ln ε: 1e-9 away at ε = 1e-10.
        assert!((added_mass_normal_exact(1e-10) - ADDED_MASS_CONTACT).abs() < 1e-8);
        assert!((added_mass_normal(0.0) - ADDED_MASS_CONTACT).abs() < 3e-8);
        // Far away: 1/2 + (3/16) s³.
        let s: f64 = 1.0 / 101.0;
        assert!((added_mass_normal_exact(100.0) - (0.5 + 0.1875 * s.powi(3))).abs() < 1e-12);
    }

    #[test]
    fn added_mass_fast_form_within_4e_8_of_series() {
        let (err, at) = max_rel_error(log_grid(-8.0, 7.0, 40), added_mass_normal, added_mass_normal_exact);
        assert!(err < 4e-8, "max relative error {err:e} at ε = {at}");
    }

    #[test]
    #[ignore = "prints the error curves; run with --ignored --nocapture"]
    fn print_fast_form_errors() {
        for (name, fast, exact) in [
            ("normal", wall_factor_normal as fn(f64) -> f64, brenner_normal_exact as fn(f64) -> f64),
            ("parallel", wall_factor_parallel, oneill_parallel_exact),
            ("added mass", added_mass_normal, added_mass_normal_exact),
        ] {
            let (err, at) = max_rel_error(log_grid(-6.0, 3.0, 200), fast, exact);
            println!("{name}: max relative error {err:.3e} at ε = {at:.4e}");
        }
    }
}
