//! Poiseuille carrier flow: drag acts on the slip velocity `v − u(x)` (docs/physics.md §1).

use crate::common;

use wetbounce::correlations::terminal_velocity;

/// A toluene drop rising in water that flows down a pipe with a Poiseuille profile reaches
/// `v = u(ρ) + V_t` at every distance ρ from the axis: its slip is the terminal velocity in
/// still water. The profile's gradient is across the motion, so nothing pushes the drop
/// sideways and it keeps its ρ.
#[test]
fn terminal_slip_in_poiseuille_flow_is_the_still_fluid_terminal_velocity() {
    let (u_max, radius, d) = (-0.05, 0.02, 2.5e-3);
    let scene = common::scene(&format!(
        r#"
[simulation]
dt = 1e-3
duration = 2.0
output_interval = 0.1

[fluid]
density = 997.0
viscosity = 0.89e-3
flow = {{ type = "poiseuille", point = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], radius = {radius}, max_velocity = {u_max} }}

[effects]
gravity = {{}}
buoyancy = {{}}
drag = {{ law = "schiller_naumann" }}
added_mass = {{}}

[[kinds]]
name = "toluene"
type = "drop"
density = 860.0
surface_tension = 0.026
restitution_max = 0.91

[[particles]]
kind = "toluene"
diameter = {d}
position = [0.0, 0.0, 0.0]

[[particles]]
kind = "toluene"
diameter = {d}
position = [0.01, 0.0, 0.0]

[[particles]]
kind = "toluene"
diameter = {d}
position = [0.0, 0.03, 0.0]
"#
    ));
    let mut sim = scene.simulation();
    // Many relaxation times (t_r ≈ 76 ms).
    sim.advance_to(2.0);
    let vt = terminal_velocity(860.0, 997.0, d, 0.89e-3, 9.81, |re| 1.0 + 0.15 * re.powf(0.687)).speed;
    for (i, rho) in [(0, 0.0), (1, 0.01), (2, 0.03)] {
        let u = if rho < radius { u_max * (1.0 - (rho / radius) * (rho / radius)) } else { 0.0 };
        let v = sim.world.particles.vel[i];
        assert!((v.z - (u + vt)).abs() < 1e-6 * vt, "particle {i}: v = {v}, u = {u}, V_t = {vt}");
        assert!(v.x.abs() < 1e-12 && v.y.abs() < 1e-12, "particle {i} drifts sideways: {v}");
    }
}

/// `mean_velocity` is half the centre-line velocity.
#[test]
fn mean_velocity_gives_twice_that_on_the_axis() {
    let scene = common::scene(
        r#"
[simulation]
dt = 1e-3
duration = 1.0
output_interval = 0.1

[fluid]
density = 997.0
viscosity = 0.89e-3
flow = { type = "poiseuille", point = [1.0, 2.0, 0.0], radius = 0.02, mean_velocity = 0.01 }

[[kinds]]
name = "toluene"
type = "drop"
density = 860.0
surface_tension = 0.026
restitution_max = 0.91
"#,
    );
    let u = scene.setup.fluid.flow.velocity(glam::DVec3::new(1.0, 2.0, 5.0), 0.0);
    assert_eq!(u, glam::DVec3::new(0.0, 0.0, 0.02));
}
