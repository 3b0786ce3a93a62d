//! The history effect (docs/physics.md §10) through the whole engine: a sphere released from rest
//! against the exact solution with history and added mass (`correlations::HistorySettling`, by
//! Laplace transform), the order at which the flight converges to it, what the memory does at a
//! bounce, and the scene keys refused.

use crate::common;
use common::fixture::BeadOnFloor;
use wetbounce::Scene;
use wetbounce::correlations::{HistorySettling, history_settling_velocity};

/// A 0.1 mm glass bead in water: κ = c√τ = 1.22 (a strong history force), τ = 1.7 ms.
const D: f64 = 1e-4;
const RHO_P: f64 = 2500.0;
const RHO: f64 = 998.2;
const MU: f64 = 1.0e-3;

fn exact() -> HistorySettling {
    HistorySettling::sphere(RHO_P, RHO, MU, 0.5 * D, 9.81)
}

/// The bead, no walls, released from rest at the origin.
fn bead(dt: f64, t_end: f64, effects: &str) -> BeadOnFloor {
    no_bead(dt, t_end, effects).at([0.0; 3])
}

/// The scene of [`bead`] without the bead.
fn no_bead(dt: f64, t_end: f64, effects: &str) -> BeadOnFloor {
    BeadOnFloor::new()
        .dt(dt)
        .duration(t_end)
        .output_interval(t_end)
        .fluid(RHO, MU)
        .effects(effects)
        .density(RHO_P)
        .walls("")
        .diameter(D)
}

const WITH_HISTORY: &str = "gravity = {}\nbuoyancy = {}\ndrag = { law = \"stokes\" }\nadded_mass = {}\n\
                            history = { window = 2.0, tolerance = 1e-9 }";

/// Relative error of the settling velocity at `t_end` with a step `dt`.
fn error(dt: f64, t_end: f64) -> f64 {
    let mut sim = bead(dt, t_end, WITH_HISTORY).scene().simulation();
    sim.advance_to(t_end);
    let v = -sim.world.particles.vel[0].z;
    let reference = history_settling_velocity(t_end, &exact());
    (v - reference).abs() / reference
}

#[test]
fn sphere_released_from_rest_converges_to_the_exact_history_solution_at_order_1_5_to_2() {
    let tau = exact().tau;
    let t_end = 2.0 * tau;
    let errors: Vec<f64> = [10.0, 20.0, 40.0, 80.0, 160.0].iter().map(|n| error(tau / n, t_end)).collect();
    let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    eprintln!("errors {errors:?}\norders {orders:?}");
    assert!(errors[4] < 1e-3, "{errors:?}");
    for p in &orders {
        assert!(*p > 1.4 && *p < 2.2, "observed orders {orders:?}");
    }
}

#[test]
fn history_slows_the_settling_against_the_same_bead_without_it() {
    // The memory resists every change of the slip: from rest, the bead without history is
    // ahead of the one with it at every time (the exact solution says so, and the engine too).
    let tau = exact().tau;
    let t = 3.0 * tau;
    let run = |effects: &str| {
        let mut sim = bead(tau / 40.0, t, effects).scene().simulation();
        sim.advance_to(t);
        -sim.world.particles.vel[0].z
    };
    let without = run("gravity = {}\nbuoyancy = {}\ndrag = { law = \"stokes\" }\nadded_mass = {}");
    let with = run(WITH_HISTORY);
    let reference = history_settling_velocity(t, &exact());
    assert!(with < 0.9 * without, "with {with} without {without}");
    assert!((with - reference).abs() < 1e-3 * reference, "{with} vs {reference}");
}

#[test]
fn memory_columns_exist_only_with_the_history_effect_three_numbers_per_stored_mode() {
    let plain = bead(1e-4, 1e-3, "gravity = {}\ndrag = {}").scene().simulation();
    let p = &plain.world.particles;
    assert!(p.memory.values().is_empty() && !p.memory.is_on());
    let scene = bead(1e-4, 1e-3, "gravity = {}\ndrag = {}\nhistory = {}").scene();
    // A loaded (or checked) scene holds no memory: it is allocated when the run starts.
    assert!(scene.particles.memory.values().is_empty() && !scene.particles.memory.is_on());
    let kernel = scene.setup.physics.history.as_ref().unwrap();
    // Δt = 1e-4 s: 11 of the 37 modes forget a step and are stored folded, as two numbers.
    let modes = kernel.stored_modes();
    assert_eq!((kernel.modes(), modes), (37, 28));
    let with = scene.simulation();
    let p = &with.world.particles;
    assert_eq!(p.memory.width(), 3 * modes);
    assert_eq!(p.memory.values().len(), 3 * modes * p.len());
}

/// A bead dropped onto the floor with history: it bounces, no contact gains energy, its memory
/// is empty just after each bounce and refills in flight.
#[test]
fn bouncing_with_history_gains_no_energy_and_starts_each_rebound_with_an_empty_memory() {
    let mut sim = BeadOnFloor::new()
        .dt(1e-4)
        .duration(0.3)
        .output_interval(0.3)
        .effects("gravity = {}\nbuoyancy = {}\ndrag = {}\nadded_mass = {}\nhistory = {}")
        .density(7800.0)
        .diameter(3e-3)
        .particle([0.0, 0.0, 0.02], [0.0, 0.0, 0.0])
        .scene()
        .simulation();
    let kernel = sim.setup.physics.history.clone().expect("the effect");
    let mut modes = vec![0.0; 3 * kernel.modes()];
    let mut bounces = 0;
    let mut steps_since_bounce = usize::MAX;
    while sim.world.time < 0.3 {
        sim.advance_to(sim.world.time + 1e-4);
        let events: Vec<_> = sim.record.events.drain(..).collect();
        for e in &events {
            assert!(e.energy_after <= e.energy_before * (1.0 + 1e-12), "{e:?}");
            bounces += usize::from(e.outcome == wetbounce::Outcome::Bounced);
        }
        // The modes one by one (m/s), from the memory as stored.
        kernel.expand(sim.world.particles.memory.values(), &mut modes);
        let size = modes.iter().map(|m| m.abs()).fold(0.0, f64::max);
        if !events.is_empty() {
            steps_since_bounce = 0;
            // One step after the contact at most: the memory holds only that part of a step.
            assert!(size < 0.5 * sim.world.particles.vel[0].length(), "{size}");
        } else {
            steps_since_bounce = steps_since_bounce.saturating_add(1);
        }
        if steps_since_bounce == 50 && sim.world.particles.state[0] == wetbounce::particles::State::Free {
            assert!(size > 0.0, "the memory refills in flight");
        }
    }
    assert!(bounces >= 1, "the steel bead bounces");
}

// ---- bad input ---------------------------------------------------------------------------

fn refused(text: &str) -> wetbounce::SceneError {
    match Scene::from_str(text, std::path::Path::new("scenes/history_test.toml")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

#[test]
fn history_window_shorter_than_dt_is_refused_naming_the_window() {
    let e = refused(&bead(1e-3, 0.01, "gravity = {}\ndrag = {}\nhistory = { window = 5e-4 }").toml());
    assert_eq!(e.key(), "effects.history.window", "{e}");
    assert!(e.to_string().contains("at least the time step"), "{e}");
}

#[test]
fn history_window_of_more_than_1e7_steps_is_refused_naming_the_window() {
    let e = refused(&bead(1e-6, 1e-5, "gravity = {}\ndrag = {}\nhistory = { window = 100.0 }").toml());
    assert_eq!(e.key(), "effects.history.window", "{e}");
    assert!(e.to_string().contains("at most 1e7 dt"), "{e}");
}

#[test]
fn unknown_history_key_is_refused_naming_it() {
    let e = refused(&bead(1e-4, 1e-3, "gravity = {}\ndrag = {}\nhistory = { windw = 1.0 }").toml());
    assert!(e.key().starts_with("effects.history"), "{e}");
    assert!(e.to_string().contains("windw"), "{e}");
}

#[test]
fn history_tolerance_out_of_range_and_negative_window_are_refused_naming_the_key() {
    let e = refused(&bead(1e-4, 1e-3, "gravity = {}\ndrag = {}\nhistory = { tolerance = 0.5 }").toml());
    assert_eq!(e.key(), "effects.history.tolerance", "{e}");
    let e = refused(&bead(1e-4, 1e-3, "gravity = {}\ndrag = {}\nhistory = { window = -1.0 }").toml());
    assert_eq!(e.key(), "effects.history.window", "{e}");
}

/// A smooth motion, with no start in it: the bead settles at its terminal slip across a
/// Poiseuille flow (it starts with the fluid's velocity plus that slip, so its acceleration is
/// continuous from the start), and the flow it meets changes as it crosses the streamlines.
/// With no exact solution, the order is measured from three successive halvings (Richardson).
#[test]
fn smooth_motion_with_history_converges_at_second_order() {
    let tau = exact().tau;
    let t_end = 5.0 * tau;
    let (radius, u_max, z0) = (1e-3, 0.05, 5e-4);
    let u0 = u_max * (1.0 - (z0 / radius) * (z0 / radius));
    let slip = exact().terminal_velocity();
    let state = |n: f64| {
        let mut sim = no_bead(tau / n, t_end, WITH_HISTORY)
            .flow(&format!(
                "{{ type = \"poiseuille\", point = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], radius = {radius:?}, max_velocity = {u_max:?} }}"
            ))
            .particles(&[([0.0, 0.0, z0].into(), [u0, 0.0, -slip].into())])
            .scene()
            .simulation();
        sim.advance_to(t_end);
        sim.world.particles.vel[0]
    };
    let v: Vec<_> = [10.0, 20.0, 40.0, 80.0].iter().map(|&n| state(n)).collect();
    let orders: Vec<f64> =
        (0..2).map(|i| ((v[i] - v[i + 1]).length() / (v[i + 1] - v[i + 2]).length()).log2()).collect();
    eprintln!(
        "orders {orders:?}, differences {:?}",
        (0..3).map(|i| (v[i] - v[i + 1]).length()).collect::<Vec<_>>()
    );
    for p in &orders {
        assert!((p - 2.0).abs() < 0.15, "observed orders {orders:?}");
    }
}
