//! Runs a scene with injectors and outlets and writes every injected particle's birth (time,
//! diameter, position) and its residence time at the outlets, one CSV line per particle: the
//! drop list that `tools/contactor_side_by_side.sh` hands to OpenFOAM, so that both codes
//! track the same drops, and wetbounce's own residence times beside them.
//!
//! Run: `cargo run --release --bin contactor_drops -- SCENE OUT.csv [THREADS]`
//! Prints `wall_s=…` (the stepping alone: no output files are written during the run) and the
//! residence-time distribution of each outlet.

use std::collections::HashMap;
use std::io::Write;
use std::time::Instant;
use wetbounce::Scene;

/// One injected particle as it was born.
struct Birth {
    id: u32,
    born: f64,
    diameter: f64,
    pos: glam::DVec3,
}

fn fail(msg: String) -> ! {
    eprintln!("error: {msg}");
    std::process::exit(1)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(path), Some(out)) = (args.first(), args.get(1)) else {
        eprintln!("usage: contactor_drops SCENE OUT.csv [THREADS]");
        std::process::exit(2);
    };
    let threads = args.get(2).map(|s| {
        s.parse::<usize>().unwrap_or_else(|_| fail(format!("THREADS must be a whole number, got {s}")))
    });
    let scene = Scene::load(path).unwrap_or_else(|e| fail(e.to_string()));
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        pool = pool.num_threads(t.max(1));
    }
    let pool = pool.build().unwrap_or_else(|e| fail(format!("thread pool: {e}")));
    let mut sim = scene.simulation();
    // Particles present at the start are not injected: only ids from here on are births.
    let first_injected = sim.world.next_id;
    let mut births: Vec<Birth> = Vec::new();
    let mut next_new = first_injected;
    let dt = scene.setup.dt;
    let steps = (scene.duration / dt).round() as usize;
    let start = Instant::now();
    pool.install(|| {
        for _ in 0..steps {
            sim.step(dt);
            // New ids are handed out in increasing order, so a step's births are the ids at or
            // above the next one not yet seen.
            if sim.world.next_id > next_new {
                let p = &sim.world.particles;
                for i in 0..p.len() {
                    if p.id[i] >= next_new {
                        births.push(Birth {
                            id: p.id[i],
                            born: p.born[i],
                            diameter: p.diameter[i],
                            pos: p.pos[i],
                        });
                    }
                }
                next_new = sim.world.next_id;
            }
        }
    });
    let wall = start.elapsed().as_secs_f64();
    births.sort_by_key(|b| b.id);
    let mut residence: HashMap<u32, (usize, f64)> = HashMap::new();
    for (k, removed) in sim.record.removed.iter().enumerate() {
        for r in removed {
            residence.insert(r.id, (k, r.residence_time));
        }
    }
    let file = std::fs::File::create(out).unwrap_or_else(|e| fail(format!("{out}: {e}")));
    let mut w = std::io::BufWriter::new(file);
    let mut write = || -> std::io::Result<()> {
        writeln!(w, "id,born,diameter,x,y,z,outlet,residence")?;
        for b in &births {
            let (outlet, res) = match residence.get(&b.id) {
                Some(&(k, t)) => (sim.setup.outlets[k].name.clone(), format!("{t:.6}")),
                None => (String::new(), String::new()),
            };
            writeln!(
                w,
                "{},{:.6},{:.9e},{:.9e},{:.9e},{:.9e},{outlet},{res}",
                b.id, b.born, b.diameter, b.pos.x, b.pos.y, b.pos.z
            )?;
        }
        w.flush()
    };
    write().unwrap_or_else(|e| fail(format!("{out}: {e}")));
    let reached: usize = sim.record.removed.iter().map(Vec::len).sum();
    println!(
        "{path} injected={} reached_outlets={reached} steps={steps} threads={} wall_s={wall:.3}",
        births.len(),
        pool.current_num_threads()
    );
}
