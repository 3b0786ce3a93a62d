//! L06's figures, regenerated from the engine's own correlations and simulation into
//! `OUT_DIR` (default `out/figures/`; `docs/figures` redraws the committed ones; PNG and SVG):
//!
//!     cargo run --release -p wetbounce-tools --bin paper_figures [-- OUT_DIR] [--font FILE.ttf]
//!
//! - `fig1_restitution`: `ε/ε_max` against St, L06 eq. 2 with β = 35 and St_c = 10;
//! - `fig3_contact_time_correction`: the fluid correction of L06 eq. 4 (`t_c / t_Hertz`)
//!   against St, its viscous factor alone and with the added-mass factor of glass and steel
//!   spheres in water;
//! - `fig4_drop_contact_time`: L06 eq. 5's contact time of drops of the paper's liquids,
//!   normalised by `sqrt((ρp + C_Mwall ρ) d³/σ)`, against d (the model's constant π√(5/96)),
//!   and in ms;
//! - `fig5_tc_over_tr`: `t_c / t_r` against St at terminal velocity (the engine's bisection
//!   solver with Schiller–Naumann drag) for toluene drops in water, water drops in air, glass
//!   spheres in water and in air, d from 10 µm to 10 mm;
//! - `fig6_drop`: height and velocity of the 2.75 mm toluene drop of `scenes/toluene_drop.toml`
//!   from the engine (rk2, Δt = 1e-4 s, as shipped).
//!
//! L06's measured points are not reproduced (the paper's data are not in this repository):
//! every curve is the model, as the engine computes it.

mod plotting;

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use wetbounce::Scene;
use wetbounce::correlations::{
    drag_factor_schiller_naumann, drop_contact_time, immersed_solid_contact_time, immersed_solid_correction,
    relaxation_time, restitution, stokes_number, terminal_velocity,
};
use wetbounce::particles::State;

type Drawn = plotting::Drawn;

/// `n` points spaced evenly in log between `a` and `b`.
fn logspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| a * (b / a).powf(i as f64 / (n - 1) as f64)).collect()
}

fn fig1<DB: DrawingBackend>(root: DrawingArea<DB, Shift>) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("Fig. 1: ε/ε_max = exp(−β/St), β = 35 (L06 eq. 2)", ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d((1.0..1e4).log_scale(), 0.0..1.05)?;
    chart.configure_mesh().x_desc("St").y_desc("ε / ε_max").light_line_style(WHITE).draw()?;
    // The correlation over its whole range, and what the engine applies (0 below St_c = 10).
    let st = logspace(1.0, 1e4, 400);
    chart
        .draw_series(LineSeries::new(
            st.iter().map(|&s| (s, (-35.0 / s).exp())),
            BLUE.mix(0.35).stroke_width(2),
        ))?
        .label("exp(−35/St)")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], BLUE.mix(0.35).stroke_width(3)));
    let engine: Vec<(f64, f64)> = st.iter().map(|&s| (s, restitution(s, 1.0, 35.0, 10.0).value())).collect();
    chart
        .draw_series(LineSeries::new(engine, RED.stroke_width(2)))?
        .label("engine, St_c = 10 (no rebound below)")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], RED.stroke_width(3)));
    chart.draw_series(LineSeries::new([(10.0, 0.0), (10.0, 1.05)], BLACK.mix(0.5)))?;
    chart.draw_series([Text::new("St_c = 10", (11.0, 0.9), ("sans-serif", 15).into_font())])?;
    plotting::legend(&mut chart, SeriesLabelPosition::UpperLeft, 15)?;
    root.present()?;
    Ok(())
}

fn fig3<DB: DrawingBackend>(root: DrawingArea<DB, Shift>) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("Fig. 3: contact-time correction of L06 eq. 4, t_c / t_Hertz", ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d((1.0..1e4).log_scale(), (1.0..20.0).log_scale())?;
    chart.configure_mesh().x_desc("St").y_desc("t_c / t_Hertz").light_line_style(WHITE).draw()?;
    let st = logspace(1.0, 1e4, 400);
    let curves: [(&str, Option<f64>, RGBColor); 3] = [
        ("1/(1 − 0.85 St^−0.1) (viscous factor)", None, plotting::PALETTE[0]),
        ("glass in water (ρp = 2540)", Some(2540.0), plotting::PALETTE[1]),
        ("steel in water (ρp = 7800)", Some(7800.0), plotting::PALETTE[2]),
    ];
    for (label, rho_p, color) in curves {
        let pts: Vec<(f64, f64)> = st
            .iter()
            .filter_map(|&s| match rho_p {
                None => immersed_solid_correction(1.0, 0.0, s).map(|c| (s, c)),
                Some(r) => immersed_solid_correction(r, 998.2, s).map(|c| (s, c)),
            })
            .filter(|p| p.1 < 20.0)
            .collect();
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))?
            .label(label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3)));
    }
    // L06 fitted the correction for 17 < St < 10³.
    for s in [17.0, 1e3] {
        chart.draw_series(LineSeries::new([(s, 1.0), (s, 20.0)], BLACK.mix(0.4)))?;
    }
    chart.draw_series([Text::new(
        "fitted range 17 < St < 10³",
        (19.0, 12.0),
        ("sans-serif", 15).into_font(),
    )])?;
    plotting::legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
    root.present()?;
    Ok(())
}

/// A drop liquid in a surrounding fluid: name, ρp, ρ, σ.
const DROPS: [(&str, f64, f64, f64); 3] = [
    ("toluene in water (σ = 0.026 N/m)", 860.0, 997.0, 0.026),
    ("water in air (σ = 0.072 N/m)", 998.2, 1.2, 0.072),
    ("glycerol in air (σ = 0.063 N/m)", 1260.0, 1.2, 0.063),
];

fn fig4<DB: DrawingBackend>(root: DrawingArea<DB, Shift>) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(560);
    let d = logspace(0.1e-3, 10e-3, 200);
    {
        let mut chart = ChartBuilder::on(&left)
            .caption("Fig. 4: normalised drop contact time (L06 eq. 5)", ("sans-serif", 19))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(60)
            .build_cartesian_2d((0.1..10.0).log_scale(), 0.0..1.0)?;
        chart
            .configure_mesh()
            .x_desc("d [mm]")
            .y_desc("t_c / sqrt((ρp + 0.73ρ) d³/σ)")
            .light_line_style(WHITE)
            .draw()?;
        for (i, (name, rp, r, s)) in DROPS.into_iter().enumerate() {
            let color = plotting::PALETTE[i];
            let pts: Vec<(f64, f64)> = d
                .iter()
                .map(|&d| {
                    (d * 1e3, drop_contact_time(rp, r, d, s) / ((rp + 0.73 * r) * d * d * d / s).sqrt())
                })
                .collect();
            chart
                .draw_series(LineSeries::new(pts, color.stroke_width(6 - 2 * i as u32)))?
                .label(name)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3)));
        }
        let c = std::f64::consts::PI * (5.0f64 / 96.0).sqrt();
        chart.draw_series([Text::new(
            format!("π √(5/96) = {c:.3}"),
            (0.15, c + 0.06),
            ("sans-serif", 15).into_font(),
        )])?;
        plotting::legend(&mut chart, SeriesLabelPosition::LowerRight, 14)?;
    }
    let mut chart = ChartBuilder::on(&right)
        .caption("the same contact times", ("sans-serif", 19))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d((0.1..10.0).log_scale(), (0.01..1000.0).log_scale())?;
    chart.configure_mesh().x_desc("d [mm]").y_desc("t_c [ms]").light_line_style(WHITE).draw()?;
    for (i, (name, rp, r, s)) in DROPS.into_iter().enumerate() {
        let color = plotting::PALETTE[i];
        let pts: Vec<(f64, f64)> =
            d.iter().map(|&d| (d * 1e3, drop_contact_time(rp, r, d, s) * 1e3)).collect();
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))?
            .label(name)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3)));
    }
    plotting::legend(&mut chart, SeriesLabelPosition::UpperLeft, 14)?;
    root.present()?;
    Ok(())
}

/// One system of Fig. 5: name, ρp, ρ, μ, and σ for a drop or `None` for glass on glass.
const SYSTEMS: [(&str, f64, f64, f64, Option<f64>); 4] = [
    ("toluene drops in water", 860.0, 997.0, 0.89e-3, Some(0.026)),
    ("water drops in air", 998.2, 1.2, 1.81e-5, Some(0.072)),
    ("glass spheres in water", 2540.0, 998.2, 1.002e-3, None),
    ("glass spheres in air", 2540.0, 1.2, 1.81e-5, None),
];

/// `(St, t_c/t_r)` at terminal velocity for diameters from 10 µm to 10 mm.
fn fig5_curve(rho_p: f64, rho: f64, mu: f64, sigma: Option<f64>) -> Vec<(f64, f64)> {
    logspace(10e-6, 10e-3, 300)
        .into_iter()
        .filter_map(|d| {
            let tv = terminal_velocity(rho_p, rho, d, mu, 9.81, drag_factor_schiller_naumann);
            let st = stokes_number(rho_p, rho, tv.speed, d, mu);
            let t_r = relaxation_time(rho_p, rho, 0.5, d, mu, drag_factor_schiller_naumann(tv.reynolds));
            let t_c = match sigma {
                Some(s) => drop_contact_time(rho_p, rho, d, s),
                // Glass (E = 63 GPa, ν = 0.22) on a glass wall.
                None => immersed_solid_contact_time(rho_p, rho, 63e9, 0.22, 63e9, 0.22, d, tv.speed, st)?,
            };
            Some((st, t_c / t_r))
        })
        .collect()
}

fn fig5<DB: DrawingBackend>(root: DrawingArea<DB, Shift>) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("Fig. 5: t_c / t_r at terminal velocity, d = 10 µm to 10 mm", ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d((1e-3..1e6).log_scale(), (1e-7..1e2).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("St")
        .y_desc("t_c / t_r")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .light_line_style(WHITE)
        .draw()?;
    for (i, (name, rp, r, mu, s)) in SYSTEMS.into_iter().enumerate() {
        let color = plotting::PALETTE[i];
        chart
            .draw_series(LineSeries::new(fig5_curve(rp, r, mu, s), color.stroke_width(2)))?
            .label(name)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3)));
    }
    chart.draw_series(LineSeries::new([(10.0, 1e-7), (10.0, 1e2)], BLACK.mix(0.4)))?;
    chart.draw_series([Text::new("St_c = 10", (12.0, 20.0), ("sans-serif", 15).into_font())])?;
    plotting::legend(&mut chart, SeriesLabelPosition::LowerLeft, 15)?;
    root.present()?;
    Ok(())
}

/// One sample of the Fig. 6 drop: time (s), centre height z (m), vertical velocity (m/s), state.
type Sample = (f64, f64, f64, State);

/// The Fig. 6 drop every millisecond, and its impact times.
struct Fig6 {
    samples: Vec<Sample>,
    impacts: Vec<f64>,
}

fn fig6_data() -> Result<Fig6, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/toluene_drop.toml");
    let scene = Scene::load(&path).map_err(|e| e.to_string())?;
    let mut sim = scene.simulation();
    let mut out = Fig6 { samples: Vec::new(), impacts: Vec::new() };
    for k in 0..=1000 {
        sim.advance_to(k as f64 * 1e-3);
        out.samples.push((
            sim.world.time,
            sim.world.particles.pos[0].z,
            sim.world.particles.vel[0].z,
            sim.world.particles.state[0],
        ));
        out.impacts.extend(sim.record.events.drain(..).map(|e| e.time));
    }
    Ok(out)
}

fn fig6<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, data: &Fig6) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(360);
    // The first 0.6 s: the rise, both holds and the deposit (the drop then rests to 1 s).
    let color = |s: State| match s {
        State::Free => plotting::PALETTE[0],
        State::Held | State::PairHeld => plotting::PALETTE[3],
        State::Resting => plotting::PALETTE[1],
    };
    type Panel<'a, DB> = (&'a DrawingArea<DB, Shift>, &'a str, fn(&Sample) -> f64, std::ops::Range<f64>);
    let panels: [Panel<DB>; 2] = [
        (&top, "centre height z [mm] (wall at 0; touching at −1.375)", |s| s.1 * 1e3, -28.5..0.5),
        (&bottom, "vertical velocity [mm/s]", |s| s.2 * 1e3, -40.0..90.0),
    ];
    for (k, (area, ylabel, f, range)) in panels.into_iter().enumerate() {
        let caption = if k == 0 {
            "Fig. 6: 2.75 mm toluene drop rising to a wall in water (engine, rk2, Δt = 1e-4 s)"
        } else {
            "blue: free; orange: held for t_c; red: resting (St < St_c)"
        };
        let mut chart = ChartBuilder::on(area)
            .caption(caption, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..0.6, range.clone())?;
        chart.configure_mesh().x_desc("t [s]").y_desc(ylabel).light_line_style(WHITE).draw()?;
        for w in data.samples.windows(2) {
            chart.draw_series(LineSeries::new(
                [(w[0].0, f(&w[0])), (w[1].0, f(&w[1]))],
                color(w[0].3).stroke_width(3),
            ))?;
        }
        for &t in &data.impacts {
            chart.draw_series(LineSeries::new([(t, range.start), (t, range.end)], BLACK.mix(0.25)))?;
        }
    }
    root.present()?;
    Ok(())
}

// The closures around `fig1` … are needed: a generic function item names one backend
// lifetime, the closures accept any (clippy's suggestion does not compile).
#[allow(clippy::redundant_closure)]
fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let font = match plotting::take_font_arg(&mut args) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let out = PathBuf::from(args.first().map_or("out/figures", |s| s.as_str()));
    let result = (|| -> Result<(), String> {
        plotting::register(&font)?;
        std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        let size = (900, 560);
        plotting::png_and_svg(&out.join("fig1_restitution"), size, |a| fig1(a), |a| fig1(a))?;
        plotting::png_and_svg(&out.join("fig3_contact_time_correction"), size, |a| fig3(a), |a| fig3(a))?;
        plotting::png_and_svg(&out.join("fig4_drop_contact_time"), (1120, 520), |a| fig4(a), |a| fig4(a))?;
        plotting::png_and_svg(&out.join("fig5_tc_over_tr"), size, |a| fig5(a), |a| fig5(a))?;
        let data = fig6_data()?;
        plotting::png_and_svg(&out.join("fig6_drop"), (900, 720), |a| fig6(a, &data), |a| fig6(a, &data))?;
        Ok(())
    })();
    match result {
        Ok(()) => {
            println!(
                "wrote {}/fig1_restitution, fig3_contact_time_correction, fig4_drop_contact_time, fig5_tc_over_tr, fig6_drop (.png, .svg)",
                out.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
