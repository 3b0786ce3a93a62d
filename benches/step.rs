//! Criterion benches: whole steps of shipped scenes, and the hot kernels.
//!
//! Run: `cargo bench --bench step` (one group: `cargo bench --bench step -- column`).
//! Throughput is in particles per second (particle-steps/s).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use wetbounce::Scene;
use wetbounce::correlations::{drag_factor_schiller_naumann, terminal_velocity};

fn scene(name: &str) -> Scene {
    Scene::load(format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"))).expect("shipped scene")
}

/// One step of the 10,000-bead dilute scene of the LIGGGHTS peer, per integrator.
fn dilute_step(c: &mut Criterion) {
    let base = scene("bench_dilute.toml");
    let mut group = c.benchmark_group("dilute_step");
    group.throughput(Throughput::Elements(base.particles.len() as u64));
    for integrator in ["euler", "rk2", "rk4", "exponential"] {
        let text = base.source.replace("integrator = \"euler\"", &format!("integrator = \"{integrator}\""));
        let s = Scene::from_str(&text, &base.path).expect("variant");
        let mut sim = s.simulation();
        group.bench_with_input(BenchmarkId::from_parameter(integrator), &s.setup.dt, |b, &dt| {
            b.iter_custom(|iters| {
                let start = std::time::Instant::now();
                sim.run_steps(iters as usize, dt);
                start.elapsed()
            })
        });
    }
    group.finish();
}

/// Simulated time (s) the column is advanced to before it is measured: the swarm is then 2500
/// drops, its head ~0.4 m up the column, and reaching it costs ~2 s of setup, not the half
/// minute the whole 16 s run takes.
const COLUMN_START: f64 = 5.0;

/// Simulated time (s) the measurement may run past `COLUMN_START` before the state is put back
/// to the one at `COLUMN_START` (outside the timing): the swarm keeps rising while measured, and
/// in one second it loses only a few of its drops through the outlet.
const COLUMN_WINDOW: f64 = 1.0;

/// One step of `scenes/column.toml` (drops rising in a walled column, pair and wall contacts),
/// from the state at `COLUMN_START`.
///
/// The column injects drops over time, so the state is built first (outside the measurement)
/// and the injectors are then removed: otherwise the count would grow by one drop per step
/// while criterion runs its hundreds of steps, and the throughput (fixed when the group is
/// made) would be wrong. The state still evolves while it is measured (the swarm rises, drops
/// leave through the outlet), so it is put back to the saved one every `COLUMN_WINDOW` of
/// simulated time, and the smallest count measured is printed next to criterion's figure.
fn column_step(c: &mut Criterion) {
    let s = scene("column.toml");
    let mut sim = s.simulation();
    let setup = std::time::Instant::now();
    sim.advance_to(COLUMN_START);
    sim.setup.injectors.clear();
    sim.world.injection.clear();
    // Contact events and lost particles are drained by the output sinks in a real run; here
    // nothing drains them, so they are dropped each step rather than grow for the whole bench.
    sim.record.events.clear();
    sim.record.lost.clear();
    let saved = sim.clone();
    let alive = sim.world.particles.len();
    eprintln!(
        "column: advanced to t = {COLUMN_START} s in {:.1} s of setup; {alive} drops alive",
        setup.elapsed().as_secs_f64()
    );
    let mut group = c.benchmark_group("column_step");
    group.throughput(Throughput::Elements(alive as u64));
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_secs(1));
    group.measurement_time(std::time::Duration::from_secs(3));
    let mut fewest = alive;
    group.bench_function("rk2", |b| {
        b.iter_custom(|iters| {
            let mut timed = std::time::Duration::ZERO;
            let mut left = iters;
            while left > 0 {
                if sim.world.time >= COLUMN_START + COLUMN_WINDOW {
                    sim = saved.clone();
                }
                let n = left.min(
                    ((COLUMN_START + COLUMN_WINDOW - sim.world.time) / s.setup.dt).ceil().max(1.0) as u64,
                );
                let start = std::time::Instant::now();
                // Inside the pool, as in a real run.
                rayon::scope(|_| {
                    for _ in 0..n {
                        sim.step(s.setup.dt);
                        sim.record.events.clear();
                        sim.record.lost.clear();
                    }
                });
                timed += start.elapsed();
                fewest = fewest.min(sim.world.particles.len());
                left -= n;
            }
            timed
        })
    });
    group.finish();
    eprintln!(
        "column: at least {fewest} drops alive while measured (t = {COLUMN_START}–{} s)",
        COLUMN_START + COLUMN_WINDOW
    );
}

/// One step of the Fig. 6 drop with contact handling (one particle: the per-step overhead).
fn single_drop_step(c: &mut Criterion) {
    let s = scene("toluene_drop.toml");
    let mut sim = s.simulation();
    c.bench_function("toluene_drop_step", |b| b.iter(|| sim.step(s.setup.dt)));
}

fn kernels(c: &mut Criterion) {
    c.bench_function("drag_factor_schiller_naumann", |b| {
        b.iter(|| drag_factor_schiller_naumann(black_box(253.0)))
    });
    c.bench_function("terminal_velocity", |b| {
        b.iter(|| {
            terminal_velocity(black_box(860.0), 997.0, 2.75e-3, 0.89e-3, 9.81, drag_factor_schiller_naumann)
        })
    });
}

criterion_group!(benches, dilute_step, column_step, single_drop_step, kernels);
criterion_main!(benches);
