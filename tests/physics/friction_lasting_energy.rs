//! No lasting contact adds energy (issue 16): in vacuum, with no force at all, beads resting on
//! a floor and on each other, thrown about with any velocities and spins, only lose kinetic
//! energy, translational plus rotational, to the lasting-contact solver's normal, friction and
//! rolling rows (walls and pairs, warm-started from step to step). Impacts are covered by
//! `no_impact_adds_energy` in tests/physics/friction_impacts.rs.

use crate::common;
use glam::DVec3;
use proptest::prelude::*;
use wetbounce::contact::LastingContact;
use wetbounce::particles::State;

const D: f64 = 2e-3;
const RHO: f64 = 7800.0;

/// Three steel beads in a row on a floor, touching, and a fourth on the first two; friction
/// `mu` and rolling friction `mu_r`; no fluid, no gravity.
fn pile(mu: f64, mu_r: f64) -> wetbounce::Simulation {
    let r = 0.5 * D;
    let text = format!(
        r#"
[simulation]
dt = 1e-4
duration = 0.01
output_interval = 0.01
[fluid]
density = 0.0
viscosity = 0.0
[effects]
[[kinds]]
name = "steel"
type = "solid"
density = {RHO}
youngs_modulus = 2e11
poisson_ratio = 0.3
restitution_max = 0.8
friction = {mu}
tangential_restitution = 0.0
rolling_friction = {mu_r}
[[walls]]
name = "floor"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[particles]]
kind = "steel"
diameter = {D}
position = [0.0, 0.0, {r}]
[[particles]]
kind = "steel"
diameter = {D}
position = [{D}, 0.0, {r}]
[[particles]]
kind = "steel"
diameter = {D}
position = [{d2}, 0.0, {r}]
[[particles]]
kind = "steel"
diameter = {D}
position = [{r}, 0.0, {top}]
"#,
        d2 = 2.0 * D,
        top = r + 3f64.sqrt() * r
    );
    let mut sim = common::scene(&text).simulation();
    let p = &mut sim.world.particles;
    for i in 0..3 {
        (p.state[i], p.wall[i]) = (State::Resting, 0);
    }
    sim.world.lasting = [(0, 1), (1, 2), (0, 3), (1, 3)].map(|(a, b)| LastingContact::resting(a, b)).to_vec();
    sim
}

/// Kinetic energy, translational and rotational (J).
fn energy(sim: &wetbounce::Simulation) -> f64 {
    let p = &sim.world.particles;
    let m = RHO * std::f64::consts::PI * D.powi(3) / 6.0;
    let i = 0.1 * m * D * D;
    (0..p.len()).map(|k| 0.5 * m * p.vel[k].length_squared() + 0.5 * i * p.spin(k).length_squared()).sum()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn no_lasting_contact_adds_energy(
        v in prop::collection::vec(prop::array::uniform3(-0.05..0.05f64), 4),
        w in prop::collection::vec(prop::array::uniform3(-100.0..100.0f64), 4),
        (mu, mu_r) in (0.0..1.5f64, 0.0..0.5f64),
    ) {
        let mut sim = pile(mu, mu_r);
        let p = &mut sim.world.particles;
        for k in 0..4 {
            let mut vk = DVec3::from_array(v[k]);
            if k < 3 {
                vk.z = 0.0; // resting on the floor: sliding along it
            }
            (p.vel[k], p.omega.values_mut()[k]) = (vk, DVec3::from_array(w[k]));
        }
        let mut before = energy(&sim);
        for step in 0..20 {
            sim.step(1e-4);
            let after = energy(&sim);
            prop_assert!(sim.record.lost.is_empty());
            prop_assert!(
                after <= before * (1.0 + 1e-9) + 1e-18,
                "step {step}: {before:e} J -> {after:e} J"
            );
            before = after;
        }
    }
}
