//! The picture of the contactor in docs/cfd.md: the water's flow and the drops in it, for the
//! flow OpenFOAM computed (`scenes/contactor.toml`) beside the empty pipe's Poiseuille profile
//! (`scenes/contactor_poiseuille.toml`), and the drops' residence times at the top outlet in
//! each.
//!
//!     cargo run --release --manifest-path tools/plots/Cargo.toml --bin contactor_picture -- [OUT_DIR] [--font FILE.ttf]
//!
//! writes `OUT_DIR/contactor_field.png` (default `out/figures`; `docs/figures` redraws the committed one) and prints the residence-time
//! statistics of both runs. It runs both scenes to their end (about 2 min of CPU each).
//!
//! Each column lies on its side, up to the right: the horizontal axis is the height `z`, the
//! vertical one the signed radius (`x` of the diametral plane `y = 0`). The colour is the
//! water's upward velocity `u_z` there. A drop is drawn at its height and at `±r`, its distance
//! from the axis with the sign of its `x`: the flow is axisymmetric, so the colour under a drop
//! is the flow it is in. The baffles are the cuts of their meshes by the plane `y = 0`.

#[allow(dead_code)]
mod plotting;

use glam::DVec3;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use wetbounce::Scene;
use wetbounce::particles::State;
use wetbounce::walls::Shape;

/// When the drops are drawn (s): the end of the injection, with drops all along the column.
const SNAPSHOT: f64 = 6.0;
/// Colour scale of `u_z` (m/s): saturates at ±this (the jets reach −0.04, the vortices +0.04).
const U_SCALE: f64 = 0.03;

/// One run of a scene: what the picture needs.
struct Run {
    title: String,
    /// The column's radius and height (m).
    radius: f64,
    height: f64,
    /// `u_z` (m/s) on a grid over (z, x) in the plane y = 0: `u[iz][ix]`.
    u: Vec<Vec<f64>>,
    /// Cuts of the baffles by the plane y = 0, as segments in (z, x) (m).
    baffles: Vec<[(f64, f64); 2]>,
    /// Drops at [`SNAPSHOT`]: (z, ±r) in m, and whether they are held on a baffle.
    drops: Vec<(f64, f64, bool)>,
    /// Residence times (s) of the drops the top outlet removed.
    residence: Vec<f64>,
    /// Drops still in the column at the end, and drops injected.
    left: usize,
    injected: usize,
}

/// The segment where the plane y = 0 cuts the triangle `t`, if it does.
fn cut(t: [DVec3; 3]) -> Option<[(f64, f64); 2]> {
    let mut ends = Vec::with_capacity(2);
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        if (a.y < 0.0) != (b.y < 0.0) {
            let s = a.y / (a.y - b.y);
            let p = a + s * (b - a);
            ends.push((p.z, p.x));
        }
    }
    (ends.len() == 2).then(|| [ends[0], ends[1]])
}

fn run(path: &Path, title: &str) -> Result<Run, String> {
    let scene = Scene::load(path).map_err(|e| e.to_string())?;
    let setup = &scene.setup;
    let (radius, height) = setup
        .walls
        .iter()
        .find_map(|w| match &w.shape {
            Shape::Cylinder(c) => Some((c.radius, c.base.z + c.hi)),
            _ => None,
        })
        .ok_or_else(|| format!("{}: no cylinder wall (the column's shell)", path.display()))?;
    let (nz, nx) = (840, 100);
    let u = (0..nz)
        .map(|i| {
            let z = (i as f64 + 0.5) / nz as f64 * height;
            (0..nx)
                .map(|j| {
                    let x = -radius + (j as f64 + 0.5) / nx as f64 * 2.0 * radius;
                    setup.fluid.flow.velocity(DVec3::new(x, 0.0, z), 0.0).z
                })
                .collect()
        })
        .collect();
    let mut baffles = Vec::new();
    for w in &setup.walls {
        if let Shape::Mesh(m) = &w.shape {
            let verts = m.mesh.vertices();
            for tri in m.mesh.indices() {
                let t = tri.map(|k| verts[k as usize]);
                baffles.extend(cut(t));
            }
        }
    }
    let mut sim = scene.simulation();
    sim.advance_to(SNAPSHOT);
    let p = &sim.world.particles;
    let drops = (0..p.len())
        .map(|i| {
            let x = p.pos[i];
            let r = x.x.hypot(x.y);
            (x.z, if x.x < 0.0 { -r } else { r }, p.state[i] == State::Held)
        })
        .collect();
    sim.advance_to(scene.duration);
    // The drops' way out is the outlet named "top" (the first one if none is).
    let top = setup.outlets.iter().position(|o| o.name == "top").unwrap_or(0);
    if setup.outlets.is_empty() {
        return Err(format!("{}: no outlet", path.display()));
    }
    let residence: Vec<f64> = sim.record.removed[top].iter().map(|r| r.residence_time).collect();
    let removed: usize = sim.record.removed.iter().map(Vec::len).sum();
    let left = sim.world.particles.len();
    Ok(Run {
        title: title.into(),
        radius,
        height,
        u,
        baffles,
        drops,
        residence,
        left,
        injected: left + removed,
    })
}

/// Blue (down) – white – red (up), saturating at ±[`U_SCALE`].
fn colour(uz: f64) -> RGBColor {
    let s = (uz / U_SCALE).clamp(-1.0, 1.0);
    let fade = |c: u8| (255.0 - (255.0 - f64::from(c)) * s.abs()) as u8;
    let (r, g, b) = if s < 0.0 { (0x21, 0x66, 0xac) } else { (0xb2, 0x18, 0x2b) };
    RGBColor(fade(r), fade(g), fade(b))
}

/// Percentile `q` (0–1) of sorted values.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn stats(r: &Run) -> String {
    let mut t = r.residence.clone();
    t.sort_by(f64::total_cmp);
    if t.is_empty() {
        return format!("{}: no drop reached the top outlet", r.title);
    }
    format!(
        "{}: {} of {} drops reached the top outlet ({} still in the column); residence time mean {:.2} s, p10 {:.2}, p50 {:.2}, p90 {:.2}, max {:.2}",
        r.title,
        t.len(),
        r.injected,
        r.left,
        t.iter().sum::<f64>() / t.len() as f64,
        percentile(&t, 0.1),
        percentile(&t, 0.5),
        percentile(&t, 0.9),
        t[t.len() - 1]
    )
}

fn draw_column<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, r: &Run) -> plotting::Drawn
where
    DB::ErrorType: 'static,
{
    let (zmax, rmax) = (r.height * 1e3, r.radius * 1e3);
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{}: u_z and the drops at t = {SNAPSHOT} s (up is to the right)", r.title),
            ("sans-serif", 19),
        )
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..zmax, -rmax..rmax)?;
    chart.configure_mesh().x_desc("z [mm]").y_desc("x [mm]").disable_mesh().draw()?;
    let (nz, nx) = (r.u.len(), r.u[0].len());
    let (dz, dx) = (zmax / nz as f64, 2.0 * rmax / nx as f64);
    chart.draw_series(r.u.iter().enumerate().flat_map(|(i, row)| {
        row.iter().enumerate().map(move |(j, &uz)| {
            let (z, x) = (i as f64 * dz, -rmax + j as f64 * dx);
            Rectangle::new([(z, x), (z + dz, x + dx)], colour(uz).filled())
        })
    }))?;
    chart.draw_series(r.baffles.iter().map(|[a, b]| {
        PathElement::new([(a.0 * 1e3, a.1 * 1e3), (b.0 * 1e3, b.1 * 1e3)], BLACK.stroke_width(2))
    }))?;
    chart.draw_series(
        r.drops.iter().filter(|d| !d.2).map(|&(z, x, _)| Circle::new((z * 1e3, x * 1e3), 2, BLACK.filled())),
    )?;
    chart.draw_series(
        r.drops
            .iter()
            .filter(|d| d.2)
            .map(|&(z, x, _)| Circle::new((z * 1e3, x * 1e3), 3, RGBColor(0xff, 0xbf, 0x00).filled())),
    )?;
    Ok(())
}

fn draw_residence<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, runs: &[Run]) -> plotting::Drawn
where
    DB::ErrorType: 'static,
{
    let all = runs.iter().flat_map(|r| r.residence.iter().copied());
    let (lo, hi) = all.fold((f64::INFINITY, 0.0f64), |(a, b), t| (a.min(t), b.max(t)));
    let bin = 0.1;
    let (lo, hi) = ((lo / bin).floor() * bin, (hi / bin).ceil() * bin + bin);
    let nb = ((hi - lo) / bin).round() as usize;
    let counts: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| {
            let mut c = vec![0.0; nb];
            for &t in &r.residence {
                c[(((t - lo) / bin) as usize).min(nb - 1)] += 1.0;
            }
            c
        })
        .collect();
    let top = counts.iter().flatten().copied().fold(0.0, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(area)
        .caption("Residence time of the drops at the top outlet", ("sans-serif", 19))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(50)
        .build_cartesian_2d(lo..hi, 0.0..top)?;
    chart.configure_mesh().x_desc("residence time [s]").y_desc(format!("drops per {bin} s")).draw()?;
    for (k, (r, c)) in runs.iter().zip(&counts).enumerate() {
        let colour = plotting::PALETTE[k];
        let steps = c
            .iter()
            .enumerate()
            .flat_map(|(i, &n)| [(lo + i as f64 * bin, n), (lo + (i + 1) as f64 * bin, n)]);
        let mean = r.residence.iter().sum::<f64>() / r.residence.len().max(1) as f64;
        chart
            .draw_series(LineSeries::new(steps, colour.stroke_width(2)))?
            .label(format!("{} (mean {mean:.2} s)", r.title))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
        chart.draw_series(LineSeries::new([(mean, 0.0), (mean, top)], colour.stroke_width(1)))?;
    }
    plotting::legend(&mut chart, SeriesLabelPosition::UpperRight, 15)
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, runs: &[Run]) -> plotting::Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (key, body) = root.split_vertically(30);
    key.draw(&Text::new(
        format!(
            "colour: water velocity u_z, blue down, red up, saturating at ±{} mm/s;  black: free drop;  amber: drop held on a baffle",
            U_SCALE * 1e3
        ),
        (12, 7),
        ("sans-serif", 16),
    ))?;
    let h = body.dim_in_pixel().1;
    let (columns, hist) = body.split_vertically(h * 62 / 100);
    for (area, r) in columns.split_evenly((runs.len(), 1)).iter().zip(runs) {
        draw_column(area, r)?;
    }
    draw_residence(&hist, runs)?;
    root.present()?;
    Ok(())
}

fn main() -> std::process::ExitCode {
    plotting::main_writing_into("out/figures", |out| {
        let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let runs = [
            run(&scenes.join("contactor.toml"), "OpenFOAM flow (contactor.toml)")?,
            run(&scenes.join("contactor_poiseuille.toml"), "Poiseuille flow (contactor_poiseuille.toml)")?,
        ];
        for r in &runs {
            println!("{}", stats(r));
        }
        let png = out.join("contactor_field.png");
        let root = BitMapBackend::new(&png, (1600, 1000)).into_drawing_area();
        draw(root, &runs).map_err(|e| format!("{}: {e}", png.display()))?;
        println!("wrote {}", png.display());
        Ok(())
    })
}
