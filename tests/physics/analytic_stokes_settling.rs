//! Every integrator, through the whole engine, against the closed-form Stokes settling
//! solution of docs/physics.md §1: from rest, `v(t) = V_t (1 − e^{−t/τ})`,
//! `τ = (ρp + C_M ρ) d² / (18 μ)`, in a uniform flow `u`: `v → u + V_t`.

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;

const D: f64 = 1e-3;
const RHO_P: f64 = 2540.0;
const RHO: f64 = 1000.0;
const MU: f64 = 0.01;
const T_END: f64 = 0.05;
const U: [f64; 3] = [0.02, 0.0, 0.0];

fn tau() -> f64 {
    (RHO_P + 0.5 * RHO) * D * D / (18.0 * MU)
}

fn exact(t: f64) -> (DVec3, DVec3) {
    let tau = tau();
    let vt = DVec3::new(0.0, 0.0, -(RHO_P - RHO) * 9.81 / (RHO_P + 0.5 * RHO)) * tau + DVec3::from(U);
    let decay = (-t / tau).exp();
    (vt * (t - tau * (1.0 - decay)), vt * (1.0 - decay))
}

/// Relative error of position and velocity at T_END, for an integrator and a step.
fn error(integrator: &str, dt: f64) -> f64 {
    let mut sim = BeadOnFloor::new()
        .dt(dt)
        .duration(T_END)
        .output_interval(T_END)
        .integrator(integrator)
        .fluid(RHO, MU)
        .flow(&format!("{{ type = \"uniform\", velocity = {U:?} }}"))
        .effects("gravity = {}\nbuoyancy = {}\ndrag = { law = \"stokes\" }\nadded_mass = {}")
        .density(RHO_P)
        .walls("")
        .diameter(D)
        .at([0.0; 3])
        .scene()
        .simulation();
    sim.advance_to(T_END);
    let (x, v) = exact(T_END);
    (sim.world.particles.pos[0] - x).length() / x.length()
        + (sim.world.particles.vel[0] - v).length() / v.length()
}

fn observed_order(integrator: &str, dt: f64) -> f64 {
    (error(integrator, dt) / error(integrator, dt / 2.0)).log2()
}

#[test]
fn euler_is_first_order_against_stokes_settling() {
    let p = observed_order("euler", 1e-3);
    assert!((p - 1.0).abs() < 0.1, "observed order {p}");
}

#[test]
fn rk2_is_second_order_against_stokes_settling() {
    let p = observed_order("rk2", 1e-3);
    assert!((p - 2.0).abs() < 0.1, "observed order {p}");
}

#[test]
fn rk4_is_fourth_order_against_stokes_settling() {
    let p = observed_order("rk4", 2e-3);
    assert!((p - 4.0).abs() < 0.2, "observed order {p}");
}

#[test]
fn exponential_is_exact_to_round_off_for_stokes_settling_at_any_step() {
    // τ ≈ 17 ms: from steps far below τ to a step of three τ.
    for dt in [1e-4, 1e-3, T_END] {
        let e = error("exponential", dt);
        assert!(e < 1e-12, "dt = {dt}: relative error {e}");
    }
}

#[test]
fn output_times_land_exactly_whatever_the_step() {
    // 0.05 s is not a multiple of 0.0007 s: the last step is shortened.
    let e = error("exponential", 7e-4);
    assert!(e < 1e-12, "relative error {e}");
}
