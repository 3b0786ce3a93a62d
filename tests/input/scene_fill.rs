//! Initial particles: a random fill keeps clear of the walls it overlaps.

use crate::common;
use wetbounce::walls::Surface;

#[test]
fn random_fill_wider_than_its_column_places_every_bead_inside_the_column() {
    let scene = common::scene(
        r#"
[simulation]
dt = 1e-3
duration = 0.1
output_interval = 0.1
[fluid]
density = 997.0
viscosity = 0.89e-3
[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.23
[[walls]]
name = "column"
type = "cylinder"
base = [0.0, 0.0, 0.0]
radius = 0.01
length = 0.1
[[random_fill]]
kind = "glass"
diameter = 2e-3
min = [-0.01, -0.01, 0.01]
max = [0.01, 0.01, 0.05]
count = 300
seed = 11
"#,
    );
    assert_eq!(scene.particles.len(), 300);
    for x in &scene.particles.pos {
        assert!(scene.setup.walls[0].shape.gap(*x, 1e-3).gap >= 0.0, "bead at {x} overlaps the column");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// The memory and output estimate counts the initial particles from the file without
    /// placing them (issue 25, point 11): for any lattice, explicit particles and random fill
    /// it counts exactly the particles the loader places, and its memory is that count times
    /// the bytes per particle.
    #[test]
    fn the_estimates_particle_count_is_the_number_the_loader_places(
        lo in proptest::array::uniform3(-0.02..0.0f64),
        size in proptest::array::uniform3(1e-4..0.02f64),
        spacing in 2e-3..6e-3f64,
        singles in 0usize..4,
        fill in 0u32..20,
        frames in 1u32..50,
    ) {
        let hi = [lo[0] + size[0], lo[1] + size[1], lo[2] + size[2]];
        let mut text = format!(
            "[simulation]\ndt = 1e-3\nduration = 0.1\noutput_interval = {}\n[fluid]\ndensity = 997.0\n\
             viscosity = 0.89e-3\n[[kinds]]\nname = \"glass\"\ntype = \"solid\"\ndensity = 2500.0\n\
             youngs_modulus = 6e10\npoisson_ratio = 0.23\n[[lattice]]\nkind = \"glass\"\ndiameter = 1e-3\n\
             min = {lo:?}\nmax = {hi:?}\nspacing = {spacing:e}\n",
            0.1 / frames as f64
        );
        for i in 0..singles {
            text += &format!("[[particles]]\nkind = \"glass\"\ndiameter = 1e-3\nposition = [0.5, 0.5, {}]\n", 0.01 * i as f64);
        }
        if fill > 0 {
            text += &format!("[[random_fill]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [1.0, 1.0, 1.0]\n\
                              max = [1.05, 1.05, 1.05]\ncount = {fill}\nseed = 5\n");
        }
        let scene = common::scene(&text);
        let e = &scene.estimate;
        proptest::prop_assert_eq!(e.initial_particles, scene.particles.len() as f64);
        proptest::prop_assert_eq!(e.max_particles, scene.particles.len() as f64);
        proptest::prop_assert_eq!(e.memory_bytes(), e.max_particles * e.bytes_per_particle);
        proptest::prop_assert_eq!(e.particle_frames, e.frames * scene.particles.len() as f64);
    }
}
