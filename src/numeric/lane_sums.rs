//! The history effect's two sweeps along a particle's own array of numbers (its memory modes,
//! by component), by lane groups of four: [`lane_sums`], two sums of products, each kept as
//! four running sums, one per lane, in the order of the array; and [`lane_update`], each
//! number moved on by three products. Every product is added by a fused multiply-add (one
//! rounding), so the same operations give the same bits on every processor.
//!
//! Unlike [`super::lanes`] (four particles side by side, whose plain arrays the compiler turns
//! into vectors of the calling function's width), a sum along one array defeats the compiler:
//! on plain arrays of four, LLVM's loop vectoriser interleaved lanes 0 and 2, 1 and 3 with
//! shuffles, and took 1.4 times the history scene's instructions (3492M against 2512M at 200
//! steps, callgrind). And without the fused multiply-add in the instruction set it may use,
//! the compiler never fuses a product and a sum of its own (that would change the bits). So
//! both sweeps take 256-bit AVX instructions with FMA where the code is compiled for them and
//! the processor has them ([`Avx`]); elsewhere each number goes by `f64::mul_add`, the same
//! fused operation (an instruction where the processor has one, the C library's `fma`
//! otherwise): the same bits either way.

use multiversion::target::TargetFeatures;

/// Whether [`lane_sums`] and [`lane_update`] may use AVX with FMA. Made by [`Avx::of`] from the
/// target a `multiversion` copy of the calling function is compiled for (`selected_target!()`:
/// a constant there, so the other way is compiled out) and whether the processor has both (so
/// their instructions never run where it has not).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Avx(bool);

impl Avx {
    /// AVX and FMA when `target` has both and the processor too.
    #[inline(always)]
    pub fn of(target: TargetFeatures) -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            use multiversion::target_features::x86_64::{AVX, FMA};
            let compiled = target.contains(AVX) && target.contains(FMA);
            Avx(compiled
                && std::arch::is_x86_feature_detected!("avx")
                && std::arch::is_x86_feature_detected!("fma"))
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
/// each in the order of `g`, each term added by a fused multiply-add: two sums in one pass
/// over `f`.
#[inline(always)]
pub fn lane_sums(f: &[[f64; 4]], (a, b): (&[[f64; 4]], &[[f64; 4]]), avx: Avx) -> ([f64; 4], [f64; 4]) {
    let (mut sa, mut sb) = ([0.0; 4], [0.0; 4]);
    #[cfg(target_arch = "x86_64")]
    if avx.0 {
        use std::arch::x86_64::{_mm256_fmadd_pd, _mm256_loadu_pd, _mm256_setzero_pd, _mm256_storeu_pd};
        // SAFETY: `Avx(true)` is made only where the processor has AVX and FMA (`Avx::of`);
        // every pointer is to an array of four f64s.
        unsafe {
            let (mut s, mut t) = (_mm256_setzero_pd(), _mm256_setzero_pd());
            for ((f, a), b) in f.iter().zip(a).zip(b) {
                let f = _mm256_loadu_pd(f.as_ptr());
                s = _mm256_fmadd_pd(_mm256_loadu_pd(a.as_ptr()), f, s);
                t = _mm256_fmadd_pd(_mm256_loadu_pd(b.as_ptr()), f, t);
            }
            _mm256_storeu_pd(sa.as_mut_ptr(), s);
            _mm256_storeu_pd(sb.as_mut_ptr(), t);
        }
        return (sa, sb);
    }
    let _ = avx;
    for ((f, a), b) in f.iter().zip(a).zip(b) {
        for j in 0..4 {
            sa[j] = a[j].mul_add(f[j], sa[j]);
            sb[j] = b[j].mul_add(f[j], sb[j]);
        }
    }
    (sa, sb)
}

/// `o_i = f_i e_i + a p_i + b q_i` for every `i`, as `fma(b, q_i, fma(a, p_i, f_i e_i))`; without
/// `f` (an empty array), `o_i = fma(b, q_i, a p_i)`. Every slice is at least as long as `o`.
/// By groups of four in AVX with FMA, the last `len mod 4` one by one (the same operations).
#[inline(always)]
pub fn lane_update(
    o: &mut [f64],
    (f, e): (&[f64], &[f64]),
    (a, p): (f64, &[f64]),
    (b, q): (f64, &[f64]),
    avx: Avx,
) {
    let n = o.len();
    let (p, q, e) = (&p[..n], &q[..n], &e[..n]);
    let f = if f.is_empty() { None } else { Some(&f[..n]) };
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if avx.0 {
        use std::arch::x86_64::{
            _mm256_fmadd_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_storeu_pd,
        };
        done = n / 4 * 4;
        // SAFETY: `Avx(true)` is made only where the processor has AVX and FMA (`Avx::of`);
        // every load and store is of four f64s at an index below `done ≤ n`, the length of
        // every slice.
        unsafe {
            let (a4, b4) = (_mm256_set1_pd(a), _mm256_set1_pd(b));
            let (p, q, e, o) = (p.as_ptr(), q.as_ptr(), e.as_ptr(), o.as_mut_ptr());
            // One loop with a memory and one without, so that neither tests which it is for
            // every group (the compiler kept that test inside a single loop, and did not unroll
            // it: 3.2 instructions per number against 1.6, callgrind). No closures: a call of
            // its own would be compiled without AVX.
            match f {
                Some(f) => {
                    let f = f.as_ptr();
                    for i in (0..done).step_by(4) {
                        let start = _mm256_fmadd_pd(
                            a4,
                            _mm256_loadu_pd(p.add(i)),
                            _mm256_mul_pd(_mm256_loadu_pd(f.add(i)), _mm256_loadu_pd(e.add(i))),
                        );
                        _mm256_storeu_pd(o.add(i), _mm256_fmadd_pd(b4, _mm256_loadu_pd(q.add(i)), start));
                    }
                }
                None => {
                    for i in (0..done).step_by(4) {
                        let start = _mm256_mul_pd(a4, _mm256_loadu_pd(p.add(i)));
                        _mm256_storeu_pd(o.add(i), _mm256_fmadd_pd(b4, _mm256_loadu_pd(q.add(i)), start));
                    }
                }
            }
        }
    }
    let _ = avx;
    // Written out, not in a closure: a call of its own would be compiled without FMA.
    for i in done..n {
        let start = match f {
            Some(f) => a.mul_add(p[i], f[i] * e[i]),
            None => a * p[i],
        };
        o[i] = b.mul_add(q[i], start);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every feature the target can have, AVX and FMA among them on x86-64.
    fn everything() -> TargetFeatures {
        let everything = TargetFeatures::enabled_for_target();
        #[cfg(target_arch = "x86_64")]
        let everything = everything
            .with(multiversion::target_features::x86_64::AVX)
            .with(multiversion::target_features::x86_64::FMA);
        everything
    }

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn avx_and_portable_lane_sums_are_the_same_bits() {
        // Numbers whose sums round differently in another order, or unfused.
        let f: Vec<[f64; 4]> =
            (0..37).map(|i| [1e16 / (i + 1) as f64, 0.1 * i as f64, -3.3, 1.0 / 3.0]).collect();
        let a: Vec<[f64; 4]> = (0..37).map(|i| [0.7, 1e-3 * i as f64, 1.0 + 1e-16 * i as f64, 7.0]).collect();
        let b: Vec<[f64; 4]> = a.iter().map(|a| a.map(|x| 1.0 - x / 3.0)).collect();
        let portable = lane_sums(&f, (&a, &b), Avx::NONE);
        let mut by_hand = ([0.0; 4], [0.0; 4]);
        for ((f, a), b) in f.iter().zip(&a).zip(&b) {
            for j in 0..4 {
                by_hand.0[j] = a[j].mul_add(f[j], by_hand.0[j]);
                by_hand.1[j] = b[j].mul_add(f[j], by_hand.1[j]);
            }
        }
        let both = |(s, t): ([f64; 4], [f64; 4])| (bits(&s), bits(&t));
        assert_eq!(both(portable), both(by_hand));
        assert_eq!(both(lane_sums(&f, (&a, &b), Avx::of(everything()))), both(portable));
    }

    #[test]
    fn avx_and_portable_updates_are_the_same_bits_with_and_without_a_memory() {
        let n = 37;
        let f: Vec<f64> = (0..n).map(|i| 1e8 / (i + 1) as f64 + 0.1).collect();
        let e: Vec<f64> = (0..n).map(|i| (-(i as f64) / 3.0).exp()).collect();
        let p: Vec<f64> = (0..n).map(|i| 1.0 / 3.0 + 1e-3 * i as f64).collect();
        let q: Vec<f64> = p.iter().map(|p| 0.5 * p - 1e-17).collect();
        let (a, b) = (9.81 / 7.0, -2.0 / 3.0);
        for start in [&f[..], &[]] {
            let (mut portable, mut avx) = (vec![0.0; n], vec![0.0; n]);
            lane_update(&mut portable, (start, &e), (a, &p), (b, &q), Avx::NONE);
            lane_update(&mut avx, (start, &e), (a, &p), (b, &q), Avx::of(everything()));
            let by_hand: Vec<f64> = (0..n)
                .map(|i| match start.is_empty() {
                    true => b.mul_add(q[i], a * p[i]),
                    false => b.mul_add(q[i], a.mul_add(p[i], f[i] * e[i])),
                })
                .collect();
            assert_eq!(bits(&portable), bits(&by_hand));
            assert_eq!(bits(&avx), bits(&portable));
        }
    }
}
