//! Stability case 5 (docs/stability.md): inelastic collapse. A bead bouncing on a floor with
//! ε → 0 comes to rest after a finite number of contacts — in water (St falls below St_c) and
//! in vacuum, where St = ∞ and the rebounds shrink geometrically (the Zeno sequence ends when
//! the rebound speed rounds to zero); and a bead resting on a floor (a plane, a box, a mesh)
//! for 10⁶ steps drifts less than 1e-9 m.

use crate::common;
use common::fixture::BeadOnFloor;
use wetbounce::particles::State;

const D: f64 = 2e-3;

/// A 2 mm bead (ν = 0.22, ε_max = `eps_max`) at rest at height `z0` over `floor` (the body of a
/// `[[walls]]` table), falling in `fluid` (with drag and added mass when it is viscous).
fn bead_on(fluid: (f64, f64), eps_max: f64, dt: f64, floor: &str, z0: f64) -> wetbounce::Scene {
    let effects = if fluid.1 > 0.0 { "drag = {}\nadded_mass = {}\n" } else { "" };
    BeadOnFloor::new()
        .kind("bead")
        .poisson_ratio(0.22)
        .restitution_max(eps_max)
        .fluid(fluid.0, fluid.1)
        .effects(&format!("gravity = {{}}\nbuoyancy = {{}}\n{effects}"))
        .dt(dt)
        .walls(&format!("[[walls]]\nname = \"floor\"\n{floor}\n"))
        .at([0.001, 0.002, z0])
        .scene()
}

const PLANE: &str = "type = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]";
const BOX: &str = "type = \"box\"\nmin = [-0.05, -0.05, 0.0]\nmax = [0.05, 0.05, 0.1]\ninside = true";
const MESH: &str = "type = \"mesh\"\nfile = \"meshes/plate_binary.stl\"";

#[test]
fn bead_with_vanishing_restitution_comes_to_rest_after_finitely_many_contacts() {
    for (fluid, name) in [((998.2, 1.0e-3), "water"), ((0.0, 0.0), "vacuum")] {
        for eps_max in [0.5, 0.1, 1e-3, 1e-9, 0.0] {
            for dt in [1e-4, 1e-2] {
                let mut sim = bead_on(fluid, eps_max, dt, PLANE, 0.02).simulation();
                let events = common::run_collect(&mut sim, 1.0);
                let what = format!("{name}, ε_max {eps_max}, dt {dt}");
                common::assert_clear_of_walls(&sim);
                assert_eq!(sim.world.particles.state[0], State::Resting, "{what}: {events:?}");
                assert!(
                    (sim.world.particles.pos[0].z - 0.5 * D).abs() < 1e-15,
                    "{what}: z = {}",
                    sim.world.particles.pos[0].z
                );
                assert!(
                    sim.world.particles.vel[0].length() < 1e-12,
                    "{what}: v = {:?}",
                    sim.world.particles.vel[0]
                );
                // The last contact is the deposit, and no contact after it: finitely many.
                assert!(events.len() <= 80, "{what}: {} contacts", events.len());
                assert_eq!(events.last().map(|e| e.outcome), Some(wetbounce::Outcome::Deposited), "{what}");
            }
        }
    }
}

#[test]
fn bead_resting_on_a_plane_box_or_mesh_floor_for_a_million_steps_drifts_less_than_1e_9_m() {
    // 10⁶ steps on the plane; 2·10⁵ on the box and the mesh, to keep CI short.
    for (floor, name, steps) in [(PLANE, "plane", 1_000_000), (BOX, "box", 200_000), (MESH, "mesh", 200_000)]
    {
        let start = std::time::Instant::now();
        let mut sim = bead_on((998.2, 1.0e-3), 0.97, 1e-4, floor, 0.5 * D).simulation();
        // One step to settle (it starts touching, at rest: a contact at V∞ = 0, deposited).
        sim.advance_to(sim.setup.dt);
        assert_eq!(sim.world.particles.state[0], State::Resting, "{name}");
        let x0 = sim.world.particles.pos[0];
        for _ in 1..steps {
            sim.step(sim.setup.dt);
        }
        let drift = (sim.world.particles.pos[0] - x0).length();
        println!("{name}: {steps} steps in {:.1} s, drift {drift:.3e} m", start.elapsed().as_secs_f64());
        assert!(drift < 1e-9, "{name}: drifted {drift:.3e} m in {steps} steps");
        assert_eq!(sim.world.particles.state[0], State::Resting, "{name}");
        common::assert_clear_of_walls(&sim);
    }
}
