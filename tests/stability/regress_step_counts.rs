//! Issue 13, finding 2: steps were silently skipped when `dt` is much larger than
//! `output_interval` (`dt = 1e4`, `duration = 0.01`, `output_interval = 1e-3` took no step at
//! all; `dt = 1e-4` with `output_interval = 1e-10` took 71 of 100). A remainder shorter than
//! `1e-6 Δt` was taken for round-off, so a whole output interval shorter than that was dropped.
//! The class test runs free fall over output intervals and time steps whose ratio spans 24
//! orders of magnitude: every interval is at least one step, and the fall is exact.

use crate::common;
use common::fixture::BeadOnFloor;
use std::sync::atomic::AtomicBool;
use wetbounce::run::run;

const G: f64 = 9.81;

fn free_fall(dt: f64, duration: f64, interval: f64) -> wetbounce::Simulation {
    BeadOnFloor::new()
        .dt(dt)
        .duration(duration)
        .output_interval(interval)
        .integrator("rk2")
        .vacuum()
        .gravity([0.0, 0.0, -G])
        .effects("gravity = {}")
        .kind("steel")
        .density(7800.0)
        .elastic(2e11, 0.3)
        .walls("")
        .diameter(1e-3)
        .at([0.0, 0.0, 0.0])
        .scene()
        .simulation()
}

/// Runs free fall for `duration` with frames every `interval`; returns the steps taken and the
/// fall's error (m).
fn fall(dt: f64, duration: f64, interval: f64) -> (u64, f64) {
    let mut sim = free_fall(dt, duration, interval);
    let report = run(&mut sim, duration, interval, &mut [], &AtomicBool::new(false)).unwrap();
    assert_eq!(report.time, duration);
    let z = sim.world.particles.pos[0].z;
    (report.steps, (z + 0.5 * G * duration * duration).abs())
}

#[test]
fn a_step_far_longer_than_the_output_interval_still_steps_every_interval() {
    for dt in [1e4, 1000.0, 1.0] {
        let (steps, error) = fall(dt, 0.01, 1e-3);
        assert_eq!(steps, 10, "dt = {dt}");
        assert!(error < 1e-15, "dt = {dt}: fall off by {error} m");
    }
}

#[test]
fn output_intervals_far_below_the_step_each_take_one_step() {
    let (steps, error) = fall(1e-4, 1e-8, 1e-10);
    assert_eq!(steps, 100);
    assert!(error < 1e-25, "fall off by {error} m");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, ..Default::default() })]

    /// Class test: any ratio of Δt to the output interval, from 1e-12 to 1e12.
    #[test]
    fn every_output_interval_takes_at_least_one_step_and_the_fall_is_exact(
        log_interval in -10.0f64..0.0,
        log_ratio in -12.0f64..12.0,
        frames in 1u32..40,
    ) {
        let interval = 10f64.powf(log_interval);
        let dt = interval * 10f64.powf(log_ratio);
        let duration = interval * f64::from(frames);
        // Keep the test short (at most ~10⁴ steps), and Δt within the scene's range (1e-12 to 1e9 s).
        proptest::prop_assume!(duration / dt < 1e4 && (1e-12..=1e9).contains(&dt));
        let (steps, error) = fall(dt, duration, interval);
        proptest::prop_assert!(steps >= u64::from(frames), "{} steps for {} frames", steps, frames);
        // RK2 is exact for a constant acceleration: only round-off is left.
        proptest::prop_assert!(error <= 1e-12 * 0.5 * G * duration * duration + 1e-300, "fall off by {}", error);
    }
}
