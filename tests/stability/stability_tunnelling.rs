//! Stability case 3 (docs/stability.md): tunnelling. A bead at 10 m/s with Δt = 10 ms moves 50
//! diameters per step; against a plate thinner than its diameter — a box, a triangle mesh, and
//! a zero-thickness mesh disc — it never passes through. Then 10⁵ random fast impacts (1 to
//! 100 m/s, up to 80° from the normal) on the three thin walls: zero crossings.

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wetbounce::Other;

const D: f64 = 2e-3;
const R: f64 = 0.5 * D;

/// Thin walls with their top face at z = 0: a 0.2 d box plate, the 40 × 40 × 1 mm mesh plate
/// scaled to 0.2 d thick (16 × 16 mm), a zero-thickness disc of radius 0.3 m.
const WALLS: [(&str, &str, f64); 3] = [
    ("box", "type = \"box\"\nmin = [-0.3, -0.3, -4e-4]\nmax = [0.3, 0.3, 0.0]\ninside = false", 0.3),
    ("mesh", "type = \"mesh\"\nfile = \"meshes/plate_binary.stl\"\nscale = 0.4", 0.008),
    (
        "disc",
        "type = \"annulus\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nouter_radius = 0.3\nsegments = 64",
        0.3,
    ),
];

/// A 2 mm bead (ν = 0.22) in water, with no drag, starting 15 cm above the plate `wall` at
/// `velocity`.
fn scene(wall: &str, dt: f64, velocity: DVec3) -> wetbounce::Scene {
    BeadOnFloor::new()
        .poisson_ratio(0.22)
        .dt(dt)
        .effects("gravity = {}\nbuoyancy = {}\nadded_mass = {}")
        .walls(&format!("[[walls]]\nname = \"plate\"\n{wall}\n"))
        .particle([0.0, 0.0, 0.15], velocity)
        .scene()
}

#[test]
fn bead_at_10_m_s_with_10_ms_steps_never_passes_through_a_plate_thinner_than_itself() {
    for (name, wall, _) in WALLS {
        for angle in [0.0f64, 30.0, 60.0] {
            let a = angle.to_radians();
            let v = 10.0 * DVec3::new(a.sin() * 0.01, 0.0, -a.cos());
            let mut sim = scene(wall, 1e-2, v).simulation();
            let events = common::run_collect(&mut sim, 0.1);
            assert!(
                sim.world.particles.pos[0].z >= R * (1.0 - 1e-9),
                "{name}, {angle}°: passed through, z = {}",
                sim.world.particles.pos[0].z
            );
            assert!(events.iter().any(|e| e.other == Other::Wall(0)), "{name}, {angle}°: no impact");
        }
    }
}

#[test]
fn hundred_thousand_random_fast_impacts_on_thin_walls_give_zero_crossings() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let per_wall = 34_000;
    let (mut impacts, mut crossings) = (0usize, 0usize);
    for (name, wall, half) in WALLS {
        let mut sim = scene(wall, 1e-2, DVec3::ZERO).simulation();
        sim.setup.pair_collisions = false;
        let p = &mut sim.world.particles;
        *p = Default::default();
        for id in 0..per_wall {
            let speed = 10f64.powf(rng.random_range(0.0..2.0));
            let polar = rng.random_range(0.0f64..80.0).to_radians();
            let azimuth = rng.random_range(0.0..std::f64::consts::TAU);
            let dir = DVec3::new(polar.sin() * azimuth.cos(), polar.sin() * azimuth.sin(), -polar.cos());
            let v = speed * dir;
            // Start within one step of the plate, above a point that the straight move meets
            // on the plate.
            let s = rng.random_range(0.05..1.0) * 1e-2;
            // (In the disc inscribed in the plate, so that every move meets the plate.)
            let (rho, phi) =
                (0.8 * half * rng.random::<f64>().sqrt(), rng.random_range(0.0..std::f64::consts::TAU));
            let target = DVec3::new(rho * phi.cos(), rho * phi.sin(), R);
            p.push(id as u32, 0, D, target - v * s, v);
        }
        let above: Vec<bool> = (0..p.len()).map(|i| p.pos[i].z >= R).collect();
        assert!(above.iter().all(|&a| a), "{name}: every bead starts above the plate");
        let events = common::run_collect(&mut sim, 0.05);
        let hits = events.iter().filter(|e| e.other == Other::Wall(0)).count();
        let crossed = (0..sim.world.particles.len())
            .filter(|&i| sim.world.particles.pos[i].z < R * (1.0 - 1e-9))
            .count();
        assert!(sim.record.lost.is_empty(), "{name}: {:?}", sim.record.lost);
        assert_eq!(sim.world.particles.len(), per_wall);
        assert!(hits >= per_wall, "{name}: {hits} impacts for {per_wall} beads");
        impacts += hits;
        crossings += crossed;
    }
    println!("{impacts} impacts, {crossings} crossings");
    assert!(impacts >= 100_000, "{impacts} impacts");
    assert_eq!(crossings, 0, "{crossings} crossings in {impacts} impacts");
}
