//! Dense contacts stay sound: 200 glass beads poured into a small box of water never overlap
//! by more than 1 % of a diameter, never go below the floor or through a wall, and none is lost.
//! (The 2000-bead `scenes/settling_bed.toml` is the full-size case; it takes about a minute.)

mod common;
use std::path::Path;
use wetbounce::Scene;

#[test]
fn poured_beads_never_overlap_more_than_one_percent_or_leave_the_box() {
    let scene =
        Scene::load(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/pour_200.toml")).unwrap();
    let mut sim = scene.simulation();
    let d = 2.5e-3;
    let mut pair_events = 0;
    while sim.time < scene.duration {
        let t = (sim.time + 0.02).min(scene.duration);
        pair_events += common::run_collect(&mut sim, t)
            .iter()
            .filter(|e| matches!(e.other, wetbounce::Other::Particle(_)))
            .count();
        let p = &sim.particles;
        for i in 0..p.len() {
            let x = p.pos[i];
            assert!(
                x.z >= 0.5 * d * (1.0 - 1e-12),
                "t = {}: bead {i} below the floor: z = {}",
                sim.time,
                x.z
            );
            assert!(
                x.x >= 0.5 * d * (1.0 - 1e-12) && x.x <= 0.015 - 0.5 * d * (1.0 - 1e-12),
                "bead {i} x = {}",
                x.x
            );
            for j in i + 1..p.len() {
                let overlap = d - (p.pos[j] - x).length();
                assert!(
                    overlap < 0.01 * d,
                    "t = {}: beads {i}, {j} overlap by {:.2e} d",
                    sim.time,
                    overlap / d
                );
            }
        }
    }
    assert!(sim.lost.is_empty());
    assert_eq!(sim.particles.len(), 200);
    assert!(pair_events > 100, "{pair_events} pair contacts");
}
