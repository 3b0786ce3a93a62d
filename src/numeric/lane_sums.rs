//! Sums of products along a particle's own array of numbers (the history effect's modes), by
//! lane groups of four: four running sums, one per lane, each in the order of the array.
//!
//! Unlike [`super::lanes`] (four particles side by side, whose plain arrays the compiler turns
//! into vectors of the calling function's width), a sum along one array defeats the compiler:
//! on plain arrays of four, LLVM's loop vectoriser interleaved lanes 0 and 2, 1 and 3 with
//! shuffles, and took 1.4 times the history scene's instructions (3492M against 2512M at 200
//! steps, callgrind). The `wide` crate's `f64x4` keeps the lanes, but its instruction set is
//! fixed when that crate is compiled: two SSE2 halves, even in the AVX2 copy of a function.
//! So the sums take 256-bit AVX instructions where the code is compiled for them and the
//! processor has them ([`Avx`]), `wide` elsewhere: the same operations lane by lane, so the
//! same bits either way.

use multiversion::target::TargetFeatures;

/// Whether [`lane_sums`] may use AVX. Made by [`Avx::of`] from the target a `multiversion`
/// copy of the calling function is compiled for (`selected_target!()`: a constant there, so
/// the other way is compiled out) and whether the processor has AVX (so its instructions never
/// run where it has not).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Avx(bool);

impl Avx {
    /// AVX when `target` has it and the processor too.
    #[inline(always)]
    pub fn of(target: TargetFeatures) -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            let compiled = target.contains(multiversion::target_features::x86_64::AVX);
            Avx(compiled && std::arch::is_x86_feature_detected!("avx"))
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = target;
            Avx(false)
        }
    }

    /// Never AVX: the portable way.
    pub const NONE: Avx = Avx(false);
}

/// The four lane sums `s_j = Σ_g a[g][j] f[g][j]` and the four `t_j = Σ_g b[g][j] f[g][j]`,
/// each in the order of `g`: two sums in one pass over `f`.
#[inline(always)]
pub fn lane_sums(f: &[[f64; 4]], (a, b): (&[[f64; 4]], &[[f64; 4]]), avx: Avx) -> ([f64; 4], [f64; 4]) {
    #[cfg(target_arch = "x86_64")]
    if avx.0 {
        use std::arch::x86_64::{
            _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_setzero_pd, _mm256_storeu_pd,
        };
        let (mut sa, mut sb) = ([0.0; 4], [0.0; 4]);
        // SAFETY: `Avx(true)` is made only where the processor has AVX (`Avx::of`); every
        // pointer is to an array of four f64s.
        unsafe {
            let (mut s, mut t) = (_mm256_setzero_pd(), _mm256_setzero_pd());
            for ((f, a), b) in f.iter().zip(a).zip(b) {
                let f = _mm256_loadu_pd(f.as_ptr());
                s = _mm256_add_pd(s, _mm256_mul_pd(_mm256_loadu_pd(a.as_ptr()), f));
                t = _mm256_add_pd(t, _mm256_mul_pd(_mm256_loadu_pd(b.as_ptr()), f));
            }
            _mm256_storeu_pd(sa.as_mut_ptr(), s);
            _mm256_storeu_pd(sb.as_mut_ptr(), t);
        }
        return (sa, sb);
    }
    let _ = avx;
    let (mut s, mut t) = (wide::f64x4::ZERO, wide::f64x4::ZERO);
    for ((f, a), b) in f.iter().zip(a).zip(b) {
        let f = wide::f64x4::from(*f);
        s += wide::f64x4::from(*a) * f;
        t += wide::f64x4::from(*b) * f;
    }
    (s.to_array(), t.to_array())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn avx_and_portable_lane_sums_are_the_same_bits() {
        // Numbers whose sums round differently in another order.
        let f: Vec<[f64; 4]> =
            (0..37).map(|i| [1e16 / (i + 1) as f64, 0.1 * i as f64, -3.3, 1.0 / 3.0]).collect();
        let a: Vec<[f64; 4]> = (0..37).map(|i| [0.7, 1e-3 * i as f64, 1.0 + 1e-16 * i as f64, 7.0]).collect();
        let b: Vec<[f64; 4]> = a.iter().map(|a| a.map(|x| 1.0 - x / 3.0)).collect();
        let portable = lane_sums(&f, (&a, &b), Avx::NONE);
        let mut by_hand = ([0.0; 4], [0.0; 4]);
        for ((f, a), b) in f.iter().zip(&a).zip(&b) {
            for j in 0..4 {
                by_hand.0[j] += a[j] * f[j];
                by_hand.1[j] += b[j] * f[j];
            }
        }
        let bits = |(s, t): ([f64; 4], [f64; 4])| (s.map(f64::to_bits), t.map(f64::to_bits));
        assert_eq!(bits(portable), bits(by_hand));
        let everything = multiversion::target_features::TargetFeatures::enabled_for_target();
        #[cfg(target_arch = "x86_64")]
        let everything = everything.with(multiversion::target_features::x86_64::AVX);
        let avx = lane_sums(&f, (&a, &b), Avx::of(everything));
        assert_eq!(bits(avx), bits(portable));
    }
}
