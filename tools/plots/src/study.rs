//! The work–precision study's core: the cases, one run of the engine with one method, and its
//! errors against a reference. Shared by `tools/plots/src/accuracy_study.rs` (the full study,
//! its CSV and plots) and `tests/physics/accuracy_study.rs` (the reduced study CI runs), so that both
//! measure the same thing. Depends on the engine and the standard library only.
//!
//! A *method* is an integrator, a time step, where impacts are placed in time (inside the step
//! or at its end) and whether rebounding particles are held for their contact time — or one of
//! the scenes' accuracy settings (`dt = "auto"`), which choose the integrator and the step.
//! Errors are relative (see [`Errors`]); the cost is the wall time per particle per simulated
//! second.
#![allow(dead_code)]

use glam::DVec3;
use std::path::Path;
use std::time::Instant;
use wetbounce::contact::ImpactLocation;
use wetbounce::integrate::IntegratorKind;
use wetbounce::scene::Accuracy;
use wetbounce::{Other, Scene, Simulation};

/// The study's cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Case {
    /// (a) L06 Fig. 6: `scenes/toluene_drop.toml`, the 2.75 mm toluene drop through its first
    /// three impacts (1 s).
    Fig6,
    /// (b) `scenes/glass_bead.toml`: a 2.5 mm glass bead bouncing on a floor in water (1 s).
    GlassBead,
    /// (c) A dilute column: 1000 toluene drops rising past a conical baffle to an outlet.
    Column,
    /// (d) Closed-form Stokes settling of a 0.2 mm glass bead from rest (no walls).
    Stokes,
}

impl Case {
    pub const ALL: [Case; 4] = [Case::Fig6, Case::GlassBead, Case::Column, Case::Stokes];

    pub fn name(self) -> &'static str {
        match self {
            Case::Fig6 => "fig6_drop",
            Case::GlassBead => "glass_bead",
            Case::Column => "column",
            Case::Stokes => "stokes",
        }
    }

    pub fn title(self) -> &'static str {
        match self {
            Case::Fig6 => "(a) Fig. 6 toluene drop, 3 impacts",
            Case::GlassBead => "(b) glass bead on a floor in water",
            Case::Column => "(c) dilute column, 1000 drops",
            Case::Stokes => "(d) Stokes settling (closed form)",
        }
    }

    /// Whether rebounding particles are held in the case's own physics (the shipped scene's).
    pub fn default_hold(self) -> bool {
        matches!(self, Case::Fig6 | Case::Column)
    }

    /// Simulated time (s).
    pub fn duration(self) -> f64 {
        match self {
            Case::Fig6 | Case::GlassBead => 1.0,
            Case::Column => COLUMN_DURATION,
            Case::Stokes => 0.05,
        }
    }

    /// How many of the first impacts (of particle 0) are compared.
    pub fn impacts_compared(self) -> usize {
        match self {
            Case::Fig6 => 3,
            Case::GlassBead => 5,
            Case::Column | Case::Stokes => 0,
        }
    }

    /// Whether the case has walls, so that impact location and hold are study axes.
    pub fn has_walls(self) -> bool {
        self != Case::Stokes
    }

    /// The reference's time step (s): rk4, much smaller than the study's steps.
    pub fn reference_dt(self) -> f64 {
        match self {
            Case::Fig6 | Case::GlassBead => 1e-6,
            Case::Column => 1e-4,
            Case::Stokes => f64::NAN, // closed form
        }
    }

    /// The scene text without its `[simulation]` table.
    fn body(self) -> String {
        let shipped = |name: &str| {
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
            let path = if path.exists() {
                path
            } else {
                // Built from tools/plots: the scenes are two folders up.
                Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
            };
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        };
        match self {
            Case::Fig6 => without_simulation(&shipped("toluene_drop.toml")),
            Case::GlassBead => without_simulation(&shipped("glass_bead.toml")),
            Case::Column => COLUMN_BODY.to_string(),
            Case::Stokes => STOKES_BODY.to_string(),
        }
    }

    /// The scene for a method.
    pub fn scene(self, stepping: Stepping, location: ImpactLocation, hold: bool) -> Scene {
        let d = self.duration();
        let step = match stepping {
            Stepping::Fixed { integrator, dt } => {
                format!("dt = {dt:e}\nintegrator = \"{}\"", integrator.name())
            }
            Stepping::Auto(a) => format!("dt = \"auto\"\naccuracy = \"{}\"", a.name()),
        };
        let text = format!(
            "[simulation]\n{step}\nduration = {d}\noutput_interval = {d}\nimpact_location = \"{}\"\n\n{}",
            location.name(),
            with_hold(&self.body(), hold)
        );
        Scene::from_str(&text, Path::new(&format!("study/{}.toml", self.name())))
            .unwrap_or_else(|e| panic!("{e}"))
    }
}

/// How a run steps: a fixed integrator and step, or an accuracy setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stepping {
    Fixed { integrator: IntegratorKind, dt: f64 },
    Auto(Accuracy),
}

/// Every integrator, in the order of the plots.
pub const INTEGRATORS: [IntegratorKind; 4] =
    [IntegratorKind::Euler, IntegratorKind::Rk2, IntegratorKind::Rk4, IntegratorKind::Exponential];

/// Both impact locations.
pub const LOCATIONS: [ImpactLocation; 2] = [ImpactLocation::InStep, ImpactLocation::EndOfStep];

/// `n_per_decade` time steps per decade from `from` down to `to` (s), both included.
pub fn dt_range(from: f64, to: f64, n_per_decade: usize) -> Vec<f64> {
    let decades = (from / to).log10();
    let n = (decades * n_per_decade as f64).round() as usize;
    (0..=n).map(|k| from * 10f64.powf(-(k as f64) / n_per_decade as f64)).collect()
}

/// The scene text with its `[simulation]` table removed (the study writes its own).
fn without_simulation(text: &str) -> String {
    let mut out = String::new();
    let mut skipping = false;
    for line in text.lines() {
        let header = line.trim_start().starts_with('[');
        if header {
            skipping = line.trim() == "[simulation]";
        }
        if !skipping {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// The scene text with the `contact_time` effect present (hold on) or not (hold off).
fn with_hold(text: &str, hold: bool) -> String {
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("contact_time") {
            continue;
        }
        out.push_str(line);
        out.push('\n');
        if hold && line.trim() == "[effects]" {
            out.push_str("contact_time = {}\n");
        }
    }
    out
}

/// Simulated time of the column case (s): time for the slowest drop to rise, be held, slide
/// off the baffle and leave.
pub const COLUMN_DURATION: f64 = 3.5;

/// (c): a 50 mm water column with 1000 toluene drops (250 each of 2.0, 2.3, 2.6 and 2.9 mm)
/// placed at random in its lowest 80 mm at t = 0; a conical disc baffle 110 mm up holds them,
/// they rebound weakly, rest and slide off its rim, and leave through the outlet plane at
/// 150 mm. The drops start together (random fills, not an injector) so that the same drops
/// start at the same places whatever the method; pair contacts are off in the study (the
/// dilute limit), so each drop's path is a deterministic function of the method.
const COLUMN_BODY: &str = r#"
[fluid]
density = 997.0
viscosity = 0.89e-3

[effects]
gravity = {}
buoyancy = {}
drag = { law = "schiller_naumann" }
added_mass = {}
contact_time = {}

[[kinds]]
name = "toluene"
type = "drop"
density = 860.0
surface_tension = 0.026
restitution_max = 0.91

[[walls]]
name = "shell"
type = "cylinder"
base = [0.0, 0.0, 0.0]
radius = 0.025
length = 0.16

[[walls]]
name = "baffle"
type = "annulus"
center = [0.0, 0.0, 0.11]
normal = [0.0, 0.0, 1.0]
outer_radius = 0.017
cone_height = -0.006

[[random_fill]]
kind = "toluene"
diameter = 2.0e-3
min = [-0.018, -0.018, 0.002]
max = [0.018, 0.018, 0.08]
count = 250
seed = 1

[[random_fill]]
kind = "toluene"
diameter = 2.3e-3
min = [-0.018, -0.018, 0.002]
max = [0.018, 0.018, 0.08]
count = 250
seed = 2

[[random_fill]]
kind = "toluene"
diameter = 2.6e-3
min = [-0.018, -0.018, 0.002]
max = [0.018, 0.018, 0.08]
count = 250
seed = 3

[[random_fill]]
kind = "toluene"
diameter = 2.9e-3
min = [-0.018, -0.018, 0.002]
max = [0.018, 0.018, 0.08]
count = 250
seed = 4

[[outlets]]
name = "top"
type = "plane"
point = [0.0, 0.0, 0.15]
normal = [0.0, 0.0, -1.0]
"#;

/// (d): constants of the closed-form case.
pub const STOKES_D: f64 = 0.2e-3;
pub const STOKES_RHO_P: f64 = 2540.0;
pub const STOKES_RHO: f64 = 998.2;
pub const STOKES_MU: f64 = 1.002e-3;

const STOKES_BODY: &str = r#"
[fluid]
density = 998.2
viscosity = 1.002e-3

[effects]
gravity = {}
buoyancy = {}
drag = { law = "stokes" }
added_mass = {}

[[kinds]]
name = "glass"
type = "solid"
density = 2540.0
youngs_modulus = 63e9
poisson_ratio = 0.22

[[particles]]
kind = "glass"
diameter = 0.2e-3
position = [0.0, 0.0, 0.0]
"#;

/// docs/physics.md §1: from rest, with Stokes drag, `v(t) = V_t (1 − e^{−t/τ})`,
/// `τ = (ρp + C_M ρ) d²/(18 μ)`; returns the height and vertical velocity.
pub fn stokes_exact(t: f64) -> (f64, f64) {
    let tau = (STOKES_RHO_P + 0.5 * STOKES_RHO) * STOKES_D * STOKES_D / (18.0 * STOKES_MU);
    let vt = -(STOKES_RHO_P - STOKES_RHO) * 9.81 / (STOKES_RHO_P + 0.5 * STOKES_RHO) * tau;
    let decay = (-t / tau).exp();
    (vt * (t - tau * (1.0 - decay)), vt * (1.0 - decay))
}

/// What one run recorded.
#[derive(Debug, Clone, Default)]
pub struct Run {
    /// The integrator and step actually used (an accuracy setting's choice).
    pub integrator: Option<IntegratorKind>,
    pub dt: f64,
    pub steps: u64,
    /// Wall time of the fastest repetition (s).
    pub wall: f64,
    /// Particles × simulated time (s), summed over steps.
    pub particle_seconds: f64,
    /// Particle 0 at every step end: time, position, velocity (single-particle cases).
    pub path: Vec<(f64, DVec3, DVec3)>,
    /// Particle 0's wall impacts: time, normal speed.
    pub impacts: Vec<(f64, f64)>,
    /// Each particle's first wall impact: id, normal speed (sorted by id).
    pub first_impacts: Vec<(u32, f64)>,
    /// Residence times of the particles that left, sorted by id.
    pub residence: Vec<(u32, f64)>,
}

impl Run {
    /// Cost: wall time per particle per simulated second.
    pub fn cost(&self) -> f64 {
        self.wall / self.particle_seconds
    }
}

/// Runs `scene` to the case's end on the current thread pool, repeating short runs until they
/// add up to `min_wall` seconds and keeping the fastest (timings on a shared machine are noisy).
pub fn run(case: Case, scene: &Scene, min_wall: f64) -> Run {
    let mut best: Option<Run> = None;
    let mut total = 0.0;
    for _ in 0..50 {
        let r = run_once(case, scene);
        total += r.wall;
        if best.as_ref().is_none_or(|b| r.wall < b.wall) {
            best = Some(r);
        }
        if total >= min_wall {
            break;
        }
    }
    best.expect("one run")
}

fn run_once(case: Case, scene: &Scene) -> Run {
    let mut sim: Simulation = scene.simulation();
    // The column is studied in the dilute limit: drops pass through each other.
    sim.setup.pair_collisions = case != Case::Column;
    let single = case.impacts_compared() > 0 || case == Case::Stokes;
    let t_end = case.duration();
    let dt = sim.setup.dt;
    let mut out = Run { integrator: Some(sim.setup.integrator), dt, ..Run::default() };
    if single {
        out.path.reserve((t_end / dt) as usize + 2);
        out.path.push((0.0, sim.world.particles.pos[0], sim.world.particles.vel[0]));
    }
    let mut first = std::collections::BTreeMap::new();
    let clock = Instant::now();
    while sim.world.time < t_end {
        let remaining = t_end - sim.world.time;
        if remaining <= 1e-6 * dt {
            break;
        }
        let h = if remaining < 1.000_001 * dt { remaining } else { dt };
        out.particle_seconds += sim.world.particles.len() as f64 * h;
        sim.step(h);
        if single {
            out.path.push((sim.world.time, sim.world.particles.pos[0], sim.world.particles.vel[0]));
        }
        for e in sim.record.events.drain(..) {
            if let Other::Wall(_) = e.other {
                if single && e.id == 0 {
                    out.impacts.push((e.time, e.normal_speed));
                }
                first.entry(e.id).or_insert(e.normal_speed);
            }
        }
    }
    out.wall = clock.elapsed().as_secs_f64();
    out.steps = sim.world.steps;
    out.first_impacts = first.into_iter().collect();
    let mut residence: Vec<(u32, f64)> =
        sim.record.removed.iter().flat_map(|o| o.iter().map(|r| (r.id, r.residence_time))).collect();
    residence.sort_by_key(|r| r.0);
    out.residence = residence;
    out
}

/// Relative errors of a run; `None` where the case has no such measure.
///
/// - `position`: the largest distance between the run's particle 0 and the reference's at the
///   run's step ends, over the largest distance the reference travels from its start;
/// - `impact_time`: the largest `|t_i − t_i,ref| / t_i,ref` over the compared impacts (times
///   from the release at t = 0); 1 if an impact is missing;
/// - `impact_speed`: the largest `|V_i − V_i,ref| / V_i,ref` (V = normal speed at contact);
///   for the column, the error of the mean over the drops of their first impact's speed;
/// - `residence`: for the column, the error of the mean residence time.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Errors {
    pub position: Option<f64>,
    pub impact_time: Option<f64>,
    pub impact_speed: Option<f64>,
    pub residence: Option<f64>,
}

impl Errors {
    /// The case's error: the largest of its measures.
    pub fn max(&self) -> f64 {
        [self.position, self.impact_time, self.impact_speed, self.residence]
            .into_iter()
            .flatten()
            .fold(0.0, f64::max)
    }
}

/// The errors of `run` against `reference` (ignored for the closed-form case).
pub fn errors(case: Case, run: &Run, reference: Option<&Run>) -> Errors {
    let mut e = Errors::default();
    match case {
        Case::Stokes => {
            let scale = stokes_exact(case.duration()).0.abs();
            let worst = run.path.iter().map(|&(t, x, _)| (x.z - stokes_exact(t).0).abs()).fold(0.0, f64::max);
            e.position = Some(worst / scale);
        }
        Case::Fig6 | Case::GlassBead => {
            let r = reference.expect("a reference run");
            let start = r.path[0].1;
            let scale = r.path.iter().map(|p| (p.1 - start).length()).fold(0.0, f64::max);
            let worst =
                run.path.iter().map(|&(t, x, _)| (x - interpolate(&r.path, t)).length()).fold(0.0, f64::max);
            e.position = Some(worst / scale);
            let k = case.impacts_compared().min(r.impacts.len());
            let (mut et, mut ev) = (0.0f64, 0.0f64);
            for i in 0..k {
                match run.impacts.get(i) {
                    Some(&(t, v)) => {
                        et = et.max((t - r.impacts[i].0).abs() / r.impacts[i].0);
                        ev = ev.max((v - r.impacts[i].1).abs() / r.impacts[i].1);
                    }
                    None => (et, ev) = (1.0, 1.0),
                }
            }
            e.impact_time = Some(et);
            e.impact_speed = Some(ev);
        }
        Case::Column => {
            let r = reference.expect("a reference run");
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
            let res = |run: &Run| mean(&run.residence.iter().map(|r| r.1).collect::<Vec<_>>());
            let (m, m_ref) = (res(run), res(r));
            e.residence = Some((m - m_ref).abs() / m_ref);
            let speeds = |run: &Run| mean(&run.first_impacts.iter().map(|r| r.1).collect::<Vec<_>>());
            let (v, v_ref) = (speeds(run), speeds(r));
            e.impact_speed = Some((v - v_ref).abs() / v_ref);
        }
    }
    e
}

/// The reference path at time `t`: cubic Hermite interpolation between its step ends (its
/// steps are so short that the interpolation error is far below the errors measured).
fn interpolate(path: &[(f64, DVec3, DVec3)], t: f64) -> DVec3 {
    let i = path.partition_point(|p| p.0 < t);
    if i == 0 {
        return path[0].1;
    }
    if i >= path.len() {
        return path[path.len() - 1].1;
    }
    let (t0, x0, v0) = path[i - 1];
    let (t1, x1, v1) = path[i];
    let h = t1 - t0;
    if h <= 0.0 {
        return x1;
    }
    let s = (t - t0) / h;
    let (s2, s3) = (s * s, s * s * s);
    x0 * (2.0 * s3 - 3.0 * s2 + 1.0)
        + v0 * h * (s3 - 2.0 * s2 + s)
        + x1 * (-2.0 * s3 + 3.0 * s2)
        + v1 * h * (s3 - s2)
}

/// The observed order of convergence between two runs: `log(e1/e2) / log(dt1/dt2)`.
pub fn order(dt1: f64, e1: f64, dt2: f64, e2: f64) -> f64 {
    (e1 / e2).ln() / (dt1 / dt2).ln()
}
