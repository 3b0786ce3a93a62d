//! Particle–particle contacts **[ext]** (docs/physics.md §2, §4, §5 for pairs).

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;
use wetbounce::correlations::{ADDED_MASS_WALL, sphere_volume, spring_pair_contact_time};
use wetbounce::particles::State;
use wetbounce::{Other, Outcome};

const D: f64 = 2.5e-3;

/// Two toluene drops in water (St from the fluid, no force acting), approaching head-on.
fn drops(speed: f64, hold: bool) -> wetbounce::Scene {
    let effects = if hold { "contact_time = {}" } else { "" };
    common::scene(&format!(
        r#"
[simulation]
dt = 1e-4
duration = 1.0
output_interval = 0.01
[fluid]
density = 997.0
viscosity = 0.89e-3
[effects]
{effects}
[[kinds]]
name = "toluene"
type = "drop"
density = 860.0
surface_tension = 0.026
restitution_max = 0.91
[[particles]]
kind = "toluene"
diameter = {D}
position = [-0.005, 0.0, 0.0]
velocity = [{speed}, 0.0, 0.0]
[[particles]]
kind = "toluene"
diameter = {D}
position = [0.005, 0.0, 0.0]
velocity = [-{speed}, 0.0, 0.0]
"#
    ))
}

#[test]
fn head_on_equal_drops_are_held_for_the_spring_time_then_released_at_eps_vn() {
    let speed = 0.1;
    let mut sim = drops(speed, true).simulation();
    let events = common::run_collect(&mut sim, 0.2);
    assert_eq!(events.len(), 1, "{events:?}");
    let e = events[0];
    assert_eq!((e.outcome, e.other), (Outcome::Held, Other::Particle(1)));
    // Contact when the gap 10 mm − d closes at 0.2 m/s.
    assert!((e.time - (0.01 - D) / (2.0 * speed)).abs() < 1e-12, "t = {}", e.time);
    assert!((e.normal_speed - 2.0 * speed).abs() < 1e-12);
    // Two equal springs in series and the reduced mass (docs/physics.md §4 [ext]).
    let m = (860.0 + ADDED_MASS_WALL * 997.0) * sphere_volume(D);
    let expected = spring_pair_contact_time(m, m, 0.026, 0.026);
    assert!((e.contact_time - expected).abs() < 1e-15);
    // During the hold both move at the centre-of-mass velocity (zero), in contact.
    let mut sim = drops(speed, true).simulation();
    sim.advance_to(e.time + 0.5 * e.contact_time);
    assert_eq!(sim.world.particles.state[0], State::PairHeld);
    assert!(sim.world.particles.vel[0].length() < 1e-15 && sim.world.particles.vel[1].length() < 1e-15);
    assert!(((sim.world.particles.pos[1] - sim.world.particles.pos[0]).length() - D).abs() < 1e-12);
    // After the hold (released at the first step after t_c): ±ε Vn / 2, momentum zero.
    sim.advance_to(e.time + e.contact_time + 2e-4);
    let (va, vb) = (sim.world.particles.vel[0], sim.world.particles.vel[1]);
    assert_eq!(sim.world.particles.state[0], State::Free);
    assert!((va.x + 0.5 * e.eps * e.normal_speed).abs() < 1e-12, "va = {va}");
    assert!((va + vb).length() < 1e-15);
}

#[test]
fn instantaneous_pair_rebound_conserves_momentum_and_applies_eps() {
    let mut sim = drops(0.1, false).simulation();
    let events = common::run_collect(&mut sim, 0.2);
    assert_eq!(events.len(), 1);
    let e = events[0];
    assert_eq!(e.outcome, Outcome::Bounced);
    let (va, vb) = (sim.world.particles.vel[0], sim.world.particles.vel[1]);
    assert!((va + vb).length() < 1e-16);
    assert!((vb.x - va.x - e.eps * e.normal_speed).abs() < 1e-14);
}

#[test]
fn slow_pair_stays_in_contact_and_moves_at_the_common_velocity() {
    // 2 mm/s each: St ≈ 2 < St_c: relative normal velocity removed, momentum kept (zero).
    let mut sim = drops(0.002, false).simulation();
    let events = common::run_collect(&mut sim, 2.0);
    assert_eq!(events.len(), 1);
    assert_eq!(events[0].outcome, Outcome::Deposited);
    assert!(sim.world.particles.vel[0].length() < 1e-15);
    assert!(((sim.world.particles.pos[1] - sim.world.particles.pos[0]).length() - D).abs() < 1e-12);
    assert_eq!(sim.world.lasting.len(), 1);
}

#[test]
fn many_colliding_beads_conserve_total_momentum_to_round_off() {
    // 64 beads converging on the origin in vacuum, no walls and no forces.
    let mut beads = BeadOnFloor::new()
        .output_interval(0.1)
        .vacuum()
        .gravity([0.0; 3])
        .effects("")
        .restitution_max(0.9)
        .walls("")
        .diameter(3e-3);
    for i in 0..64 {
        let f = i as f64;
        // Spread over ±30 mm: at ±20 mm two pairs started overlapping, which a scene may not.
        let x = DVec3::new((f * 1.3).sin(), (f * 2.1).cos(), (f * 0.7).sin()) * 0.03
            + DVec3::new(0.0, 0.0, f * 1e-3);
        let v = DVec3::ZERO - x * 2.0; // (0 − 2x: +0.0, not −0.0, where x is 0.)
        beads = beads.particle(x, v);
    }
    let mut sim = beads.scene().simulation();
    let momentum = |s: &wetbounce::Simulation| s.world.particles.vel.iter().copied().sum::<DVec3>();
    let before = momentum(&sim);
    // They meet around t = 0.5 s.
    let events = common::run_collect(&mut sim, 0.8);
    assert!(events.len() > 10, "{} collisions", events.len());
    let after = momentum(&sim);
    assert!((after - before).length() < 1e-12, "{before} → {after}");
    // No pair ends overlapping by more than 1e-9 of a diameter.
    for i in 0..sim.world.particles.len() {
        for j in i + 1..sim.world.particles.len() {
            let gap = (sim.world.particles.pos[j] - sim.world.particles.pos[i]).length() - 3e-3;
            assert!(gap > -3e-12, "{i}-{j} overlap {gap}");
        }
    }
}
