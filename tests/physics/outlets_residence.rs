//! Outlets: residence times are measured from birth, and a wall outlet removes what touches it.

use crate::common;
use common::fixture::BeadOnFloor;

/// Beads in vacuum (no forces) injected moving up at 1 m/s from a thin disk at z = 0, leaving
/// through a plane at z = 0.1: each one's residence time is 0.1 s to within a step.
#[test]
fn plane_outlet_residence_time_is_the_flight_time_from_birth() {
    let scene = common::scene(
        r#"
[simulation]
dt = 1e-3
duration = 0.5
output_interval = 0.1

[fluid]
density = 0.0
viscosity = 0.0

[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.23

[[injectors]]
kind = "glass"
rate = 100.0
region = { type = "disk", center = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0], radius = 0.05 }
diameter = { distribution = "uniform", min = 1e-3, max = 2e-3 }
velocity = [0.0, 0.0, 1.0]
seed = 3
stop = 0.3

[[outlets]]
type = "plane"
point = [0.0, 0.0, 0.1]
normal = [0.0, 0.0, -1.0]
"#,
    );
    let mut sim = scene.simulation();
    sim.advance_to(0.5);
    assert_eq!(sim.setup.outlets[0].name, "outlets[0]");
    let removed = &sim.record.removed[0];
    assert_eq!(removed.len(), 30, "every bead injected in 0.3 s at 100/s leaves");
    assert!(sim.world.particles.is_empty());
    for r in removed {
        // Born at the end of a step on the disk, crossing z = 0.1 inside a later step.
        assert!(r.residence_time > 0.1 - 1e-9 && r.residence_time <= 0.1 + 1e-3 + 1e-9, "{r:?}");
    }
}

/// A bead falling on a floor that is an outlet is taken out at the end of the step in which it
/// touches it, instead of staying on it; its impact is still an event.
#[test]
fn wall_outlet_removes_the_particle_that_touches_it() {
    let lid =
        "[[walls]]\nname = \"lid\"\ntype = \"plane\"\npoint = [0.0, 0.0, 0.1]\nnormal = [0.0, 0.0, -1.0]\n";
    let scene = BeadOnFloor::new()
        .duration(0.5)
        .output_interval(0.1)
        .fluid(997.0, 0.89e-3)
        .effects("gravity = {}\nbuoyancy = {}\ndrag = {}")
        .wall(lid)
        .at([0.0, 0.0, 0.02])
        .particle([0.01, 0.0, 0.09], [0.0, 0.0, 0.5])
        .extra("[[outlets]]\nname = \"drain\"\ntype = \"wall\"\nwall = \"floor\"")
        .scene();
    let mut sim = scene.simulation();
    let mut floor_events = 0;
    // Bead 0 reaches the floor at about 0.08 s; bead 1, after the lid, only after 0.3 s.
    while sim.world.time < 0.2 - 1e-9 {
        sim.advance_to(sim.world.time + sim.setup.dt);
        floor_events += sim.record.events.iter().filter(|e| e.other == wetbounce::Other::Wall(0)).count();
        sim.record.events.clear();
    }
    assert_eq!(
        sim.record.removed[0].iter().map(|r| r.id).collect::<Vec<_>>(),
        vec![0],
        "only the bead on the floor"
    );
    assert_eq!(floor_events, 1);
    // The other bead bounced on the lid (not an outlet) and falls; it has not reached the floor.
    assert_eq!(sim.world.particles.id, vec![1]);
}
