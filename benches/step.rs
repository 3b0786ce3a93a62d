//! Criterion benches: whole steps of shipped scenes, and the hot kernels.
//!
//! Run: `cargo bench --bench step`. Throughput is in particles per second (particle-steps/s).

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
        group.bench_with_input(BenchmarkId::from_parameter(integrator), &s.dt, |b, &dt| {
            b.iter(|| sim.step(dt))
        });
    }
    group.finish();
}

/// One step of the Fig. 6 drop with contact handling (one particle: the per-step overhead).
fn single_drop_step(c: &mut Criterion) {
    let s = scene("toluene_drop.toml");
    let mut sim = s.simulation();
    c.bench_function("toluene_drop_step", |b| b.iter(|| sim.step(s.dt)));
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

criterion_group!(benches, dilute_step, single_drop_step, kernels);
criterion_main!(benches);
