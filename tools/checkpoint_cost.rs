//! What a checkpoint costs: its size per particle and the time to write and to read it, for
//! the shipped column's drops, with and without the history effect (issue 27, item 7).
//!
//! Run: `cargo run --release --bin checkpoint_cost -- [N...]` (default 100000 1000000). The
//! column scene (scenes/column.toml) gets N toluene drops placed at random in the column (the
//! state's size does not depend on where they are), with its own effects, then with `history =
//! {}` added; a run of 20 steps gives the world its contacts and neighbour list, then a
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
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
            for i in 0..n {
                let (r, phi, z) = (
                    0.02 * rng.random::<f64>().sqrt(),
                    rng.random::<f64>() * std::f64::consts::TAU,
                    0.45 * rng.random::<f64>(),
                );
                let pos = DVec3::new(r * phi.cos(), r * phi.sin(), 0.02 + z);
                scene.particles.push(i as u32, 0, 2.5e-3, pos, DVec3::ZERO);
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
