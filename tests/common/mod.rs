//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod fixture;

use std::path::Path;
use wetbounce::{Scene, Simulation};

/// Builds a scene from TOML text, as if it were a file in `scenes/`.
pub fn scene(text: &str) -> Scene {
    Scene::from_str(text, Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/test.toml")))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Loads a shipped scene with one `[simulation]` value replaced (e.g. `dt`, `integrator`).
pub fn shipped_with(name: &str, key: &str, value: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let replaced: Vec<String> = text
        .lines()
        .map(|l| {
            if l.trim_start().starts_with(&format!("{key} "))
                || l.trim_start().starts_with(&format!("{key}="))
            {
                format!("{key} = {value}")
            } else {
                l.to_string()
            }
        })
        .collect();
    Scene::from_str(&replaced.join("\n"), &path).unwrap_or_else(|e| panic!("{e}"))
}

/// The smallest gap between any particle and any wall (negative inside), in particle radii, less
/// the round-off of the position's coordinates (1e-13 |x|, a few hundred ulps: a particle
/// that slid 20 km from the origin is not 'inside' by 1e-12 m), with the particle and the wall.
pub fn deepest_overlap(sim: &Simulation) -> (f64, usize, usize) {
    use wetbounce::walls::Surface;
    let p = &sim.world.particles;
    let mut worst = (f64::INFINITY, 0, 0);
    for i in 0..p.len() {
        let r = 0.5 * p.diameter[i];
        for (w, wall) in sim.setup.walls.iter().enumerate() {
            let g = (wall.shape.gap(p.pos[i], r).gap + 1e-13 * p.pos[i].length()) / r;
            if g < worst.0 {
                worst = (g, i, w);
            }
        }
    }
    worst
}

/// Panics when a particle overlaps a wall by more than round-off (1e-9 of its radius).
pub fn assert_clear_of_walls(sim: &Simulation) {
    let (g, i, w) = deepest_overlap(sim);
    assert!(
        g >= -1e-9,
        "t = {}: particle {} at {:?} is inside wall \"{}\" by {:.3e} radii",
        sim.world.time,
        sim.world.particles.id[i],
        sim.world.particles.pos[i],
        sim.setup.walls[w].name,
        -g
    );
}

/// Runs a simulation to `t_end`, collecting every contact event. Every contact of every test
/// that runs through here is checked to give no kinetic energy (docs/stability.md, case 7).
pub fn run_collect(sim: &mut Simulation, t_end: f64) -> Vec<wetbounce::ContactEvent> {
    let mut events = Vec::new();
    while sim.world.time < t_end {
        let next = (sim.world.time + 64.0 * sim.setup.dt).min(t_end);
        sim.advance_to(next);
        events.append(&mut sim.record.events);
    }
    for e in &events {
        assert!(e.energy_not_gained(), "a contact gained kinetic energy: {e:?}");
    }
    events
}

/// A scene of glass beads in water (gravity and drag only, no wall, 10 steps of 1 ms) whose
/// `fluid.flow` is `flow`: what the field-file tests load their fields into.
pub fn field_scene(flow: &str) -> String {
    format!(
        r#"
[simulation]
dt = 1e-3
duration = 0.01
output_interval = 0.01

[fluid]
density = 997.0
viscosity = 0.89e-3
flow = {flow}

[effects]
gravity = {{}}
drag = {{}}

[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.23
"#
    )
}
