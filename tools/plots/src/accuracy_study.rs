//! The work–precision study: what accuracy costs in time (`docs/accuracy.md`).
//!
//!     cargo run --release -p wetbounce-tools --bin accuracy_study [-- OUT_DIR] [--font FILE.ttf] [--quick]
//!
//! (`--quick`: a smoke test of the program with one step per decade down to 1e-3 s, which
//! leaves README.md and docs/accuracy.md alone.)
//! Runs the engine over the study's cases (`study.rs`: the Fig. 6 drop, the glass bead, a
//! dilute column of 1000 drops, closed-form Stokes settling), every integrator, time steps
//! from 1e-2 s down to 1e-5 s at 5 per decade (down to 1e-3 s for the column, whose smaller
//! steps would take minutes each), impacts located inside the step or detected at its end,
//! and the hold at contact on and off; then each accuracy setting (`dt = "auto"`). Each run's
//! errors are measured against the closed form (Stokes) or a reference run (rk4 at a much
//! smaller step, itself checked against rk4 at twice its step). Writes into OUT_DIR (default
//! `docs/accuracy`): `study.csv` (every run), `orders.csv` (the fitted convergence orders),
//! `table.md` (the cheapest method per error target, also written into README.md between its
//! `accuracy-table` markers), `settings.md` (the error each accuracy setting delivers) and
//! one work–precision plot per case, `CASE.png` and `CASE.svg`.
//!
//! Everything runs on one worker thread, so that the timings of different methods compare
//! like with like; they are still wall times on whatever machine runs the study.

mod plotting;
mod study;

use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use study::*;
use wetbounce::contact::ImpactLocation;
use wetbounce::integrate::IntegratorKind;
use wetbounce::scene::Accuracy;

/// One run of the study.
#[derive(Debug, Clone)]
struct Row {
    case: Case,
    /// The integrator's name, an accuracy setting's name, or "reference_check".
    method: String,
    integrator: IntegratorKind,
    location: ImpactLocation,
    hold: bool,
    dt: f64,
    steps: u64,
    wall: f64,
    cost: f64,
    errors: Errors,
}

/// Time steps of a case (s).
/// `--quick` (a smoke test of the program, not a study): 1 per decade, and down to 1e-3 s.
fn dts(case: Case, quick: bool) -> Vec<f64> {
    match (case, quick) {
        (Case::Column, false) => dt_range(1e-2, 1e-3, 5),
        (_, false) => dt_range(1e-2, 1e-5, 5),
        (_, true) => dt_range(1e-2, 1e-3, 1),
    }
}

/// Shortest total wall time of a measurement (s): short runs are repeated and the fastest kept.
const MIN_WALL: f64 = 0.02;

fn study_case(case: Case, quick: bool, rows: &mut Vec<Row>) {
    let holds: Vec<bool> =
        if case.has_walls() { vec![case.default_hold(), !case.default_hold()] } else { vec![false] };
    let locations: &[ImpactLocation] = if case.has_walls() { &LOCATIONS } else { &LOCATIONS[..1] };
    for hold in holds {
        let row = |method: &str, location, r: &Run, errors| Row {
            case,
            method: method.to_string(),
            integrator: r.integrator.expect("set by run"),
            location,
            hold,
            dt: r.dt,
            steps: r.steps,
            wall: r.wall,
            cost: r.cost(),
            errors,
        };
        let reference = (case != Case::Stokes).then(|| {
            let fixed = |dt| Stepping::Fixed { integrator: IntegratorKind::Rk4, dt };
            let dt = case.reference_dt();
            eprintln!("{}: reference, rk4, dt = {dt:e} s, hold {hold}", case.name());
            let reference = run(case, &case.scene(fixed(dt), ImpactLocation::InStep, hold), 0.0);
            // The reference's own error, estimated by the same run at twice its step.
            let check = run(case, &case.scene(fixed(2.0 * dt), ImpactLocation::InStep, hold), 0.0);
            rows.push(row(
                "reference_check",
                ImpactLocation::InStep,
                &check,
                errors(case, &check, Some(&reference)),
            ));
            reference
        });
        for &location in locations {
            for integrator in INTEGRATORS {
                eprintln!("{}: {} {} hold {hold}", case.name(), integrator.name(), location.name());
                for dt in dts(case, quick) {
                    let scene = case.scene(Stepping::Fixed { integrator, dt }, location, hold);
                    let r = run(case, &scene, MIN_WALL);
                    let e = errors(case, &r, reference.as_ref());
                    rows.push(row(integrator.name(), location, &r, e));
                }
            }
        }
        if hold == case.default_hold() {
            for a in Accuracy::ALL {
                let r = run(case, &case.scene(Stepping::Auto(a), ImpactLocation::InStep, hold), MIN_WALL);
                let e = errors(case, &r, reference.as_ref());
                rows.push(row(a.name(), ImpactLocation::InStep, &r, e));
            }
        }
    }
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| format!("{v:.4e}"))
}

fn write_csv(path: &Path, rows: &[Row]) -> std::io::Result<()> {
    let mut s = String::from(
        "case,method,integrator,impact_location,hold,dt,steps,wall_s,cost_s_per_particle_s,\
         err_position,err_impact_time,err_impact_speed,err_residence,err_max\n",
    );
    for r in rows {
        let e = &r.errors;
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.6e},{},{:.6e},{:.6e},{},{},{},{},{:.4e}",
            r.case.name(),
            r.method,
            r.integrator.name(),
            r.location.name(),
            r.hold,
            r.dt,
            r.steps,
            r.wall,
            r.cost,
            opt(e.position),
            opt(e.impact_time),
            opt(e.impact_speed),
            opt(e.residence),
            e.max()
        );
    }
    std::fs::write(path, s)
}

/// A method's line: rows of one case, integrator, location and hold, by decreasing dt.
fn line(rows: &[Row], case: Case, integ: IntegratorKind, loc: ImpactLocation, hold: bool) -> Vec<&Row> {
    rows.iter()
        .filter(|r| r.case == case && r.method == integ.name() && r.location == loc && r.hold == hold)
        .collect()
}

/// Least-squares slope of log(error) against log(dt) over the points whose error lies between
/// the round-off floor and 5 % (the asymptotic range), with at least 3 points.
fn fitted_order(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> =
        points.iter().filter(|p| p.1 > 1e-11 && p.1 < 5e-2).map(|p| (p.0.ln(), p.1.ln())).collect();
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    Some(sxy / sxx)
}

type Measure = (&'static str, fn(&Errors) -> Option<f64>);

const MEASURES: [Measure; 4] = [
    ("position", |e| e.position),
    ("impact time", |e| e.impact_time),
    ("impact speed", |e| e.impact_speed),
    ("mean residence", |e| e.residence),
];

fn measures(case: Case) -> Vec<Measure> {
    match case {
        Case::Fig6 | Case::GlassBead => MEASURES[..3].to_vec(),
        Case::Column => vec![MEASURES[3], MEASURES[2]],
        Case::Stokes => vec![MEASURES[0]],
    }
}

fn write_orders(path: &Path, rows: &[Row]) -> std::io::Result<String> {
    let mut csv = String::from("case,integrator,impact_location,hold,measure,fitted_order\n");
    let mut md = String::from(
        "| case | hold | impact location | measure | euler | rk2 | rk4 | exponential |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for case in Case::ALL {
        let holds: Vec<bool> =
            if case.has_walls() { vec![case.default_hold(), !case.default_hold()] } else { vec![false] };
        let locations: &[ImpactLocation] = if case.has_walls() { &LOCATIONS } else { &LOCATIONS[..1] };
        for hold in holds {
            for &loc in locations {
                for (name, f) in measures(case) {
                    let mut cells = Vec::new();
                    for integ in INTEGRATORS {
                        let pts: Vec<(f64, f64)> = line(rows, case, integ, loc, hold)
                            .iter()
                            .filter_map(|r| f(&r.errors).map(|e| (r.dt, e)))
                            .collect();
                        let o = fitted_order(&pts);
                        let _ = writeln!(
                            csv,
                            "{},{},{},{},{name},{}",
                            case.name(),
                            integ.name(),
                            loc.name(),
                            hold,
                            opt(o)
                        );
                        cells.push(o.map_or("–".to_string(), |o| format!("{o:.2}")));
                    }
                    let _ = writeln!(
                        md,
                        "| {} | {} | {} | {name} | {} |",
                        case.name(),
                        if hold { "on" } else { "off" },
                        loc.name(),
                        cells.join(" | ")
                    );
                }
            }
        }
    }
    std::fs::write(path, csv)?;
    Ok(md)
}

/// The README table: for each case and error target, the cheapest run (in the case's own
/// physics, hold as shipped) whose error is within the target.
fn cheapest_table(rows: &[Row]) -> String {
    let mut s =
        String::from("| case | error ≤ 1 % | error ≤ 0.1 % | error ≤ 0.01 % |\n| --- | --- | --- | --- |\n");
    for case in Case::ALL {
        let mut cells = Vec::new();
        for target in [1e-2, 1e-3, 1e-4] {
            let best = rows
                .iter()
                .filter(|r| r.case == case && r.hold == case.default_hold() && r.method != "reference_check")
                .filter(|r| r.errors.max() <= target)
                .min_by(|a, b| a.cost.total_cmp(&b.cost));
            cells.push(best.map_or("not reached".to_string(), |r| {
                let loc = if r.location == ImpactLocation::EndOfStep { ", end of step" } else { "" };
                let how = if INTEGRATORS.iter().any(|i| i.name() == r.method) {
                    format!("{} Δt = {:.2e} s{loc}", r.method, r.dt)
                } else {
                    format!("`{}` ({} Δt = {:.2e} s)", r.method, r.integrator.name(), r.dt)
                };
                format!("{how}: {:.2e} s", r.cost)
            }));
        }
        let _ = writeln!(s, "| {} | {} |", case.title(), cells.join(" | "));
    }
    s
}

/// The error each accuracy setting delivered, per case.
fn settings_table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| case | setting | integrator | Δt [s] | error (largest measure) | promised | cost [s per particle per s] |\n| --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for case in Case::ALL {
        for a in Accuracy::ALL {
            if let Some(r) = rows.iter().find(|r| r.case == case && r.method == a.name()) {
                let _ = writeln!(
                    s,
                    "| {} | `{}` | {} | {:.3e} | {:.2e} | {:.0e} | {:.2e} |",
                    case.name(),
                    a.name(),
                    r.integrator.name(),
                    r.dt,
                    r.errors.max(),
                    a.target_error(),
                    r.cost
                );
            }
        }
    }
    s
}

/// Replaces the text between `<!-- NAME -->` and `<!-- /NAME -->` in `file`.
fn splice(file: &Path, name: &str, text: &str) -> Result<(), String> {
    let src = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let (open, close) = (format!("<!-- {name} -->"), format!("<!-- /{name} -->"));
    let (Some(a), Some(b)) = (src.find(&open), src.find(&close)) else {
        return Err(format!("{}: no {open} … {close} markers", file.display()));
    };
    let out = format!("{}{open}\n{text}{}", &src[..a], &src[b..]);
    std::fs::write(file, out).map_err(|e| format!("{}: {e}", file.display()))
}

/// Error values are drawn no lower than this (an exact method's round-off).
const FLOOR: f64 = 1e-16;

fn draw_case<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, rows: &[Row], case: Case) -> plotting::Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(40);
    title.draw(&Text::new(
        format!("{}: relative error against cost", case.title()),
        (14, 10),
        ("sans-serif", 22).into_font(),
    ))?;
    let combos: Vec<(ImpactLocation, bool)> = if case.has_walls() {
        let h = case.default_hold();
        vec![
            (ImpactLocation::InStep, h),
            (ImpactLocation::EndOfStep, h),
            (ImpactLocation::InStep, !h),
            (ImpactLocation::EndOfStep, !h),
        ]
    } else {
        vec![(ImpactLocation::InStep, false)]
    };
    let ms = measures(case);
    let case_rows: Vec<&Row> =
        rows.iter().filter(|r| r.case == case && r.method != "reference_check").collect();
    let (mut c0, mut c1) = (f64::INFINITY, 0.0f64);
    for r in &case_rows {
        c0 = c0.min(r.cost);
        c1 = c1.max(r.cost);
    }
    let (c0, c1) = (c0 / 1.5, c1 * 1.5);
    let areas = body.split_evenly((combos.len(), ms.len()));
    for (k, area) in areas.iter().enumerate() {
        let (loc, hold) = combos[k / ms.len()];
        let (mname, f) = ms[k % ms.len()];
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!(
                    "{mname}; impacts {}, hold {}",
                    loc.name().replace('_', " "),
                    if hold { "on" } else { "off" }
                ),
                ("sans-serif", 17),
            )
            .margin(8)
            .x_label_area_size(38)
            .y_label_area_size(62)
            .build_cartesian_2d((c0..c1).log_scale(), (FLOOR..2.0).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("cost [s per particle per s]")
            .y_desc("relative error")
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .light_line_style(WHITE)
            .draw()?;
        for (i, integ) in INTEGRATORS.into_iter().enumerate() {
            let color = plotting::PALETTE[i];
            let pts: Vec<(f64, f64)> = line(rows, case, integ, loc, hold)
                .iter()
                .filter_map(|r| f(&r.errors).map(|e| (r.cost, e.clamp(FLOOR, 1.0))))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?
                .label(integ.name())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3)));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
        }
        if loc == ImpactLocation::InStep && hold == case.default_hold() {
            for a in Accuracy::ALL {
                if let Some(r) = case_rows.iter().find(|r| r.method == a.name())
                    && let Some(e) = f(&r.errors)
                {
                    let p = (r.cost, e.clamp(FLOOR, 1.0));
                    chart.draw_series([TriangleMarker::new(p, 7, BLACK.filled())])?;
                    chart.draw_series([Text::new(
                        a.name().to_string(),
                        p,
                        ("sans-serif", 14).into_font(),
                    )])?;
                }
            }
        }
        plotting::legend(&mut chart, SeriesLabelPosition::LowerLeft, 14)?;
    }
    root.present()?;
    Ok(())
}

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let font = match plotting::take_font_arg(&mut args) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let quick = args.iter().any(|a| a == "--quick");
    args.retain(|a| a != "--quick");
    let out = PathBuf::from(args.first().map_or("docs/accuracy", |s| s.as_str()));
    if let Err(e) = plotting::register(&font) {
        eprintln!("error: --font {e}");
        return ExitCode::FAILURE;
    }
    if let Err(e) = std::fs::create_dir_all(&out) {
        eprintln!("error: {}: {e}", out.display());
        return ExitCode::FAILURE;
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a thread pool");
    let started = std::time::Instant::now();
    let mut rows = Vec::new();
    pool.install(|| {
        for case in Case::ALL {
            study_case(case, quick, &mut rows);
        }
    });
    eprintln!("study: {} runs in {:.0} s", rows.len(), started.elapsed().as_secs_f64());
    let result = (|| -> Result<(), String> {
        fn io(p: &Path) -> impl Fn(std::io::Error) -> String + '_ {
            move |e| format!("{}: {e}", p.display())
        }
        let p = out.join("study.csv");
        write_csv(&p, &rows).map_err(io(&p))?;
        let p = out.join("orders.csv");
        let orders = write_orders(&p, &rows).map_err(io(&p))?;
        let table = cheapest_table(&rows);
        let settings = settings_table(&rows);
        let checks: String = rows
            .iter()
            .filter(|r| r.method == "reference_check")
            .map(|r| {
                format!(
                    "| {} | {} | {:.0e} | {:.2e} |\n",
                    r.case.name(),
                    if r.hold { "on" } else { "off" },
                    r.dt / 2.0,
                    r.errors.max()
                )
            })
            .collect();
        let checks = format!(
            "| case | hold | reference Δt [s] | error of rk4 at 2Δt against it |\n| --- | --- | --- | --- |\n{checks}"
        );
        let p = out.join("tables.md");
        let text = format!(
            "# Work–precision study: tables\n\nWritten by `cargo run --release -p wetbounce-tools --bin accuracy_study`; \
             do not edit.\n\n## Cheapest method per error target\n\n{table}\n## Accuracy settings\n\n{settings}\n\
             ## Fitted convergence orders\n\n{orders}\n## References\n\n{checks}"
        );
        std::fs::write(&p, text).map_err(io(&p))?;
        for case in Case::ALL {
            let n = if case.has_walls() { 4 } else { 1 };
            let size = ((460 * measures(case).len() as u32 + 40).max(640), 40 + 380 * n);
            plotting::png_and_svg(
                &out.join(case.name()),
                size,
                |a| draw_case(a, &rows, case),
                |a| draw_case(a, &rows, case),
            )?;
        }
        let readme = Path::new("README.md");
        if readme.exists() && !quick {
            splice(readme, "accuracy-table", &table)?;
        }
        let doc = Path::new("docs/accuracy.md");
        if doc.exists() && !quick {
            splice(doc, "accuracy-settings", &settings)?;
            splice(doc, "accuracy-orders", &orders)?;
            splice(doc, "accuracy-references", &checks)?;
        }
        Ok(())
    })();
    match result {
        Ok(()) => {
            println!("{}", cheapest_table(&rows));
            println!("{}", settings_table(&rows));
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
