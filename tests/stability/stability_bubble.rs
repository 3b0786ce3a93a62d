//! Stability case 2 (docs/stability.md): bubble-like particles. A 1 mm air bubble in water
//! treated as a sphere (ρp/ρ = 1e-3, so its inertia is almost all added mass: `ρp + C_M ρ`
//! with `C_M = ½` is 500 times `ρp`) rises, meets a top wall, stays finite and outside it, and
//! comes to rest there; so does a 3 mm one, which rebounds (held for its contact time) first.

use crate::common;
use wetbounce::Other;
use wetbounce::particles::State;

fn bubble(d: f64, integrator: &str, dt: f64) -> wetbounce::Scene {
    common::scene(&format!(
        r#"
[simulation]
dt = {dt:e}
duration = 2.0
output_interval = 0.01
integrator = "{integrator}"

[fluid]
density = 998.2
viscosity = 1.0e-3

[effects]
gravity = {{}}
buoyancy = {{}}
drag = {{ law = "schiller_naumann" }}
added_mass = {{}}
contact_time = {{}}

[[kinds]]
name = "air"
type = "drop"
density = 0.9982
surface_tension = 0.072
restitution_max = 0.9

[[walls]]
name = "lid"
type = "plane"
point = [0.0, 0.0, 0.05]
normal = [0.0, 0.0, -1.0]

[[particles]]
kind = "air"
diameter = {d:e}
position = [0.0, 0.0, 0.0]
"#
    ))
}

#[test]
fn one_and_three_mm_bubbles_rise_hit_the_lid_and_come_to_rest_with_every_integrator() {
    for d in [1e-3, 3e-3] {
        for integrator in ["euler", "rk2", "rk4", "exponential"] {
            let scene = bubble(d, integrator, 1e-4);
            let mut sim = scene.simulation();
            let mut events = Vec::new();
            let mut top_speed: f64 = 0.0;
            while sim.world.time < scene.duration {
                let t = sim.world.time + 0.01;
                events.extend(common::run_collect(&mut sim, t));
                let (x, v) = (sim.world.particles.pos[0], sim.world.particles.vel[0]);
                assert!(x.is_finite() && v.is_finite(), "d = {d}, {integrator}: {x:?} {v:?}");
                common::assert_clear_of_walls(&sim);
                top_speed = top_speed.max(v.length());
            }
            let lid = events.iter().filter(|e| e.other == Other::Wall(0)).count();
            assert!(lid >= 1, "d = {d}, {integrator}: never reached the lid");
            // It rose at a finite terminal speed (tens of cm/s), not at the 1000 g an inertia
            // without added mass would give.
            assert!(top_speed > 0.05 && top_speed < 0.5, "d = {d}, {integrator}: top speed {top_speed}");
            let p = &sim.world.particles;
            assert_eq!(p.state[0], State::Resting, "d = {d}, {integrator}: {events:?}");
            assert!(p.vel[0].length() < 1e-12, "d = {d}, {integrator}: still moving at {:?}", p.vel[0]);
            assert!(
                (p.pos[0].z - (0.05 - 0.5 * d)).abs() < 1e-12,
                "d = {d}, {integrator}: z = {}",
                p.pos[0].z
            );
            if d > 2e-3 {
                assert!(events[0].st >= 10.0, "the 3 mm bubble rebounds first: {:?}", events[0]);
            }
        }
    }
}
