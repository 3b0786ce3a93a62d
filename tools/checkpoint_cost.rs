//! What a checkpoint costs: its size per particle and the time to write and to read it, for
//! the shipped column's drops, with and without the history effect (issue 27, item 7).
//!
//! Run: `cargo run --release --bin checkpoint_cost -- [N...]` (default 100000 1000000). The
//! column scene (scenes/column.toml) gets N toluene drops on a lattice at 3 d spacing (its
//! walls and injector taken out: 10⁶ drops do not fit in it), with its own effects, then with
//! `history = {}` added; a run of 20 steps gives the world its neighbour list, then a
//! checkpoint is written (`run::save_to`: encode, zstd, write, sync) and read back
//! (`checkpoint::read`: read, checks, decompress, decode), each timed on the wall clock.

use glam::DVec3;
use rand::{Rng, SeedableRng};
use std::path::Path;
use std::time::Instant;
use wetbounce::Scene;
use wetbounce::run::checkpoint::{self, RunPosition, SavedScene};

fn main() {
    let sizes: Vec<usize> =
        std::env::args().skip(1).map(|s| s.parse().expect("N: a particle count")).collect();
    let sizes = if sizes.is_empty() { vec![100_000, 1_000_000] } else { sizes };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/column.toml");
    let text = std::fs::read_to_string(&path).expect("scenes/column.toml");
    println!("| particles | history | file (MB) | bytes/particle | write (s) | read (s) |");
    println!("| ---: | --- | ---: | ---: | ---: | ---: |");
    for &n in &sizes {
        for history in [false, true] {
            let source = if history {
                text.replacen("[effects]\n", "[effects]\nhistory = {}\n", 1)
            } else {
                text.clone()
            };
            let mut scene = Scene::from_str(&source, &path).expect("the column loads");
            // A lattice at 3 d spacing, clear of each other, with the walls and the injector
            // taken out (10⁶ drops do not fit in the column): the state per particle is the
            // column's drops', its contacts and neighbour list those of a dilute swarm.
            scene.setup.walls.clear();
            scene.setup.injectors.clear();
            scene.setup.outlets.clear();
            // Sizes, places and velocities drawn (a lattice of equal drops at rest compresses to
            // nothing, which no real state does).
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
            let mut draw = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
            let side = (n as f64).cbrt().ceil() as usize;
            for i in 0..n {
                let (a, b, c) = (i % side, (i / side) % side, i / (side * side));
                let jitter = DVec3::new(draw(-1.0, 1.0), draw(-1.0, 1.0), draw(-1.0, 1.0)) * 1e-3;
                let pos = DVec3::new(a as f64, b as f64, c as f64) * 7.5e-3 + jitter;
                let vel = DVec3::new(draw(-0.02, 0.02), draw(-0.02, 0.02), draw(0.0, 0.1));
                scene.particles.push(i as u32, 0, draw(2.0e-3, 3.0e-3), pos, vel);
            }
            let mut sim = scene.take_simulation().expect("memory for the run");
            sim.run_steps(20, scene.setup.dt);
            let saved = SavedScene {
                path: path.clone(),
                given: path.clone(),
                source: source.clone(),
                output_interval: scene.output_interval,
                formats: vec![],
                stem: "column".into(),
                max_spheres: 1000,
            };
            let file =
                std::env::temp_dir().join(format!("wetbounce-checkpoint-cost-{}.wbck", std::process::id()));
            let start = Instant::now();
            wetbounce::run::save_to(&file, &sim, &saved, RunPosition::default(), &[]).expect("written");
            let write = start.elapsed().as_secs_f64();
            let bytes = std::fs::metadata(&file).expect("the file").len();
            let start = Instant::now();
            let (_, back) = checkpoint::read(&file).expect("read back");
            let read = start.elapsed().as_secs_f64();
            assert_eq!(back.world.particles.len(), sim.world.particles.len());
            let _ = std::fs::remove_file(&file);
            println!(
                "| {} | {} | {:.1} | {:.0} | {:.3} | {:.3} |",
                sim.world.particles.len(),
                if history { "yes" } else { "no" },
                bytes as f64 / 1e6,
                bytes as f64 / sim.world.particles.len() as f64,
                write,
                read
            );
        }
    }
}
