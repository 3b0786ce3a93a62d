//! Stability cases 7 and 8 (docs/stability.md): property-based tests over random particle
//! kinds (solid or drop), sizes, densities (bubble-like to tungsten), speeds and directions,
//! fluids (vacuum to glycerol), gravity directions, wall shapes and orientations (plane, box
//! container, thin box plate, cylinder, mesh plate, flat or conical annulus), integrators and
//! time steps. Every case must load (or be refused for an explicit step above the stability
//! limit, with an error naming `simulation.dt`), and then, after every step: every state
//! finite and none taken out, no particle inside a wall, no contact that gains kinetic energy.
//!
//! CI runs 512 cases; the long run (docs/stability.md) is
//! `WETBOUNCE_CASES=1000000 cargo test --release --test stability stability_properties -- --ignored`.

use crate::common;
use glam::DVec3;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError};

#[derive(Debug, Clone)]
struct Case {
    fluid: usize,
    drag: bool,
    added_mass: bool,
    contact_time: bool,
    solid: bool,
    density: f64,
    eps_max: f64,
    diameter: f64,
    count: usize,
    speed: f64,
    angles: [f64; 2],
    wall: usize,
    normal: [f64; 2],
    size: f64,
    thickness: f64,
    integrator: usize,
    dt: f64,
    gap: f64,
    gravity: [f64; 2],
    inner: f64,
    cone: f64,
}

/// (density, viscosity): vacuum, air, water, glycerol.
const FLUIDS: [(f64, f64); 4] = [(0.0, 0.0), (1.204, 1.825e-5), (998.2, 1.0e-3), (1260.0, 1.0)];
const INTEGRATORS: [&str; 4] = ["euler", "rk2", "rk4", "exponential"];
const WALLS: [&str; 6] = ["plane", "box", "plate", "cylinder", "mesh", "annulus"];
/// Steps per case: enough for several contacts, since the particles start close to a wall.
const STEPS: usize = 60;

fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..hi.log10()).prop_map(|e| 10f64.powf(e))
}

fn unit(a: [f64; 2]) -> DVec3 {
    // a[0] = cos(polar angle) uniform in [-1, 1], a[1] azimuth: uniform on the sphere.
    let s = (1.0 - a[0] * a[0]).max(0.0).sqrt();
    DVec3::new(s * a[1].cos(), s * a[1].sin(), a[0])
}

fn angles() -> impl Strategy<Value = [f64; 2]> {
    (-1.0f64..=1.0, 0.0f64..std::f64::consts::TAU).prop_map(|(a, b)| [a, b])
}

fn case() -> impl Strategy<Value = Case> {
    (
        (0..4usize, any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>()),
        (log_uniform(1.0, 2e4), 0.0f64..=1.0, log_uniform(1e-5, 1e-2), 1..4usize, log_uniform(1e-4, 30.0)),
        (angles(), 0..WALLS.len(), angles(), 2.0f64..12.0, log_uniform(0.01, 2.0)),
        (0..4usize, log_uniform(1e-6, 1e-1), 0.0f64..1.0, angles(), 0.0f64..0.8, -1.0f64..=0.0),
    )
        .prop_map(|(a, b, c, d)| Case {
            fluid: a.0,
            drag: a.1,
            added_mass: a.2,
            contact_time: a.3,
            solid: a.4,
            density: b.0,
            eps_max: b.1,
            diameter: b.2,
            count: b.3,
            speed: b.4,
            angles: c.0,
            wall: c.1,
            normal: c.2,
            size: c.3,
            thickness: c.4,
            integrator: d.0,
            dt: d.1,
            gap: d.2,
            gravity: d.3,
            inner: d.4,
            cone: d.5,
        })
}

fn v3(v: DVec3) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

/// The scene of a case, with `integrator`.
fn scene_text(c: &Case, integrator: &str) -> String {
    let (rho, mu) = FLUIDS[c.fluid];
    let d = c.diameter;
    let r = 0.5 * d;
    let mut effects = String::from("gravity = {}\nbuoyancy = {}\n");
    if c.drag && mu > 0.0 {
        effects += "drag = {}\n";
    }
    if c.added_mass {
        effects += "added_mass = {}\n";
    }
    if c.contact_time {
        effects += "contact_time = {}\n";
    }
    let kind = if c.solid {
        format!(
            "type = \"solid\"\nyoungs_modulus = 6e10\npoisson_ratio = 0.2\nrestitution_max = {}",
            c.eps_max
        )
    } else {
        format!("type = \"drop\"\nsurface_tension = 0.03\nrestitution_max = {}", c.eps_max)
    };
    let g = 9.81 * unit(c.gravity);
    let n = unit(c.normal);
    let (t1, t2) = (n.any_orthonormal_vector(), n.cross(n.any_orthonormal_vector()));
    // The wall's extent (m) and where the particles start: close to the wall (a gap of up to
    // the distance they would fly in a tenth of the case), side by side 1.5 d apart.
    let extent = c.size * d;
    let gap = c.gap * (0.1 * STEPS as f64 * c.dt * c.speed).min(extent);
    let along = |k: usize| (k as f64 - 0.5 * (c.count as f64 - 1.0)) * 1.5 * d;
    let (wall, starts): (String, Vec<DVec3>) = match WALLS[c.wall] {
        "plane" => (
            format!("type = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = {}", v3(n)),
            (0..c.count).map(|k| n * (r + gap) + t1 * along(k)).collect(),
        ),
        "box" => {
            // A container just big enough for the particles in a row along x.
            let half = DVec3::new(extent.max(0.75 * d * c.count as f64 + r), extent, extent);
            let half = half + DVec3::splat(r);
            (
                format!("type = \"box\"\nmin = {}\nmax = {}\ninside = true", v3(-half), v3(half)),
                (0..c.count).map(|k| DVec3::X * along(k)).collect(),
            )
        }
        "plate" => {
            let w = extent.max(2.0 * d * c.count as f64);
            let t = c.thickness * d;
            (
                format!(
                    "type = \"box\"\nmin = {}\nmax = {}\ninside = false",
                    v3(DVec3::new(-w, -w, -t)),
                    v3(DVec3::new(w, w, 0.0))
                ),
                (0..c.count).map(|k| DVec3::Z * (r + gap) + DVec3::X * along(k)).collect(),
            )
        }
        "cylinder" => {
            let radius = extent.max(0.75 * d * c.count as f64 + r) + r;
            (
                format!(
                    "type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\naxis = {}\nradius = {:e}",
                    v3(n),
                    radius
                ),
                (0..c.count).map(|k| t1 * along(k)).collect(),
            )
        }
        "mesh" => {
            // The 40 × 40 × 1 mm plate (top face at z = 0) scaled to `thickness` d thick.
            let scale = c.thickness * d / 1e-3;
            (
                format!("type = \"mesh\"\nfile = \"meshes/plate_binary.stl\"\nscale = {scale:e}"),
                // Drawn together over a small plate, but not closer than 1.05 d: particles may
                // not start overlapping one another (the row used to shrink with the plate).
                (0..c.count)
                    .map(|k| DVec3::Z * (r + gap) + DVec3::X * along(k) * scale.clamp(0.7, 1.0))
                    .collect(),
            )
        }
        _ => {
            // A ring (or a disc) of zero thickness, its cone (if any) on the far side.
            let outer = extent.max(1.0 * d * c.count as f64);
            (
                format!(
                    "type = \"annulus\"\ncenter = [0.0, 0.0, 0.0]\nnormal = {}\ninner_radius = {:e}\nouter_radius = {:e}\ncone_height = {:e}\nsegments = 24",
                    v3(n),
                    c.inner * outer,
                    outer,
                    c.cone * outer
                ),
                (0..c.count).map(|k| n * (r + gap) + t2 * along(k)).collect(),
            )
        }
    };
    // Mostly towards the wall (or a container's side), at any angle.
    let toward = match WALLS[c.wall] {
        "box" | "cylinder" => t1,
        "plate" | "mesh" => -DVec3::Z,
        _ => -n,
    };
    let dir = unit(c.angles);
    let dir = if dir.dot(toward) > 0.0 { dir } else { dir - 1.5 * dir.dot(toward) * toward };
    let vel = c.speed * dir.normalize();
    let mut text = format!(
        r#"
[simulation]
dt = {dt:e}
duration = {duration:e}
output_interval = {duration:e}
integrator = "{integrator}"

[fluid]
density = {rho:e}
viscosity = {mu:e}
gravity = {g}

[effects]
{effects}
[[kinds]]
name = "k"
density = {density:e}
{kind}

[[walls]]
name = "w"
{wall}
"#,
        dt = c.dt,
        duration = c.dt * STEPS as f64,
        g = v3(g),
        density = c.density,
    );
    for x in starts {
        text += &format!(
            "\n[[particles]]\nkind = \"k\"\ndiameter = {d:e}\nposition = {}\nvelocity = {}\n",
            v3(x),
            v3(vel)
        );
    }
    text
}

/// Runs one case; `Err` with the reason when a property fails.
fn check(c: &Case) -> Result<(), TestCaseError> {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/property.toml"));
    let integrator = INTEGRATORS[c.integrator];
    let text = scene_text(c, integrator);
    let scene = match wetbounce::Scene::from_str(&text, path) {
        Ok(s) => s,
        Err(e) if integrator != "exponential" && e.key() == "simulation.dt" => {
            // Refused as too stiff for the explicit scheme: the error says so; run the case with
            // the exponential scheme instead.
            prop_assert!(e.to_string().contains("exponential"), "{e}");
            wetbounce::Scene::from_str(&scene_text(c, "exponential"), path)
                .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?
        }
        Err(e) => return Err(TestCaseError::fail(format!("{e}\n{text}"))),
    };
    let mut sim = scene.simulation();
    for _ in 0..STEPS {
        let t = sim.world.time + sim.setup.dt;
        sim.advance_to(t);
        prop_assert!(
            sim.record.lost.is_empty(),
            "non-finite state at t = {}: {:?}\n{text}",
            sim.world.time,
            sim.record.lost
        );
        let p = &sim.world.particles;
        for i in 0..p.len() {
            prop_assert!(p.pos[i].is_finite() && p.vel[i].is_finite());
        }
        let (g, i, _) = common::deepest_overlap(&sim);
        prop_assert!(
            g >= -1e-9,
            "t = {}: particle {i} inside the wall by {:.3e} radii at {:?}\n{text}",
            sim.world.time,
            -g,
            sim.world.particles.pos[i]
        );
        for e in sim.record.events.drain(..) {
            prop_assert!(e.energy_not_gained(), "energy gained at {e:?}\n{text}");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(Config { cases: 512, failure_persistence: None, ..Config::default() })]

    #[test]
    fn random_particles_walls_and_steps_stay_finite_outside_walls_without_energy_gain(c in case()) {
        check(&c)?;
    }
}

/// The long run: `WETBOUNCE_CASES` cases (default 10⁶), reported in docs/stability.md.
#[test]
#[ignore]
fn long_run_of_random_cases() {
    let cases: u32 = std::env::var("WETBOUNCE_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(1_000_000);
    let start = std::time::Instant::now();
    let mut runner = proptest::test_runner::TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let result = runner.run(&case(), |c| check(&c));
    println!("{cases} cases in {:.1} s: {result:?}", start.elapsed().as_secs_f64());
    result.unwrap();
}

/// Cases the long run found, kept as scenes (`tests/scenes/regress_*.toml`) and checked the
/// same way (with the exponential integrator when the scene's step is refused).
#[test]
fn regressions_found_by_the_long_run_stay_finite_and_outside_the_walls() {
    for name in
        ["regress_pair_with_held.toml", "regress_bead_in_ring_hole.toml", "regress_rk4_near_limit.toml"]
    {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes").join(name);
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = wetbounce::Scene::from_str(&text, &path)
            .or_else(|e| {
                assert_eq!(e.key(), "simulation.dt", "{e}");
                let text = ["\"euler\"", "\"rk2\"", "\"rk4\""]
                    .iter()
                    .fold(text.clone(), |t, name| t.replace(name, "\"exponential\""));
                wetbounce::Scene::from_str(&text, &path)
            })
            .unwrap_or_else(|e| panic!("{e}"));
        let mut sim = scene.simulation();
        for _ in 0..STEPS {
            let t = sim.world.time + sim.setup.dt;
            common::run_collect(&mut sim, t);
            assert!(sim.record.lost.is_empty(), "{name}: {:?}", sim.record.lost);
            common::assert_clear_of_walls(&sim);
        }
    }
}
