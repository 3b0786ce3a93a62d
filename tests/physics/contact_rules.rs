//! The bounce rule's cases (docs/physics.md §5) on simple geometries.

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;
use wetbounce::Outcome;
use wetbounce::particles::State;

/// A 2 mm glass bead (ε_max = 0.95) in a viscous liquid over the floor, at height `z0`, moving
/// at `velocity`.
fn bead(velocity: [f64; 3], z0: f64) -> BeadOnFloor {
    BeadOnFloor::new()
        .dt(1e-4)
        .output_interval(0.01)
        .fluid(1000.0, 1e-3)
        .restitution_max(0.95)
        .particle([0.0, 0.0, z0], velocity)
}

#[test]
fn slow_impact_below_st_c_deposits_and_the_bead_rests_without_drift() {
    // Starting 10 µm above the floor at rest: reaches ~1 cm/s, St ≈ 6.6 < 10.
    let mut sim = bead([0.0; 3], 1.01e-3).scene().simulation();
    let events = common::run_collect(&mut sim, 0.1);
    assert_eq!(events.len(), 1, "{events:#?}");
    assert_eq!(events[0].outcome, Outcome::Deposited);
    assert!(events[0].st < 10.0);
    let rest = sim.world.particles.pos[0];
    sim.advance_to(1.0);
    assert_eq!(sim.world.particles.state[0], State::Resting);
    assert!(
        (sim.world.particles.pos[0] - rest).length() < 1e-15,
        "drifted to {}",
        sim.world.particles.pos[0]
    );
    assert_eq!(sim.world.particles.vel[0], DVec3::ZERO);
}

#[test]
fn resting_bead_slides_with_the_flow_and_stays_on_the_floor() {
    let flow = r#"{ type = "uniform", velocity = [0.01, 0.0, 0.0] }"#;
    let mut sim = bead([0.01, 0.0, 0.0], 1.01e-3).flow(flow).scene().simulation();
    sim.advance_to(1.0);
    assert_eq!(sim.world.particles.state[0], State::Resting);
    let (x, v) = (sim.world.particles.pos[0], sim.world.particles.vel[0]);
    assert!((x.z - 1e-3).abs() < 1e-15, "z = {}", x.z);
    assert!((v.x - 0.01).abs() < 1e-6 && v.z == 0.0, "v = {v}");
}

#[test]
fn resting_bead_leaves_when_the_net_force_points_away() {
    // Gravity reversed after deposit: an upward flow pulls it off. Simulated with a strong
    // upward uniform flow: drag points away from the floor, so the bead leaves at once.
    let flow = r#"{ type = "uniform", velocity = [0.0, 0.0, 0.5] }"#;
    let mut sim = bead([0.0; 3], 1.0e-3).flow(flow).scene().simulation();
    sim.world.particles.state[0] = State::Resting;
    sim.world.particles.wall[0] = 0;
    sim.advance_to(0.01);
    assert_eq!(sim.world.particles.state[0], State::Free);
    assert!(sim.world.particles.pos[0].z > 1.0e-3);
}

#[test]
fn fast_impact_rebounds_with_eps_and_tangential_restitution() {
    // 0.5 m/s down and 0.2 m/s along x, starting just above the floor, e_t = 0.5.
    let mut sim = bead([0.2, 0.0, -0.5], 1.05e-3).bounce("tangential_restitution = 0.5").scene().simulation();
    let mut events = Vec::new();
    while events.is_empty() {
        sim.step(1e-5);
        events.append(&mut sim.record.events);
    }
    let e = events[0];
    assert_eq!(e.outcome, Outcome::Bounced);
    let expected_eps = 0.95 * (-35.0 / e.st).exp();
    assert!((e.eps - expected_eps).abs() < 1e-15);
    // Right after: v_z = ε V∞ (up to the drag and gravity of a fraction of a 10 µs step).
    let v = sim.world.particles.vel[0];
    assert!((v.z - e.eps * e.normal_speed).abs() < 1e-3 * e.normal_speed, "v = {v}, e = {e:?}");
    assert!((v.x - 0.5 * 0.2).abs() < 2e-3, "v = {v}");
}

#[test]
fn bead_inside_a_cylinder_grazing_at_89_degrees_stays_inside() {
    // In vacuum at 1 m/s, 89° from the wall normal: radial speed 1.75 cm/s, first impact at
    // 1.38 s, the next at 4.1 s.
    let column = "[[walls]]\nname = \"column\"\ntype = \"cylinder\"\nbase = [0.0, 0.0, -1.0]\nradius = 0.025\nlength = 10.0\n";
    let mut sim = BeadOnFloor::new()
        .output_interval(0.01)
        .vacuum()
        .gravity([0.0; 3])
        .effects("")
        .kind("steel")
        .density(7800.0)
        .elastic(2e11, 0.3)
        .walls(column)
        .particle([0.0; 3], [0.0174524, 0.0, 0.9998477])
        .scene()
        .simulation();
    let events = common::run_collect(&mut sim, 5.0);
    assert_eq!(events.len(), 2);
    for e in &events {
        assert_eq!(e.outcome, Outcome::Bounced);
    }
    let x = sim.world.particles.pos[0];
    assert!(x.truncate().length() <= 0.024 + 1e-12, "outside: {x}");
    // Vacuum, ε_max = 1: speed kept.
    assert!((sim.world.particles.vel[0].length() - 1.0).abs() < 1e-6);
}

/// Toluene drops rising to a lid and glass beads falling to a floor in one water column, with
/// `contact_time` given `effects` (issue 30, item 6).
fn mixed(contact_time: &str, dt: &str) -> Result<wetbounce::Scene, wetbounce::scene::SceneError> {
    let text = format!(
        r#"
[simulation]
dt = {dt}
duration = 0.6
output_interval = 0.01
[fluid]
density = 997.0
viscosity = 0.89e-3
[effects]
gravity = {{}}
buoyancy = {{}}
drag = {{}}
added_mass = {{}}
contact_time = {contact_time}
[[kinds]]
name = "toluene"
type = "drop"
density = 860.0
surface_tension = 0.026
restitution_max = 0.91
[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.23
restitution_max = 0.97
[[walls]]
name = "lid"
type = "plane"
point = [0.0, 0.0, 0.05]
normal = [0.0, 0.0, -1.0]
[[walls]]
name = "floor"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[particles]]
kind = "toluene"
diameter = 2.75e-3
position = [0.0, 0.0, 0.0225]
[[particles]]
kind = "glass"
diameter = 3e-3
position = [0.01, 0.0, 0.0275]
"#
    );
    wetbounce::Scene::from_str(&text, std::path::Path::new("mixed.toml"))
}

#[test]
fn contact_time_naming_the_drops_holds_them_and_lets_the_beads_rebound_at_once() {
    let scene = mixed(r#"{ kinds = ["toluene"] }"#, "1e-4").unwrap();
    let mut sim = scene.simulation();
    let events = common::run_collect(&mut sim, scene.duration);
    let of = |id: u32| events.iter().filter(move |e| e.id == id && e.st >= 10.0).collect::<Vec<_>>();
    let (drop, bead) = (of(0), of(1));
    assert!(!drop.is_empty() && !bead.is_empty(), "{events:#?}");
    assert!(drop.iter().all(|e| e.outcome == Outcome::Held), "{drop:#?}");
    assert!(bead.iter().all(|e| e.outcome == Outcome::Bounced), "{bead:#?}");
    // Every kind held when none is named: the bead is held for its Hertz time too.
    let scene = mixed("{}", "1e-4").unwrap();
    let mut sim = scene.simulation();
    let events = common::run_collect(&mut sim, scene.duration);
    assert!(events.iter().filter(|e| e.id == 1 && e.st >= 10.0).all(|e| e.outcome == Outcome::Held));
}

#[test]
fn auto_step_takes_a_contact_time_only_from_the_kinds_held() {
    let all = mixed("{}", "\"auto\"").unwrap();
    let drops = mixed(r#"{ kinds = ["toluene"] }"#, "\"auto\"").unwrap();
    let (a, d) = (all.auto_step.as_ref().unwrap(), drops.auto_step.as_ref().unwrap());
    // Holding the beads bound Δt to their microsecond Hertz time.
    assert!(a.limited_by.contains("contact time") && a.limited_by.contains("glass"), "{}", a.limited_by);
    assert!(a.dt < 1e-5, "{}", a.dt);
    assert!(!d.limited_by.contains("glass d") || !d.limited_by.contains("contact time"), "{}", d.limited_by);
    assert!(d.dt > 10.0 * a.dt, "{} against {}", d.dt, a.dt);
}

#[test]
fn contact_time_naming_an_unknown_kind_is_refused_naming_the_entry() {
    let e = mixed(r#"{ kinds = ["toluene", "water"] }"#, "1e-4").unwrap_err();
    assert_eq!(e.key(), "effects.contact_time.kinds[1]", "{e}");
    assert!(e.to_string().contains("unknown kind \"water\"") && e.to_string().contains("glass"), "{e}");
    let e = mixed("{ kinds = [] }", "1e-4").unwrap_err();
    assert_eq!(e.key(), "effects.contact_time.kinds", "{e}");
}

#[test]
fn check_warns_when_an_automatic_step_below_10_us_comes_from_a_contact_time() {
    let dir = tempfile::tempdir().unwrap();
    let text = |contact_time: &str| mixed(contact_time, "\"auto\"").unwrap().source;
    let check = |name: &str, source: String| {
        let path = dir.path().join(name);
        std::fs::write(&path, source).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_wetbounce"))
            .arg("check")
            .arg(&path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let all = check("all.toml", text("{}"));
    assert!(all.contains("warning: dt = ") && all.contains("contact_time = { kinds = [..] }"), "{all}");
    let drops = check("drops.toml", text(r#"{ kinds = ["toluene"] }"#));
    assert!(!drops.contains("warning: dt = "), "{drops}");
}
