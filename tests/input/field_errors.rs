//! Bad flow fields are refused with an error naming the key, the file and what is wrong
//! (issue 14, "Bad input"), never a panic.

use crate::common;
use std::path::Path;
use vtkio::model::*;
use wetbounce::{Scene, SceneError};

use common::field_scene as scene;

/// An image of 3 × `ny` × 3 points at 0.5 m with point array `name` of `comps` components,
/// every value `value`.
fn write_image(path: &Path, ny: usize, name: &str, comps: u32, value: f64) {
    let n = 3 * ny * 3;
    let extent = Extent::Ranges([0..=2, 0..=(ny as i32 - 1), 0..=2]);
    let array = DataArray {
        name: name.into(),
        elem: ElementType::Generic(comps),
        data: IOBuffer::F64(vec![value; n * comps as usize]),
    };
    let data = DataSet::ImageData {
        extent: extent.clone(),
        origin: [0.0; 3],
        spacing: [0.5; 3],
        meta: None,
        pieces: vec![Piece::Inline(Box::new(ImageDataPiece {
            extent,
            data: Attributes { point: vec![Attribute::DataArray(array)], cell: vec![] },
        }))],
    };
    Vtk {
        version: Version::new_xml(1, 0),
        byte_order: ByteOrder::LittleEndian,
        title: String::new(),
        file_path: None,
        data,
    }
    .export(path)
    .unwrap();
}

/// Loads `flow` in a scene inside `dir`; the error, which must be one.
fn refused(dir: &Path, flow: &str) -> SceneError {
    match Scene::from_str(&scene(flow), &dir.join("scene.toml")) {
        Ok(_) => panic!("accepted: {flow}"),
        Err(e) => e,
    }
}

fn assert_says(e: &SceneError, key: &str, parts: &[&str]) {
    let text = e.to_string();
    assert_eq!(e.key(), key, "{text}");
    for p in parts {
        assert!(text.contains(p), "{text:?} should say {p:?}");
    }
}

#[test]
fn a_missing_field_file_is_named_with_its_key() {
    let dir = tempfile::tempdir().unwrap();
    let e = refused(dir.path(), r#"{ type = "field", file = "nowhere.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["nowhere.vti", "cannot read the field file"]);
}

#[test]
fn an_unknown_format_lists_the_known_ones() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("u.dat"), "1 2 3").unwrap();
    let e = refused(dir.path(), r#"{ type = "field", file = "u.dat" }"#);
    assert_says(&e, "fluid.flow.file", &["u.dat", "unknown field format \"dat\"", ".vtu"]);
}

#[test]
fn a_file_that_is_not_vtk_is_refused_not_panicked_on() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("u.vtu"), "this is not XML").unwrap();
    let e = refused(dir.path(), r#"{ type = "field", file = "u.vtu" }"#);
    assert_says(&e, "fluid.flow.file", &["u.vtu", "cannot read it as VTK XML unstructured grid"]);
    std::fs::write(dir.path().join("u.vtk"), "# vtk DataFile Version 2.0\ncut short\n").unwrap();
    let e = refused(dir.path(), r#"{ type = "field", file = "u.vtk" }"#);
    assert_says(&e, "fluid.flow.file", &["u.vtk", "cannot read it as legacy VTK"]);
}

#[test]
fn a_file_without_a_velocity_array_lists_the_arrays_it_has() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("p.vti"), 3, "p", 1, 0.0);
    let e = refused(dir.path(), r#"{ type = "field", file = "p.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["p.vti", "no velocity array", "\"p\" (1)", "fluid.flow.array"]);
    let e = refused(dir.path(), r#"{ type = "field", file = "p.vti", array = "W" }"#);
    assert_says(&e, "fluid.flow.file", &["no array \"W\""]);
}

#[test]
fn a_velocity_with_the_wrong_number_of_components_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("u.vti"), 3, "U", 1, 0.0);
    let e = refused(dir.path(), r#"{ type = "field", file = "u.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["u.vti", "\"U\" has 1 components, a velocity needs 3"]);
    write_image(&dir.path().join("rz.vti"), 3, "U", 2, 0.0);
    let e = refused(dir.path(), r#"{ type = "field", file = "rz.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["axisymmetric = true"]);
}

#[test]
fn nan_or_infinite_velocities_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("u.vti"), 3, "U", 3, f64::NAN);
    let e = refused(dir.path(), r#"{ type = "field", file = "u.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["u.vti", "holds NaN at value 0", "must be finite"]);
    write_image(&dir.path().join("v.vti"), 3, "U", 3, f64::INFINITY);
    let e = refused(dir.path(), r#"{ type = "field", file = "v.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["holds inf"]);
}

#[test]
fn a_flat_grid_is_degenerate_unless_it_is_an_axisymmetric_table() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("flat.vti"), 1, "U", 3, 0.0);
    let e = refused(dir.path(), r#"{ type = "field", file = "flat.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["flat.vti", "degenerate grid: one point along y"]);
    let ok = Scene::from_str(
        &scene(r#"{ type = "field", file = "flat.vti", axisymmetric = true }"#),
        &dir.path().join("scene.toml"),
    );
    assert!(ok.is_ok(), "{:?}", ok.err().map(|e| e.to_string()));
}

#[test]
fn keys_that_a_field_does_not_have_are_refused_with_the_list() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("u.vti"), 3, "U", 3, 0.0);
    let e = refused(dir.path(), r#"{ type = "field", file = "u.vti", radius = 0.1 }"#);
    assert_says(&e, "fluid.flow.radius", &["file", "outside"]);
    let e = refused(dir.path(), r#"{ type = "field", file = "u.vti", point = [0.0, 0.0, 0.0] }"#);
    assert_says(&e, "fluid.flow.point", &["axisymmetric = true"]);
    let e = refused(dir.path(), r#"{ type = "uniform", velocity = [0.0, 0.0, 0.0], file = "u.vti" }"#);
    assert_says(&e, "fluid.flow.file", &["type = \"field\""]);
    let e = refused(dir.path(), r#"{ type = "field", file = "u.vti", outside = "clamp" }"#);
    assert_says(&e, "fluid.flow.outside", &["clamp"]);
}

#[test]
fn a_series_whose_times_do_not_increase_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("a.vti"), 3, "U", 3, 0.0);
    write_image(&dir.path().join("b.vti"), 3, "U", 3, 1.0);
    let e = refused(dir.path(), r#"{ type = "field", files = ["a.vti", "b.vti"], times = [1.0, 1.0] }"#);
    assert_says(&e, "fluid.flow.times[1]", &["b.vti", "must increase"]);
    let e = refused(dir.path(), r#"{ type = "field", files = ["a.vti", "b.vti"], times = [0.0] }"#);
    assert_says(&e, "fluid.flow.times", &["2 files, 1 times"]);
    let pvd = r#"<?xml version="1.0"?>
<VTKFile type="Collection" version="0.1"><Collection>
<DataSet timestep="2" file="a.vti"/>
<DataSet timestep="1" file="b.vti"/>
</Collection></VTKFile>"#;
    std::fs::write(dir.path().join("s.pvd"), pvd).unwrap();
    let e = refused(dir.path(), r#"{ type = "field", file = "s.pvd" }"#);
    assert_says(&e, "fluid.flow.file", &["b.vti", "must increase"]);
    let e = refused(
        dir.path(),
        r#"{ type = "field", files = ["a.vti", "b.vti"], times = [0.0, 1.0], period = 0.5 }"#,
    );
    assert_says(&e, "fluid.flow.period", &["must exceed"]);
}

#[test]
fn snapshots_on_different_grids_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("a.vti"), 3, "U", 3, 0.0);
    write_image(&dir.path().join("b.vti"), 4, "U", 3, 0.0);
    let e = refused(dir.path(), r#"{ type = "field", files = ["a.vti", "b.vti"], times = [0.0, 1.0] }"#);
    assert_says(&e, "fluid.flow.files[1]", &["b.vti", "same grid"]);
}
