//! The machine's two roofs, measured (docs/roofline.md): the peak rate of double-precision
//! arithmetic and the memory bandwidth, each on 1 thread and on every core.
//!
//! Run: `cargo run --release --bin peak`. It prints, per thread count:
//! - **flops**: twelve independent chains of four-lane fused multiply-adds (AVX2 + FMA, the
//!   widest code the engine is compiled for: its hot loops have an AVX2 copy picked at run
//!   time), 8 flops each, so the FMA pipes never wait on a result. Code that does not
//!   vectorise issues the same instructions with one lane of four busy: its ceiling is a
//!   quarter of this (docs/roofline.md);
//! - **clock**: a chain of dependent integer additions, one per cycle (x86-64 only), for
//!   instructions per cycle from instruction counts and times;
//! - **bandwidth**: the STREAM triad `a = b + s c` over three arrays of 64 MiB each (well past
//!   the last-level cache), counting 24 bytes per element (two read, one written; the write's
//!   read for ownership not counted, as STREAM does not).
//!
//! Each figure is the best of five runs. Without AVX2 and FMA (another processor) the flops
//! column says so.

use rayon::prelude::*;
use std::time::Instant;

/// Fused multiply-adds per chain and run.
const ITERATIONS: u64 = 50_000_000;
/// Elements of each triad array (64 MiB of f64).
const TRIAD_LEN: usize = 8 << 20;

fn main() {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut counts = vec![1];
    if cores > 1 {
        counts.push(cores);
    }
    if let Some(hz) = best(clock) {
        println!("clock: {:.2} GHz (one thread)", hz / 1e9);
    }
    println!("threads | AVX2 FMA (Gflop/s) | triad (GB/s)");
    for threads in counts {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
        let (vector, triad) = pool.install(|| (best(|| vector_rate(threads)), best(|| triad_rate(threads))));
        let vector = vector.map_or("no AVX2/FMA".to_string(), |r| format!("{:.1}", r / 1e9));
        println!("{threads} | {vector} | {:.1}", triad.unwrap_or(0.0) / 1e9);
    }
}

/// The largest of five measurements, `None` when the measurement is not possible here.
fn best(f: impl Fn() -> Option<f64>) -> Option<f64> {
    (0..5).filter_map(|_| f()).reduce(f64::max)
}

/// Cycles per second of one thread: a chain of dependent additions, each waiting one cycle
/// for the last.
fn clock() -> Option<f64> {
    #[cfg(target_arch = "x86_64")]
    {
        const ROUNDS: u64 = 100_000_000;
        let mut x: u64 = 0;
        let start = Instant::now();
        for _ in 0..ROUNDS {
            // SAFETY: eight register additions, no memory touched.
            unsafe {
                std::arch::asm!(
                    "add {0}, 1", "add {0}, 1", "add {0}, 1", "add {0}, 1",
                    "add {0}, 1", "add {0}, 1", "add {0}, 1", "add {0}, 1",
                    inout(reg) x,
                    options(nomem, nostack, pure),
                );
            }
        }
        let secs = start.elapsed().as_secs_f64();
        std::hint::black_box(x);
        return Some(8.0 * ROUNDS as f64 / secs);
    }
    #[allow(unreachable_code)]
    None
}

/// Flop/s of `threads` threads each running [`fma_chains`].
fn vector_rate(threads: usize) -> Option<f64> {
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma") {
        let start = Instant::now();
        let sums: f64 = (0..threads)
            .into_par_iter()
            .map(|t| {
                // SAFETY: the processor has AVX2 and FMA (tested above).
                unsafe { fma_chains(1.0 + t as f64 * 1e-9) }
            })
            .sum();
        let secs = start.elapsed().as_secs_f64();
        std::hint::black_box(sums);
        return Some(threads as f64 * ITERATIONS as f64 * 12.0 * 8.0 / secs);
    }
    let _ = threads;
    None
}

/// Twelve independent four-lane FMA chains of [`ITERATIONS`] steps each; returns their sum.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn fma_chains(seed: f64) -> f64 {
    use std::arch::x86_64::*;
    let a = _mm256_set1_pd(0.999_999_9);
    let b = _mm256_set1_pd(1e-9 * seed);
    let mut acc = [_mm256_set1_pd(seed); 12];
    for _ in 0..ITERATIONS {
        for x in acc.iter_mut() {
            *x = _mm256_fmadd_pd(*x, a, b);
        }
    }
    let mut total = [0.0; 4];
    let sum = acc.iter().fold(_mm256_setzero_pd(), |s, &x| _mm256_add_pd(s, x));
    // SAFETY: `total` holds four f64, the width of the store.
    unsafe { _mm256_storeu_pd(total.as_mut_ptr(), sum) };
    total.iter().sum()
}

/// Bytes/s of the triad on `threads` threads (each thread its own contiguous share).
fn triad_rate(threads: usize) -> Option<f64> {
    let b = vec![1.0f64; TRIAD_LEN];
    let c = vec![2.0f64; TRIAD_LEN];
    // Written once before the timing: a fresh allocation's pages fault on the first write.
    let mut a = vec![0.0f64; TRIAD_LEN];
    let share = TRIAD_LEN.div_ceil(threads);
    let triad = |a: &mut [f64]| {
        a.par_chunks_mut(share).zip(b.par_chunks(share)).zip(c.par_chunks(share)).for_each(|((a, b), c)| {
            for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
                *a = b + 3.0 * c;
            }
        })
    };
    triad(&mut a);
    let start = Instant::now();
    triad(&mut a);
    let secs = start.elapsed().as_secs_f64();
    std::hint::black_box(&a);
    Some(24.0 * TRIAD_LEN as f64 / secs)
}
