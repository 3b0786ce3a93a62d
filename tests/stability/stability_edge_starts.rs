//! Stability case 6 (docs/stability.md): edge starts. A particle starting exactly touching a
//! wall at rest (plane, box, cylinder, mesh; pushed into it by gravity, or pulled away); two
//! particles starting exactly in contact; an impact with St exactly at St_c (it rebounds:
//! `St < St_c` is the no-rebound rule); an impact with V∞ = 0 (sliding along the wall), in a
//! viscous fluid and in vacuum (St = 0/0, taken as 0). Every state stays finite, no particle
//! goes into a wall, no contact gains energy, and each ends as the bounce rule says.

use crate::common;
use common::fixture::{BeadOnFloor, FALLING, FLOOR};
use glam::DVec3;
use wetbounce::correlations::stokes_number;
use wetbounce::particles::State;
use wetbounce::{Other, Outcome};

const D: f64 = 2e-3;
const R: f64 = 0.5 * D;

const WATER: (f64, f64) = (998.2, 1.0e-3);
const VACUUM: (f64, f64) = (0.0, 0.0);

/// A 2 mm bead (ν = 0.22) falling in water onto the floor.
fn bead() -> BeadOnFloor {
    BeadOnFloor::new().kind("bead").poisson_ratio(0.22)
}

fn run(scene: &wetbounce::Scene, t_end: f64) -> (wetbounce::Simulation, Vec<wetbounce::ContactEvent>) {
    let mut sim = scene.simulation();
    let mut events = Vec::new();
    while sim.world.time < t_end {
        let t = (sim.world.time + 0.01).min(t_end);
        events.extend(common::run_collect(&mut sim, t));
        common::assert_clear_of_walls(&sim);
        assert!(sim.record.lost.is_empty(), "{:?}", sim.record.lost);
    }
    (sim, events)
}

#[test]
fn bead_starting_exactly_on_a_wall_at_rest_deposits_at_once_or_leaves_it() {
    // Touching the floor of each shape at gap 0 exactly, at rest.
    let floors = [
        (FLOOR.to_string(), DVec3::new(0.0, 0.0, R)),
        ("[[walls]]\nname = \"floor\"\ntype = \"box\"\nmin = [-0.01, -0.01, 0.0]\nmax = [0.01, 0.01, 0.02]\ninside = true\n".into(), DVec3::new(0.0, 0.0, R)),
        ("[[walls]]\nname = \"floor\"\ntype = \"mesh\"\nfile = \"meshes/plate_binary.stl\"\n".into(), DVec3::new(0.001, 0.002, R)),
        // The inside of a horizontal pipe: resting at its bottom.
        ("[[walls]]\nname = \"floor\"\ntype = \"cylinder\"\nbase = [-0.05, 0.0, 0.005]\naxis = [1.0, 0.0, 0.0]\nradius = 0.005\n".into(), DVec3::new(0.0, 0.0, R)),
    ];
    for (walls, x) in &floors {
        // Pushed into the wall: one contact at V∞ = 0 (St = 0), then it rests where it started.
        let (sim, events) = run(&bead().walls(walls).at(*x).scene(), 0.2);
        assert_eq!(events.len(), 1, "{walls}: {events:?}");
        assert_eq!((events[0].normal_speed, events[0].st, events[0].outcome), (0.0, 0.0, Outcome::Deposited));
        assert_eq!(sim.world.particles.state[0], State::Resting);
        assert!(
            (sim.world.particles.pos[0] - *x).length() < 1e-15,
            "{walls}: moved to {:?}",
            sim.world.particles.pos[0]
        );
        // Pulled away (a bead lighter than the fluid: ρp < ρ in a denser fluid): no contact.
        let light = bead().fluid(5000.0, 1.0e-3).walls(walls).at(*x).scene();
        let (sim, events) = run(&light, 0.05);
        assert!(events.is_empty(), "{walls}: {events:?}");
        assert!(sim.world.particles.pos[0].z > x.z, "{walls}: it should rise");
    }
}

#[test]
fn two_beads_starting_exactly_in_contact_stay_finite_without_overlap_or_energy_gain() {
    // Side by side on the floor, stacked on the floor, and in mid-water touching and
    // approaching each other.
    let cases: [Vec<(DVec3, DVec3)>; 3] = [
        vec![(DVec3::new(0.0, 0.0, R), DVec3::ZERO), (DVec3::new(D, 0.0, R), DVec3::ZERO)],
        vec![(DVec3::new(0.0, 0.0, R), DVec3::ZERO), (DVec3::new(0.0, 0.0, R + D), DVec3::ZERO)],
        vec![
            (DVec3::new(0.0, 0.0, 0.01), DVec3::new(0.05, 0.0, 0.0)),
            (DVec3::new(D, 0.0, 0.01), DVec3::new(-0.05, 0.0, 0.0)),
        ],
    ];
    for particles in &cases {
        let (sim, _) = run(&bead().particles(particles).scene(), 0.3);
        let p = &sim.world.particles;
        assert_eq!(p.len(), 2);
        let gap = (p.pos[1] - p.pos[0]).length() - D;
        assert!(gap > -0.01 * D, "{particles:?}: they overlap by {:.3e} d", -gap / D);
        assert!(p.pos.iter().chain(&p.vel).all(|v| v.is_finite()));
    }
}

#[test]
fn impact_with_st_exactly_at_st_c_rebounds_and_just_below_deposits() {
    // No forces: the bead meets the floor at exactly the speed it starts with.
    let v = 0.015;
    let st = stokes_number(2500.0, WATER.0, v, D, WATER.1);
    assert!((st - 10.0).abs() < 0.1, "St = {st}");
    for (st_c, outcome) in [(st, Outcome::Bounced), (st.next_up(), Outcome::Deposited)] {
        let bounce = format!("st_critical = {st_c:?}");
        let scene = bead().effects("").bounce(&bounce).particle([0.0, 0.0, 0.003], [0.0, 0.0, -v]).scene();
        let (_, events) = run(&scene, 0.3);
        let first = events.first().expect("an impact");
        assert_eq!(first.other, Other::Wall(0));
        assert_eq!(first.st, st, "St at contact is computed from V∞ exactly");
        assert_eq!(first.outcome, outcome, "St_c = {st_c:?}: {first:?}");
    }
}

#[test]
fn contact_with_zero_normal_speed_deposits_with_st_0_in_water_and_in_vacuum() {
    // Touching the floor and sliding along it (V∞ = 0), with gravity holding it there.
    for fluid in [WATER, VACUUM] {
        let effects = if fluid.1 > 0.0 { FALLING } else { "gravity = {}" };
        let scene =
            bead().fluid(fluid.0, fluid.1).effects(effects).particle([0.0, 0.0, R], [0.1, 0.0, 0.0]).scene();
        let (sim, events) = run(&scene, 0.1);
        let first = events.first().expect("a contact");
        assert_eq!((first.normal_speed, first.st, first.eps), (0.0, 0.0, 0.0), "{first:?}");
        assert_eq!(first.outcome, Outcome::Deposited);
        assert_eq!(sim.world.particles.state[0], State::Resting);
        assert_eq!(sim.world.particles.pos[0].z, R);
        assert!(sim.world.particles.vel[0].x > 0.0, "it slides on: {:?}", sim.world.particles.vel[0]);
    }
}
