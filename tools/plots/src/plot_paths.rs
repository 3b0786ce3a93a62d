//! Draws the height of every particle against simulated time, one panel per scene, coloured
//! by state (free / held / resting, the colours of the MCAP and rerun outputs), with the
//! scene's horizontal plane walls — the README's picture.
//!
//!     plot_paths OUT.png SCENE.toml=TRAJECTORIES.csv[@T0:T1] [...] [--font FILE.ttf]
//!
//! `@T0:T1` keeps only the frames from T0 to T1 (s): a close-up of the contacts.
//! The trajectories come from `wetbounce run SCENE --formats csv`. The font is loaded at run
//! time (default: DejaVu Sans, as Debian installs it) so that nothing links a system library.

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use wetbounce::Scene;
use wetbounce::output::geometry::state_color;
use wetbounce::particles::State;
use wetbounce::walls::Shape;

const DEFAULT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// One particle's samples: time (s), height (m), state.
type Path3 = Vec<(f64, f64, State)>;

struct Panel {
    title: String,
    /// Heights (m) of the horizontal plane walls, with their names.
    walls: Vec<(String, f64)>,
    paths: BTreeMap<u32, Path3>,
}

fn state(name: &str) -> Result<State, String> {
    match name {
        "free" => Ok(State::Free),
        "held" => Ok(State::Held),
        "resting" => Ok(State::Resting),
        other => Err(format!("unknown state '{other}'")),
    }
}

fn load_panel(spec: &str) -> Result<Panel, String> {
    let (scene_path, rest) =
        spec.split_once('=').ok_or_else(|| format!("'{spec}': expected SCENE.toml=TRAJECTORIES.csv"))?;
    let (csv_path, window) = match rest.split_once('@') {
        None => (rest, None),
        Some((csv, w)) => {
            let bad = || format!("'{spec}': expected @T0:T1 with times in s");
            let (a, b) = w.split_once(':').ok_or_else(bad)?;
            let (a, b): (f64, f64) = (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
            (csv, Some((a, b)))
        }
    };
    let scene = Scene::load(scene_path).map_err(|e| e.to_string())?;
    let walls = scene
        .setup
        .walls
        .iter()
        .filter_map(|w| match &w.shape {
            Shape::Plane(p) if p.normal.z.abs() > 0.999 => Some((w.name.clone(), p.point.z)),
            _ => None,
        })
        .collect();
    let mut reader = csv::Reader::from_path(csv_path).map_err(|e| format!("{csv_path}: {e}"))?;
    let mut paths: BTreeMap<u32, Path3> = BTreeMap::new();
    for (line, record) in reader.records().enumerate() {
        let r = record.map_err(|e| format!("{csv_path}: {e}"))?;
        let bad = |what: &str| format!("{csv_path}: row {}: bad {what}", line + 2);
        let t: f64 = r.get(0).and_then(|s| s.parse().ok()).ok_or_else(|| bad("t"))?;
        let id: u32 = r.get(1).and_then(|s| s.parse().ok()).ok_or_else(|| bad("id"))?;
        let z: f64 = r.get(4).and_then(|s| s.parse().ok()).ok_or_else(|| bad("z"))?;
        let s = state(r.get(8).unwrap_or("")).map_err(|e| format!("{csv_path}: row {}: {e}", line + 2))?;
        if window.is_none_or(|(a, b)| (a..=b).contains(&t)) {
            paths.entry(id).or_default().push((t, z, s));
        }
    }
    let mut title =
        Path::new(scene_path).file_stem().map_or(scene_path.into(), |s| s.to_string_lossy().into_owned());
    if let Some((a, b)) = window {
        title = format!("{title}, close-up {a} to {b} s");
    }
    Ok(Panel { title, walls, paths })
}

fn rgb(s: State) -> RGBColor {
    let [r, g, b, _] = state_color(s);
    RGBColor((r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8)
}

fn draw(out: &Path, panels: &[Panel]) -> Result<(), Box<dyn std::error::Error>> {
    // Two panels a row, so the picture stays readable at the README's width.
    let cols = panels.len().min(2);
    let rows = panels.len().div_ceil(cols);
    let root = BitMapBackend::new(out, (560 * cols as u32, 34 + 400 * rows as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let (legend, body) = root.split_vertically(34);
    // The legend: one swatch per state.
    for (k, s) in [State::Free, State::Held, State::Resting].into_iter().enumerate() {
        let x = 20 + 150 * k as i32;
        legend.draw(&Rectangle::new([(x, 12), (x + 26, 22)], rgb(s).filled()))?;
        legend.draw(&Text::new(s.name(), (x + 34, 9), ("sans-serif", 17).into_font()))?;
    }
    for (area, p) in body.split_evenly((rows, cols)).iter().zip(panels) {
        let (mut t0, mut t1) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for path in p.paths.values() {
            for &(t, z, _) in path {
                t0 = t0.min(t);
                t1 = t1.max(t);
                lo = lo.min(z);
                hi = hi.max(z);
            }
        }
        // A wall far from the close-up's paths would squash them: show the walls in range.
        let near = (hi - lo).max(1e-3);
        for (_, z) in &p.walls {
            if *z > lo - near && *z < hi + near {
                lo = lo.min(*z);
                hi = hi.max(*z);
            }
        }
        let pad = 0.05 * (hi - lo).max(1e-6);
        let (lo, hi) = ((lo - pad) * 1e3, (hi + pad) * 1e3);
        let mut chart = ChartBuilder::on(area)
            .caption(&p.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(56)
            .build_cartesian_2d(t0..t1, lo..hi)?;
        chart
            .configure_mesh()
            .x_desc("t [s]")
            .y_desc("centre height z [mm]")
            .light_line_style(WHITE)
            .draw()?;
        for (name, z) in &p.walls {
            let z = z * 1e3;
            if z < lo || z > hi {
                continue;
            }
            chart.draw_series(LineSeries::new([(t0, z), (t1, z)], BLACK.stroke_width(2)))?;
            // The label sits beside the line, on the side of the paths (into the plot), never
            // on it: (4, 4) puts its top 4 px below the line, (4, -19) its bottom 4 px above.
            let at = (t0 + 0.02 * (t1 - t0), z);
            let below = z > 0.5 * (lo + hi);
            let label = EmptyElement::at(at)
                + Text::new(format!("wall {name}"), (4, if below { 4 } else { -19 }), ("sans-serif", 15));
            chart.draw_series([label])?;
        }
        for path in p.paths.values() {
            // Each stretch between two frames takes the colour of the state at its start.
            for w in path.windows(2) {
                let (a, b) = (w[0], w[1]);
                chart.draw_series(LineSeries::new(
                    [(a.0, a.1 * 1e3), (b.0, b.1 * 1e3)],
                    rgb(a.2).stroke_width(3),
                ))?;
            }
        }
    }
    root.present()?;
    Ok(())
}

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut font = PathBuf::from(DEFAULT_FONT);
    if let Some(k) = args.iter().position(|a| a == "--font") {
        if k + 1 >= args.len() {
            eprintln!("error: --font needs a file");
            return ExitCode::FAILURE;
        }
        font = PathBuf::from(args.remove(k + 1));
        args.remove(k);
    }
    if args.len() < 2 {
        eprintln!("usage: plot_paths OUT.png SCENE.toml=TRAJECTORIES.csv [...] [--font FILE.ttf]");
        return ExitCode::FAILURE;
    }
    let bytes = match std::fs::read(&font) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("error: --font {}: {e}", font.display());
            return ExitCode::FAILURE;
        }
    };
    // plotters keeps the font for the life of the program.
    if register_font("sans-serif", FontStyle::Normal, Box::leak(bytes.into_boxed_slice())).is_err() {
        eprintln!("error: --font {}: not a TrueType font", font.display());
        return ExitCode::FAILURE;
    }
    let panels: Result<Vec<Panel>, String> = args[1..].iter().map(|s| load_panel(s)).collect();
    let panels = match panels {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    match draw(Path::new(&args[0]), &panels) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}: {e}", args[0]);
            ExitCode::FAILURE
        }
    }
}
