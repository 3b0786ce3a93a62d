//! Initial particles: a random fill keeps clear of the walls it overlaps.

mod common;
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
