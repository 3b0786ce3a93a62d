//! Regression tests for the scene-loading and CLI faults found by the adversarial run of
//! issue 13 (docs/stability.md, "Adversarial findings (issue 13)"): one test per finding, each
//! failing before its fix. The classes of fault are searched for by the property tests of
//! `tests/stability/stability_fuzz_input.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;
use wetbounce::{Scene, SceneError};

/// A valid scene: a 2 mm glass bead above a floor in water. `extra` is appended (more tables).
fn base(extra: &str) -> String {
    format!(
        r#"
[simulation]
dt = 1e-4
duration = 0.01
output_interval = 1e-3

[fluid]
density = 997.0
viscosity = 0.89e-3

[effects]
gravity = {{}}
buoyancy = {{}}
drag = {{}}

[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.23

[[walls]]
name = "floor"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
{extra}
"#
    )
}

fn path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/adversarial.toml")
}

fn load(text: &str) -> Result<Scene, SceneError> {
    Scene::from_str(text, &path())
}

/// The error of a scene that must be refused; panics if it loads.
fn refused(text: &str) -> SceneError {
    match load(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// Asserts the error is about `key` and its message contains every one of `parts`.
fn assert_error(e: &SceneError, key: &str, parts: &[&str]) {
    assert_eq!(e.key(), key, "{e}");
    for p in parts {
        assert!(e.to_string().contains(p), "lacks {p:?}: {e}");
    }
}

fn wetbounce() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_wetbounce"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

// ---- 6. vectors longer than three -------------------------------------------------------

#[test]
fn vector_with_four_components_is_refused_naming_the_key() {
    let text = base("").replace("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 1.0, 5.0]");
    let e = refused(&text);
    assert_error(&e, "walls[0].normal", &["must be 3 numbers [x, y, z], got 4 values"]);
}

#[test]
fn position_with_six_mixed_values_is_refused_naming_the_key() {
    let e = refused(&base(
        "[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, 0.0, 1.0, 99.0, \"x\", true]\n",
    ));
    assert_error(&e, "particles[0].position", &["must be 3 numbers [x, y, z], got 6 values"]);
}

#[test]
fn four_component_gravity_is_refused_naming_the_key() {
    let text =
        base("").replace("viscosity = 0.89e-3", "viscosity = 0.89e-3\ngravity = [0.0, 0.0, -9.81, 1.0]");
    assert_error(&refused(&text), "fluid.gravity", &["got 4 values"]);
}

#[test]
fn vector_with_a_string_component_is_refused_naming_the_key_and_the_component() {
    let e =
        refused(&base("[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, \"x\", 1.0]\n"));
    assert_error(&e, "particles[0].position", &["must be 3 numbers [x, y, z]", "component 1 is a string"]);
}

// ---- 7. huge values ---------------------------------------------------------------------

#[test]
fn outlet_normal_of_1e200_is_normalised_and_removes_what_is_behind_it() {
    let scene =
        load(&base("[[outlets]]\ntype = \"plane\"\npoint = [0.0, 0.0, 0.5]\nnormal = [0.0, 0.0, -1e200]\n"))
            .unwrap();
    match scene.setup.outlets[0].shape {
        wetbounce::pipeline::outlets::OutletShape::Plane { normal, .. } => {
            assert_eq!(normal, glam::DVec3::NEG_Z)
        }
        ref other => panic!("{other:?}"),
    }
}

#[test]
fn poiseuille_axis_of_1e200_keeps_the_flow_on() {
    let text = base("").replace(
        "viscosity = 0.89e-3",
        "viscosity = 0.89e-3\nflow = { type = \"poiseuille\", point = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1e200], radius = 0.02, mean_velocity = 0.01 }",
    );
    let scene = load(&text).unwrap();
    match scene.setup.fluid.flow {
        wetbounce::fluid::Flow::Poiseuille(p) => assert_eq!(p.axis, glam::DVec3::Z),
        ref other => panic!("{other:?}"),
    }
}

#[test]
fn plane_normal_of_1e200_is_normalised_not_blamed_on_a_particle() {
    let text = base("[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, 0.0, 0.01]\n")
        .replace("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 1e200]");
    let scene = load(&text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.particles.len(), 1);
}

#[test]
fn initial_speed_of_1e155_is_refused_with_the_speed_range() {
    let e = refused(&base(
        "[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, 0.0, 0.01]\nvelocity = [1e155, 0.0, 0.0]\n",
    ));
    assert_error(&e, "particles[0].velocity", &["1e155", "1e4 m/s"]);
}

#[test]
fn fluid_density_of_1e300_is_refused_with_the_density_range() {
    let e = refused(&base("").replace("density = 997.0", "density = 1e300"));
    assert_error(&e, "fluid.density", &["1e300", "1e-6", "1e5 kg/m³"]);
}

#[test]
fn diameter_of_1e_minus_300_is_refused_with_the_diameter_range() {
    let e =
        refused(&base("[[particles]]\nkind = \"glass\"\ndiameter = 1e-300\nposition = [0.0, 0.0, 0.01]\n"));
    assert_error(&e, "particles[0].diameter", &["1e-300", "1e-7", "10 m"]);
}

// ---- 8. impossible or absurd requests -----------------------------------------------------

#[test]
fn random_fill_of_six_times_its_volume_is_refused_at_once_with_the_fraction() {
    let e = refused(&base(
        "[[random_fill]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [0.0, 0.0, 0.0]\nmax = [0.02, 0.02, 0.02]\ncount = 100000\nseed = 1\n",
    ));
    assert_error(&e, "random_fill[0].count", &["654 %"]);
}

#[test]
fn output_interval_of_1e_minus_300_is_refused() {
    let e = refused(&base("").replace("output_interval = 1e-3", "output_interval = 1e-300"));
    assert_error(&e, "simulation.output_interval", &["1e-300"]);
}

#[test]
fn run_of_1e9_frames_is_refused_with_the_frame_count() {
    let e = refused(
        &base("")
            .replace("duration = 0.01", "duration = 1.0")
            .replace("output_interval = 1e-3", "output_interval = 1e-9"),
    );
    assert_error(&e, "simulation.output_interval", &["1e9 frames", "--allow-long-run"]);
}

#[test]
fn duration_of_1e300_is_refused() {
    let e = refused(&base("").replace("duration = 0.01", "duration = 1e300"));
    assert_error(&e, "simulation.duration", &["1e300"]);
}

#[test]
fn run_of_1e12_steps_is_refused_with_the_step_count() {
    let e = refused(
        &base("")
            .replace("duration = 0.01", "duration = 1e8")
            .replace("output_interval = 1e-3", "output_interval = 1e3"),
    );
    assert_error(&e, "simulation.duration", &["1e12 steps", "--allow-long-run"]);
}

#[test]
fn allow_long_run_flag_lets_check_accept_a_long_run() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("long.toml");
    std::fs::write(&scene, base("").replace("output_interval = 1e-3", "output_interval = 1e-12")).unwrap();
    let refused = wetbounce().arg("check").arg(&scene).output().unwrap();
    assert!(!refused.status.success());
    let allowed = wetbounce().args(["check", "--allow-long-run"]).arg(&scene).output().unwrap();
    assert!(allowed.status.success(), "{}", String::from_utf8_lossy(&allowed.stderr));
}

#[test]
fn output_interval_flag_giving_absurd_frames_is_refused_unless_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bead.toml");
    std::fs::write(&scene, base("")).unwrap();
    let run = |extra: &[&str]| {
        wetbounce()
            .arg("run")
            .arg(&scene)
            .args(["--quiet", "--formats", "csv", "--output-interval", "1e-12", "--out"])
            .arg(dir.path().join("out"))
            .args(extra)
            .output()
            .unwrap()
    };
    let refused = run(&[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success()
            && stderr.contains("--output-interval 1e-12: duration / output_interval is 1e10 frames"),
        "{stderr}"
    );
    assert!(!dir.path().join("out/trajectories.csv").exists(), "refused before writing");
}

#[test]
fn injector_region_behind_a_wall_is_refused_naming_the_region() {
    let e = refused(&base(
        "[[injectors]]\nkind = \"glass\"\nrate = 10.0\nseed = 1\n\
         region = { type = \"box\", min = [-0.01, -0.01, -0.03], max = [0.01, 0.01, -0.01] }\n\
         diameter = { distribution = \"fixed\", value = 1e-3 }\n",
    ));
    assert_error(&e, "injectors[0].region", &["floor"]);
}

#[test]
fn injector_in_a_tank_narrower_than_its_particles_is_refused_naming_the_diameter() {
    let e = refused(&base(
        "[[walls]]\nname = \"slot\"\ntype = \"box\"\nmin = [-0.01, -0.0005, 0.0]\nmax = [0.01, 0.0005, 0.05]\ninside = true\n\
         [[injectors]]\nkind = \"glass\"\nrate = 10.0\nseed = 1\n\
         region = { type = \"disk\", center = [0.0, 0.0, 0.02], normal = [0.0, 0.0, 1.0], radius = 0.005 }\n\
         diameter = { distribution = \"fixed\", value = 2e-3 }\n",
    ));
    assert_error(&e, "injectors[0].diameter", &["slot"]);
}

// ---- 9. overlapping initial particles --------------------------------------------------------

#[test]
fn lattices_offset_by_half_a_spacing_are_refused_naming_both_particles() {
    let lattice = |lo: f64| {
        format!(
            "[[lattice]]\nkind = \"glass\"\ndiameter = 2e-3\nspacing = 2e-3\nmin = [{lo}, {lo}, {lo}]\nmax = [0.01, 0.01, 0.01]\n"
        )
    };
    let e = refused(&base(&(lattice(0.0) + &lattice(0.001))));
    assert_error(&e, "lattice[1]", &["lattice[1] element 0", "lattice[0] element 0", "overlap"]);
}

#[test]
fn coincident_particles_are_refused_naming_both() {
    let p = "[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, 0.0, 0.01]\n";
    let e = refused(&base(&format!("{p}{p}")));
    assert_error(&e, "particles[1].position", &["particles[0]", "0.002 m"]);
}

#[test]
fn particles_in_exact_contact_are_accepted() {
    let p =
        |z: f64| format!("[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, 0.0, {z}]\n");
    let scene = load(&base(&(p(0.001) + &p(0.003) + &p(0.005)))).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.particles.len(), 3);
    let lattice = "[[lattice]]\nkind = \"glass\"\ndiameter = 2e-3\nspacing = 2e-3\nmin = [0.0, 0.0, 0.0]\nmax = [0.02, 0.02, 0.02]\n";
    assert_eq!(load(&base(lattice)).unwrap_or_else(|e| panic!("{e}")).particles.len(), 1000);
}

// ---- 10. smaller -------------------------------------------------------------------------

/// A scene in a temporary folder with a mesh wall whose `file` is `name`.
fn mesh_scene(dir: &Path, name: &str) -> PathBuf {
    let scene = dir.join("scene.toml");
    let text = base(&format!("[[walls]]\nname = \"plate\"\ntype = \"mesh\"\nfile = \"{name}\"\n"));
    std::fs::write(&scene, text).unwrap();
    scene
}

#[cfg(unix)]
#[test]
fn mesh_path_to_dev_zero_is_refused_as_not_a_regular_file() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("zero.stl")).unwrap();
    let e = Scene::load(mesh_scene(dir.path(), "zero.stl")).expect_err("refused");
    assert_error(&e, "walls[1].file", &["zero.stl", "not a regular file"]);
}

#[test]
fn mesh_file_beyond_the_size_cap_is_refused_without_reading_it() {
    let dir = tempfile::tempdir().unwrap();
    // Sparse: takes no disk space.
    let f = std::fs::File::create(dir.path().join("huge.stl")).unwrap();
    f.set_len(600 << 20).unwrap();
    let e = Scene::load(mesh_scene(dir.path(), "huge.stl")).expect_err("refused");
    assert_error(&e, "walls[1].file", &["huge.stl", "512 MiB"]);
}

#[test]
fn ball_larger_than_its_tank_is_blamed_on_the_diameter() {
    let e = refused(
        &base(
            "[[walls]]\nname = \"tank\"\ntype = \"box\"\nmin = [-0.05, -0.05, 0.0]\nmax = [0.05, 0.05, 0.1]\ninside = true\n\
             [[random_fill]]\nkind = \"glass\"\ndiameter = 10.0\nmin = [-20.0, -20.0, -20.0]\nmax = [20.0, 20.0, 20.0]\ncount = 1\nseed = 1\n",
        )
        .replace("[[walls]]\nname = \"floor\"", "[[walls]]\nname = \"floor0\""),
    );
    assert_error(&e, "random_fill[0].diameter", &["tank"]);
}

#[test]
fn huge_values_are_printed_in_short_scientific_form() {
    let e = refused(&base("").replace("dt = 1e-4", "dt = 1e300"));
    let message = e.to_string();
    assert!(message.contains("1e300"), "{message}");
    assert!(message.len() < 300, "{} characters: {message}", message.len());
}

/// A tank without the floor plane, plus `extra`.
fn tank(extra: &str) -> String {
    base(&format!(
        "[[walls]]\nname = \"tank\"\ntype = \"box\"\nmin = [-0.05, -0.05, 0.0]\nmax = [0.05, 0.05, 0.1]\ninside = true\n{extra}"
    ))
    .replace("[[walls]]\nname = \"floor\"", "[[walls]]\nname = \"floor0\"")
}

const FILL: &str = "[[random_fill]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [-0.04, -0.04, 0.01]\nmax = [0.04, 0.04, 0.09]\ncount = 5\nseed = 1\n";

/// Issue 25, finding 14: a 10 m ball in a 0.1 m tank plus a random fill blamed
/// `random_fill[0].min` with a false hint ("one fits at [0, 0, 0.11]", inside the ball).
#[test]
fn ball_through_its_tank_before_a_random_fill_is_blamed_on_its_own_position() {
    let e = refused(&tank(&format!(
        "[[particles]]\nkind = \"glass\"\ndiameter = 10.0\nposition = [0.0, 0.0, 0.05]\n{FILL}"
    )));
    assert_error(&e, "particles[0].position", &["starts inside wall", "d = 10 m"]);
    // The same with a lattice of large beads through the tank's side.
    let e = refused(&tank(&format!(
        "[[lattice]]\nkind = \"glass\"\ndiameter = 0.03\nmin = [0.03, -0.01, 0.0]\nmax = [0.09, 0.01, 0.02]\nspacing = 0.03\n{FILL}"
    )));
    assert_error(&e, "lattice[0]", &["starts inside wall \"tank\""]);
    assert!(!e.to_string().contains("fits at"), "{e}");
}

/// The variant: a ball clear of the walls that covers the whole fill region. The fill is what
/// cannot be placed, and the message names the ball, never a point inside it.
#[test]
fn random_fill_covered_by_a_ball_placed_before_names_the_ball_not_a_false_free_point() {
    let e = refused(&tank(
        "[[particles]]\nkind = \"glass\"\ndiameter = 0.098\nposition = [0.0, 0.0, 0.05]\n\
         [[random_fill]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [-0.01, -0.01, 0.04]\nmax = [0.01, 0.01, 0.06]\ncount = 5\nseed = 1\n",
    ));
    assert_error(&e, "random_fill[0].min", &["particles[0]", "d = 0.098"]);
    assert!(!e.to_string().contains("fits at"), "{e}");
    // The ball's centre outside the region, the region inside the ball: every draw fails.
    let e = refused(&tank(
        "[[particles]]\nkind = \"glass\"\ndiameter = 0.098\nposition = [0.0, 0.0, 0.05]\n\
         [[random_fill]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [0.01, 0.01, 0.05]\nmax = [0.02, 0.02, 0.06]\ncount = 5\nseed = 1\n",
    ));
    assert_error(&e, "random_fill[0].min", &["particles[0]", "d = 0.098"]);
    assert!(!e.to_string().contains("fits at"), "{e}");
}

#[test]
fn random_fill_seed_of_2_to_the_63_is_refused_as_the_docs_say() {
    let fill = |seed: &str| {
        base(&format!(
            "[[random_fill]]\nkind = \"glass\"\ndiameter = 1e-3\nmin = [0.0, 0.0, 0.0]\nmax = [0.01, 0.01, 0.01]\ncount = 3\nseed = {seed}\n"
        ))
    };
    assert!(load(&fill("9223372036854775807")).is_ok());
    assert_error(&refused(&fill("9223372036854775808")), "random_fill[0].seed", &["2^63 - 1"]);
}

/// `wetbounce run SCENE --quiet --formats FORMATS --out OUT`, which must succeed; its stderr.
fn run_quietly(scene: &Path, formats: &str, out: &Path) -> String {
    let o = wetbounce()
        .arg("run")
        .arg(scene)
        .args(["--quiet", "--formats", formats, "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn rerun_with_fewer_formats_removes_the_stale_outputs_of_the_earlier_run() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bead.toml");
    std::fs::write(
        &scene,
        base("[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, 0.0, 0.01]\n"),
    )
    .unwrap();
    let out = dir.path().join("out");
    let run = |formats: &str| run_quietly(&scene, formats, &out);
    run("mcap,csv");
    assert!(out.join("events.csv").exists() && out.join("bead.mcap").exists());
    let stderr = run("mcap");
    assert!(!out.join("events.csv").exists(), "events.csv of the first run left behind");
    assert!(!out.join("trajectories.csv").exists(), "trajectories.csv of the first run left behind");
    assert!(stderr.contains("events.csv"), "the removal is not reported: {stderr}");
}

/// Issue 25, finding 13: a rerun into the same folder left the earlier run's VTK frames (1,001
/// files beside a `.pvd` that lists 11) and, with `--formats mcap`, the old `.pvd` and walls.
#[test]
fn rerun_into_the_same_folder_leaves_no_vtk_frame_the_new_pvd_does_not_list() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bead.toml");
    let with_interval = |interval: &str| {
        base("[[particles]]\nkind = \"glass\"\ndiameter = 2e-3\nposition = [0.0, 0.0, 0.01]\n")
            .replace("output_interval = 1e-3", &format!("output_interval = {interval}"))
    };
    let out = dir.path().join("out");
    let run = |formats: &str| run_quietly(&scene, formats, &out);
    let frames = || -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(out.join("bead_vtk"))
            .map(|d| d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect())
            .unwrap_or_default();
        names.sort();
        names
    };
    let listed = || -> Vec<String> {
        let pvd = std::fs::read_to_string(out.join("bead.pvd")).unwrap();
        let mut names: Vec<String> = pvd
            .split("file=\"")
            .skip(1)
            .map(|rest| rest.split('"').next().unwrap().trim_start_matches("bead_vtk/").to_string())
            .collect();
        names.sort();
        names
    };
    // Many frames, then few: every frame in the folder is one the new .pvd lists.
    std::fs::write(&scene, with_interval("1e-3")).unwrap();
    run("vtk");
    let many = frames().len();
    std::fs::write(&scene, with_interval("5e-3")).unwrap();
    run("vtk");
    assert!(frames().len() < many, "{} frames before, {} after", many, frames().len());
    assert_eq!(frames(), listed());
    // Then without VTK: the .pvd, the walls and the frames go, a user's file in the folder stays.
    std::fs::write(out.join("bead_vtk/mine.txt"), "notes").unwrap();
    let stderr = run("mcap");
    assert!(!out.join("bead.pvd").exists() && !out.join("bead_walls.vtp").exists(), "{stderr}");
    assert_eq!(frames(), vec!["mine.txt".to_string()]);
    assert!(stderr.contains("bead.pvd"), "the removal is not reported: {stderr}");
}

#[test]
fn injector_seed_of_2_to_the_63_is_refused_too() {
    let injector = |seed: &str| {
        base(&format!(
            "[[injectors]]\nkind = \"glass\"\nrate = 10.0\nseed = {seed}\n\
             region = {{ type = \"box\", min = [-0.01, -0.01, 0.01], max = [0.01, 0.01, 0.02] }}\n\
             diameter = {{ distribution = \"fixed\", value = 1e-3 }}\n"
        ))
    };
    assert!(load(&injector("9223372036854775807")).is_ok());
    assert_error(&refused(&injector("18446744073709551615")), "injectors[0].seed", &["2^63 - 1"]);
}
