//! Flow fields read from every VTK format and encoding the reader takes (issue 14): the files
//! are written here with `vtkio` (image data, rectilinear and unstructured grids, legacy ASCII
//! and binary) or are the committed fixtures of `tests/fields/` (XML ASCII, inline base64 with
//! UInt64 headers, appended raw and zlib-compressed data, foamToVTK's legacy layout), and
//! particles are tracked in them through whole scenes.

use glam::DVec3;
use std::path::{Path, PathBuf};
use vtkio::model::*;
use wetbounce::Scene;
use wetbounce::fluid::FlowField;
use wetbounce::fluid::field::read::{Request, load};
use wetbounce::fluid::field::unstructured::hexahedron_corners;
use wetbounce::fluid::field::{DataAt, Field, FieldInfo, Outside, Snapshot};

/// The linear field of the fixtures: every reader and every grid must reproduce it exactly.
fn linear(p: DVec3) -> DVec3 {
    DVec3::new(1.0 + 2.0 * p.x - p.y, 3.0 * p.z, -p.x + 0.5 * p.y)
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fields").join(name)
}

fn field_of(path: &Path, data: Option<DataAt>) -> Field {
    let loaded =
        load(path, Request { array: None, data, axisymmetric: false }).unwrap_or_else(|e| panic!("{e}"));
    let snapshots = vec![Snapshot { time: 0.0, values: loaded.values }];
    Field::new(loaded.grid, snapshots, None, Outside::Error, None, FieldInfo::default())
}

const PROBES: [[f64; 3]; 4] = [[0.1, 0.2, 0.3], [0.5, 0.5, 0.5], [0.99, 0.01, 0.7], [0.25, 0.75, 0.0]];

fn assert_reproduces_linear(field: &Field, what: &str) {
    let at = field.at(0.0);
    for p in PROBES.map(DVec3::from_array) {
        let err = (at.velocity(p) - linear(p)).length();
        assert!(err < 1e-6, "{what}: at {p} got {}, expected {}", at.velocity(p), linear(p));
    }
}

#[test]
fn every_unstructured_encoding_reads_the_same_point_data() {
    for name in [
        "hex_ascii.vtu",
        "hex_base64_uint64.vtu",
        "hex_appended_raw.vtu",
        "hex_appended_zlib.vtu",
        "hex_legacy_binary.vtk",
    ] {
        let field = field_of(&fixture(name), Some(DataAt::Point));
        assert_eq!(field.info.cells, 8, "{name}");
        assert_reproduces_linear(&field, name);
    }
}

#[test]
fn cell_data_keeps_each_cell_value_at_its_centre() {
    for name in ["hex_ascii.vtu", "hex_appended_zlib.vtu", "hex_legacy_binary.vtk"] {
        let field = field_of(&fixture(name), Some(DataAt::Cell));
        let at = field.at(0.0);
        for c in [DVec3::splat(0.25), DVec3::new(0.75, 0.25, 0.75)] {
            assert!((at.velocity(c) - linear(c)).length() < 1e-6, "{name} at {c}");
        }
    }
}

/// `n + 1` nodes per axis on the unit cube: coordinates and point values of `linear`.
fn lattice(n: usize) -> (Vec<f64>, Vec<f64>) {
    let c: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
    let mut u = Vec::new();
    for &z in &c {
        for &y in &c {
            for &x in &c {
                u.extend(linear(DVec3::new(x, y, z)).to_array());
            }
        }
    }
    (c, u)
}

fn point_data(u: Vec<f64>) -> Attributes {
    Attributes {
        point: vec![Attribute::DataArray(DataArray {
            name: "U".into(),
            elem: ElementType::Vectors,
            data: IOBuffer::F64(u),
        })],
        cell: vec![],
    }
}

fn xml(data: DataSet) -> Vtk {
    Vtk {
        version: Version::new_xml(1, 0),
        byte_order: ByteOrder::LittleEndian,
        title: String::new(),
        file_path: None,
        data,
    }
}

fn image(n: usize) -> DataSet {
    let (_, u) = lattice(n);
    let extent = Extent::Ranges([0..=n as i32, 0..=n as i32, 0..=n as i32]);
    DataSet::ImageData {
        extent: extent.clone(),
        origin: [0.0; 3],
        spacing: [1.0 / n as f32; 3],
        meta: None,
        pieces: vec![Piece::Inline(Box::new(ImageDataPiece { extent, data: point_data(u) }))],
    }
}

fn unstructured(n: usize) -> DataSet {
    let (c, u) = lattice(n);
    let mut points = Vec::new();
    for &z in &c {
        for &y in &c {
            for &x in &c {
                points.extend([x, y, z]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u64;
    let (mut connectivity, mut offsets, mut types) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                connectivity.extend(hexahedron_corners(i, j, k).map(|(a, b, c)| id(a, b, c)));
                offsets.push(connectivity.len() as u64);
                types.push(CellType::Hexahedron);
            }
        }
    }
    DataSet::inline(UnstructuredGridPiece {
        points: IOBuffer::F64(points),
        cells: Cells { cell_verts: VertexNumbers::XML { connectivity, offsets }, types },
        data: point_data(u),
    })
}

/// The unstructured grid as a legacy file: cells as counts and point lists.
fn legacy(n: usize) -> Vtk {
    let mut v = xml(unstructured(n));
    v.version = Version::new_legacy(2, 0);
    v.byte_order = ByteOrder::BigEndian;
    if let DataSet::UnstructuredGrid { pieces, .. } = &mut v.data
        && let Piece::Inline(p) = &mut pieces[0]
        && let VertexNumbers::XML { connectivity, offsets } = &p.cells.cell_verts
    {
        let mut vertices = Vec::new();
        let mut start = 0;
        for &end in offsets {
            vertices.push((end - start) as u32);
            vertices.extend(connectivity[start as usize..end as usize].iter().map(|&i| i as u32));
            start = end;
        }
        p.cells.cell_verts = VertexNumbers::Legacy { num_cells: offsets.len() as u32, vertices };
    }
    v
}

#[test]
fn image_rectilinear_and_unstructured_files_written_by_vtkio_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let n = 3;
    let (c, u) = lattice(n);
    let extent = Extent::Ranges([0..=n as i32, 0..=n as i32, 0..=n as i32]);
    let rect = DataSet::RectilinearGrid {
        extent: extent.clone(),
        meta: None,
        pieces: vec![Piece::Inline(Box::new(RectilinearGridPiece {
            extent,
            coords: Coordinates {
                x: IOBuffer::F64(c.clone()),
                y: IOBuffer::F64(c.clone()),
                z: IOBuffer::F64(c),
            },
            data: point_data(u),
        }))],
    };
    let cases: Vec<(&str, Vtk)> =
        vec![("f.vti", xml(image(n))), ("f.vtr", xml(rect)), ("f.vtu", xml(unstructured(n)))];
    for (name, vtk) in cases {
        let path = dir.path().join(name);
        vtk.export(&path).unwrap();
        assert_reproduces_linear(&field_of(&path, None), name);
    }
    // NOTE: a legacy file written by vtkio 0.7.0-rc2 (`legacy(n)`) is not read back by vtkio
    // itself ("Parse error: IsNot"); legacy input is tested with the foamToVTK-layout fixture.
    let _ = legacy;
}

/// A bead in water over a floor, in the flow `flow` (a TOML inline table).
fn bead_scene(flow: &str, duration: f64) -> String {
    format!(
        r#"
[simulation]
dt = 1e-3
duration = {duration}
output_interval = 0.01

[fluid]
density = 997.0
viscosity = 0.89e-3
flow = {flow}

[effects]
gravity = {{}}
buoyancy = {{}}
drag = {{ law = "schiller_naumann" }}

[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6e10
poisson_ratio = 0.23

[[particles]]
kind = "glass"
diameter = 1e-3
position = [0.5, 0.5, 0.5]
"#
    )
}

#[test]
fn a_uniform_field_read_from_a_file_moves_a_bead_like_the_uniform_flow() {
    let dir = tempfile::tempdir().unwrap();
    let n: i32 = 2;
    let u: Vec<f64> = (0..(n + 1) * (n + 1) * (n + 1)).flat_map(|_| [0.02, -0.01, 0.005]).collect();
    let extent = Extent::Ranges([0..=n, 0..=n, 0..=n]);
    let data = DataSet::ImageData {
        extent: extent.clone(),
        origin: [0.0; 3],
        spacing: [0.5; 3],
        meta: None,
        pieces: vec![Piece::Inline(Box::new(ImageDataPiece { extent, data: point_data(u) }))],
    };
    xml(data).export(dir.path().join("u.vti")).unwrap();
    let scene_path = dir.path().join("scene.toml");
    let run = |flow: &str| {
        let scene = Scene::from_str(&bead_scene(flow, 0.2), &scene_path).unwrap_or_else(|e| panic!("{e}"));
        let mut sim = scene.simulation();
        sim.advance_to(0.2);
        (sim.world.particles.pos[0], sim.world.particles.vel[0])
    };
    let (x_field, v_field) = run(r#"{ type = "field", file = "u.vti" }"#);
    let (x_uniform, v_uniform) = run(r#"{ type = "uniform", velocity = [0.02, -0.01, 0.005] }"#);
    assert!((x_field - x_uniform).length() < 1e-12, "{x_field} vs {x_uniform}");
    assert!((v_field - v_uniform).length() < 1e-12);
    assert!(x_field.x > 0.5 && x_field.y < 0.5, "carried by the flow: {x_field}");
}

#[test]
fn a_bead_that_leaves_the_field_stops_the_run_naming_it_its_position_and_the_time() {
    let dir = tempfile::tempdir().unwrap();
    xml(image(2)).export(dir.path().join("u.vti")).unwrap();
    let scene_path = dir.path().join("scene.toml");
    // u_x = 1 + 2x − y ≈ 1.5 m/s at the start: the bead leaves the unit cube within a second.
    let scene =
        Scene::from_str(&bead_scene(r#"{ type = "field", file = "u.vti" }"#, 2.0), &scene_path).unwrap();
    let mut sim = scene.simulation();
    let stop = std::sync::atomic::AtomicBool::new(false);
    let report = wetbounce::run::run(&mut sim, 2.0, 0.01, &mut [], &stop).unwrap();
    let left = sim.record.left_field.expect("the run must stop on the particle outside the field");
    assert!(report.interrupted && report.time < 1.0, "stopped at {}", report.time);
    assert_eq!(left.id, 0);
    assert!(left.position.x > 1.0 || left.position.z > 1.0 || left.position.z < 0.0, "{}", left.position);
    let message = left.to_string();
    assert!(message.contains("particle 0") && message.contains("t = "), "{message}");
    // With outside = "nearest" the same run goes to its end.
    let nearest = r#"{ type = "field", file = "u.vti", outside = "nearest" }"#;
    let mut sim = Scene::from_str(&bead_scene(nearest, 2.0), &scene_path).unwrap().simulation();
    let report = wetbounce::run::run(&mut sim, 2.0, 0.01, &mut [], &stop).unwrap();
    assert!(!report.interrupted && sim.record.left_field.is_none());
}

#[test]
fn the_run_driver_writes_the_flow_error_into_summary_json_for_the_cli_and_python_alike() {
    // Both `wetbounce run` and Python's `Simulation.run` end their runs through
    // `run::Driver::finish` (issue 26, item 3); Python's summary.json lacked the flow error.
    let dir = tempfile::tempdir().unwrap();
    xml(image(2)).export(dir.path().join("u.vti")).unwrap();
    let scene_path = dir.path().join("scene.toml");
    let scene =
        Scene::from_str(&bead_scene(r#"{ type = "field", file = "u.vti" }"#, 2.0), &scene_path).unwrap();
    let mut sim = scene.simulation();
    let out = dir.path().join("out");
    let folder = wetbounce::output::Folder {
        out: &out,
        stem: "scene",
        scene_path: &scene_path,
        scene_source: &scene.source,
        max_spheres: 10,
        rotation: false,
    };
    let formats = [wetbounce::output::Format::Csv];
    let mut driver = wetbounce::run::Driver::new(Some(&folder), &formats, 2.0, 0.01).unwrap();
    let stop = std::sync::atomic::AtomicBool::new(false);
    let result = driver.run(&mut sim, Vec::new(), &stop);
    let ended = driver.finish(&sim, result, None);
    assert!(ended.report.interrupted && ended.errors.is_empty());
    let names: Vec<_> = ended.written.iter().map(|p| p.file_name().unwrap().to_owned()).collect();
    assert_eq!(names, ["trajectories.csv", "events.csv", "summary.json"]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(json["flow_error"].as_str().is_some_and(|e| e.contains("particle 0")), "{json}");
    assert_eq!(json["interrupted"], true);
    assert_eq!(json["signal"], serde_json::Value::Null);
    assert_eq!(json["scene"], scene_path.display().to_string());
}
