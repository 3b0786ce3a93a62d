//! Runs a scene and reports how close its particles are to rest, and, for a heap, its angle
//! of repose; writes the final positions and speeds as CSV for the pictures.
//!
//! Run: `cargo run --release --bin rest -- SCENE [EVERY_S] [OUT.csv]` (defaults: a report every
//! 0.25 s of simulated time, no CSV). Each report line gives the simulated time, the wall time,
//! the median, 99th percentile and largest speed (m/s), the largest `|ω| a` (m/s), the number of
//! lasting contacts between particles and of particles resting on a wall, and, summed over the
//! steps since the last line, the contact events (impacts) with a wall and between particles,
//! the lasting pair contacts made and broken, and the particles that left their wall; the
//! fastest particle (`id:state:pairs:z:v`: its id, state, number of lasting pair contacts,
//! height in mm and velocity), to tell a rattler from a bead its contacts push; last, the
//! heap's angle of repose (`wetbounce::heap::angle_of_repose`). A bed at rest makes and breaks
//! nothing.

use std::collections::HashSet;
use std::io::Write;
use std::time::Instant;
use wetbounce::Scene;
use wetbounce::contact::Other;
use wetbounce::particles::State;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: rest SCENE [EVERY_S] [OUT.csv]");
        std::process::exit(2);
    };
    let scene = Scene::load(path).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    let every: f64 = match args.get(1).map(|s| s.parse::<f64>()) {
        None => 0.25,
        Some(Ok(x)) if x > 0.0 => x,
        Some(_) => {
            eprintln!("error: EVERY_S must be a positive number of seconds, not {:?}", args[1]);
            std::process::exit(2)
        }
    };
    let mut sim = scene.simulation();
    let start = Instant::now();
    let dt = scene.setup.dt;
    let pairs = |sim: &wetbounce::Simulation| -> HashSet<(u32, u32)> {
        let id = &sim.world.particles.id;
        sim.world.lasting.iter().map(|c| (id[c.a as usize], id[c.b as usize])).collect()
    };
    let mut t = 0.0;
    while t < scene.duration - 1e-9 * dt {
        t = (t + every).min(scene.duration);
        let (mut wall_events, mut pair_events, mut made, mut broken, mut left_wall) = (0, 0, 0, 0, 0);
        while sim.world.time < t - 1e-6 * dt {
            let before = pairs(&sim);
            let resting: HashSet<u32> = (0..sim.world.particles.len())
                .filter(|&i| sim.world.particles.state[i] == State::Resting)
                .map(|i| sim.world.particles.id[i])
                .collect();
            sim.step(dt.min(t - sim.world.time));
            for e in sim.record.events.drain(..) {
                match e.other {
                    Other::Wall(_) => wall_events += 1,
                    Other::Particle(_) => pair_events += 1,
                }
            }
            let after = pairs(&sim);
            made += after.difference(&before).count();
            broken += before.difference(&after).count();
            let p = &sim.world.particles;
            left_wall +=
                (0..p.len()).filter(|&i| p.state[i] != State::Resting && resting.contains(&p.id[i])).count();
        }
        let p = &sim.world.particles;
        let mut s: Vec<f64> = p.vel.iter().map(|v| v.length()).collect();
        s.sort_by(f64::total_cmp);
        let spin = (0..p.len()).map(|i| p.spin(i).length() * 0.5 * p.diameter[i]).fold(0.0, f64::max);
        let (m, q, top) = if s.is_empty() {
            (0.0, 0.0, 0.0)
        } else {
            (s[s.len() / 2], s[s.len() * 99 / 100], s[s.len() - 1])
        };
        let angle = wetbounce::heap::angle_of_repose(&p.pos, &p.diameter);
        let on_wall = (0..p.len()).filter(|&i| p.state[i] == State::Resting).count();
        // The fastest particle, to tell a rattler (no contact) from a bead its contacts let go.
        let fastest =
            (0..p.len()).max_by(|&a, &b| p.vel[a].length_squared().total_cmp(&p.vel[b].length_squared()));
        let fastest = fastest.map_or("-".to_string(), |i| {
            let contacts =
                sim.world.lasting.iter().filter(|c| c.a as usize == i || c.b as usize == i).count();
            let v = p.vel[i];
            format!(
                "id{}:{}:pairs{}:z{:.2}mm:v({:.1e},{:.1e},{:.1e})",
                p.id[i],
                p.state[i].name(),
                contacts,
                p.pos[i].z * 1e3,
                v.x,
                v.y,
                v.z
            )
        });
        println!(
            "t={t:.2} wall_s={:.1} n={} median={m:.2e} p99={q:.2e} max={top:.2e} max_spin_a={spin:.2e} lasting={} on_wall={on_wall} events_wall={wall_events} events_pair={pair_events} made={made} broken={broken} left_wall={left_wall} fastest={fastest} angle_deg={}",
            start.elapsed().as_secs_f64(),
            p.len(),
            sim.world.lasting.len(),
            angle.map_or("-".to_string(), |a| format!("{:.1}", a.degrees)),
        );
        let _ = std::io::stdout().flush();
    }
    if let Some(out) = args.get(2) {
        let p = &sim.world.particles;
        let write = || -> std::io::Result<()> {
            let mut f = std::io::BufWriter::new(std::fs::File::create(out)?);
            writeln!(f, "id,x,y,z,diameter,speed")?;
            for i in 0..p.len() {
                let (x, v) = (p.pos[i], p.vel[i]);
                writeln!(f, "{},{},{},{},{},{}", p.id[i], x.x, x.y, x.z, p.diameter[i], v.length())?;
            }
            f.flush()
        };
        if let Err(e) = write() {
            eprintln!("error: writing {out}: {e}");
            std::process::exit(1);
        }
    }
}
