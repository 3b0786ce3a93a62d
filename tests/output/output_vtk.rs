//! The ParaView output (`--formats vtk`), read back with `vtkio`: the `.pvd` lists one frame per
//! CSV frame at the CSV's times; each `.vtp` frame has every particle with the documented arrays
//! and the CSV's positions and velocities bit for bit; the walls' file has a surface per wall;
//! a stopped, killed or starved run leaves a `.pvd` that is a whole document naming whole files.

use crate::outputs_common;

use outputs_common::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};
use std::time::Duration;
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece, PolyDataPiece, VertexNumbers, Vtk};

/// The point arrays of a frame, in order, with their VTK types (docs/output.md).
const ARRAYS: &[(&str, &str, usize)] = &[
    ("id", "U32", 1),
    ("kind", "U16", 1),
    ("diameter", "F64", 1),
    ("radius", "F64", 1),
    ("velocity", "F64", 3),
    ("speed", "F64", 1),
    ("state", "U8", 1),
];

fn run_into(scene: &Path, out: &Path, formats: &str) -> Output {
    wetbounce()
        .arg("run")
        .arg(scene)
        .args(["--formats", formats, "--quiet", "--threads", "1", "--out"])
        .arg(out)
        .output()
        .unwrap()
}

/// The `.pvd`'s entries, (timestep as written, file), after checking that it is a whole
/// collection document.
fn read_pvd(path: &Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(text.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\""), "{text}");
    // Whitespace may follow the document: the room a failed write took for a next entry.
    assert!(text.trim_end().ends_with("  </Collection>\n</VTKFile>"), "{}: not closed", path.display());
    let attr = |line: &str, name: &str| -> String {
        let start = line.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        line[start..start + line[start..].find('"').unwrap()].to_string()
    };
    text.lines()
        .filter(|l| l.trim_start().starts_with("<DataSet "))
        .map(|l| {
            assert!(l.trim_end().ends_with("/>"), "{l}");
            assert_eq!(attr(l, "part"), "0");
            (attr(l, "timestep"), attr(l, "file"))
        })
        .collect()
}

/// Reads a `.vtp` with vtkio: its one inline PolyData piece.
fn read_vtp(path: &Path) -> PolyDataPiece {
    let vtk = Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let DataSet::PolyData { pieces, .. } = vtk.data else { panic!("{}: not PolyData", path.display()) };
    assert_eq!(pieces.len(), 1, "{}", path.display());
    match pieces.into_iter().next().unwrap() {
        Piece::Inline(p) => *p,
        _ => panic!("{}: the piece is not inline", path.display()),
    }
}

fn f64s(b: &IOBuffer) -> Vec<f64> {
    match b {
        IOBuffer::F64(v) => v.clone(),
        other => panic!("not Float64: {:?}", other.scalar_type()),
    }
}

/// The point arrays by name: (buffer, components).
fn point_arrays(p: &PolyDataPiece) -> Vec<(String, IOBuffer, usize)> {
    p.data
        .point
        .iter()
        .map(|a| match a {
            Attribute::DataArray(d) => (d.name.clone(), d.data.clone(), d.num_comp()),
            Attribute::Field { name, .. } => panic!("field {name}"),
        })
        .collect()
}

fn kind_of(b: &IOBuffer) -> &'static str {
    match b {
        IOBuffer::U8(_) => "U8",
        IOBuffer::U16(_) => "U16",
        IOBuffer::U32(_) => "U32",
        IOBuffer::F64(_) => "F64",
        _ => "other",
    }
}

/// trajectories.csv's rows grouped by frame time as written: per frame, id → the row's fields.
fn csv_frames(dir: &Path) -> Vec<(String, BTreeMap<u32, Vec<String>>)> {
    let csv = read_csv(&dir.join("trajectories.csv"), TRAJECTORY_HEADER);
    let mut by_time: Vec<(String, BTreeMap<u32, Vec<String>>)> =
        frames(&csv).into_iter().map(|(t, _)| (t, BTreeMap::new())).collect();
    let mut k = 0;
    for l in csv.lines.iter().skip(1) {
        let f: Vec<String> = l.split(',').map(str::to_string).collect();
        while by_time[k].0 != f[0] {
            k += 1;
        }
        by_time[k].1.insert(f[1].parse().unwrap(), f);
    }
    by_time
}

/// Checks one frame against the CSV's rows at its time: the point count, the arrays and their
/// types, positions, velocities and states bit for bit, speed = |v|, radius = diameter / 2, a
/// vertex cell per point.
fn check_frame(path: &Path, rows: &BTreeMap<u32, Vec<String>>) {
    let p = read_vtp(path);
    let n = rows.len();
    assert_eq!(p.num_points(), n, "{}", path.display());
    let arrays = point_arrays(&p);
    let names: Vec<(&str, &str, usize)> =
        arrays.iter().map(|(n, b, c)| (n.as_str(), kind_of(b), *c)).collect();
    assert_eq!(names, ARRAYS, "{}", path.display());
    let get = |name: &str| arrays.iter().find(|a| a.0 == name).unwrap().1.clone();
    let points = f64s(&p.points);
    let ids = get("id").into_vec::<u32>().unwrap();
    let velocity = f64s(&get("velocity"));
    let (diameter, radius, speed) = (f64s(&get("diameter")), f64s(&get("radius")), f64s(&get("speed")));
    let state = get("state").into_vec::<u8>().unwrap();
    assert_eq!(get("kind").into_vec::<u16>().unwrap().len(), n);
    for i in 0..n {
        let row =
            rows.get(&ids[i]).unwrap_or_else(|| panic!("{}: id {} not in the CSV", path.display(), ids[i]));
        let num = |k: usize| row[k].parse::<f64>().unwrap();
        for c in 0..3 {
            assert_eq!(
                points[3 * i + c].to_bits(),
                num(2 + c).to_bits(),
                "{}: id {} x[{c}]",
                path.display(),
                ids[i]
            );
            assert_eq!(
                velocity[3 * i + c].to_bits(),
                num(5 + c).to_bits(),
                "{}: id {} v[{c}]",
                path.display(),
                ids[i]
            );
        }
        let v = [num(5), num(6), num(7)];
        assert_eq!(speed[i], (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
        assert_eq!(radius[i], 0.5 * diameter[i]);
        let code = match row[8].as_str() {
            "free" => 0,
            "held" => 1,
            "resting" => 2,
            s => panic!("state {s}"),
        };
        assert_eq!(state[i], code, "{}: id {}", path.display(), ids[i]);
    }
    match p.verts {
        Some(VertexNumbers::XML { connectivity, offsets }) => {
            assert_eq!(connectivity, (0..n as u64).collect::<Vec<_>>());
            assert_eq!(offsets, (1..=n as u64).collect::<Vec<_>>());
        }
        ref other => panic!("{}: verts {other:?}", path.display()),
    }
}

/// The walls' triangles per wall index: (wall → its vertices), after checking that every cell
/// is a triangle of existing points.
fn walls_by_index(path: &Path) -> BTreeMap<u32, Vec<[f64; 3]>> {
    let p = read_vtp(path);
    let points = f64s(&p.points);
    let Some(VertexNumbers::XML { connectivity, offsets }) = p.polys else { panic!("no polys") };
    let cells = offsets.len();
    assert_eq!(offsets, (1..=cells as u64).map(|k| 3 * k).collect::<Vec<_>>(), "triangles only");
    assert!(connectivity.iter().all(|&i| (i as usize) < points.len() / 3));
    let Attribute::DataArray(wall) = &p.data.cell[0] else { panic!() };
    assert_eq!(wall.name, "wall");
    let wall = wall.data.clone().into_vec::<u32>().unwrap();
    assert_eq!(wall.len(), cells);
    let mut by: BTreeMap<u32, Vec<[f64; 3]>> = BTreeMap::new();
    for (c, w) in wall.iter().enumerate() {
        for &i in &connectivity[3 * c..3 * c + 3] {
            let i = i as usize;
            by.entry(*w).or_default().push([points[3 * i], points[3 * i + 1], points[3 * i + 2]]);
        }
    }
    by
}

/// Checks the run in `out` of the scene `stem`: the `.pvd` against trajectories.csv, every frame.
/// A frame without particles has no CSV row; every CSV frame is in the `.pvd`, in order.
/// Returns the number of frames.
fn check_run(out: &Path, stem: &str) -> usize {
    let pvd = read_pvd(&out.join(format!("{stem}.pvd")));
    let csv = csv_frames(out);
    let mut csv_at = csv.iter().peekable();
    let none = BTreeMap::new();
    for (k, (t, file)) in pvd.iter().enumerate() {
        assert_eq!(file, &format!("{stem}_vtk/particles_{k:06}.vtp"));
        let t: f64 = t.parse().unwrap();
        let rows = match csv_at.peek() {
            Some((t_csv, rows)) if t_csv.parse::<f64>().unwrap() == t => {
                csv_at.next();
                rows
            }
            _ => &none,
        };
        check_frame(&out.join(file), rows);
    }
    assert!(csv_at.next().is_none(), "a CSV frame is not in the .pvd");
    pvd.len()
}

#[test]
fn contactor_frames_hold_every_particle_with_the_csv_numbers_and_the_walls_are_surfaces() {
    let dir = tempfile::tempdir().unwrap();
    // 0.3 s of the contactor: drops injected from empty (frame 0 has none), 7 walls of 3 shapes.
    let scene = scene_with(
        // The Poiseuille version: copied alone, the shipped scene would miss its field file.
        "scenes/contactor_poiseuille.toml",
        "contactor.toml",
        dir.path(),
        &[("duration", "0.3"), ("output_interval", "0.05")],
    );
    let out = dir.path().join("out");
    let run = run_into(&scene, &out, "vtk,csv");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(check_run(&out, "contactor"), 7);
    let last = csv_frames(&out).pop().unwrap();
    assert!(last.1.len() > 10, "drops were injected: {}", last.1.len());
    assert_eq!(read_vtp(&out.join("contactor_vtk/particles_000000.vtp")).num_points(), 0);

    // events.csv is written for ParaView's table.
    read_csv(&out.join("events.csv"), EVENT_HEADER);

    // Walls: 0 shell (cylinder r = 25 mm, z from 0 to 0.42 m), 1 bottom (plane z = 0, a slab
    // under it), 2..6 annuli (meshes) at their heights.
    let walls = walls_by_index(&out.join("contactor_walls.vtp"));
    assert_eq!(walls.keys().copied().collect::<Vec<_>>(), (0..7).collect::<Vec<_>>());
    let shell = &walls[&0];
    assert_eq!(shell.len(), 3 * 2 * 48, "48 quads around");
    for v in shell {
        assert!(((v[0] * v[0] + v[1] * v[1]).sqrt() - 0.025).abs() < 1e-12, "{v:?}");
        assert!(v[2].abs() < 1e-12 || (v[2] - 0.42).abs() < 1e-12, "{v:?}");
    }
    let bottom = &walls[&1];
    assert_eq!(bottom.len(), 3 * 12, "a slab: 12 triangles");
    assert!(bottom.iter().all(|v| v[2] <= 1e-12), "the slab is under the plane");
    assert!(bottom.iter().any(|v| v[2].abs() < 1e-12), "its top face is the plane");
    for (w, z) in [(2, 0.08), (3, 0.14), (4, 0.20)] {
        let (lo, hi) =
            walls[&w].iter().fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v[2]), hi.max(v[2])));
        assert!(
            (lo - z).abs() < 0.0061 && (hi - z).abs() < 0.0061 && hi - lo > 0.005,
            "wall {w}: {lo}..{hi}"
        );
        let r_max = walls[&w].iter().map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt()).fold(0.0, f64::max);
        assert!(r_max <= 0.025 + 1e-12, "wall {w}: r {r_max}");
    }
}

#[test]
fn toluene_drop_frames_have_the_csv_times_and_the_box_wall_is_its_six_faces() {
    let dir = tempfile::tempdir().unwrap();
    let run = run_into(Path::new("scenes/toluene_drop.toml"), dir.path(), "vtk,csv");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    for f in ["toluene_drop.pvd", "toluene_drop_walls.vtp", "events.csv"] {
        assert!(stdout.contains(&dir.path().join(f).display().to_string()), "{f} not listed: {stdout}");
    }
    assert_eq!(check_run(dir.path(), "toluene_drop"), 1001);
    let pvd = read_pvd(&dir.path().join("toluene_drop.pvd"));
    assert_eq!((pvd[0].0.as_str(), pvd[500].0.as_str(), pvd[1000].0.as_str()), ("0", "0.5", "1"));
    let walls = walls_by_index(&dir.path().join("toluene_drop_walls.vtp"));
    let top = &walls[&0];
    assert_eq!(top.len(), 3 * 12);
    // scenes/toluene_drop.toml: the box from (−0.055, −0.055, 0) to (0.055, 0.055, 5.5e-5).
    for (c, (lo, hi)) in [(-0.055, 0.055), (-0.055, 0.055), (0.0, 5.5e-5)].into_iter().enumerate() {
        let (min, max) = top.iter().fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v[c]), b.max(v[c])));
        assert!((min - lo).abs() < 1e-12 && (max - hi).abs() < 1e-12, "axis {c}: {min}..{max}");
    }
}

/// The entries and files of a `.pvd` left by a run that did not finish: a whole document whose
/// every file vtkio reads. Returns the entries.
fn check_left(out: &Path, stem: &str) -> Vec<(String, String)> {
    let pvd = read_pvd(&out.join(format!("{stem}.pvd")));
    for (_, file) in &pvd {
        read_vtp(&out.join(file));
    }
    pvd
}

#[test]
fn a_stopped_or_killed_run_leaves_a_whole_pvd_up_to_its_last_frame() {
    let dir = tempfile::tempdir().unwrap();
    // Far longer than the test waits: the signal always comes mid-run.
    let scene = scene_with(
        "tests/scenes/pour_200.toml",
        "pour_200.toml",
        dir.path(),
        &[("duration", "3600.0"), ("output_interval", "0.002")],
    );
    let spawn = |out: &PathBuf| {
        wetbounce()
            .arg("run")
            .arg(&scene)
            // The hour-long pour would not fit on the disk (it is always stopped long before).
            .args(["--formats", "vtk,csv", "--quiet", "--threads", "1", "--allow-large-output", "--out"])
            .arg(out)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let has_frames = |out: &Path, n: usize| {
        std::fs::read_to_string(out.join("pour_200.pvd")).is_ok_and(|t| t.matches("<DataSet ").count() >= n)
    };

    // SIGTERM: the run writes a last frame and closes; the .pvd has every CSV frame.
    let out = dir.path().join("term");
    let mut child = spawn(&out);
    wait_until(&mut child, Duration::from_secs(60), "three frames", || has_frames(&out, 3));
    send(&child, "TERM");
    let done = wait_bounded(child, Duration::from_secs(60));
    assert_eq!(done.status.code(), Some(143), "{}", String::from_utf8_lossy(&done.stderr));
    let n = check_run(&out, "pour_200");
    assert!(n >= 4, "{n} frames: three and the last, at the stop");

    // SIGKILL: nothing is closed, yet the .pvd is whole and names only whole frames.
    let out = dir.path().join("kill");
    let mut child = spawn(&out);
    wait_until(&mut child, Duration::from_secs(60), "three frames", || has_frames(&out, 3));
    child.kill().unwrap();
    let _ = child.wait();
    let left = check_left(&out, "pour_200");
    assert!(left.len() >= 3, "{} frames", left.len());
}

/// A full disk under the `.pvd` or under a frame stops the run with an error naming that file;
/// the `.pvd` then still names every whole frame written before.
#[test]
fn a_full_disk_names_the_vtk_file_and_leaves_the_frames_before() {
    const FULL: &str = "cannot write: No space left on device (os error 28)";
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new("scenes/toluene_drop.toml");

    let out = dir.path().join("pvd");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink("/dev/full", out.join("toluene_drop.pvd")).unwrap();
    let run = run_into(scene, &out, "vtk");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!("error: {}: {FULL}", out.join("toluene_drop.pvd").display())),
        "{stderr}"
    );

    let out = dir.path().join("frame");
    std::fs::create_dir_all(out.join("toluene_drop_vtk")).unwrap();
    std::os::unix::fs::symlink("/dev/full", out.join("toluene_drop_vtk/particles_000003.vtp")).unwrap();
    let run = run_into(scene, &out, "vtk,csv");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    let frame = out.join("toluene_drop_vtk/particles_000003.vtp");
    assert!(stderr.contains(&format!("error: {}: {FULL}", frame.display())), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let left = check_left(&out, "toluene_drop");
    assert_eq!(left.len(), 3, "frames 0, 1, 2: {left:?}");
    assert_eq!(read_summary(&out)["output_errors"].as_array().unwrap().len(), 1);
}

/// A `.pvd` that cannot grow mid-run (a file-size limit: the write that crosses it is cut, as
/// on a disk that fills) stops the run with an error naming it, and is still a whole document
/// naming whole frames: room for a frame's entry is taken (as whitespace after the document)
/// before the closing tags are overwritten.
#[test]
fn a_pvd_that_cannot_grow_stays_a_whole_document() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    // Frames of toluene_drop are about 2 KB, its .pvd grows by 88 bytes a frame: the .pvd
    // reaches the limit first, after about 110 frames.
    let bytes: u64 = 10_000;
    let run = run_with_file_limit(Path::new("scenes/toluene_drop.toml"), &out, "vtk", bytes);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    let pvd = out.join("toluene_drop.pvd");
    assert!(
        stderr.contains(&format!("error: {}: cannot write: File too large (os error 27)", pvd.display())),
        "{stderr}"
    );
    let left = check_left(&out, "toluene_drop");
    assert!(left.len() > 50, "{} frames", left.len());
    assert!(std::fs::metadata(&pvd).unwrap().len() <= bytes);
}
