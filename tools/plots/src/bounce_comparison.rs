//! Two comparisons of a bead bouncing on a floor, height against time, into `OUT_DIR`
//! (default `out/figures/`; `docs/figures` redraws the committed ones; CSV, PNG and SVG):
//!
//!     cargo run --release -p wetbounce-tools --bin bounce_comparison [-- OUT_DIR] [--font FILE.ttf]
//!
//! - `history_gondret`: the 3 mm steel bead in silicone oil of Gondret, Lance & Petit (2002),
//!   `scenes/steel_bead_oil.toml` (L06's rule, no history force) beside
//!   `scenes/steel_bead_oil_history.toml` (the `history` effect, docs/physics.md §10),
//!   `scenes/steel_bead_oil_lubrication.toml` (`wall_lubrication` and the `e` rule, §8) and
//!   `scenes/steel_bead_oil_lubrication_history.toml` (both);
//! - `lubrication_glass_bead`: the 2.5 mm glass bead in water, `scenes/glass_bead.toml` (L06's
//!   ε(St) rule) beside `scenes/glass_bead_lubrication.toml` (`wall_lubrication` and the `e`
//!   rule, docs/physics.md §8).
//!
//! Each scene runs as shipped, through the library, and the gap under the bead (its height less
//! its radius) is taken at every output interval. Printed per scene: each contact's time,
//! impact speed, restitution and outcome, and the highest point after each rebound.

mod plotting;

use plotters::coord::Shift;
use plotters::prelude::*;
use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use wetbounce::{Outcome, Scene};

type Drawn = plotting::Drawn;

/// One scene's run: its label, the gap under the bead (mm) against time (s), its contacts.
struct Run {
    label: &'static str,
    path: Vec<(f64, f64)>,
}

fn run_scene(file: &str, label: &'static str) -> Result<Run, String> {
    let scene = Scene::load(Path::new(file)).map_err(|e| e.to_string())?;
    let (duration, interval) = (scene.duration, scene.output_interval);
    let mut sim = scene.simulation();
    let radius = 0.5 * sim.world.particles.diameter[0];
    let mut path = vec![(0.0, 1e3 * (sim.world.particles.pos[0].z - radius))];
    let frames = (duration / interval).round() as usize;
    println!("{file} ({label}):");
    let mut peak: Option<f64> = None;
    for i in 1..=frames {
        let t = i as f64 * interval;
        sim.advance_to(t);
        let gap = 1e3 * (sim.world.particles.pos[0].z - radius);
        path.push((t, gap));
        for e in sim.record.events.drain(..) {
            if let Some(p) = peak.take() {
                println!("    highest point after the last rebound: {p:.3} mm");
            }
            let outcome = match e.outcome {
                Outcome::Bounced => "bounced",
                Outcome::Held => "held",
                Outcome::Deposited => "deposited",
            };
            println!(
                "  contact at t = {:.4} s: impact speed {:.4} m/s, St {:.1}, restitution {:.3}, {outcome}",
                e.time, e.normal_speed, e.st, e.eps
            );
            if e.outcome == Outcome::Bounced {
                peak = Some(0.0);
            }
        }
        if let Some(p) = peak.as_mut() {
            *p = p.max(gap);
        }
    }
    if let Some(p) = peak {
        println!("    highest point after the last rebound (to the end): {p:.3} mm");
    }
    Ok(Run { label, path })
}

fn figure<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, title: &str, runs: &[Run]) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let t_max = runs.iter().flat_map(|r| r.path.iter().map(|p| p.0)).fold(0.0, f64::max);
    let z_max = runs.iter().flat_map(|r| r.path.iter().map(|p| p.1)).fold(0.0, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d(0.0..t_max, 0.0..1.05 * z_max)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("gap under the bead (mm)")
        .light_line_style(WHITE)
        .draw()?;
    for (k, run) in runs.iter().enumerate() {
        let color = plotting::PALETTE[k];
        chart
            .draw_series(LineSeries::new(run.path.iter().copied(), color.stroke_width(2)))?
            .label(run.label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3)));
    }
    plotting::legend(&mut chart, SeriesLabelPosition::UpperRight, 14)?;
    root.present()?;
    Ok(())
}

fn write_csv(file: &Path, runs: &[Run]) -> Result<(), String> {
    let mut text = String::from("t_s");
    for r in runs {
        text += &format!(",gap_mm ({})", r.label);
    }
    text.push('\n');
    for i in 0..runs[0].path.len() {
        text += &format!("{:.6}", runs[0].path[i].0);
        for r in runs {
            text += &format!(",{:.6}", r.path[i].1);
        }
        text.push('\n');
    }
    let mut f = std::fs::File::create(file).map_err(|e| format!("{}: {e}", file.display()))?;
    f.write_all(text.as_bytes()).map_err(|e| format!("{}: {e}", file.display()))
}

fn compare(out: &Path, stem: &str, title: &str, scenes: &[(&str, &'static str)]) -> Result<(), String> {
    let runs = scenes.iter().map(|&(file, label)| run_scene(file, label)).collect::<Result<Vec<_>, _>>()?;
    write_csv(&out.join(format!("{stem}.csv")), &runs)?;
    plotting::png_and_svg(
        &out.join(stem),
        (900, 500),
        |a| figure(a, title, &runs),
        |a| figure(a, title, &runs),
    )?;
    println!("wrote {}/{stem} (.csv, .png, .svg)", out.display());
    Ok(())
}

fn run(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    compare(
        out,
        "history_gondret",
        "3 mm steel bead on glass in silicone oil (Gondret et al. 2002 case, St ≈ 150)",
        &[
            ("scenes/steel_bead_oil.toml", "L06's ε(St) rule"),
            ("scenes/steel_bead_oil_history.toml", "L06's rule + history force"),
            ("scenes/steel_bead_oil_lubrication.toml", "wall lubrication + e rule"),
            ("scenes/steel_bead_oil_lubrication_history.toml", "lubrication + e rule + history force"),
        ],
    )?;
    compare(
        out,
        "lubrication_glass_bead",
        "2.5 mm glass bead on glass in water",
        &[
            ("scenes/glass_bead.toml", "L06's ε(St) rule"),
            ("scenes/glass_bead_lubrication.toml", "wall lubrication + e rule"),
        ],
    )
}

fn main() -> ExitCode {
    plotting::main_writing_into("out/figures", run)
}
