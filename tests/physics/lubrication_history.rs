//! Wall lubrication and the history force together (docs/physics.md §8, §10): the lubricated
//! sub-steps near a wall carry the memory. Each effect keeps its own reference where the other
//! is known exactly or negligible, and no contact gains energy with both.

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;
use wetbounce::correlations::{
    HistorySettling, history_settling_velocity, oneill_parallel_exact, wall_factor_parallel,
};

/// The glass bead of `history.rs` (0.1 mm in water, κ = 1.22, a strong memory), with a
/// roughness far below its radius.
const D: f64 = 1e-4;
const RHO_P: f64 = 2500.0;
const RHO: f64 = 998.2;
const MU: f64 = 1.0e-3;
const H_R: f64 = 1e-9;

/// A vertical wall, the plane x = 0 facing +x.
const SIDE_WALL: &str =
    "[[walls]]\nname = \"side\"\ntype = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n";

const BOTH: &str = "gravity = {}\nbuoyancy = {}\ndrag = { law = \"stokes\" }\nadded_mass = {}\n\
                    wall_lubrication = {}\nhistory = { window = 2.0, tolerance = 1e-9 }";

/// The bead released from rest at lubrication gap `gap` radii from [`SIDE_WALL`], settling
/// beside it: the velocity along the wall at `t_end` with a step `dt`, and the largest drift
/// of its gap (m).
fn beside_the_wall(gap: f64, dt: f64, t_end: f64) -> (f64, f64) {
    let a = 0.5 * D;
    let x0 = a + gap * a - H_R;
    let mut sim = BeadOnFloor::new()
        .dt(dt)
        .duration(t_end)
        .output_interval(t_end)
        .fluid(RHO, MU)
        .effects(BOTH)
        .density(RHO_P)
        .roughness(H_R)
        .walls(SIDE_WALL)
        .diameter(D)
        .particle([x0, 0.0, 0.0], [0.0; 3])
        .scene()
        .simulation();
    let events = common::run_collect(&mut sim, t_end);
    assert!(events.is_empty(), "the bead touched the wall: {events:?}");
    let p = &sim.world.particles;
    (-p.vel[0].z, (p.pos[0].x - x0).abs())
}

/// Moving along a plane wall at a fixed gap, the Stokes drag is `λ∥` times the free one
/// (O'Neill 1964) and the flow is still unsteady Stokes flow, so the exact solution with
/// history (`correlations::HistorySettling`, by Laplace transform) holds with `τ / λ∥` for
/// `τ`: the lubrication's factor and the memory meet in one reference. At half a radius from
/// the wall `λ∥ = 1.60`. The flight converges to it at about the order the history scheme reaches
/// from a start at rest (1.5, docs/physics.md §10.1; 1.65 falling to 1.53 here), and the bead
/// keeps its gap.
#[test]
fn bead_settling_beside_a_wall_with_history_follows_the_exact_solution_with_drag_raised_by_lambda_parallel() {
    let gap = 0.5;
    let free = HistorySettling::sphere(RHO_P, RHO, MU, 0.5 * D, 9.81);
    // The engine's fast form of λ∥, 2.6e-5 from O'Neill's exact series at most: with the exact
    // value the errors below would stop falling at about 2e-6.
    let lambda = wall_factor_parallel(gap);
    assert!((lambda / oneill_parallel_exact(gap) - 1.0).abs() < 3e-5);
    let exact = HistorySettling { tau: free.tau / lambda, ..free };
    let t_end = 2.0 * exact.tau;
    let runs: Vec<(f64, f64)> =
        [10.0, 20.0, 40.0, 80.0, 160.0].iter().map(|n| beside_the_wall(gap, exact.tau / n, t_end)).collect();
    let reference = history_settling_velocity(t_end, &exact);
    let errors: Vec<f64> = runs.iter().map(|(v, _)| (v - reference).abs() / reference).collect();
    let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    eprintln!("λ∥ = {lambda}; errors {errors:?}\norders {orders:?}");
    // Without the wall's factor the answer would be 20 % off; without the memory, more.
    let no_wall = history_settling_velocity(t_end, &free);
    assert!((no_wall - reference).abs() > 0.1 * reference);
    assert!(errors[4] < 1e-3, "{errors:?}");
    for p in &orders {
        assert!(*p > 1.4 && *p < 2.2, "observed orders {orders:?}");
    }
    for (_, drift) in &runs {
        assert!(*drift < 1e-9 * D, "the gap drifted by {drift} m");
    }
}

/// The quasi-steady Stokes approach of `wall_lubrication.rs` with the history effect named:
/// a steel bead in an oil a hundred times more viscous than that test's, so the approach is
/// slow (a minute, against a relaxation time of 19 µs) and the memory's force, about
/// `κ √(τ/T)` of the drag with `T = a / V_t`, about 1e-3 of it: the contact time stays that of
/// `∫ λ⊥ dh / V_t` within the lubrication test's tolerance (5e-3; measured 2.3e-4 at
/// `dt` = 0.05, 0.005 and 0.0005 s alike, so the memory's own effect and not the step's).
#[test]
fn stokes_approach_with_negligible_history_keeps_the_integral_of_lambda_perp() {
    let (err, speed_err) = crate::wall_lubrication::stokes_approach(
        (2e-3, 8000.0, 1000.0, 100.0),
        "history = { window = 200.0, tolerance = 1e-4 }",
        // With history every free flight is the history scheme, stable at any step; the
        // integrator named only sets the scene's check of `dt`.
        ("exponential", 0.05),
        200.0,
    );
    assert!(err < 5e-3, "contact time: relative error {err:.2e}");
    assert!(speed_err < 1e-2, "impact speed: relative error {speed_err:.2e}");
}

/// A steel bead dropped onto a plate through silicone oil with both effects, the shipped
/// scene: it bounces at the roughness, every contact loses energy, and it comes to rest.
#[test]
fn steel_bead_in_oil_with_lubrication_and_history_bounces_and_no_contact_gains_energy() {
    let scene = wetbounce::Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/steel_bead_oil_lubrication_history.toml"
    ));
    let scene = scene.expect("the shipped scene loads");
    let duration = scene.duration;
    let mut sim = scene.simulation();
    let events = common::run_collect(&mut sim, duration);
    let bounces = events.iter().filter(|e| e.outcome == wetbounce::Outcome::Bounced).count();
    assert!(bounces >= 2, "{events:?}");
    for e in &events {
        assert!(e.energy_after <= e.energy_before, "{e:?}");
    }
    assert_ne!(sim.world.particles.state[0], wetbounce::particles::State::Free, "it comes to rest");
}

/// Free beads with memory fly by lane groups of four (`Kernel::remembered_lanes`) when they come
/// several at once, and one at a time when alone; a lane within the film's reach of a wall goes
/// alone to the sub-steps. 21 beads from 0.3 to 30 radii from the side wall (the film reaches
/// ten), at several velocities, with both effects and with the history force alone, end where
/// each ends alone in the same scene, to the last bit, and so does each one's memory.
#[test]
fn free_beads_with_memory_flown_by_lane_groups_end_where_each_ends_alone() {
    let a = 0.5 * D;
    let starts: Vec<(DVec3, DVec3)> = (0..21)
        .map(|i| {
            let x = DVec3::new(a + a * (0.3 + 1.5 * i as f64), 0.0, 30.0 * a * i as f64);
            let v = DVec3::new([-2e-3, 0.0, 1e-3, -5e-4][i % 4], 1e-4, -1e-3 * (i % 3) as f64);
            (x, v)
        })
        .collect();
    let history_only = "gravity = {}\nbuoyancy = {}\ndrag = {}\nadded_mass = {}\nhistory = {}";
    for effects in [BOTH, history_only] {
        let run = |starts: &[(DVec3, DVec3)]| {
            let bead = BeadOnFloor::new()
                .dt(1e-5)
                .duration(1e-3)
                .output_interval(1e-3)
                .fluid(RHO, MU)
                .effects(effects)
                .density(RHO_P)
                .walls(SIDE_WALL)
                .diameter(D)
                .particles(starts);
            // The roughness is the film's: a scene without it refuses the key.
            let bead = if effects == BOTH { bead.roughness(H_R) } else { bead };
            let mut sim = bead.scene().simulation();
            let events = common::run_collect(&mut sim, 1e-3);
            assert!(events.is_empty(), "{effects}: no bead touches the wall: {events:?}");
            let p = &sim.world.particles;
            let width = p.memory.width();
            let memory = |i: usize| p.memory.values()[i * width..(i + 1) * width].to_vec();
            (0..p.len()).map(|i| (p.id[i], p.pos[i], p.vel[i], memory(i))).collect::<Vec<_>>()
        };
        let together = run(&starts);
        assert_eq!(together.len(), starts.len());
        for (i, start) in starts.iter().enumerate() {
            let alone = run(std::slice::from_ref(start)).remove(0);
            let t = together.iter().find(|t| t.0 as usize == i).expect("every bead kept");
            assert_eq!((t.1, t.2), (alone.1, alone.2), "{effects}: bead {i}, from {start:?}");
            assert!(
                t.3.iter().zip(&alone.3).all(|(x, y)| x.to_bits() == y.to_bits()),
                "{effects}: bead {i}'s memory"
            );
        }
    }
}
