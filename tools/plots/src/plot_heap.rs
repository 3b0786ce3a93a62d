//! Draws a heap from the side: the beads of a slice one diameter thick through the pile's axis
//! (vertical, through the centroid), as circles coloured by speed on a log scale, with the
//! angle of repose `wetbounce::heap::angle_of_repose` measures on the whole pile — the heap pictures of
//! docs/heaps.md.
//!
//!     plot_heap OUT_STEM FINAL.csv TITLE [--font FILE.ttf]
//!
//! FINAL.csv is what `rest SCENE EVERY_S FINAL.csv` writes (`id,x,y,z,diameter,speed`); the
//! figure goes to OUT_STEM.png and OUT_STEM.svg.

// The shared palette and legend are for line charts; this picture has neither.
#[allow(dead_code)]
mod plotting;

use glam::DVec3;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::process::ExitCode;

struct Bead {
    pos: DVec3,
    d: f64,
    speed: f64,
}

fn load(path: &str) -> Result<Vec<Bead>, String> {
    let mut reader = csv::Reader::from_path(path).map_err(|e| format!("{path}: {e}"))?;
    let mut beads = Vec::new();
    for (line, row) in reader.records().enumerate() {
        let row = row.map_err(|e| format!("{path}: {e}"))?;
        let num = |k: usize| -> Result<f64, String> {
            row.get(k)
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| format!("{path}: row {}: column {} is not a number", line + 2, k + 1))
        };
        beads.push(Bead { pos: DVec3::new(num(1)?, num(2)?, num(3)?), d: num(4)?, speed: num(5)? });
    }
    if beads.is_empty() {
        return Err(format!("{path}: no beads"));
    }
    Ok(beads)
}

/// Blue (1e-8 m/s or slower) to red (1e-2 m/s or faster), by log10 of the speed.
fn colour(speed: f64) -> RGBColor {
    let s = ((speed.max(1e-30).log10() + 8.0) / 6.0).clamp(0.0, 1.0);
    RGBColor(
        (255.0 * s) as u8,
        (60.0 + 80.0 * (1.0 - (2.0 * s - 1.0).abs())) as u8,
        (255.0 * (1.0 - s)) as u8,
    )
}

fn draw<DB: DrawingBackend>(area: DrawingArea<DB, Shift>, beads: &[Bead], title: &str) -> plotting::Drawn
where
    DB::ErrorType: 'static,
{
    area.fill(&WHITE)?;
    let n = beads.len() as f64;
    let centre = beads.iter().fold(DVec3::ZERO, |s, b| s + b.pos) / n;
    let d = beads.iter().map(|b| b.d).sum::<f64>() / n;
    let slice: Vec<&Bead> = beads.iter().filter(|b| (b.pos.y - centre.y).abs() < 0.5 * d).collect();
    let half = beads.iter().map(|b| (b.pos.x - centre.x).abs()).fold(0.0, f64::max) + d;
    let top = beads.iter().map(|b| b.pos.z).fold(0.0, f64::max) + d;
    let (w, h) = area.dim_in_pixel();
    let (x0, x1) = (1e3 * (centre.x - half), 1e3 * (centre.x + half));
    let mut chart = ChartBuilder::on(&area)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(x0..x1, 0.0..1e3 * top)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x (mm)")
        .y_desc("z (mm)")
        .label_style(("sans-serif", 15))
        .draw()?;
    // Pixels per mm along x, for the circles' radii.
    let scale = (w as f64 - 74.0) / (x1 - x0);
    let _ = h;
    chart.draw_series(slice.iter().map(|b| {
        let c = colour(b.speed);
        Circle::new((1e3 * b.pos.x, 1e3 * b.pos.z), (0.5e3 * b.d * scale).max(1.0) as i32, c.filled())
    }))?;
    Ok(())
}

fn run(args: &[String]) -> Result<(), String> {
    let [stem, csv, title] = args else {
        return Err("usage: plot_heap OUT_STEM FINAL.csv TITLE [--font FILE.ttf]".into());
    };
    let beads = load(csv)?;
    let pos: Vec<DVec3> = beads.iter().map(|b| b.pos).collect();
    let diameter: Vec<f64> = beads.iter().map(|b| b.d).collect();
    let angle = wetbounce::heap::angle_of_repose(&pos, &diameter)
        .map_or("no flank".to_string(), |a| format!("angle of repose {:.1}°", a.degrees));
    let fastest = beads.iter().map(|b| b.speed).fold(0.0, f64::max);
    let title = format!("{title}: {} beads, {angle}, fastest {fastest:.1e} m/s", beads.len());
    let size = (1000, 420);
    plotting::png_and_svg(Path::new(stem), size, |a| draw(a, &beads, &title), |a| draw(a, &beads, &title))
}

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let result = plotting::take_font_arg(&mut args).and_then(|font| {
        plotting::register(&font)?;
        run(&args)
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
