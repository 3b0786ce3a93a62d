//! The restitution that emerges from the resolved mode (wall lubrication and the `e` rule,
//! docs/physics.md §8), against L06's `exp(−35/St)`, into `OUT_DIR` (default
//! `out/figures/`; `docs/figures` redraws the committed ones; CSV, PNG and SVG):
//!
//!     cargo run --release -p wetbounce-tools --bin restitution_emergent [-- OUT_DIR] [--font FILE.ttf]
//!
//! Single normal impacts on a floor: a 2 mm glass-like bead (ρp = 2500 kg/m³, e = ε_max = 0.97,
//! instantaneous contact) and a 2 mm drop (ρp = 1500 kg/m³, σ = 0.03 N/m, e = ε_max = 0.91,
//! held for `t_c` of L06 eq. 5 by `contact_time`) in a liquid of ρ = 1000 kg/m³, Stokes drag,
//! added mass, gravity and buoyancy, for roughnesses `h_r/a` = 1e-5, 1e-4, 1e-3, 1e-2 (the
//! kind's; the floor has none) and St from 1 to 10⁴ (25 values, 6 per decade).
//!
//! The particle approaches at its terminal speed `V0` = 0.1 m/s: it starts at a lubrication gap
//! of 10 radii (where the wall terms begin, tapered to zero, and Brenner's `λ⊥ − 1` is 0.11)
//! moving at `V0`, and the viscosity sets St = (ρp + ρ/2) V0 d / (9 μ), while gravity is scaled
//! with μ, `g = 18 μ V0 / ((ρp − ρ) d²)`, so that `V0` is the Stokes terminal speed: the bulk
//! drag balances the apparent weight and only the wall decelerates the particle before contact
//! (as in L06's experiments, where the particle arrives at terminal speed). In these units the
//! result depends only on St, `h_r/a`, ρp/ρ and `e`.
//!
//! ε is measured as L06 does: the release speed — the largest upward speed after the first
//! contact — over the speed before the particle feels the wall, `V0` at 10 radii. A particle
//! that the film stops (deposited, `e St_imp < ln 2`) has ε = 0. Printed per roughness and kind:
//! the critical St (bracketed by the grid: the highest St without a rebound and the lowest with
//! one) and the β of the least-squares fit of `ln(ε/e) = −β/St` over the rebounding points, and
//! over those with St ≥ 50 alone (the fit over all is dominated by the few points just above the
//! cut-off, where `ln(ε/e)` is large).

mod plotting;

use plotters::coord::Shift;
use plotters::prelude::*;
use rayon::prelude::*;
use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use wetbounce::Outcome;
use wetbounce::Scene;
use wetbounce::particles::State;

type Drawn = plotting::Drawn;

/// Diameter (m), approach (terminal) speed (m/s), fluid density (kg/m³).
const D: f64 = 2e-3;
const V0: f64 = 0.1;
const RHO: f64 = 1000.0;
/// Roughness over radius.
const ROUGHNESS: [f64; 4] = [1e-5, 1e-4, 1e-3, 1e-2];
/// The fine step (s) with which the particle is followed, so that the release speed is caught;
/// the wall's sub-steps inside it are the engine's own.
const H: f64 = 1e-5;

#[derive(Clone, Copy)]
struct Kind {
    name: &'static str,
    rho_p: f64,
    e: f64,
    /// Surface tension (N/m) for a drop; `None` for a solid.
    sigma: Option<f64>,
}

const KINDS: [Kind; 2] = [
    Kind { name: "solid", rho_p: 2500.0, e: 0.97, sigma: None },
    Kind { name: "drop", rho_p: 1500.0, e: 0.91, sigma: Some(0.03) },
];

/// `n` points spaced evenly in log between `a` and `b`.
fn logspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| a * (b / a).powf(i as f64 / (n - 1) as f64)).collect()
}

/// One measured impact.
#[derive(Clone, Copy)]
struct Point {
    kind: usize,
    roughness: f64,
    st: f64,
    eps: f64,
}

fn scene_text(kind: Kind, roughness: f64, st: f64) -> String {
    let a = 0.5 * D;
    let mu = (kind.rho_p + 0.5 * RHO) * V0 * D / (9.0 * st);
    let g = 18.0 * mu * V0 / ((kind.rho_p - RHO) * D * D);
    let h_r = roughness * a;
    // The wall's surface is the tops of the asperities: the lubrication gap is the surface gap
    // plus h_r, so a start at lubrication gap 10 a puts the centre at a + 10 a − h_r.
    let z0 = a + 10.0 * a - h_r;
    let (material, contact_time) = match kind.sigma {
        None => ("type = \"solid\"\nyoungs_modulus = 63e9\npoisson_ratio = 0.22".to_string(), ""),
        Some(s) => (format!("type = \"drop\"\nsurface_tension = {s:?}"), "contact_time = {}\n"),
    };
    format!(
        "[simulation]\ndt = 1e-4\nduration = 10.0\noutput_interval = 1.0\nintegrator = \"exponential\"\n\n\
         [fluid]\ndensity = {RHO:?}\nviscosity = {mu:?}\ngravity = [0.0, 0.0, {:?}]\n\n\
         [bounce]\nrule = \"e\"\n\n\
         [effects]\ngravity = {{}}\nbuoyancy = {{}}\ndrag = {{ law = \"stokes\" }}\nadded_mass = {{}}\n{contact_time}wall_lubrication = {{}}\n\n\
         [[kinds]]\nname = \"{}\"\n{material}\ndensity = {:?}\nrestitution_max = {:?}\nroughness = {h_r:?}\n\n\
         [[walls]]\nname = \"floor\"\ntype = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n\n\
         [[particles]]\nkind = \"{}\"\ndiameter = {D:?}\nposition = [0.0, 0.0, {z0:?}]\nvelocity = [0.0, 0.0, {:?}]\n",
        -g, kind.name, kind.rho_p, kind.e, kind.name, -V0
    )
}

/// ε of one impact: the largest upward speed after the first contact over `V0`; 0 when the
/// particle is deposited (or has not rebounded after 10 s).
fn measure(kind: Kind, roughness: f64, st: f64) -> Result<f64, String> {
    let text = scene_text(kind, roughness, st);
    let scene = Scene::from_str(&text, Path::new("scenes/restitution_emergent.toml"))
        .map_err(|e| format!("St = {st}, h_r/a = {roughness}: {e}"))?;
    let mut sim = scene.simulation();
    let mut touched = false;
    let mut best = 0.0f64;
    while sim.world.time < 10.0 {
        sim.step(H);
        for ev in sim.record.events.drain(..) {
            if !touched && ev.outcome == Outcome::Deposited {
                return Ok(0.0);
            }
            touched = true;
        }
        let p = &sim.world.particles;
        let (vz, state) = (p.vel[0].z, p.state[0]);
        if touched {
            if state == State::Resting {
                break;
            }
            best = best.max(vz);
            // Past the top of the rebound (a held drop has vz = 0 until it is released).
            if state == State::Free && best > 0.0 && vz <= 0.0 {
                break;
            }
        }
    }
    Ok(best / V0)
}

/// Per kind and roughness: the highest St without a rebound below the lowest St with one (the
/// bracket of the critical St on the grid), and the least-squares β of `ln(ε/e) = −β/St` over
/// the rebounding points.
fn fit(points: &[Point], e: f64) -> (Option<f64>, Option<f64>, Option<f64>) {
    let up: Vec<&Point> = points.iter().filter(|p| p.eps > 0.0).collect();
    let st_c = up.iter().map(|p| p.st).reduce(f64::min);
    let below = points
        .iter()
        .filter(|p| p.eps == 0.0 && st_c.is_none_or(|c| p.st < c))
        .map(|p| p.st)
        .reduce(f64::max);
    (below, st_c, beta(&up, e))
}

/// The least-squares β of `ln(ε/e) = −β/St` over `points`.
fn beta(points: &[&Point], e: f64) -> Option<f64> {
    let (num, den) =
        points.iter().fold((0.0, 0.0), |(n, d), p| (n - (p.eps / e).ln() / p.st, d + 1.0 / (p.st * p.st)));
    (den > 0.0).then(|| num / den)
}

fn figure<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, points: &[Point]) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "ε/ε_max emerging from wall lubrication + the e rule (engine), against L06 eq. 2",
            ("sans-serif", 20),
        )
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d((1.0..1e4).log_scale(), 0.0..1.1)?;
    chart.configure_mesh().x_desc("St").y_desc("ε / ε_max").light_line_style(WHITE).draw()?;
    let st = logspace(1.0, 1e4, 400);
    chart
        .draw_series(LineSeries::new(st.iter().map(|&s| (s, (-35.0 / s).exp())), BLACK.stroke_width(2)))?
        .label("L06: exp(−35/St)")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], BLACK.stroke_width(3)));
    chart.draw_series(LineSeries::new([(10.0, 0.0), (10.0, 1.1)], BLACK.mix(0.4)))?;
    chart.draw_series([Text::new("L06 St_c = 10", (10.5, 1.03), ("sans-serif", 14).into_font())])?;
    for (k, kind) in KINDS.iter().enumerate() {
        for (r, &rough) in ROUGHNESS.iter().enumerate() {
            let color = plotting::PALETTE[r];
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.kind == k && p.roughness == rough)
                .map(|p| (p.st, p.eps / kind.e))
                .collect();
            let label = format!("{}, h_r/a = {rough:e}", kind.name);
            if k == 0 {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))?
                    .label(label)
                    .legend(move |(x, y)| Circle::new((x + 9, y), 4, color.filled()));
            } else {
                chart
                    .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 6, color.stroke_width(2))))?
                    .label(label)
                    .legend(move |(x, y)| TriangleMarker::new((x + 9, y), 6, color.stroke_width(2)));
            }
        }
    }
    plotting::legend(&mut chart, SeriesLabelPosition::LowerRight, 14)?;
    root.present()?;
    Ok(())
}

fn run(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let sts = logspace(1.0, 1e4, 25);
    let mut cases: Vec<(usize, f64, f64)> = Vec::new();
    for k in 0..KINDS.len() {
        for &r in &ROUGHNESS {
            cases.extend(sts.iter().map(|&s| (k, r, s)));
        }
    }
    let points: Vec<Point> = cases
        .par_iter()
        .map(|&(kind, roughness, st)| {
            measure(KINDS[kind], roughness, st).map(|eps| Point { kind, roughness, st, eps })
        })
        .collect::<Result<_, _>>()?;
    let csv = out.join("restitution_emergent.csv");
    let mut f = std::fs::File::create(&csv).map_err(|e| format!("{}: {e}", csv.display()))?;
    let mut text = String::from("kind,roughness_over_radius,St,eps,eps_over_e\n");
    for p in &points {
        let e = KINDS[p.kind].e;
        text +=
            &format!("{},{:e},{:.6e},{:.6},{:.6}\n", KINDS[p.kind].name, p.roughness, p.st, p.eps, p.eps / e);
    }
    f.write_all(text.as_bytes()).map_err(|e| format!("{}: {e}", csv.display()))?;
    println!(
        "kind   h_r/a   St_c: no rebound at | rebound at   β (fit of ln(ε/e) = −β/St): all rebounds | St ≥ 50"
    );
    for (k, kind) in KINDS.iter().enumerate() {
        for &rough in &ROUGHNESS {
            let pts: Vec<Point> =
                points.iter().filter(|p| p.kind == k && p.roughness == rough).copied().collect();
            let (below, st_c, all) = fit(&pts, kind.e);
            let tail: Vec<&Point> = pts.iter().filter(|p| p.eps > 0.0 && p.st >= 50.0).collect();
            let show = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.1}"));
            println!(
                "{:<6} {rough:<7e} {:>18} | {:<10} {:>40} | {}",
                kind.name,
                show(below),
                show(st_c),
                show(all),
                show(beta(&tail, kind.e))
            );
        }
    }
    plotting::png_and_svg(
        &out.join("restitution_emergent"),
        (900, 600),
        |a| figure(a, &points),
        |a| figure(a, &points),
    )?;
    println!("wrote {}/restitution_emergent (.csv, .png, .svg)", out.display());
    Ok(())
}

fn main() -> ExitCode {
    plotting::main_writing_into("out/figures", run)
}
