//! Results do not depend on the thread count (docs/architecture.md: determinism by construction): the same scene run with
//! 1 and 2 threads, and twice, writes byte-identical output files (stability case 11,
//! docs/stability.md).

use std::process::Command;

fn run(scene: &str, threads: &str, dir: &std::path::Path) -> Vec<u8> {
    run_formats(scene, threads, dir, "csv")
}

/// Runs `scene` and returns the bytes of every file it wrote: the CSV files, the MCAP if asked
/// for, and summary.json without its one measured field, the wall-clock time.
fn run_formats(scene: &str, threads: &str, dir: &std::path::Path, formats: &str) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_wetbounce"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["run", scene, "--formats", formats, "--quiet", "--threads", threads, "--out"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut bytes = std::fs::read(dir.join("trajectories.csv")).unwrap();
    bytes.extend(std::fs::read(dir.join("events.csv")).unwrap());
    let stem = std::path::Path::new(scene).file_stem().unwrap().to_string_lossy().into_owned();
    if formats.contains("mcap") {
        bytes.extend(std::fs::read(dir.join(format!("{stem}.mcap"))).unwrap());
    }
    let mut summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap();
    summary.as_object_mut().unwrap().remove("wall_time_s");
    bytes.extend(summary.to_string().into_bytes());
    bytes
}

/// 200 glass beads poured into a box: wall and pair contacts, lasting contacts, islands
/// resolved in parallel.
const POUR: &str = "tests/scenes/pour_200.toml";

#[test]
fn one_and_two_threads_write_identical_files_for_a_pour_with_pair_contacts() {
    let dirs: Vec<_> = (0..3).map(|_| tempfile::tempdir().unwrap()).collect();
    let one = run(POUR, "1", dirs[0].path());
    let two = run(POUR, "2", dirs[1].path());
    let again = run(POUR, "2", dirs[2].path());
    assert!(one.len() > 100_000, "{} bytes", one.len());
    assert!(one == two, "1 and 2 threads differ");
    assert!(two == again, "two runs with 2 threads differ");
    let events = std::fs::read_to_string(dirs[0].path().join("events.csv")).unwrap();
    assert!(events.contains(",particle,"), "the pour must have particle contacts");
}

/// 300 glass beads with friction and rolling resistance poured into a box, cut to 0.5 s (the bed
/// forming): spin, friction rows of the lasting contacts warm-started from the last step, and
/// positions that follow the solved velocities (physics.md §9.1).
#[test]
fn one_and_two_threads_write_identical_files_for_a_pour_with_friction() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/scenes/bed_friction_300.toml"))
            .unwrap()
            .replace("duration = 2.0", "duration = 0.5");
    assert!(text.contains("duration = 0.5"));
    let scenes = tempfile::tempdir().unwrap();
    let (one, dirs) = one_and_two_threads(scenes.path(), "bed_friction.toml", &text);
    assert!(one.len() > 10_000, "{} bytes", one.len());
    let header = std::fs::read_to_string(dirs[0].path().join("trajectories.csv")).unwrap();
    assert!(header.lines().next().unwrap().contains(",wx,wy,wz"), "the spin is written");
}

/// Writes scene `text` as `name` into `scenes`, runs it with 1 and with 2 threads, asserts the
/// two wrote the same bytes, and returns them with the two output folders.
fn one_and_two_threads(
    scenes: &std::path::Path,
    name: &str,
    text: &str,
) -> (Vec<u8>, Vec<tempfile::TempDir>) {
    let scene = scenes.join(name);
    std::fs::write(&scene, text).unwrap();
    let scene = scene.to_str().unwrap();
    let dirs: Vec<_> = (0..2).map(|_| tempfile::tempdir().unwrap()).collect();
    let one = run(scene, "1", dirs[0].path());
    let two = run(scene, "2", dirs[1].path());
    assert!(one == two, "1 and 2 threads differ");
    (one, dirs)
}

/// The column scene (seeded injector, log-normal sizes, outlet, baffle-like plate, holds)
/// shortened to 1.5 s: about 750 drops injected, the first reaching the plate.
#[test]
fn seeded_column_writes_identical_csv_mcap_and_summary_with_1_and_2_threads_and_twice() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/column.toml")).unwrap();
    let text: String = text
        .lines()
        .map(|l| if l.starts_with("duration =") { "duration = 1.5".to_string() } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let scenes = tempfile::tempdir().unwrap();
    let scene = scenes.path().join("column_short.toml");
    std::fs::write(&scene, text).unwrap();
    let scene = scene.to_str().unwrap();
    let dirs: Vec<_> = (0..3).map(|_| tempfile::tempdir().unwrap()).collect();
    let one = run_formats(scene, "1", dirs[0].path(), "mcap,csv");
    let two = run_formats(scene, "2", dirs[1].path(), "mcap,csv");
    let again = run_formats(scene, "2", dirs[2].path(), "mcap,csv");
    assert!(one.len() > 100_000, "{} bytes", one.len());
    assert!(one == two, "1 and 2 threads differ");
    assert!(two == again, "two runs with 2 threads differ");
}

/// A swirl `u = ω (−(y − c), x − c, 0)` about the box's vertical centre line on an unstructured
/// grid of `n × n × 8n` hexahedra over the pour's box, as ASCII VTK XML.
fn swirl_vtu(n: usize) -> String {
    use std::fmt::Write as _;
    let (side, height, omega) = (0.015, 0.1, 2.0);
    let nz = 8 * n;
    let (mut points, mut velocity, mut cells, mut offsets, mut types) =
        (String::new(), String::new(), String::new(), String::new(), String::new());
    for k in 0..=nz {
        for j in 0..=n {
            for i in 0..=n {
                let (x, y, z) =
                    (i as f64 * side / n as f64, j as f64 * side / n as f64, k as f64 * height / nz as f64);
                let _ = writeln!(points, "{x} {y} {z}");
                let _ = writeln!(velocity, "{} {} 0", -omega * (y - 0.5 * side), omega * (x - 0.5 * side));
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| i + (n + 1) * (j + (n + 1) * k);
    let mut count = 0;
    for k in 0..nz {
        for j in 0..n {
            for i in 0..n {
                let v =
                    [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
                        .map(|(a, b, c)| id(i + a, j + b, k + c).to_string());
                let _ = writeln!(cells, "{}", v.join(" "));
                count += 1;
                let _ = writeln!(offsets, "{}", 8 * count);
                let _ = writeln!(types, "12");
            }
        }
    }
    let n_points = (n + 1) * (n + 1) * (nz + 1);
    format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n\
         <UnstructuredGrid>\n<Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{count}\">\n<PointData>\n\
         <DataArray type=\"Float64\" Name=\"U\" NumberOfComponents=\"3\" format=\"ascii\">\n{velocity}</DataArray>\n\
         </PointData>\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n{points}</DataArray>\n\
         </Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n{cells}</DataArray>\n\
         <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n{offsets}</DataArray>\n\
         <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n{types}</DataArray>\n</Cells>\n</Piece>\n\
         </UnstructuredGrid>\n</VTKFile>\n"
    )
}

/// The pour in a swirl read from an unstructured grid: each particle's flow lookups walk from
/// the tetrahedron it remembers (physics.md §7), one column per particle, so the threads
/// cannot change which tetrahedron a lookup finds.
#[test]
fn one_and_two_threads_write_identical_files_for_a_pour_in_an_unstructured_field() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/",
        "tests/scenes/pour_200.toml"
    ))
    .unwrap()
    .replace("duration = 1.0", "duration = 0.3")
    .replace(
        "viscosity = 1.002e-3\n",
        "viscosity = 1.002e-3\nflow = { type = \"field\", file = \"swirl.vtu\", outside = \"nearest\" }\n",
    );
    assert!(text.contains("swirl.vtu"));
    let scenes = tempfile::tempdir().unwrap();
    std::fs::write(scenes.path().join("swirl.vtu"), swirl_vtu(6)).unwrap();
    let (one, _) = one_and_two_threads(scenes.path(), "pour_swirl.toml", &text);
    assert!(one.len() > 10_000, "{} bytes", one.len());
}
