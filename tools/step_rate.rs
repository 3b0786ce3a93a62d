//! Prints how fast a scene steps: particle-steps per second and the time of each stage.
//!
//! Run: `cargo run --release --bin step_rate -- SCENE [STEPS] [THREADS]`
//! (defaults: the scene's own step count up to 20,000, all cores). No output files are written,
//! so the figure is the engine's alone — the LIGGGHTS peer is timed the same way ("Loop time").

use std::io::Write;
use std::time::Instant;
use wetbounce::Scene;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: step_rate SCENE [STEPS] [THREADS]");
        std::process::exit(2);
    };
    let scene = Scene::load(path).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    let parse = |i: usize, what: &str| {
        args.get(i).map(|s| {
            s.parse::<usize>().unwrap_or_else(|_| {
                eprintln!("error: {what} must be a whole number, got {s}");
                std::process::exit(2)
            })
        })
    };
    let steps = parse(1, "STEPS").unwrap_or(((scene.duration / scene.setup.dt).round() as usize).min(20_000));
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = parse(2, "THREADS") {
        pool = pool.num_threads(threads.max(1));
    }
    let pool = pool.build().expect("thread pool");
    let mut sim = scene.simulation();
    let n = sim.world.particles.len();
    let start = Instant::now();
    // The whole run inside the pool, as `Simulation::advance_to` does: the serial stages then
    // run on a worker instead of a third thread competing with the spinning workers.
    pool.install(|| sim.run_steps(steps, scene.setup.dt));
    let wall = start.elapsed().as_secs_f64();
    // One write, whose error is ignored: a reader that stops after the first line (`| head -1`)
    // closes the pipe, and `println!` would panic on the second.
    let _ = writeln!(
        std::io::stdout(),
        "{path} N={n} steps={steps} threads={} wall_s={wall:.3} particle_steps_per_s={:.4e}\nstages: {:?}",
        pool.current_num_threads(),
        n as f64 * steps as f64 / wall,
        sim.record.stage_times
    );
}
