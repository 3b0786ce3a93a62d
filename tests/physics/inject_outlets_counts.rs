//! Injectors and outlets: every particle is accounted for, injected particles never start
//! overlapping, ids are never reused, and injection does not depend on the thread count.

use crate::common;

use wetbounce::Simulation;

/// Drops injected at 2000/s into the bottom of a 30 mm water box, rising through an outlet
/// plane 20 mm above; dense enough that some injections must be redrawn.
pub(crate) const RISING: &str = r#"
[simulation]
dt = 1e-3
duration = 1.0
output_interval = 0.1

[fluid]
density = 997.0
viscosity = 0.89e-3

[effects]
gravity = {}
buoyancy = {}
drag = {}
added_mass = {}
contact_time = {}

[[kinds]]
name = "toluene"
type = "drop"
density = 860.0
surface_tension = 0.026
restitution_max = 0.91

[[walls]]
name = "tank"
type = "box"
min = [-0.015, -0.015, 0.0]
max = [0.015, 0.015, 0.05]
inside = true

[[particles]]
kind = "toluene"
diameter = 2e-3
position = [0.0, 0.0, 0.04]

[[injectors]]
kind = "toluene"
rate = 2000.0
region = { type = "box", min = [-0.012, -0.012, 0.002], max = [0.012, 0.012, 0.006] }
diameter = { distribution = "log_normal", median = 2.5e-3, sigma = 0.2, min = 1.5e-3, max = 4e-3 }
seed = 11
stop = 0.5

[[outlets]]
name = "top"
type = "plane"
point = [0.0, 0.0, 0.02]
normal = [0.0, 0.0, -1.0]
"#;

fn removed(sim: &Simulation) -> usize {
    sim.record.removed.iter().map(Vec::len).sum::<usize>() + sim.record.lost.len()
}

#[test]
fn initial_plus_injected_equals_alive_plus_removed_at_every_step() {
    let scene = common::scene(RISING);
    let mut sim = scene.simulation();
    let initial = sim.world.particles.len();
    while sim.world.time < 1.0 - 1e-9 {
        sim.advance_to(sim.world.time + sim.setup.dt);
        let injected: u64 = sim.world.injection.iter().map(|i| i.injected).sum();
        assert_eq!(
            initial + injected as usize,
            sim.world.particles.len() + removed(&sim),
            "t = {}",
            sim.world.time
        );
    }
    let inj = &sim.world.injection[0];
    assert_eq!(inj.due, 1000, "0.5 s at 2000/s");
    assert_eq!(inj.injected + inj.skipped, inj.due);
    assert!(inj.injected > 500, "most injections find a place: {}", inj.injected);
    assert!(sim.record.removed[0].len() > 100, "drops leave through the top");
    // The drop that started above the outlet plane is removed at the first step.
    assert_eq!(sim.record.removed[0][0].id, 0);
}

#[test]
fn injected_particles_never_start_overlapping_a_particle_or_a_wall() {
    use wetbounce::walls::Surface;
    let scene = common::scene(RISING);
    let mut sim = scene.simulation();
    let mut checked = 0;
    while sim.world.time < 0.3 {
        sim.advance_to(sim.world.time + sim.setup.dt);
        let p = &sim.world.particles;
        for i in (0..p.len()).filter(|&i| p.born[i] == sim.world.time) {
            checked += 1;
            let r = 0.5 * p.diameter[i];
            for w in &sim.setup.walls {
                assert!(
                    w.shape.gap(p.pos[i], r).gap >= 0.0,
                    "particle {} starts in wall {}",
                    p.id[i],
                    w.name
                );
            }
            for j in (0..p.len()).filter(|&j| j != i) {
                let reach = r + 0.5 * p.diameter[j];
                assert!(
                    (p.pos[i] - p.pos[j]).length() >= reach * (1.0 - 1e-12),
                    "particle {} starts overlapping particle {}",
                    p.id[i],
                    p.id[j]
                );
            }
        }
    }
    assert!(checked > 300, "checked {checked} injections");
}

#[test]
fn injected_ids_are_new_and_never_reused() {
    let scene = common::scene(RISING);
    let mut sim = scene.simulation();
    sim.advance_to(1.0);
    let mut ids: Vec<u32> = sim.world.particles.id.clone();
    ids.extend(sim.record.removed.iter().flat_map(|o| o.iter().map(|r| r.id)));
    let n = ids.len();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), n, "an id appears twice");
    assert_eq!(*ids.last().unwrap() + 1, sim.world.next_id);
}

#[test]
fn injection_and_removal_do_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut sim = common::scene(RISING).simulation();
            sim.advance_to(0.6);
            let removed: Vec<(u32, u64)> =
                sim.record.removed[0].iter().map(|r| (r.id, r.residence_time.to_bits())).collect();
            let state: Vec<(u32, [u64; 3], [u64; 3])> = (0..sim.world.particles.len())
                .map(|i| {
                    let p = &sim.world.particles;
                    (p.id[i], p.pos[i].to_array().map(f64::to_bits), p.vel[i].to_array().map(f64::to_bits))
                })
                .collect();
            (state, removed)
        })
    };
    assert_eq!(run(1), run(2));
}
