//! Each wall shape and flow type refuses a key of another type, naming it, and reads its own
//! (`scene::table`).

use crate::scene::{Scene, SceneError};
use std::path::Path;

/// A scene in vacuum with `fluid.flow = flow` and one wall (`wall`, its keys after `name`).
fn scene(flow: &str, wall: &str) -> Result<Scene, SceneError> {
    let text = format!(
        "[simulation]\ndt = 1e-4\nduration = 0.01\noutput_interval = 1e-3\n\n\
         [fluid]\ndensity = 0.0\nviscosity = 0.0\nflow = {flow}\n\n\
         [[kinds]]\nname = \"glass\"\ntype = \"solid\"\ndensity = 2500.0\nyoungs_modulus = 6e10\n\
         poisson_ratio = 0.23\n\n[[walls]]\nname = \"w\"\n{wall}\n"
    );
    Scene::from_str(&text, Path::new("typed.toml"))
}

fn wall(keys: &str) -> Result<Scene, SceneError> {
    scene("{}", keys)
}

fn flow(table: &str) -> Result<Scene, SceneError> {
    scene(table, "type = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]")
}

/// Asserts the error is about `key` and its message contains every one of `parts`.
fn refused(result: Result<Scene, SceneError>, key: &str, parts: &[&str]) {
    let e = result.expect_err("refused");
    assert_eq!(e.key(), key, "{e}");
    let text = e.to_string();
    assert!(text.starts_with("typed.toml: "), "{text}");
    for p in parts {
        assert!(text.contains(p), "lacks {p:?}: {text}");
    }
}

const PLANE: &str = "type = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]";
const BOX: &str = "type = \"box\"\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\ninside = true";
const CYLINDER: &str = "type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\nradius = 0.5\nlength = 1.0";
const ANNULUS: &str =
    "type = \"annulus\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nouter_radius = 0.5";

#[test]
fn each_wall_shape_reads_its_own_keys() {
    for keys in [PLANE, BOX, CYLINDER, ANNULUS] {
        let scene = wall(keys).unwrap_or_else(|e| panic!("{keys}: {e}"));
        assert_eq!(scene.setup.walls.len(), 1);
    }
    // `type` after the shape's keys, and the common keys anywhere.
    let late = "point = [0.0, 0.0, 0.0]\nmaterial = { restitution_max = 0.5 }\nnormal = [0.0, 0.0, 1.0]\ntype = \"plane\"";
    let scene = wall(late).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.setup.walls[0].material.restitution_max, Some(0.5));
}

#[test]
fn a_plane_refuses_a_key_of_another_shape_naming_it() {
    refused(
        wall(&format!("{PLANE}\nradius = 0.1")),
        "walls[0].radius",
        &["not a key of a plane; its keys are: point, normal", "type = \"cylinder\"", "(line "],
    );
}

#[test]
fn a_box_refuses_a_key_of_another_shape_naming_it() {
    refused(
        wall(&format!("{BOX}\nnormal = [0.0, 0.0, 1.0]")),
        "walls[0].normal",
        &["not a key of a box; its keys are: min, max, inside", "\"plane\" and \"annulus\""],
    );
}

#[test]
fn a_cylinder_refuses_a_key_of_another_shape_naming_it() {
    refused(
        wall(&format!("{CYLINDER}\nouter_radius = 0.1")),
        "walls[0].outer_radius",
        &["not a key of a cylinder; its keys are: base, axis, radius, length", "\"annulus\""],
    );
}

#[test]
fn a_mesh_refuses_a_key_of_another_shape_naming_it() {
    refused(
        wall("type = \"mesh\"\nfile = \"plate.stl\"\ninside = false"),
        "walls[0].inside",
        &["not a key of a mesh; its keys are: file, scale, translate", "\"box\""],
    );
}

#[test]
fn an_annulus_refuses_a_key_of_another_shape_naming_it() {
    refused(
        wall(&format!("{ANNULUS}\nscale = 2.0")),
        "walls[0].scale",
        &["not a key of an annulus; its keys are: center, normal, inner_radius, outer_radius", "\"mesh\""],
    );
}

#[test]
fn an_unknown_wall_key_is_refused_with_the_keys_of_the_shape() {
    refused(wall(&format!("{PLANE}\nnormall = 1")), "walls[0].normall", &["its keys are: point, normal"]);
}

#[test]
fn a_missing_or_mistyped_wall_key_is_named() {
    refused(
        wall("type = \"plane\"\npoint = [0.0, 0.0, 0.0]"),
        "walls[0].normal",
        &["missing: required for a plane"],
    );
    refused(
        wall("type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\nradius = \"big\""),
        "walls[0].radius",
        &["invalid type: string \"big\", expected f64", "(line 22, column 10)"],
    );
    refused(
        wall("type = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]"),
        "walls[0].inside",
        &["true: particles inside it"],
    );
    refused(wall("point = [0.0, 0.0, 0.0]"), "walls[0]", &["missing field `type`"]);
    refused(wall("type = \"sphere\""), "walls[0].type", &["unknown variant `sphere`"]);
    refused(
        wall(&format!("{PLANE}\nmaterial = {{ rough = 1 }}")),
        "walls[0].material.rough",
        &["unknown field"],
    );
}

/// A value that fails in the file's own reader (a float beyond f64) is reported at its key,
/// not at the private field through which `toml::Spanned` keeps it.
#[test]
fn a_value_that_toml_cannot_read_is_reported_at_its_key() {
    refused(
        wall("type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\nradius = 1e400"),
        "walls[0].radius",
        &["overflowed", "(line 22, column 10)"],
    );
    refused(
        flow("{ type = \"poiseuille\", point = [0.0, 0.0, 0.0], radius = 1e400, max_velocity = 0.1 }"),
        "fluid.flow.radius",
        &["overflowed"],
    );
}

/// A date is shown as in the file's other tables: not taken for a string.
#[test]
fn a_date_in_a_wall_or_flow_is_not_taken_for_a_string() {
    refused(
        wall("type = \"plane\"\npoint = [0.0, 0.0, 1979-05-27]\nnormal = [0.0, 0.0, 1.0]"),
        "walls[0].point",
        &["component 2 is a table or a date"],
    );
    refused(
        wall("type = \"mesh\"\nfile = 1979-05-27"),
        "walls[0].file",
        &["invalid type: map, expected a string"],
    );
}

#[test]
fn each_flow_reads_its_own_keys() {
    for table in [
        "{}",
        "{ type = \"quiescent\" }",
        "{ type = \"uniform\", velocity = [0.1, 0.0, 0.0] }",
        "{ point = [0.0, 0.0, 0.0], radius = 0.1, max_velocity = 0.2, type = \"poiseuille\" }",
    ] {
        flow(table).unwrap_or_else(|e| panic!("{table}: {e}"));
    }
}

#[test]
fn a_quiescent_flow_refuses_any_key_naming_it() {
    refused(
        flow("{ velocity = [0.1, 0.0, 0.0] }"),
        "fluid.flow.velocity",
        &["not a key of a quiescent flow; it has no other keys", "\"uniform\""],
    );
}

#[test]
fn a_uniform_flow_refuses_a_key_of_another_flow_naming_it() {
    refused(
        flow("{ type = \"uniform\", velocity = [0.1, 0.0, 0.0], radius = 0.1 }"),
        "fluid.flow.radius",
        &["not a key of a uniform flow; its keys are: velocity", "\"poiseuille\""],
    );
}

#[test]
fn a_poiseuille_flow_refuses_a_key_of_another_flow_naming_it() {
    refused(
        flow(
            "{ type = \"poiseuille\", point = [0.0, 0.0, 0.0], radius = 0.1, max_velocity = 0.2, period = 1.0 }",
        ),
        "fluid.flow.period",
        &["not a key of a poiseuille flow; its keys are: point, axis, radius", "\"field\""],
    );
}

#[test]
fn a_field_flow_refuses_a_key_of_another_flow_naming_it() {
    refused(
        flow("{ type = \"field\", file = \"u.vti\", velocity = [0.1, 0.0, 0.0] }"),
        "fluid.flow.velocity",
        &["not a key of a field flow; its keys are: file, files, times", "\"uniform\""],
    );
}

#[test]
fn a_missing_or_mistyped_flow_key_is_named() {
    refused(flow("{ type = \"uniform\" }"), "fluid.flow.velocity", &["missing: required for a uniform flow"]);
    refused(
        flow("{ type = \"uniform\", velocity = [0.1, 0.0] }"),
        "fluid.flow.velocity",
        &["must be 3 numbers [x, y, z], got 2 values"],
    );
}
