//! The history effect's two sweeps along a particle's own array of numbers (its memory modes,
//! the three components one after the other), by lane groups of four, all three components in
//! one pass: [`component_sums`], two sums of products per component, each kept as four running
//! sums, one per lane, in the order of the array; and [`component_update`], each number moved
//! on by three products. Every product is added by a fused multiply-add (one rounding), so the
//! same operations give the same bits on every processor.
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
//!
//! The three components go through one loop, not one each: each loop's set-up, last group and
//! the adding up of its lanes cost about forty instructions, as much as the loop itself over
//! 28 modes (callgrind, `tools/roofline/by_execution_count.py`), and the coefficients are
//! loaded once for the three.

use multiversion::target::TargetFeatures;

/// Whether [`component_sums`] and [`component_update`] may use AVX with FMA. Made by
/// [`Avx::of`] from the target a `multiversion` copy of the calling function is compiled for
/// (`selected_target!()`: a constant there, so the other way is compiled out) and whether the
/// processor has both (so their instructions never run where it has not).
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

/// For each component `c` of `f` (`3 n` numbers, the components one after the other), the two
/// sums `Σ_i a_i f[c n + i]` and `Σ_i b_i f[c n + i]`: each over the groups of four as four lane
/// sums in the order of the groups, the lanes added as `(s0 + s1) + (s2 + s3)`, then the last
/// `n mod 4` terms in order; every term added by a fused multiply-add. `a` and `b` hold at
/// least `n` numbers.
#[inline(always)]
pub fn component_sums(f: &[f64], (a, b): (&[f64], &[f64]), avx: Avx) -> ([f64; 3], [f64; 3]) {
    component_sums_of([f], (a, b), avx)[0]
}

/// [`component_sums`] of `B` particles' memories `fs` (each `3 n` numbers) in one pass: each
/// group of `a` and `b` is loaded once for all of them. The same operations particle by
/// particle, so the same bits as one at a time. Two particles at once keep their twelve running
/// sums, the two coefficients and a number of the memory in the sixteen AVX registers.
// The loops' indices address the running sums and the memory's offsets together, and the
// compiler unrolls them (`B` and 3 are constants); the measured code is this one.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
pub fn component_sums_of<const B: usize>(
    fs: [&[f64]; B],
    (a, b): (&[f64], &[f64]),
    avx: Avx,
) -> [([f64; 3], [f64; 3]); B] {
    let n = fs[0].len() / 3;
    let (a, b) = (&a[..n], &b[..n]);
    let mut f = [&fs[0][..0]; B];
    for j in 0..B {
        f[j] = &fs[j][..3 * n];
    }
    let done = n / 4 * 4;
    let mut sums = [([0.0; 3], [0.0; 3]); B];
    let mut portable = true;
    #[cfg(target_arch = "x86_64")]
    if avx.0 {
        use std::arch::x86_64::{
            __m256d, _mm_add_pd, _mm_storeu_pd, _mm256_castpd256_pd128, _mm256_extractf128_pd, _mm256_hadd_pd,
        };
        portable = false;
        // SAFETY: `Avx(true)` is made only where the processor has AVX and FMA (`Avx::of`),
        // and the slices are as `lane_sums_avx` needs.
        unsafe {
            let acc = lane_sums_avx(f, (a, b), n);
            // `hadd(s, t)` is `[s0 + s1, t0 + t1, s2 + s3, t2 + t3]`; its halves added, the
            // lanes of both sums in the order above. A loop, not a closure (which could be a
            // call of its own, compiled without AVX).
            for j in 0..B {
                for c in 0..3 {
                    let (s, t) = acc[j][c];
                    let h: __m256d = _mm256_hadd_pd(s, t);
                    let mut st = [0.0; 2];
                    _mm_storeu_pd(
                        st.as_mut_ptr(),
                        _mm_add_pd(_mm256_castpd256_pd128(h), _mm256_extractf128_pd(h, 1)),
                    );
                    [sums[j].0[c], sums[j].1[c]] = st;
                }
            }
        }
    }
    if portable {
        let _ = avx;
        for j in 0..B {
            for c in 0..3 {
                let (mut s, mut t) = ([0.0; 4], [0.0; 4]);
                for i in (0..done).step_by(4) {
                    for l in 0..4 {
                        s[l] = a[i + l].mul_add(f[j][c * n + i + l], s[l]);
                        t[l] = b[i + l].mul_add(f[j][c * n + i + l], t[l]);
                    }
                }
                sums[j].0[c] = (s[0] + s[1]) + (s[2] + s[3]);
                sums[j].1[c] = (t[0] + t[1]) + (t[2] + t[3]);
            }
        }
    }
    for j in 0..B {
        for c in 0..3 {
            for i in done..n {
                sums[j].0[c] = a[i].mul_add(f[j][c * n + i], sums[j].0[c]);
                sums[j].1[c] = b[i].mul_add(f[j][c * n + i], sums[j].1[c]);
            }
        }
    }
    sums
}

/// The AVX loop of [`component_sums_of`]: per particle and component, the running sums with
/// `a` and with `b`, four lanes each, over the first `n / 4` groups of four, their lanes not
/// yet added.
///
/// # Safety
/// The processor has AVX and FMA; `a` and `b` hold at least `n` numbers, each `f[j]` `3 n`.
#[cfg(target_arch = "x86_64")]
#[allow(clippy::needless_range_loop)]
#[inline(always)]
unsafe fn lane_sums_avx<const B: usize>(
    f: [&[f64]; B],
    (a, b): (&[f64], &[f64]),
    n: usize,
) -> [[(std::arch::x86_64::__m256d, std::arch::x86_64::__m256d); 3]; B] {
    use std::arch::x86_64::{__m256d, _mm256_fmadd_pd, _mm256_loadu_pd, _mm256_setzero_pd};
    // SAFETY: every load is of four f64s at an index below `n / 4 * 4` into `a` and `b` and
    // into each component of each `f[j]` (the caller's promise).
    unsafe {
        let (ap, bp) = (a.as_ptr(), b.as_ptr());
        let mut acc: [[(__m256d, __m256d); 3]; B] = [[(_mm256_setzero_pd(), _mm256_setzero_pd()); 3]; B];
        for i in (0..n / 4 * 4).step_by(4) {
            let (a4, b4) = (_mm256_loadu_pd(ap.add(i)), _mm256_loadu_pd(bp.add(i)));
            for j in 0..B {
                for c in 0..3 {
                    let x = _mm256_loadu_pd(f[j].as_ptr().add(c * n + i));
                    let (s, t) = acc[j][c];
                    acc[j][c] = (_mm256_fmadd_pd(a4, x, s), _mm256_fmadd_pd(b4, x, t));
                }
            }
        }
        acc
    }
}

/// For each component `c` of `o` (`3 n` numbers, the components one after the other)
/// `o[c n + i] = f[c n + i] e_i + a_c p_i + b_c q_i`, as `fma(b_c, q_i, fma(a_c, p_i, f e_i))`;
/// without `f` (an empty array), `fma(b_c, q_i, a_c p_i)`. `f` (when given) is as long as `o`,
/// `e`, `p` and `q` hold at least `n` numbers. By groups of four in AVX with FMA, the last
/// `n mod 4` one by one (the same operations).
#[inline(always)]
pub fn component_update(
    o: &mut [f64],
    (f, e): (&[f64], &[f64]),
    (a, p): ([f64; 3], &[f64]),
    (b, q): ([f64; 3], &[f64]),
    avx: Avx,
) {
    let n = o.len() / 3;
    let o = &mut o[..3 * n];
    let (p, q, e) = (&p[..n], &q[..n], &e[..n]);
    let f = if f.is_empty() { None } else { Some(&f[..3 * n]) };
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if avx.0 {
        use std::arch::x86_64::{
            _mm256_fmadd_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_storeu_pd,
        };
        if let Some(f) = f {
            // SAFETY: `Avx(true)` is made only where the processor has AVX and FMA
            // (`Avx::of`); `o` and `f` hold `3 n` numbers, `e`, `p` and `q` `n`.
            unsafe { update_avx(o.as_mut_ptr(), f.as_ptr(), (e, p, q), (a, b)) };
            return;
        }
        done = n / 4 * 4;
        // A memory that starts empty. SAFETY: as above; every load and store is of four f64s
        // at an index below `done ≤ n` into `p`, `q` and into each component of `o`.
        unsafe {
            let (ax, ay, az) = (_mm256_set1_pd(a[0]), _mm256_set1_pd(a[1]), _mm256_set1_pd(a[2]));
            let (bx, by, bz) = (_mm256_set1_pd(b[0]), _mm256_set1_pd(b[1]), _mm256_set1_pd(b[2]));
            let (p, q) = (p.as_ptr(), q.as_ptr());
            let ox = o.as_mut_ptr();
            let (oy, oz) = (ox.add(n), ox.add(2 * n));
            // No closure: a call of its own would be compiled without AVX.
            for i in (0..done).step_by(4) {
                let (p4, q4) = (_mm256_loadu_pd(p.add(i)), _mm256_loadu_pd(q.add(i)));
                _mm256_storeu_pd(ox.add(i), _mm256_fmadd_pd(bx, q4, _mm256_mul_pd(ax, p4)));
                _mm256_storeu_pd(oy.add(i), _mm256_fmadd_pd(by, q4, _mm256_mul_pd(ay, p4)));
                _mm256_storeu_pd(oz.add(i), _mm256_fmadd_pd(bz, q4, _mm256_mul_pd(az, p4)));
            }
        }
    }
    let _ = avx;
    // Written out, not in a closure: a call of its own would be compiled without FMA.
    for c in 0..3 {
        for i in done..n {
            let start = match f {
                Some(f) => a[c].mul_add(p[i], f[c * n + i] * e[i]),
                None => a[c] * p[i],
            };
            o[c * n + i] = b[c].mul_add(q[i], start);
        }
    }
}

/// [`component_update`] of one particle's memory `f` into `o` (each `3 n` numbers, `n` the
/// length of `e`, `p` and `q`) in AVX with FMA, by groups of four and the last `n mod 4` one by
/// one, with no check of its own: its callers make them, [`component_update_of_four`] once for
/// its four particles (about ten instructions a particle fewer, callgrind).
///
/// # Safety
/// The processor has AVX and FMA; `o` and `f` point at `3 n` numbers each.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn update_avx(
    o: *mut f64,
    f: *const f64,
    (e, p, q): (&[f64], &[f64], &[f64]),
    (a, b): ([f64; 3], [f64; 3]),
) {
    use std::arch::x86_64::{
        _mm256_fmadd_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_storeu_pd,
    };
    let n = e.len();
    let done = n / 4 * 4;
    // SAFETY: every load and store is at an index below `n` into `e`, `p`, `q` (length `n`,
    // as `p` and `q` by the caller's promise) and below `3 n` into `o` and `f`.
    unsafe {
        let (ax, ay, az) = (_mm256_set1_pd(a[0]), _mm256_set1_pd(a[1]), _mm256_set1_pd(a[2]));
        let (bx, by, bz) = (_mm256_set1_pd(b[0]), _mm256_set1_pd(b[1]), _mm256_set1_pd(b[2]));
        let (ep, pp, qp) = (e.as_ptr(), p.as_ptr(), q.as_ptr());
        let (oy, oz, fy, fz) = (o.add(n), o.add(2 * n), f.add(n), f.add(2 * n));
        for i in (0..done).step_by(4) {
            let (e4, p4, q4) =
                (_mm256_loadu_pd(ep.add(i)), _mm256_loadu_pd(pp.add(i)), _mm256_loadu_pd(qp.add(i)));
            let x = _mm256_fmadd_pd(ax, p4, _mm256_mul_pd(_mm256_loadu_pd(f.add(i)), e4));
            _mm256_storeu_pd(o.add(i), _mm256_fmadd_pd(bx, q4, x));
            let y = _mm256_fmadd_pd(ay, p4, _mm256_mul_pd(_mm256_loadu_pd(fy.add(i)), e4));
            _mm256_storeu_pd(oy.add(i), _mm256_fmadd_pd(by, q4, y));
            let z = _mm256_fmadd_pd(az, p4, _mm256_mul_pd(_mm256_loadu_pd(fz.add(i)), e4));
            _mm256_storeu_pd(oz.add(i), _mm256_fmadd_pd(bz, q4, z));
        }
        for c in 0..3 {
            for i in done..n {
                let start = a[c].mul_add(p[i], *f.add(c * n + i) * e[i]);
                *o.add(c * n + i) = b[c].mul_add(q[i], start);
            }
        }
    }
}

/// [`component_sums`] of four particles whose memories lie one after the other in `f`
/// (`4 × 3 n` numbers), particle by particle with the same operations: the two sums by
/// component (`x`, `y`, `z`), each as the four particles' lanes, ready for a lane group
/// ([`super::lanes`]) without moving them about.
#[inline(always)]
pub fn component_sums_of_four(
    f: &[f64],
    (a, b): (&[f64], &[f64]),
    avx: Avx,
) -> ([[f64; 4]; 3], [[f64; 4]; 3]) {
    let width = f.len() / 4;
    // Written out, two particles at a time, not in a loop over the four: the compiler then
    // shares the set-up (the slices, the loop's unrolling) among them, which it did not do in a
    // loop (733 instructions per particle-step of `bench_paper_history` against 710, callgrind).
    let (f0, f1) = (&f[..width], &f[width..2 * width]);
    let (f2, f3) = (&f[2 * width..3 * width], &f[3 * width..4 * width]);
    #[cfg(target_arch = "x86_64")]
    if avx.0 {
        use std::arch::x86_64::{_mm256_add_pd, _mm256_hadd_pd, _mm256_permute2f128_pd, _mm256_storeu_pd};
        let n = width / 3;
        let (a, b) = (&a[..n], &b[..n]);
        let fs = [&f0[..3 * n], &f1[..3 * n], &f2[..3 * n], &f3[..3 * n]];
        let (mut now, mut later) = ([[0.0; 4]; 3], [[0.0; 4]; 3]);
        // SAFETY: `Avx(true)` is made only where the processor has AVX and FMA (`Avx::of`);
        // `a`, `b` hold `n` numbers and each memory `3 n`.
        unsafe {
            let p01 = lane_sums_avx([fs[0], fs[1]], (a, b), n);
            let p23 = lane_sums_avx([fs[2], fs[3]], (a, b), n);
            // The four particles' lanes added at once, into the lanes of a group:
            // `hadd(S0, S1) = [S0₀ + S0₁, S1₀ + S1₁, S0₂ + S0₃, S1₂ + S1₃]`, and with the same of
            // particles 2 and 3, the low halves side by side plus the high halves side by side
            // are `(S₀ + S₁) + (S₂ + S₃)` of each particle: the order of `component_sums_of`.
            for c in 0..3 {
                let (s01, s23) =
                    (_mm256_hadd_pd(p01[0][c].0, p01[1][c].0), _mm256_hadd_pd(p23[0][c].0, p23[1][c].0));
                let (t01, t23) =
                    (_mm256_hadd_pd(p01[0][c].1, p01[1][c].1), _mm256_hadd_pd(p23[0][c].1, p23[1][c].1));
                let s = _mm256_add_pd(
                    _mm256_permute2f128_pd(s01, s23, 0x20),
                    _mm256_permute2f128_pd(s01, s23, 0x31),
                );
                let t = _mm256_add_pd(
                    _mm256_permute2f128_pd(t01, t23, 0x20),
                    _mm256_permute2f128_pd(t01, t23, 0x31),
                );
                _mm256_storeu_pd(now[c].as_mut_ptr(), s);
                _mm256_storeu_pd(later[c].as_mut_ptr(), t);
            }
        }
        for (j, fj) in fs.iter().enumerate() {
            for c in 0..3 {
                for i in n / 4 * 4..n {
                    now[c][j] = a[i].mul_add(fj[c * n + i], now[c][j]);
                    later[c][j] = b[i].mul_add(fj[c * n + i], later[c][j]);
                }
            }
        }
        return (now, later);
    }
    let [(s0, t0), (s1, t1)] = component_sums_of([f0, f1], (a, b), avx);
    let [(s2, t2), (s3, t3)] = component_sums_of([f2, f3], (a, b), avx);
    let lanes = |c: usize| ([s0[c], s1[c], s2[c], s3[c]], [t0[c], t1[c], t2[c], t3[c]]);
    let ((x, tx), (y, ty), (z, tz)) = (lanes(0), lanes(1), lanes(2));
    ([x, y, z], [tx, ty, tz])
}

/// [`component_update`] of four particles whose memories lie one after the other in `o` and
/// `f` (`4 × 3 n` numbers each), with `a` and `b` by component, each as the four particles'
/// lanes; a particle whose `write` is false is left as it is.
#[inline(always)]
pub fn component_update_of_four(
    o: &mut [f64],
    (f, e): (&[f64], &[f64]),
    (a, p): ([[f64; 4]; 3], &[f64]),
    (b, q): ([[f64; 4]; 3], &[f64]),
    write: [bool; 4],
    avx: Avx,
) {
    let width = o.len() / 4;
    let f = &f[..4 * width];
    // Particle `j`'s lane of each component.
    let lane = |x: [[f64; 4]; 3], j: usize| [x[0][j], x[1][j], x[2][j]];
    #[cfg(target_arch = "x86_64")]
    if avx.0 {
        let n = width / 3;
        let (e, p, q) = (&e[..n], &p[..n], &q[..n]);
        let (op, fp) = (o.as_mut_ptr(), f.as_ptr());
        // Written out, not in a loop over the four (which took 676 instructions per
        // particle-step against 656 without this function, callgrind).
        // SAFETY: `Avx(true)` is made only where the processor has AVX and FMA (`Avx::of`);
        // particle `j`'s `3 n ≤ width` numbers of `o` and `f` start at `j width`, below
        // `4 width`, and `e`, `p`, `q` hold `n`.
        unsafe {
            if write[0] {
                update_avx(op, fp, (e, p, q), (lane(a, 0), lane(b, 0)));
            }
            if write[1] {
                update_avx(op.add(width), fp.add(width), (e, p, q), (lane(a, 1), lane(b, 1)));
            }
            if write[2] {
                update_avx(op.add(2 * width), fp.add(2 * width), (e, p, q), (lane(a, 2), lane(b, 2)));
            }
            if write[3] {
                update_avx(op.add(3 * width), fp.add(3 * width), (e, p, q), (lane(a, 3), lane(b, 3)));
            }
        }
        return;
    }
    // Written out particle by particle, as in `component_sums_of_four`.
    let (o0, rest) = o.split_at_mut(width);
    let (o1, rest) = rest.split_at_mut(width);
    let (o2, o3) = rest.split_at_mut(width);
    let (f0, f1, f2, f3) = (&f[..width], &f[width..2 * width], &f[2 * width..3 * width], &f[3 * width..]);
    // One at a time: two at a time, each group of `e`, `p`, `q` loaded once for both, ran out
    // of registers for the twelve arrays' addresses and took 673 instructions per particle-step
    // against 672 (callgrind).
    if write[0] {
        component_update(o0, (f0, e), (lane(a, 0), p), (lane(b, 0), q), avx);
    }
    if write[1] {
        component_update(o1, (f1, e), (lane(a, 1), p), (lane(b, 1), q), avx);
    }
    if write[2] {
        component_update(o2, (f2, e), (lane(a, 2), p), (lane(b, 2), q), avx);
    }
    if write[3] {
        component_update(&mut o3[..width], (f3, e), (lane(a, 3), p), (lane(b, 3), q), avx);
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
    fn avx_and_portable_component_sums_are_the_same_bits_as_by_hand() {
        // Numbers whose sums round differently in another order, or unfused; 37 per component,
        // so nine groups of four and one left over.
        let n = 37;
        let f: Vec<f64> = (0..3 * n)
            .map(|k| match k % 4 {
                0 => 1e16 / (k + 1) as f64,
                1 => 0.1 * k as f64,
                2 => -3.3,
                _ => 1.0 / 3.0,
            })
            .collect();
        let a: Vec<f64> =
            (0..n).map(|i| [0.7, 1e-3 * i as f64, 1.0 + 1e-16 * i as f64, 7.0][i % 4]).collect();
        let b: Vec<f64> = a.iter().map(|x| 1.0 - x / 3.0).collect();
        let mut by_hand = ([0.0; 3], [0.0; 3]);
        for c in 0..3 {
            let (mut s, mut t) = ([0.0; 4], [0.0; 4]);
            for i in 0..n / 4 * 4 {
                s[i % 4] = a[i].mul_add(f[c * n + i], s[i % 4]);
                t[i % 4] = b[i].mul_add(f[c * n + i], t[i % 4]);
            }
            let (mut s, mut t) = ((s[0] + s[1]) + (s[2] + s[3]), (t[0] + t[1]) + (t[2] + t[3]));
            for i in n / 4 * 4..n {
                s = a[i].mul_add(f[c * n + i], s);
                t = b[i].mul_add(f[c * n + i], t);
            }
            (by_hand.0[c], by_hand.1[c]) = (s, t);
        }
        let both = |(s, t): ([f64; 3], [f64; 3])| (bits(&s), bits(&t));
        let portable = component_sums(&f, (&a, &b), Avx::NONE);
        assert_eq!(both(portable), both(by_hand));
        assert_eq!(both(component_sums(&f, (&a, &b), Avx::of(everything()))), both(portable));
    }

    #[test]
    fn four_particles_side_by_side_are_each_swept_as_alone() {
        let n = 29;
        let f: Vec<f64> = (0..4 * 3 * n).map(|k| 1e3 / (k + 1) as f64 - 0.7).collect();
        let e: Vec<f64> = (0..n).map(|i| (-(i as f64) / 5.0).exp()).collect();
        let (p, q): (Vec<f64>, Vec<f64>) =
            (0..n).map(|i| (1.0 / (i + 3) as f64, 0.3 - 1e-3 * i as f64)).unzip();
        let (a, b) = (
            [[1.5, -2.0, 0.25, 9.0], [0.0, 1e-7, -3.0, 2.0], [7.0, 0.5, -0.5, 1.0 / 3.0]],
            [[-1.0; 4], [2.0; 4], [0.1; 4]],
        );
        for avx in [Avx::NONE, Avx::of(everything())] {
            let (sa, sb) = component_sums_of_four(&f, (&e, &p), avx);
            let mut o = vec![-1.0; f.len()];
            let write = [true, false, true, true];
            component_update_of_four(&mut o, (&f, &e), (a, &p), (b, &q), write, avx);
            for i in 0..4 {
                let one = &f[i * 3 * n..(i + 1) * 3 * n];
                let (s, t) = component_sums(one, (&e, &p), avx);
                for c in 0..3 {
                    assert_eq!((sa[c][i].to_bits(), sb[c][i].to_bits()), (s[c].to_bits(), t[c].to_bits()));
                }
                let mut alone = vec![-1.0; 3 * n];
                if write[i] {
                    let (ai, bi) = ([a[0][i], a[1][i], a[2][i]], [b[0][i], b[1][i], b[2][i]]);
                    component_update(&mut alone, (one, &e), (ai, &p), (bi, &q), avx);
                }
                assert_eq!(bits(&o[i * 3 * n..(i + 1) * 3 * n]), bits(&alone));
            }
        }
    }

    #[test]
    fn avx_and_portable_updates_are_the_same_bits_with_and_without_a_memory() {
        let n = 37;
        let f: Vec<f64> = (0..3 * n).map(|i| 1e8 / (i + 1) as f64 + 0.1).collect();
        let e: Vec<f64> = (0..n).map(|i| (-(i as f64) / 3.0).exp()).collect();
        let p: Vec<f64> = (0..n).map(|i| 1.0 / 3.0 + 1e-3 * i as f64).collect();
        let q: Vec<f64> = p.iter().map(|p| 0.5 * p - 1e-17).collect();
        let (a, b) = ([9.81 / 7.0, -1.0 / 3.0, 1e-9], [-2.0 / 3.0, 0.1, 7.0]);
        for start in [&f[..], &[]] {
            let (mut portable, mut avx) = (vec![0.0; 3 * n], vec![0.0; 3 * n]);
            component_update(&mut portable, (start, &e), (a, &p), (b, &q), Avx::NONE);
            component_update(&mut avx, (start, &e), (a, &p), (b, &q), Avx::of(everything()));
            let by_hand: Vec<f64> = (0..3 * n)
                .map(|k| {
                    let (c, i) = (k / n, k % n);
                    match start.is_empty() {
                        true => b[c].mul_add(q[i], a[c] * p[i]),
                        false => b[c].mul_add(q[i], a[c].mul_add(p[i], f[k] * e[i])),
                    }
                })
                .collect();
            assert_eq!(bits(&portable), bits(&by_hand));
            assert_eq!(bits(&avx), bits(&portable));
        }
    }
}
