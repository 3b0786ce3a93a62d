//! Scaling sweep: particle-steps per second over N and thread counts, for the benchmark cases
//! of the many-particles work, written as CSV.
//!
//! Run: `cargo run --release --bin scaling -- [OUT.csv] [MAX_N] [CASE]` (defaults: standard
//! output, 1,000,000, every case; `-` for standard output); `SCALING_STEPS=K` times K steps
//! instead of 2·10⁷/N between 200 and 2000; `SCALING_N=N` runs that one N instead of the sweep
//! 10³…MAX_N, `SCALING_THREADS=T` that one thread count instead of 1 and 2 (one run per process,
//! so that `/usr/bin/time -v` gives its peak memory) or `SCALING_THREADS=1,4,16` those counts
//! on one scene built once. Cases:
//! - `dilute`: the LIGGGHTS peer's scene scaled to N — beads on a cubic lattice at 3 d in a box
//!   of liquid (ρ = 1000 kg/m³, μ = 0.1 Pa·s), gravity, buoyancy, Stokes drag, Euler, 20 mm above
//!   the floor so that no bead touches a wall in the timed steps;
//! - `paper`: the same with L06's physics — Schiller–Naumann drag, added mass, RK2;
//! - `paper-no-<effect>`: `paper` with one effect left out (and `paper-no-pairs` without
//!   particle–particle contacts), to show a scene pays only for what it names;
//! - `paper-lubrication`, `paper-history`: `paper` with the wall-lubrication effect (roughness
//!   1 µm on the beads and the box; the lattice fills the box sideways, so its outer layers
//!   fly within the film's reach) or the history effect at its defaults: what each costs;
//! - `pairs5`: two bead densities at 5 % volume fraction, settling at different speeds, so the
//!   neighbour list and pair contacts are exercised;
//! - `pairs5-friction`: `pairs5` with friction on both kinds (μ = 0.3, β0 = 0.35, μ_r = 0.01,
//!   the glass of `scenes/settling_bed_friction.toml`), hence rotation: what friction costs;
//! - `fines`: `dilute` with beads of 100 µm (lattice at 3 d), N of them, and the exponential
//!   integrator (their drag relaxation time, 14 µs, is below the step);
//! - `polydisperse`: `fines` plus one bead of 10 mm (size ratio 100) 10 mm beside the lattice,
//!   far from every fine: the broad phase must not pay for the one large bead;
//! - `polydisperse-4mm`: the same with a bead of 4 mm (size ratio 40);
//! - `poiseuille`: `paper` in a Poiseuille pipe flow up the box (axis through the lattice's
//!   centre, radius 0.75 of the lattice's side, so every bead is in the pipe; mean 10 mm/s);
//! - `field`: `poiseuille` with the flow read from a `.vti` the tool writes (into the system's
//!   temporary directory): the same profile sampled on an image grid of 64 cells across the
//!   box, trilinear — the same physics except the flow's evaluation;
//! - `field-vtu`: the same profile on an unstructured grid of hexahedra (`.vtu`, 32 cells
//!   across, ~4·10⁴ cells), each cut into 12 tetrahedra, barycentric; each particle's lookups
//!   walk from the tetrahedron it was in at the end of the last step;
//! - `field-vtu-bvh`: `field-vtu` with every lookup through the search tree (the particles
//!   remember no tetrahedron), to measure what the walk saves.
//!
//! `fines` and `polydisperse` time their first step too (no untimed warm-up), since the
//! neighbour list's first build is what they measure.

use glam::DVec3;
use std::io::Write;
use std::path::Path;
use std::time::Instant;
use wetbounce::Scene;
use wetbounce::fluid::field::unstructured::hexahedron_corners;

const D: f64 = 2.5e-3;
/// The fines' diameter in `fines` and `polydisperse` (m).
const FINE: f64 = 1e-4;
/// The one large bead's diameter in `polydisperse` (m): 100 fines' diameters.
const LARGE: f64 = 1e-2;
/// The one large bead's diameter in `polydisperse-4mm` (m).
const LARGE_4MM: f64 = 4e-3;

/// Mean velocity of the `poiseuille` and `field` cases' pipe flow (m/s).
const PIPE_MEAN: f64 = 0.01;

/// The pipe of the `poiseuille` and `field` cases in a box of side `extent`: its axis point
/// (on the box's floor) and radius (m).
fn pipe(extent: f64) -> (DVec3, f64) {
    (DVec3::new(0.5 * extent, 0.5 * extent, 0.0), 0.75 * extent)
}

/// Writes the `field` cases' file: the pipe flow of a box of side `extent` and height
/// `height` sampled at the nodes of a grid of `cells` cells across, as an image (`.vti`) or as
/// an unstructured grid of hexahedra (`.vtu`), ASCII. Returns its path.
fn write_pipe_field(extent: f64, height: f64, cells: usize, unstructured: bool) -> std::path::PathBuf {
    use std::fmt::Write as _;
    let (point, radius) = pipe(extent);
    let flow = wetbounce::fluid::Poiseuille { point, axis: DVec3::Z, radius, max_velocity: 2.0 * PIPE_MEAN };
    let h = extent / cells as f64;
    let nz = (height / h).ceil() as usize;
    let (nx, ny) = (cells, cells);
    let node = |i: usize, j: usize, k: usize| DVec3::new(i as f64 * h, j as f64 * h, k as f64 * h);
    let mut velocity = String::new();
    let mut points = String::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let x = node(i, j, k);
                let u = wetbounce::fluid::FlowField::velocity(&flow, x);
                let _ = writeln!(velocity, "{} {} {}", u.x, u.y, u.z);
                let _ = writeln!(points, "{} {} {}", x.x, x.y, x.z);
            }
        }
    }
    let dir = std::env::temp_dir().join(format!("wetbounce-scaling-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| fail(format!("{}: {e}", dir.display())));
    let u_array = format!(
        "<DataArray type=\"Float64\" Name=\"U\" NumberOfComponents=\"3\" format=\"ascii\">\n{velocity}</DataArray>"
    );
    let (name, text) = if unstructured {
        let id = |i: usize, j: usize, k: usize| i + (nx + 1) * (j + (ny + 1) * k);
        let (mut conn, mut offsets, mut types) = (String::new(), String::new(), String::new());
        let mut count = 0;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let v = hexahedron_corners(i, j, k).map(|(a, b, c)| id(a, b, c));
                    let _ = writeln!(
                        conn,
                        "{} {} {} {} {} {} {} {}",
                        v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]
                    );
                    count += 1;
                    let _ = writeln!(offsets, "{}", 8 * count);
                    let _ = writeln!(types, "12");
                }
            }
        }
        let n_points = (nx + 1) * (ny + 1) * (nz + 1);
        (
            "pipe.vtu",
            format!(
                "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n\
                 <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{count}\">\n<PointData>\n{u_array}\n</PointData>\n\
                 <Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n{points}</DataArray>\n</Points>\n\
                 <Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n{conn}</DataArray>\n\
                 <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n{offsets}</DataArray>\n\
                 <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n{types}</DataArray>\n</Cells>\n\
                 </Piece>\n</UnstructuredGrid>\n</VTKFile>\n"
            ),
        )
    } else {
        (
            "pipe.vti",
            format!(
                "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n\
                 <ImageData WholeExtent=\"0 {nx} 0 {ny} 0 {nz}\" Origin=\"0 0 0\" Spacing=\"{h} {h} {h}\">\n\
                 <Piece Extent=\"0 {nx} 0 {ny} 0 {nz}\">\n<PointData>\n{u_array}\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n"
            ),
        )
    };
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
    path
}

fn scene(case: &str, n: usize) -> Scene {
    let in_pipe = matches!(case, "poiseuille" | "field" | "field-vtu" | "field-vtu-bvh");
    let paper = case.starts_with("paper") || in_pipe;
    let pairs5 = case.starts_with("pairs5");
    let friction = case == "pairs5-friction";
    let polydisperse = case.starts_with("polydisperse");
    let large = if case == "polydisperse-4mm" { LARGE_4MM } else { LARGE };
    let d = if polydisperse || case == "fines" { FINE } else { D };
    // Lattice spacing: 3 d (dilute), or the 5 % volume fraction (π/6 d³/a³ = 0.05).
    let spacing = if pairs5 { d * (std::f64::consts::PI / 0.3).cbrt() } else { 3.0 * d };
    let side = (n as f64).cbrt().ceil();
    let extent = side * spacing;
    // Room beside the lattice for the large bead (its diameter from the nearest fine) in
    // `polydisperse`: the box is the same size for both large beads.
    let beside = if polydisperse { 3.0 * LARGE } else { 0.0 };
    let mut effects = vec!["gravity = {}", "buoyancy = {}"];
    effects.push(if paper || pairs5 {
        "drag = { law = \"schiller_naumann\" }"
    } else {
        "drag = { law = \"stokes\" }"
    });
    if paper || pairs5 {
        effects.push("added_mass = {}");
    }
    let lubricated = case == "paper-lubrication";
    if lubricated {
        effects.push("wall_lubrication = {}");
    }
    if case == "paper-history" {
        effects.push("history = {}");
    }
    if let Some(off) = case.strip_prefix("paper-no-") {
        effects.retain(|e| !e.starts_with(off));
    }
    // The fines relax in 14 µs, below the step: only the exponential integrator is stable.
    let integrator = if paper || pairs5 {
        "rk2"
    } else if d == FINE {
        "exponential"
    } else {
        "euler"
    };
    let height = 0.04 + extent * 1.2;
    let (point, radius) = pipe(extent);
    let mut written = None;
    let flow = match case {
        "poiseuille" => format!(
            "flow = {{ type = \"poiseuille\", point = [{}, {}, 0.0], axis = [0.0, 0.0, 1.0], radius = {radius}, mean_velocity = {PIPE_MEAN} }}\n",
            point.x, point.y
        ),
        "field" | "field-vtu" | "field-vtu-bvh" => {
            let unstructured = case != "field";
            let path = write_pipe_field(extent, height, if unstructured { 32 } else { 64 }, unstructured);
            written = Some(path.clone());
            format!(
                "flow = {{ type = \"field\", file = {:?}, outside = \"nearest\" }}\n",
                path.display().to_string()
            )
        }
        _ => String::new(),
    };
    let mut text = format!(
        "[simulation]\ndt = 1e-4\nduration = 1.0\noutput_interval = 1.0\nintegrator = \"{integrator}\"\n\
         [fluid]\ndensity = 1000.0\nviscosity = 0.1\n{flow}[effects]\n{}\n",
        effects.join("\n")
    );
    for (name, density) in [("glass", 2540.0), ("pmma", 1190.0)] {
        text += &format!(
            "[[kinds]]\nname = \"{name}\"\ntype = \"solid\"\ndensity = {density}\nyoungs_modulus = 6e9\npoisson_ratio = 0.3\nrestitution_max = 0.9\n"
        );
        if friction {
            text += "friction = 0.3\ntangential_restitution = 0.35\nrolling_friction = 0.01\n";
        }
        if lubricated {
            text += "roughness = 1e-6\n";
        }
    }
    text += &format!(
        "[[walls]]\nname = \"box\"\ntype = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [{}, {}, {}]\ninside = true\n",
        extent + beside,
        extent + beside,
        height
    );
    if lubricated {
        text += "material = { youngs_modulus = 6e9, poisson_ratio = 0.3, roughness = 1e-6 }\n";
    }
    // Layers alternate between the two kinds in `pairs5`, so they settle through each other.
    let layers = side as usize;
    for layer in 0..layers {
        let kind = if pairs5 && layer % 2 == 1 { "pmma" } else { "glass" };
        // 20 mm above the floor: no bead reaches it within the timed steps.
        let z0 = 0.02 + layer as f64 * spacing;
        text += &format!(
            "[[lattice]]\nkind = \"{kind}\"\ndiameter = {d}\nmin = [0.0, 0.0, {z0}]\nmax = [{extent}, {extent}, {}]\nspacing = {spacing}\n",
            z0 + 0.99 * spacing
        );
    }
    if polydisperse {
        // Its centre 1.5 d beyond the lattice's side: its diameter of liquid between it and the
        // fines.
        text += &format!(
            "[[particles]]\nkind = \"glass\"\ndiameter = {large}\nposition = [{}, {}, {}]\n",
            extent + 1.5 * large,
            1.5 * large,
            0.02 + 0.5 * extent
        );
    }
    let scene = Scene::from_str(&text, Path::new("scaling.toml")).unwrap_or_else(|e| panic!("{case}: {e}"));
    // The scene holds the field it read: the file is no longer needed.
    if let Some(dir) = written.as_deref().and_then(Path::parent) {
        let _ = std::fs::remove_dir_all(dir);
    }
    scene
}

/// Ends the run with an error line (bad arguments, a file that cannot be written).
fn fail(message: String) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let max_n: usize = args.get(1).map_or(1_000_000, |s| {
        s.parse().unwrap_or_else(|_| fail(format!("MAX_N must be a whole number, got {s}")))
    });
    let only = args.get(2);
    let mut out: Box<dyn Write> = match args.first().filter(|p| *p != "-") {
        Some(path) => Box::new(std::fs::File::create(path).unwrap_or_else(|e| fail(format!("{path}: {e}")))),
        None => Box::new(std::io::stdout()),
    };
    if let Err(e) = writeln!(out, "case,n,threads,steps,wall_s,particle_steps_per_s") {
        fail(format!("writing the CSV: {e}"));
    }
    let cases = [
        "dilute",
        "paper",
        "paper-no-added_mass",
        "paper-no-buoyancy",
        "paper-no-drag",
        "paper-no-pairs",
        "paper-lubrication",
        "paper-history",
        "pairs5",
        "pairs5-friction",
        "fines",
        "polydisperse",
        "polydisperse-4mm",
        "poiseuille",
        "field",
        "field-vtu",
        "field-vtu-bvh",
    ];
    let env_number = |name: &str| {
        std::env::var(name).ok().map(|s| {
            s.parse::<usize>().unwrap_or_else(|_| fail(format!("{name} must be a whole number, got {s}")))
        })
    };
    let ns: Vec<usize> = match env_number("SCALING_N") {
        Some(n) => vec![n],
        None => [1_000, 10_000, 100_000, 1_000_000].into_iter().filter(|&n| n <= max_n).collect(),
    };
    // One count, or several separated by commas (`1,2,4,8,16`): the scene is then built once.
    let thread_counts: Vec<usize> = std::env::var("SCALING_THREADS").map_or(vec![1, 2], |s| {
        s.split(',')
            .map(|t| match t.trim().parse::<usize>() {
                Ok(t) if t > 0 => t,
                _ => fail(format!("SCALING_THREADS must be thread counts separated by commas, got {s}")),
            })
            .collect()
    });
    for case in cases.into_iter().filter(|c| only.is_none_or(|o| o == c)) {
        for &n in &ns {
            let base = scene(case, n);
            for &threads in &thread_counts {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("threads");
                let mut sim = base.simulation();
                sim.setup.pair_collisions = case != "paper-no-pairs";
                if case == "field-vtu-bvh" {
                    sim.world.particles.tet = wetbounce::particles::Column::off(0);
                }
                let count = sim.world.particles.len();
                // At least 200 steps (20 ms): enough for the Verlet list to be rebuilt in `pairs5`.
                let steps = std::env::var("SCALING_STEPS")
                    .ok()
                    .and_then(|s| s.parse().ok())
                    .unwrap_or((20_000_000 / count).clamp(200, 2_000));
                // One warm-up step builds the neighbour list and the scratch columns — except in
                // the cases that measure that build.
                if !(case == "fines" || case.starts_with("polydisperse")) {
                    pool.install(|| sim.step(base.setup.dt));
                }
                sim.record.stage_times = Default::default();
                let builds = sim.world.neighbours.builds;
                let start = Instant::now();
                pool.install(|| sim.run_steps(steps, base.setup.dt));
                let wall = start.elapsed().as_secs_f64();
                let row = writeln!(
                    out,
                    "{case},{count},{threads},{steps},{wall:.4},{:.4e}",
                    (count * steps) as f64 / wall
                )
                .and_then(|()| out.flush());
                if let Err(e) = row {
                    // A full disk, or a reader that closed the pipe: stop, saying so.
                    fail(format!("writing the CSV: {e}"));
                }
                // Where the time went, on standard error (the CSV stays plain).
                eprintln!(
                    "{case} n={count} threads={threads}: {:?}, {} neighbour-list builds, {} pairs listed, {} lasting contacts",
                    sim.record.stage_times,
                    sim.world.neighbours.builds - builds,
                    sim.world.neighbours.pairs.len(),
                    sim.world.lasting.len()
                );
            }
        }
    }
}
