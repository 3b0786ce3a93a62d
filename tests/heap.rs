//! A heap poured from a narrow injector onto a floor stands at an angle of repose that grows
//! with friction (issue 16; the angle as `wetbounce::heap::angle_of_repose` measures it,
//! docs/physics.md, "Heaps"). CI-sized: 250 beads, the pour of scenes/heap.toml made smaller.

mod common;
use wetbounce::heap::angle_of_repose;

/// 250 glass beads poured in water onto a rough floor (μ = μ_r = 1), with Coulomb friction `mu`
/// (and rolling resistance 0.05); the pile's angle of repose (degrees) at the end, with its height (m).
fn heap(mu: f64) -> (f64, f64) {
    let text = format!(
        r#"
[simulation]
dt = 2e-4
duration = 1.6
output_interval = 0.02
integrator = "rk2"
[fluid]
density = 998.2
viscosity = 1.002e-3
gravity = [0.0, 0.0, -9.81]
[effects]
gravity = {{}}
buoyancy = {{}}
drag = {{ law = "schiller_naumann" }}
added_mass = {{}}
[[kinds]]
name = "glass"
type = "solid"
density = 2540.0
youngs_modulus = 63e9
poisson_ratio = 0.22
restitution_max = 0.97
friction = {mu}
tangential_restitution = 0.35
rolling_friction = 0.05
[[walls]]
name = "box"
type = "box"
min = [0.0, 0.0, 0.0]
max = [0.06, 0.06, 0.06]
inside = true
material = {{ friction = 1.0, rolling_friction = 1.0 }}
[[injectors]]
kind = "glass"
rate = 250.0
region = {{ type = "disk", center = [0.03, 0.03, 0.025], normal = [0.0, 0.0, 1.0], radius = 4e-3 }}
diameter = {{ distribution = "fixed", value = 2.5e-3 }}
velocity = [0.0, 0.0, -0.3]
seed = 16
stop = 1.0
"#
    );
    let scene = common::scene(&text);
    let mut sim = scene.simulation();
    sim.advance_to(scene.duration);
    let p = &sim.world.particles;
    assert!(sim.record.lost.is_empty());
    assert!(p.len() > 200, "only {} beads poured", p.len());
    let a = angle_of_repose(&p.pos, &p.diameter).expect("a pile with a flank");
    eprintln!(
        "μ = {mu}: {} beads, angle of repose {:.1}°, height {:.2} mm, {} bins",
        p.len(),
        a.degrees,
        1e3 * a.height,
        a.bins
    );
    (a.degrees, a.height)
}

#[test]
fn a_heap_with_more_friction_stands_steeper() {
    // The two pours on two threads (each result is the same whatever the thread count).
    let (l, h) = std::thread::scope(|s| {
        let l = s.spawn(|| heap(0.2));
        let h = s.spawn(|| heap(0.5));
        (l.join().unwrap(), h.join().unwrap())
    });
    let ((low, h_low), (high, h_high)) = (l, h);
    // Measured (release build): 15.4° and 6.6 mm with μ = 0.2, 17.8° and 7.7 mm with μ = 0.5.
    assert!(low > 5.0, "μ = 0.2 made no pile: {low:.1}°");
    assert!(high > low + 1.0, "μ = 0.5: {high:.1}°, μ = 0.2: {low:.1}°");
    assert!(h_high > h_low, "the steeper pile is the taller: {h_high} m, {h_low} m");
}
