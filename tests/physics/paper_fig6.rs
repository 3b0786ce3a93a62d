//! L06 Fig. 6: the 2.75 mm toluene drop rising to a wall in water at 25 °C, through the
//! engine with the shipped scene `scenes/toluene_drop.toml`.

use crate::common;
use wetbounce::Outcome;
use wetbounce::correlations::{drag_factor_schiller_naumann, drop_contact_time, terminal_velocity};
use wetbounce::particles::State;

fn events_with_dt(dt: f64) -> Vec<wetbounce::ContactEvent> {
    let mut sim = common::shipped_with("toluene_drop.toml", "dt", &format!("{dt:e}")).simulation();
    common::run_collect(&mut sim, 1.0)
}

#[test]
fn first_impact_has_st_38_eps_from_eq2_and_eq5_contact_time() {
    let events = events_with_dt(1e-4);
    let first = events[0];
    // St = 38 (L06 Fig. 6), tolerance 3 %.
    assert!((first.st - 38.0).abs() / 38.0 < 0.03, "St = {}", first.st);
    // V∞ is the terminal velocity: released 27.5 mm away, ~4 t_r of travel. Tolerance 0.5 %.
    let vt = terminal_velocity(860.0, 997.0, 2.75e-3, 0.89e-3, 9.81, drag_factor_schiller_naumann).speed;
    assert!((first.normal_speed - vt).abs() / vt < 5e-3, "V∞ = {} vs V_t = {vt}", first.normal_speed);
    // ε = ε_max exp(−35/St), ε_max = 0.91: exactly the correlation.
    assert!((first.eps - 0.91 * (-35.0 / first.st).exp()).abs() < 1e-15);
    // t_c from eq. 5, independent of the speed.
    assert_eq!(first.contact_time, drop_contact_time(860.0, 997.0, 2.75e-3, 0.026));
    assert_eq!(first.outcome, Outcome::Held);
}

#[test]
fn first_impact_loses_80_to_90_percent_of_kinetic_energy() {
    // L06 §4: 80–90 % of the kinetic energy is lost in the first impact.
    let first = events_with_dt(1e-4)[0];
    let lost = 1.0 - first.eps * first.eps;
    assert!((0.80..=0.90).contains(&lost), "lost {lost}");
}

#[test]
fn drop_is_held_at_the_wall_for_the_contact_time() {
    let scene = common::shipped_with("toluene_drop.toml", "dt", "1e-4");
    let mut sim = scene.simulation();
    let first = common::run_collect(&mut sim, 0.5)[0];
    let mut sim = scene.simulation();
    sim.advance_to(first.time + 0.5 * first.contact_time);
    assert_eq!(sim.world.particles.state[0], State::Held);
    assert_eq!(sim.world.particles.vel[0].length(), 0.0);
    let held_at = sim.world.particles.pos[0];
    sim.advance_to(first.time + 0.999 * first.contact_time);
    assert_eq!(sim.world.particles.pos[0], held_at);
    sim.advance_to(first.time + 1.001 * first.contact_time);
    assert_eq!(sim.world.particles.state[0], State::Free);
    // Released away from the wall (downwards) at ε V∞.
    assert!(sim.world.particles.vel[0].z < 0.0);
}

#[test]
fn second_impact_with_eps_max_0_91_st_c_10_in_water_at_25c_is_held_again() {
    // docs/physics.md §6: whether the drop bounces a second time depends on ε_max, St_c and the
    // fluid. With ε_max = 0.91, St_c = 10, water at 25 °C: the second impact comes at
    // St ≈ 12.5 > St_c, so it is held again, then the third is below St_c.
    let events = events_with_dt(1e-4);
    assert!(events.len() >= 3, "{events:?}");
    assert_eq!(events[1].outcome, Outcome::Held);
    assert!(events[1].st > 10.0 && events[1].st < 15.0, "St2 = {}", events[1].st);
    assert_eq!(events[2].outcome, Outcome::Deposited);
    assert!(events[2].st < 10.0);
}

#[test]
fn impact_times_converge_at_second_order_as_dt_shrinks() {
    // Reference: the same run at dt = 1e-5 s. RK2 and the impact located inside the step:
    // the error of the first two impact times falls ~4× per halving of dt.
    let reference = events_with_dt(1e-5);
    let errors: Vec<(f64, f64)> = [4e-3, 2e-3, 1e-3, 5e-4]
        .iter()
        .map(|&dt| {
            let e = events_with_dt(dt);
            ((e[0].time - reference[0].time).abs(), (e[1].time - reference[1].time).abs())
        })
        .collect();
    for w in errors.windows(2) {
        for (coarse, fine) in [(w[0].0, w[1].0), (w[0].1, w[1].1)] {
            let order = (coarse / fine).log2();
            assert!(order > 1.7, "errors {errors:?}: order {order}");
        }
    }
    assert!(errors[3].0 < 1e-5 && errors[3].1 < 1e-5, "{errors:?}");
}
