//! `x^p` for one fixed exponent `p`, by table lookup and a short polynomial: the
//! Schiller–Naumann factor's `Re^0.687` is evaluated once or more per particle and stage, and
//! glibc's general `pow` took half of a step's time with L06's physics.
//!
//! Write `x = 2^e · m` with `m ∈ [1, 2)` and `m = m_j (1 + t)`, where `m_j = 1 + j/256` keeps
//! the top 8 bits of the mantissa and `0 ≤ t < 2⁻⁸`. Then
//! `x^p = 2^(e p) · m_j^p · (1 + t)^p`: the first two factors come from tables built at compile
//! time (`const fn`), the last from its binomial series to `t⁵` (truncation below 1e-16).
//! The result is within about ten units in the last place of `powf` (the tests bound it at
//! 2e-15 relative: the tables, summed in plain `f64` series at compile time, carry a few units
//! each), far below any integrator's error; exponents `e` outside the table, zero, subnormals, infinities and NaN fall back
//! to `powf`.

use super::lanes::{F64x4, Real, each};

/// Smallest binary exponent in the table: below `2⁻⁸⁰ ≈ 8e-25` the call falls back to `powf`.
const E_MIN: i64 = -80;
/// Largest binary exponent in the table: up to `2²¹ ≈ 2e6` (the Schiller–Naumann branch ends
/// at Re = 1000, Re² = 10⁶).
const E_MAX: i64 = 20;
/// Mantissa bits looked up in the table.
const MANTISSA_BITS: u32 = 8;
const ENTRIES: usize = 1 << MANTISSA_BITS;
const EXPONENTS: usize = (E_MAX - E_MIN + 1) as usize;
const FRACTION_MASK: u64 = (1 << 52) - 1;
const ONE_BITS: u64 = 1023 << 52;
/// Bits of the mantissa below the table's index.
const LOW_MASK: u64 = (1 << (52 - MANTISSA_BITS)) - 1;

/// `x^p` for a fixed `p`: build with [`FixedPower::new`] in a `static`, call [`FixedPower::pow`].
#[derive(Debug)]
pub struct FixedPower {
    p: f64,
    /// `2^(e p)` for `e = E_MIN..=E_MAX`.
    by_exponent: [f64; EXPONENTS],
    /// `m_j^p` for `m_j = 1 + j/256`.
    by_mantissa: [f64; ENTRIES],
    /// `1 / m_j`.
    inverse: [f64; ENTRIES],
    /// Binomial coefficients `C(p, n)` for `n = 1..=5`.
    series: [f64; 5],
}

impl FixedPower {
    /// The tables of `x^p`, computed at compile time when used in a `static`.
    pub const fn new(p: f64) -> Self {
        let mut by_exponent = [0.0; EXPONENTS];
        let mut i = 0;
        while i < EXPONENTS {
            by_exponent[i] = exp2_of_product(E_MIN + i as i64, p);
            i += 1;
        }
        let mut by_mantissa = [0.0; ENTRIES];
        let mut inverse = [0.0; ENTRIES];
        let mut j = 0;
        while j < ENTRIES {
            let m = 1.0 + j as f64 / ENTRIES as f64;
            by_mantissa[j] = exp(p * ln_1_2(m));
            inverse[j] = 1.0 / m;
            j += 1;
        }
        let mut series = [0.0; 5];
        let mut c = 1.0;
        let mut n = 0;
        while n < 5 {
            c = c * (p - n as f64) / (n as f64 + 1.0);
            series[n] = c;
            n += 1;
        }
        FixedPower { p, by_exponent, by_mantissa, inverse, series }
    }

    /// `x^p`.
    #[inline(always)]
    pub fn pow(&self, x: f64) -> f64 {
        let bits = x.to_bits();
        // Negative numbers have the sign bit set, so their `e` is above E_MAX too.
        let e = (bits >> 52) as i64 - 1023;
        if !(E_MIN..=E_MAX).contains(&e) {
            return x.powf(self.p);
        }
        let j = ((bits & FRACTION_MASK) >> (52 - MANTISSA_BITS)) as usize;
        let m = f64::from_bits((bits & FRACTION_MASK) | ONE_BITS);
        let m_j = f64::from_bits((bits & FRACTION_MASK & !LOW_MASK) | ONE_BITS);
        // m − m_j is exact (both in [1, 2), same top bits).
        let t = (m - m_j) * self.inverse[j];
        let c = &self.series;
        // Estrin's scheme: the same polynomial in fewer dependent steps than Horner's.
        let t2 = t * t;
        let tail = t * c[0] + t2 * ((c[1] + t * c[2]) + t2 * (c[3] + t * c[4]));
        self.by_exponent[(e - E_MIN) as usize] * (self.by_mantissa[j] + self.by_mantissa[j] * tail)
    }

    /// [`FixedPower::pow`] of four lanes: the same operations in the same order, so each lane is
    /// bit for bit its scalar result; a lane group with any lane outside the table goes lane by
    /// lane.
    #[inline(always)]
    pub fn pow_lanes(&self, x: F64x4) -> F64x4 {
        let bits = each(x.0, f64::to_bits);
        let e = each(bits, |b| (b >> 52) as i64 - 1023);
        let [e0, e1, e2, e3] = each(e, |e| (E_MIN..=E_MAX).contains(&e));
        if !(e0 & e1 & e2 & e3) {
            return x.map(|x| self.pow(x));
        }
        // `% ENTRIES` and `% EXPONENTS` below change no index (they are in range already) but
        // let the compiler drop the bounds checks of the table lookups.
        let j = each(bits, |b| ((b & FRACTION_MASK) >> (52 - MANTISSA_BITS)) as usize % ENTRIES);
        let m = F64x4(each(bits, |b| f64::from_bits((b & FRACTION_MASK) | ONE_BITS)));
        let m_j = F64x4(each(bits, |b| f64::from_bits((b & FRACTION_MASK & !LOW_MASK) | ONE_BITS)));
        let t = (m - m_j) * F64x4(each(j, |j| self.inverse[j]));
        let c = |n: usize| F64x4::splat(self.series[n]);
        let t2 = t * t;
        let tail = t * c(0) + t2 * ((c(1) + t * c(2)) + t2 * (c(3) + t * c(4)));
        let by_mantissa = F64x4(each(j, |j| self.by_mantissa[j]));
        let by_exponent = F64x4(each(e, |e| self.by_exponent[(e - E_MIN) as usize % EXPONENTS]));
        by_exponent * (by_mantissa + by_mantissa * tail)
    }
}

/// `2^(e p)` for a small integer `e`, to within a few units in the last place: `e p` is split
/// into an exact integer part (built from its bits) and a fraction (Taylor series of `exp`).
const fn exp2_of_product(e: i64, p: f64) -> f64 {
    // p = hi + lo with hi's mantissa short enough that e·hi is exact (|e| < 2⁷).
    assert!(-128 < e && e < 128);
    let hi = f64::from_bits(p.to_bits() & !((1u64 << 24) - 1));
    let lo = p - hi;
    let y = e as f64 * hi;
    let mut n = y as i64;
    if (n as f64) > y {
        n -= 1;
    }
    let fraction = (y - n as f64) + e as f64 * lo;
    f64::from_bits(((n + 1023) as u64) << 52) * exp(fraction * std::f64::consts::LN_2)
}

/// `exp(y)` for `|y| ≤ 1`: its Taylor series to 25 terms.
const fn exp(y: f64) -> f64 {
    let mut sum = 1.0;
    let mut term = 1.0;
    let mut k = 1;
    while k <= 25 {
        term = term * y / k as f64;
        sum += term;
        k += 1;
    }
    sum
}

/// `ln(m)` for `m ∈ [1, 2]`: `2 atanh(s)` with `s = (m − 1)/(m + 1) ≤ 1/3`, to 30 terms.
const fn ln_1_2(m: f64) -> f64 {
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let mut sum = 0.0;
    let mut power = s;
    let mut k = 0;
    while k < 30 {
        sum += power / (2 * k + 1) as f64;
        power *= s2;
        k += 1;
    }
    2.0 * sum
}

#[cfg(test)]
mod tests {
    use super::*;

    static POWER: FixedPower = FixedPower::new(0.687);

    fn relative_error(x: f64) -> f64 {
        let exact = x.powf(0.687);
        (POWER.pow(x) - exact).abs() / exact
    }

    #[test]
    fn matches_powf_to_2e_15_over_the_whole_table() {
        // Log-spaced over every exponent of the table, with a prime stride through the mantissa
        // so that every table entry and every part of each interval is visited.
        let (lo, hi) = (2f64.powi(E_MIN as i32), 2f64.powi(E_MAX as i32 + 1));
        let n = 2_000_003;
        let mut worst = (0.0, 0.0);
        for i in 0..n {
            let x = lo * (hi / lo).powf(i as f64 / n as f64);
            let err = relative_error(x);
            if err > worst.0 {
                worst = (err, x);
            }
        }
        assert!(worst.0 < 2e-15, "largest relative error {:e} at x = {:e}", worst.0, worst.1);
    }

    #[test]
    fn table_edges_and_entries_match_powf_to_2e_15() {
        for e in E_MIN..=E_MAX {
            for j in 0..ENTRIES as u64 {
                let m_j = f64::from_bits(ONE_BITS | (j << (52 - MANTISSA_BITS)));
                let x = m_j * 2f64.powi(e as i32);
                for y in [x, f64::from_bits(x.to_bits() - 1), f64::from_bits(x.to_bits() + 1)] {
                    assert!(relative_error(y) < 2e-15, "x = {y:e}: {:e}", relative_error(y));
                }
            }
        }
    }

    #[test]
    fn lane_groups_give_the_bits_of_one_value_at_a_time() {
        let specials = [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-30, 1e300, f64::MIN_POSITIVE / 4.0];
        let mut x = 1.234e-24;
        for i in 0..200_000 {
            // Mostly in the table, every seventh group with one value outside it.
            let mut group = [x, x * 1.7, x * 0.31, x * 5.9];
            if i % 7 == 0 {
                group[i % 4] = specials[i % specials.len()];
            }
            let lanes = POWER.pow_lanes(F64x4(group)).0;
            for (lane, &g) in group.iter().enumerate() {
                assert_eq!(lanes[lane].to_bits(), POWER.pow(g).to_bits(), "x = {g:e} in {group:?}");
            }
            x *= 1.000_37;
        }
    }

    #[test]
    fn falls_back_to_powf_outside_the_table() {
        for x in [0.0, 1e-300, 5e-324, 1e-26, 4.2e6, 1e300, f64::INFINITY] {
            assert_eq!(POWER.pow(x), x.powf(0.687), "x = {x:e}");
        }
        assert!(POWER.pow(f64::NAN).is_nan());
        assert!(POWER.pow(-1.0).is_nan());
    }
}
