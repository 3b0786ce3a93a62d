//! The fluid-acceleration effect (docs/physics.md §7.1 [ext], issue 14): `(1 + C_M) ρ Vp Du/Dt` in a
//! field flow, checked against the closed-form solution of the linear equations of a sphere in
//! solid-body rotation with Stokes drag and added mass.
//!
//! In the flow `u = Ω ẑ × r` the fluid's acceleration is centripetal, `Du/Dt = −Ω² r`
//! (steady: `∂u/∂t = 0`). With `z = x + i y` for the particle's position, `u = iΩ z`, and the
//! balance per unit effective inertia `(ρp + C_M ρ) Vp` reads
//!
//! ```text
//! z'' = (iΩ z − z')/τ − G Ω² z,   τ = (ρp + C_M ρ) d² / (18 μ),   G = (1 + C_M) ρ / (ρp + C_M ρ)
//! ```
//!
//! linear with constant coefficients: `z = A e^{s₁ t} + B e^{s₂ t}`, `s² + s/τ + G Ω² − iΩ/τ = 0`.
//! A neutrally buoyant particle (`G = 1`) has the root `s = iΩ`: it turns with the fluid on its
//! circle. Otherwise the slow root is `s₁ ≈ iΩ + (1 − G) Ω² τ / (1 + 2iΩτ)`, whose real part,
//! the rate at which the radius grows, is positive for a heavy particle (`G < 1`, it spirals
//! out) and negative for a light one (`G > 1`, in). The fast root decays at about `1/τ`.
//!
//! The field is a `.vti` written here on a uniform grid: trilinear interpolation reproduces a
//! linear field exactly, and so do the central differences of its gradient (up to rounding).
//! Drag is Stokes drag (`law = "stokes"`), so the engine's equations are exactly these linear
//! ones; the slip Reynolds numbers stay below 0.5, where Schiller–Naumann would differ by a few %.

use glam::DVec3;
use std::path::Path;
use vtkio::model::*;
use wetbounce::Scene;

/// Turning rate Ω (rad/s) of the flow.
const OMEGA: f64 = 5.0;
const FLUID_DENSITY: f64 = 1000.0;
const VISCOSITY: f64 = 0.05;
const DIAMETER: f64 = 2e-3;
const ADDED_MASS: f64 = 0.5;
/// Starting radius (m).
const R0: f64 = 0.08;

/// Writes `u = Ω ẑ × r` on the nodes of a uniform grid over [−0.25, 0.25]² × [−0.0625, 0.0625]
/// (spacing 1/16 m: exact in the f32 of a `.vti`'s origin and spacing).
fn write_rotating_field(path: &Path, omega: f64) {
    let (n, nz, h, lo, lo_z) = (8i32, 2i32, 0.0625, -0.25, -0.0625);
    let mut u = Vec::new();
    for k in 0..=nz {
        let _z = lo_z + h * k as f64;
        for j in 0..=n {
            let y = lo + h * j as f64;
            for i in 0..=n {
                let x = lo + h * i as f64;
                u.extend([-omega * y, omega * x, 0.0]);
            }
        }
    }
    let extent = Extent::Ranges([0..=n, 0..=n, 0..=nz]);
    let data = DataSet::ImageData {
        extent: extent.clone(),
        origin: [lo as f32, lo as f32, lo_z as f32],
        spacing: [h as f32; 3],
        meta: None,
        pieces: vec![Piece::Inline(Box::new(ImageDataPiece {
            extent,
            data: Attributes {
                point: vec![Attribute::DataArray(DataArray {
                    name: "U".into(),
                    elem: ElementType::Vectors,
                    data: IOBuffer::F64(u),
                })],
                cell: vec![],
            },
        }))],
    };
    Vtk {
        version: Version::new_xml(1, 0),
        byte_order: ByteOrder::LittleEndian,
        title: String::new(),
        file_path: None,
        data,
    }
    .export(path)
    .unwrap();
}

/// Heavy, neutral and light beads, one of each kind, at radius `R0` and 120° apart, starting
/// with the fluid's velocity; effects `effects` (TOML lines).
fn rotating_scene(effects: &str, dt: &str, integrator: &str) -> String {
    let mut particles = String::new();
    for (i, kind) in ["heavy", "neutral", "light"].iter().enumerate() {
        let angle = 2.0 * std::f64::consts::PI * i as f64 / 3.0;
        let (x, y) = (R0 * angle.cos(), R0 * angle.sin());
        particles += &format!(
            "[[particles]]\nkind = \"{kind}\"\ndiameter = {DIAMETER:e}\nposition = [{x:e}, {y:e}, 0.0]\n\
             velocity = [{:e}, {:e}, 0.0]\n\n",
            -OMEGA * y,
            OMEGA * x
        );
    }
    let kind = |name: &str, density: f64| {
        format!(
            "[[kinds]]\nname = \"{name}\"\ntype = \"solid\"\ndensity = {density:?}\nyoungs_modulus = 6e10\n\
             poisson_ratio = 0.23\n\n"
        )
    };
    format!(
        r#"
[simulation]
dt = {dt}
{integrator}
duration = 4.0
output_interval = 0.1

[fluid]
density = {FLUID_DENSITY:?}
viscosity = {VISCOSITY:?}
gravity = [0.0, 0.0, 0.0]
flow = {{ type = "field", file = "rotation.vti" }}

[effects]
{effects}

{}{}{}{particles}"#,
        kind("heavy", 2500.0),
        kind("neutral", FLUID_DENSITY),
        kind("light", 500.0),
    )
}

/// A complex number, enough for the closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
struct C(f64, f64);

impl C {
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
    fn sub(self, o: C) -> C {
        C(self.0 - o.0, self.1 - o.1)
    }
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: C) -> C {
        let n = o.0 * o.0 + o.1 * o.1;
        C((self.0 * o.0 + self.1 * o.1) / n, (self.1 * o.0 - self.0 * o.1) / n)
    }
    fn scale(self, k: f64) -> C {
        C(self.0 * k, self.1 * k)
    }
    fn exp(self) -> C {
        let m = self.0.exp();
        C(m * self.1.cos(), m * self.1.sin())
    }
    fn sqrt(self) -> C {
        let r = self.0.hypot(self.1);
        let re = (0.5 * (r + self.0)).sqrt();
        let im = (0.5 * (r - self.0)).sqrt().copysign(self.1);
        C(re, im)
    }
    fn abs(self) -> f64 {
        self.0.hypot(self.1)
    }
}

/// The closed form of a particle of density `density` with added mass `c_m`: the slow and fast
/// roots `(s₁, s₂)` of `s² + s/τ + G Ω² − iΩ/τ = 0`, and `z(t)` from `z0` moving at `z0'`.
struct ClosedForm {
    s1: C,
    s2: C,
    a: C,
    b: C,
}

impl ClosedForm {
    fn new(density: f64, c_m: f64, gain: f64, z0: C, dz0: C) -> ClosedForm {
        let inertia = density + c_m * FLUID_DENSITY;
        let tau = inertia * DIAMETER * DIAMETER / (18.0 * VISCOSITY);
        let g = gain;
        // s = (−1/τ ± sqrt(1/τ² − 4 (G Ω² − iΩ/τ))) / 2
        let disc = C(1.0 / (tau * tau) - 4.0 * g * OMEGA * OMEGA, 4.0 * OMEGA / tau).sqrt();
        let s1 = C(-1.0 / tau, 0.0).add(disc).scale(0.5);
        let s2 = C(-1.0 / tau, 0.0).sub(disc).scale(0.5);
        // A + B = z0, s₁ A + s₂ B = z0'.
        let a = dz0.sub(s2.mul(z0)).div(s1.sub(s2));
        ClosedForm { s1, s2, a, b: z0.sub(a) }
    }

    fn z(&self, t: f64) -> C {
        self.a.mul(self.s1.scale(t).exp()).add(self.b.mul(self.s2.scale(t).exp()))
    }

    /// The radius's growth rate once the fast mode has died out (1/s).
    fn radial_rate(&self) -> f64 {
        self.s1.0
    }
}

const EFFECTS: &str = "drag = { law = \"stokes\" }\nadded_mass = {}\nfluid_acceleration = {}";

/// Runs the scene of `effects` to each of `times`, returning each particle's radius.
fn radii(effects: &str, dt: &str, integrator: &str, times: &[f64]) -> Vec<[f64; 3]> {
    let dir = tempfile::tempdir().unwrap();
    write_rotating_field(&dir.path().join("rotation.vti"), OMEGA);
    let scene = Scene::from_str(&rotating_scene(effects, dt, integrator), &dir.path().join("scene.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut sim = scene.simulation();
    times
        .iter()
        .map(|&t| {
            sim.advance_to(t);
            let p = &sim.world.particles;
            assert_eq!(p.len(), 3, "no particle lost");
            std::array::from_fn(|i| {
                let x: DVec3 = p.pos[i];
                assert!(x.z.abs() < 1e-12, "stays in its plane: {x}");
                x.truncate().length()
            })
        })
        .collect()
}

/// The closed forms of the three beads, with added mass, in the order of the scene.
fn closed_forms(c_m: f64) -> [ClosedForm; 3] {
    [2500.0, FLUID_DENSITY, 500.0].map(|density| {
        let gain = (1.0 + c_m) * FLUID_DENSITY / (density + c_m * FLUID_DENSITY);
        let z0 = C(R0, 0.0);
        // The radius does not depend on the starting angle: start each on the x axis.
        ClosedForm::new(density, c_m, gain, z0, C(0.0, OMEGA).mul(z0))
    })
}

/// Times of the comparison: every quarter turn over three turns (about 3.8 s).
fn quarter_turns() -> Vec<f64> {
    let period = 2.0 * std::f64::consts::PI / OMEGA;
    (1..=12).map(|i| 0.25 * period * i as f64).collect()
}

#[test]
fn the_slow_root_is_the_fluid_turning_rate_for_a_neutral_bead_and_spirals_otherwise() {
    // The closed form itself: s = iΩ for G = 1; heavy out, light in, at the first-order
    // rate (1 − G) Ω² τ / (1 + 4 Ω² τ²) within the next order.
    let [heavy, neutral, light] = closed_forms(ADDED_MASS);
    assert!((neutral.s1.0).abs() < 1e-12 && (neutral.s1.1 - OMEGA).abs() < 1e-12, "{:?}", neutral.s1);
    assert!(heavy.radial_rate() > 0.0 && light.radial_rate() < 0.0);
    for (f, density) in [(&heavy, 2500.0), (&light, 500.0)] {
        let inertia = density + ADDED_MASS * FLUID_DENSITY;
        let tau = inertia * DIAMETER * DIAMETER / (18.0 * VISCOSITY);
        let g = (1.0 + ADDED_MASS) * FLUID_DENSITY / inertia;
        let first_order = (1.0 - g) * OMEGA * OMEGA * tau / (1.0 + 4.0 * OMEGA * OMEGA * tau * tau);
        let rel = (f.radial_rate() - first_order).abs() / first_order.abs();
        assert!(rel < 0.05, "ρp = {density}: {} vs {first_order}", f.radial_rate());
        assert!(f.s2.0 < -0.9 / tau, "the fast mode dies out at about 1/τ");
    }
}

#[test]
fn a_neutrally_buoyant_bead_stays_on_its_circle_in_solid_body_rotation() {
    let r = radii(EFFECTS, "5e-4", "", &quarter_turns());
    for radii in &r {
        let rel = (radii[1] - R0).abs() / R0;
        assert!(rel < 1e-6, "radius {} vs {R0}", radii[1]);
    }
}

#[test]
fn heavy_and_light_beads_spiral_out_and_in_at_the_closed_form_rates_in_solid_body_rotation() {
    let times = quarter_turns();
    let r = radii(EFFECTS, "5e-4", "", &times);
    let forms = closed_forms(ADDED_MASS);
    for (t, radii) in times.iter().zip(&r) {
        for (i, f) in forms.iter().enumerate() {
            let exact = f.z(*t).abs();
            let rel = (radii[i] - exact).abs() / exact;
            assert!(rel < 1e-4, "particle {i} at t = {t}: radius {} vs {exact} (closed form)", radii[i]);
        }
    }
    let worst = times
        .iter()
        .zip(&r)
        .flat_map(|(t, radii)| {
            forms.iter().enumerate().map(move |(i, f)| (radii[i] - f.z(*t).abs()).abs() / R0)
        })
        .fold(0.0, f64::max);
    eprintln!("largest radius error over three turns: {worst:.2e} R0");
    let (heavy, light) = (r[11][0] / R0, r[11][2] / R0);
    assert!(heavy > 1.5 && light < 0.85, "three turns: heavy × {heavy}, light × {light}");
    // The growth rate over the last two turns, once the fast mode is gone.
    let (t1, t2) = (times[3], times[11]);
    for (i, f) in forms.iter().enumerate().filter(|(i, _)| *i != 1) {
        let rate = (r[11][i] / r[3][i]).ln() / (t2 - t1);
        let rel = (rate - f.radial_rate()).abs() / f.radial_rate().abs();
        eprintln!("particle {i}: radial rate {rate:.6} 1/s, closed form {:.6} 1/s", f.radial_rate());
        assert!(rel < 1e-3, "particle {i}: rate {rate} vs {} 1/s", f.radial_rate());
    }
}

#[test]
fn without_added_mass_the_gain_is_the_density_ratio_and_the_neutral_bead_still_follows_the_fluid() {
    let times = quarter_turns();
    let effects = "drag = { law = \"stokes\" }\nfluid_acceleration = {}";
    let r = radii(effects, "5e-4", "", &times);
    let forms = [2500.0, FLUID_DENSITY, 500.0].map(|density| {
        let z0 = C(R0, 0.0);
        ClosedForm::new(density, 0.0, FLUID_DENSITY / density, z0, C(0.0, OMEGA).mul(z0))
    });
    for (t, radii) in times.iter().zip(&r) {
        for (i, f) in forms.iter().enumerate() {
            let exact = f.z(*t).abs();
            assert!(
                (radii[i] - exact).abs() / exact < 1e-4,
                "particle {i} at t = {t}: {} vs {exact}",
                radii[i]
            );
        }
    }
    assert!((r[11][1] - R0).abs() < 1e-6 * R0);
}

#[test]
fn without_the_effect_even_the_neutral_bead_drifts_out_as_the_fluid_does_not_push_it_in() {
    // The effect is what holds it: with drag alone the centripetal acceleration comes from
    // the drag, which needs an outward slip.
    let r = radii("drag = { law = \"stokes\" }\nadded_mass = {}", "5e-4", "", &quarter_turns());
    assert!(r[11][1] > 1.01 * R0, "neutral bead without the effect: {} vs {R0}", r[11][1]);
}

#[test]
fn the_force_converges_at_the_integrators_order() {
    // RK2 at Δt and Δt/2 against the closed form: the error falls about fourfold (the force is
    // evaluated at every stage, so the scheme keeps its order).
    let times = [quarter_turns()[11]];
    let exact = closed_forms(ADDED_MASS)[0].z(times[0]).abs();
    let err = |dt: &str| (radii(EFFECTS, dt, "", &times)[0][0] - exact).abs();
    let (coarse, fine) = (err("4e-3"), err("2e-3"));
    let ratio = coarse / fine;
    eprintln!("radius error at dt = 4e-3: {coarse:.3e} m, at 2e-3: {fine:.3e} m, ratio {ratio:.2}");
    assert!(ratio > 3.0 && ratio < 5.0, "errors {coarse:e}, {fine:e}: ratio {ratio}");
}

/// The scene of [`rotating_scene`] in a flow turning at `omega`, loaded (or its error).
fn load_rotating(omega: f64, dt: &str, integrator: &str) -> Result<Scene, String> {
    let dir = tempfile::tempdir().unwrap();
    write_rotating_field(&dir.path().join("rotation.vti"), omega);
    Scene::from_str(&rotating_scene(EFFECTS, dt, integrator), &dir.path().join("scene.toml"))
        .map_err(|e| e.to_string())
}

#[test]
fn auto_dt_takes_a_smaller_step_in_a_faster_field_limited_by_its_cell_crossing_time() {
    // Slow field: the light bead's relaxation time (4.4 ms) is the shortest scale. Fast field
    // (100× faster): the fluid crosses the smallest cell (62.5 mm) at up to 500 · 0.35 m/s,
    // in 0.35 ms, shorter than 1/|∇u| = 2 ms and than the relaxation times.
    let slow = load_rotating(OMEGA, "\"auto\"", "").unwrap_or_else(|e| panic!("{e}"));
    let fast = load_rotating(100.0 * OMEGA, "\"auto\"", "").unwrap_or_else(|e| panic!("{e}"));
    let (slow, fast) = (slow.auto_step.unwrap(), fast.auto_step.unwrap());
    assert!(slow.limited_by.contains("relaxation time"), "{}", slow.limited_by);
    assert!(fast.limited_by.contains("cross the smallest cell"), "{}", fast.limited_by);
    let crossing = 0.0625 / (100.0 * OMEGA * 0.25 * 2f64.sqrt());
    assert!((fast.time_scale - crossing).abs() < 1e-9 * crossing, "{} vs {crossing}", fast.time_scale);
    assert!(fast.dt < 0.1 * slow.dt, "{} vs {}", fast.dt, slow.dt);
}

#[test]
fn an_explicit_dt_beyond_the_fields_velocity_gradient_is_refused_naming_it() {
    // |∇u| = 500 1/s and the light bead's gain G = 1.5: rate √1.5 · 500 = 612 1/s, so RK2
    // (interval 2) needs dt < 3.27 ms; its drag alone would allow 2τ = 8.9 ms.
    let err = load_rotating(100.0 * OMEGA, "4e-3", "").unwrap_err();
    assert!(err.contains("simulation.dt") && err.contains("in the flow field"), "{err}");
    assert!(err.contains("3.26e-3 s") && err.contains("5.000e2 1/s"), "{err}");
    // Also the exponential scheme, which is stable for any drag: its flow velocity is explicit.
    let err = load_rotating(100.0 * OMEGA, "4e-3", "integrator = \"exponential\"").unwrap_err();
    assert!(err.contains("exponential integrator in the flow field"), "{err}");
    assert!(load_rotating(100.0 * OMEGA, "3e-3", "").is_ok());
}

/// The rotating scene in a field that flips its turning direction: snapshots `a.vti` (Ω) and
/// `b.vti` (−Ω) at `times`, repeating with `period` when given (TOML), loaded with `dt`.
fn load_flipping(dir: &Path, times: &str, period: &str, dt: &str) -> Result<Scene, String> {
    let text = rotating_scene(EFFECTS, dt, "").replace(
        "flow = { type = \"field\", file = \"rotation.vti\" }",
        &format!("flow = {{ type = \"field\", files = [\"a.vti\", \"b.vti\"], times = {times}{period} }}"),
    );
    Scene::from_str(&text, &dir.join("scene.toml")).map_err(|e| e.to_string())
}

fn flipping_files() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_rotating_field(&dir.path().join("a.vti"), OMEGA);
    write_rotating_field(&dir.path().join("b.vti"), -OMEGA);
    dir
}

#[test]
fn an_unsteady_field_faster_than_the_step_sets_the_auto_step_and_refuses_a_longer_explicit_one() {
    // Two snapshots 1e-7 s apart, period 2e-7 s (issue 25, point 3): auto took 2.7e-4 s from
    // the relaxation times and the bead bounced 52 times on an aliased flow; an explicit 1e-4 s
    // was accepted.
    let dir = flipping_files();
    let auto = load_flipping(dir.path(), "[0.0, 1e-7]", ", period = 2e-7", "\"auto\"")
        .unwrap_or_else(|e| panic!("{e}"))
        .auto_step
        .unwrap();
    assert!(auto.limited_by.contains("interval between the flow field's snapshots"), "{}", auto.limited_by);
    assert!((auto.time_scale - 1e-7).abs() < 1e-12 * 1e-7 + 1e-22, "{}", auto.time_scale);
    assert!(auto.dt <= 1e-7 / 4.0, "{}", auto.dt);
    let err = load_flipping(dir.path(), "[0.0, 1e-7]", ", period = 2e-7", "1e-4").unwrap_err();
    assert!(
        err.contains("simulation.dt: 0.0001 s is longer than the shortest interval between the flow field's snapshots, 1e-7 s"),
        "{err}"
    );
    assert!(err.contains("use dt <= 1e-7 s, or dt = \"auto\""), "{err}");
    // The wrap of a periodic series counts: snapshots 1 s apart, back to the first 1e-3 s later.
    let err = load_flipping(dir.path(), "[0.0, 1.0]", ", period = 1.001", "2e-3").unwrap_err();
    assert!(err.contains("the wrap of the periodic series"), "{err}");
    assert!(load_flipping(dir.path(), "[0.0, 1.0]", ", period = 1.001", "9e-4").is_ok());
    // A series held at its ends has no wrap: only the 1 s interval, which dt = 2e-3 s resolves.
    assert!(load_flipping(dir.path(), "[0.0, 1.0]", "", "2e-3").is_ok());
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]

    /// For any two snapshot times and any period: `dt = "auto"` never takes a step longer than
    /// a fraction of the shortest snapshot interval (the wrap included), an explicit step up to
    /// that interval is accepted and one beyond it is refused naming `simulation.dt`.
    #[test]
    fn no_accepted_step_is_longer_than_the_shortest_snapshot_interval(
        t0 in -1.0..1.0f64,
        gap_exp in -7.0..-2.0f64,
        wrap in proptest::option::of(1e-7..1e-2f64),
    ) {
        let dir = flipping_files();
        let gap = 10f64.powf(gap_exp);
        let times = format!("[{t0:e}, {:e}]", t0 + gap);
        let period = wrap.map_or(String::new(), |w| format!(", period = {:e}", gap + w));
        let scene = load_flipping(dir.path(), &times, &period, "\"auto\"");
        // Read back the interval the loader saw (the sum above rounds).
        let field = scene.as_ref().unwrap().setup.fluid.flow.field().unwrap();
        let s = &field.snapshots;
        let mut shortest = s[1].time - s[0].time;
        if let Some(p) = field.period {
            shortest = shortest.min(s[0].time + p - s[1].time);
        }
        let auto = scene.unwrap().auto_step.unwrap();
        proptest::prop_assert!(auto.dt <= shortest / 4.0 * (1.0 + 1e-12), "{} vs {shortest}", auto.dt);
        let beyond = load_flipping(dir.path(), &times, &period, &format!("{:e}", shortest * 1.01));
        let err = beyond.unwrap_err();
        proptest::prop_assert!(err.contains("simulation.dt") && err.contains("snapshots"), "{}", err);
        // Within it: accepted, unless a stability limit (the drag's, the flow's) refuses it.
        let within = load_flipping(dir.path(), &times, &period, &format!("{:e}", shortest * 0.99));
        if let Err(e) = within {
            proptest::prop_assert!(e.contains("largest stable step") && !e.contains("snapshots"), "{}", e);
        }
    }
}
