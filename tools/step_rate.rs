//! Prints how fast a scene steps: particle-steps per second and the time of each stage.
//!
//! Run: `cargo run --release --bin step_rate -- SCENE [STEPS] [THREADS] [--from CHECKPOINT]`
//! (defaults: the scene's own step count up to 20,000, all cores). No output files are written,
//! so the figure is the engine's alone — the LIGGGHTS peer is timed the same way ("Loop time").
//!
//! `--from CHECKPOINT` starts from the particles (and lasting contacts) of a checkpoint of a
//! run of a scene with the same kinds, walls and effects — typically SCENE itself with a longer
//! step, run to settle a bed (`wetbounce run … --checkpoint-every`) — stepped with SCENE's
//! step: the peer's dense bed is settled by one run and timed by another in the same way
//! (peers/liggghts/in.s2_bed_prep, in.s2_bed).

use std::io::Write;
use std::time::Instant;
use wetbounce::Scene;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let from = args.iter().position(|a| a == "--from").map(|i| {
        let Some(file) = args.get(i + 1).cloned() else {
            eprintln!("error: --from needs a checkpoint file");
            std::process::exit(2)
        };
        args.drain(i..i + 2);
        file
    });
    let Some(path) = args.first() else {
        eprintln!("usage: step_rate SCENE [STEPS] [THREADS] [--from CHECKPOINT]");
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
    let mut sim = match &from {
        None => scene.simulation(),
        Some(file) => settled(&scene, file),
    };
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

/// SCENE's simulation with the world of the checkpoint `file` (its particles, lasting contacts
/// and time); the checkpoint's scene must have SCENE's kinds and walls, which is checked.
fn settled(scene: &Scene, file: &str) -> wetbounce::Simulation {
    let fail = |e: &dyn std::fmt::Display| -> ! {
        eprintln!("error: {file}: {e}");
        std::process::exit(1)
    };
    let (_, saved) =
        wetbounce::run::checkpoint::read(std::path::Path::new(file)).unwrap_or_else(|e| fail(&e));
    let theirs = Scene::from_str_with(&saved.scene.source, &saved.scene.path, Default::default())
        .unwrap_or_else(|e| fail(&format!("its scene no longer loads: {e}")));
    let (a, b) = (&scene.setup, &theirs.setup);
    if a.kinds.len() != b.kinds.len()
        || a.walls.len() != b.walls.len()
        || a.physics.features != b.physics.features
    {
        fail(&"its scene's kinds, walls or effects are not the scene's");
    }
    let record = (Vec::new(), vec![Vec::new(); a.outlets.len()], None);
    wetbounce::Simulation::restore(a.clone(), saved.world, record).unwrap_or_else(|e| fail(&e))
}
