//! A ball in vacuum on a floor with ε = 1 keeps its bounce height: the impact is located
//! inside the step, and RK2 is exact for motion under constant gravity.

use crate::common;
use common::fixture::BeadOnFloor;
use wetbounce::Outcome;

const H0: f64 = 0.1;
const R: f64 = 0.005;
const G: f64 = 9.81;

/// A steel ball in vacuum, ε_max = 1, dropped from H0 onto the floor.
fn vacuum_scene(integrator: &str, dt: f64) -> wetbounce::Scene {
    BeadOnFloor::new()
        .dt(dt)
        .duration(10.0)
        .output_interval(0.01)
        .integrator(integrator)
        .vacuum()
        .gravity([0.0, 0.0, -G])
        .effects("gravity = {}")
        .kind("steel")
        .density(7800.0)
        .elastic(2e11, 0.3)
        .restitution_max(1.0)
        .diameter(2.0 * R)
        .at([0.0, 0.0, H0 + R])
        .scene()
}

#[test]
fn ball_in_vacuum_with_eps_1_keeps_its_bounce_height_over_10_bounces() {
    // dt = 1.3 ms: no impact falls on a step boundary. Bounce period 2·sqrt(2 H0/g) ≈ 0.286 s.
    let mut sim = vacuum_scene("rk2", 1.3e-3).simulation();
    let v0 = (2.0 * G * H0).sqrt();
    let mut bounces = 0;
    while bounces < 10 {
        let t_next = sim.world.time + 0.01;
        let events = common::run_collect(&mut sim, t_next);
        for e in events {
            assert_eq!(e.outcome, Outcome::Bounced);
            assert_eq!(e.st, f64::INFINITY, "vacuum: St = ∞, ε = ε_max");
            assert!((e.normal_speed - v0).abs() / v0 < 1e-9, "impact speed {} vs {v0}", e.normal_speed);
            bounces += 1;
            // Apex of the next flight: z = H0 + R exactly.
            let apex = e.time + v0 / G;
            let mut probe = vacuum_scene("rk2", 1.3e-3).simulation();
            probe.world.particles = sim.world.particles.clone();
            probe.world.time = sim.world.time;
            if apex > probe.world.time {
                probe.advance_to(apex);
                let h = probe.world.particles.pos[0].z - R;
                assert!((h - H0).abs() / H0 < 1e-6, "bounce {bounces}: apex height {h}");
            }
        }
        assert!(
            sim.world.particles.pos[0].z >= R * (1.0 - 1e-12),
            "below the floor: {}",
            sim.world.particles.pos[0].z
        );
    }
}

#[test]
fn impact_times_are_exact_inside_the_step() {
    // First impact at sqrt(2 H0/g), then every 2 sqrt(2 H0/g).
    let mut sim = vacuum_scene("rk2", 7e-3).simulation();
    let events = common::run_collect(&mut sim, 1.0);
    let t1 = (2.0 * H0 / G).sqrt();
    for (k, e) in events.iter().enumerate() {
        let expected = t1 * (1.0 + 2.0 * k as f64);
        assert!((e.time - expected).abs() < 1e-12, "impact {k}: {} vs {expected}", e.time);
    }
    assert!(events.len() >= 3);
}
