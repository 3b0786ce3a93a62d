//! From the parsed file to a validated [`Scene`].

use super::accuracy::auto_step;
use super::error::check::{self, forbid, required};
use super::error::fmt::{num, shorten_long_numbers};
use super::error::{Invalid, SceneError};
use super::ranges::{
    self, DENSITY, FLUID_DENSITY, GRAVITY, ROUGHNESS, SURFACE_TENSION, TIME, VISCOSITY, YOUNGS_MODULUS,
};
use super::run_length::{TooLong, run_length};
use super::schema::*;
use super::stiffness::{flow_rate, stiffest_drag};
use super::table::{key_path, line_and_column};
use super::{LoadOptions, Scene};
use super::{fill, flow, flux, overlap, walls};
use crate::contact::BounceRule;
use crate::effects::{MemoryKernel, Physics, SHORTEST_LAG, build_effect, fold_history_for_step};
use crate::fluid::Fluid;
use crate::integrate::IntegratorKind;
use crate::particles::{FrictionMaterial, Material, ParticleKind, Particles};
use crate::pipeline::Setup;
use crate::walls::Wall;
use std::path::Path;

/// The largest Stokes number at which L06 eq. 4 diverges: `0.85^10`.
const EQ4_POLE: f64 = 0.196_874_404_3;

/// Parses TOML into the schema; errors carry the key path and the line and column.
pub(super) fn parse(source: &str, path: &Path) -> Result<SceneFile, SceneError> {
    let located = |key: String, e: &toml::de::Error| {
        let at = e.span().map(|s| {
            let (line, column) = line_and_column(source, s.start);
            format!(" (line {line}, column {column})")
        });
        SceneError::Parse {
            file: path.to_path_buf(),
            key,
            message: shorten_long_numbers(&format!("{}{}", e.message().trim_end(), at.unwrap_or_default())),
        }
    };
    let de = toml::de::Deserializer::parse(source).map_err(|e| located("(top level)".into(), &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let key = key_path(e.path());
        // An empty key (`"" = 1`) has an empty path segment: name it `""`, never nothing.
        let key = match key.as_str() {
            "." => "(top level)".to_string(),
            "" => "\"\"".to_string(),
            k if k.ends_with('.') => format!("{k}\"\""),
            _ => key,
        };
        located(key, e.inner())
    })
}

/// 1-based line of byte offset `at` in `source`.
fn line_of(source: &str, at: usize) -> usize {
    line_and_column(source, at).0
}

pub(super) fn build(
    file: SceneFile,
    base: &Path,
    source: &str,
    options: LoadOptions,
) -> Result<Scene, Invalid> {
    let sim = &file.simulation;
    let dt = match sim.dt {
        DtSpec::Seconds(dt) => {
            let dt = check::positive_in("simulation.dt", dt, &TIME)?;
            if let Some(a) = sim.accuracy {
                return Err(Invalid::new(
                    "simulation.accuracy",
                    format!(
                        "only with dt = \"auto\" (it chooses dt), got \"{}\" with dt = {}",
                        a.name(),
                        num(dt)
                    ),
                ));
            }
            dt
        }
        DtSpec::Auto => {
            if let Some(i) = sim.integrator {
                return Err(Invalid::new(
                    "simulation.integrator",
                    format!(
                        "chosen by the accuracy setting with dt = \"auto\"; leave it out or give dt in s, \
                         got \"{}\"",
                        i.name()
                    ),
                ));
            }
            f64::NAN // chosen below, once the scene's time scales are known
        }
    };
    let duration = check::positive_in("simulation.duration", sim.duration, &TIME)?;
    let output_interval = check::positive_in("simulation.output_interval", sim.output_interval, &TIME)?;
    let checkpoint = checkpoint_keys(&file.checkpoint)?;

    let fluid = build_fluid(&file.fluid, base, source)?;
    let mut kinds = build_kinds(&file.kinds)?;
    let walls = walls::build_walls(&file.walls, base, source)?;

    let mut effects = Vec::new();
    for (name, table) in &file.effects {
        let key = format!("effects.{name}");
        let line = format!(" (line {})", line_of(source, table.span().start));
        let value = table.get_ref();
        if !value.is_table() {
            return Err(Invalid::new(key, format!("must be a table such as {{}}, got {value}{line}")));
        }
        let effect = build_effect(name, value.clone()).map_err(|e| {
            let key = if e.key.is_empty() { key.clone() } else { format!("{key}.{}", e.key) };
            Invalid::new(key, format!("{}{line}", e.message))
        })?;
        effect.check(&kinds).map_err(|e| {
            let key = if e.key.is_empty() { key.clone() } else { format!("{key}.{}", e.key) };
            Invalid::new(key, format!("{}{line}", e.message))
        })?;
        effects.push(effect);
    }
    let mut physics = Physics::build(&fluid, &kinds, &effects);
    if dt.is_finite() {
        // The history memory's fast modes fold for the step (`dt = "auto"`: once chosen, below).
        fold_history_for_step(&mut physics, dt);
    }
    for (kind, &held) in kinds.iter_mut().zip(&physics.held_kinds) {
        kind.held_at_contact = held;
    }
    // Friction needs the spin: a scene with a friction key has rotation (docs/physics.md §9).
    let friction =
        kinds.iter().any(|k| k.friction.named()) || walls.iter().any(|w| w.material.friction.named());
    if friction {
        crate::effects::Effect::apply(&crate::effects::Rotation {}, &fluid, &kinds, &mut physics);
    }
    let physics_has_lubrication = physics.wall_lubrication.is_some();
    if file.effects.contains_key("added_mass") {
        // The effect checks the sign itself; the range is the scene's (ranges.rs).
        ranges::ADDED_MASS.check("effects.added_mass.coefficient", physics.added_mass_coefficient)?;
    }
    if physics_has_lubrication && physics.drag.is_none() {
        return Err(Invalid::new(
            "effects.wall_lubrication",
            "needs the drag effect (it raises the drag near walls), got a scene without drag",
        ));
    }
    if physics.drag.is_some() && fluid.viscosity <= 0.0 {
        return Err(Invalid::new(
            "fluid.viscosity",
            format!("must be > 0 with the drag effect, got {}", num(fluid.viscosity)),
        ));
    }

    let b = &file.bounce;
    let rule = BounceRule {
        beta: check::non_negative("bounce.beta", b.beta.unwrap_or(DEFAULT_BETA))?,
        st_critical: check::non_negative("bounce.st_critical", b.st_critical.unwrap_or(DEFAULT_ST_CRITICAL))?,
        tangential_restitution: tangential_rule(b, friction)?,
        friction,
        hold_at_contact: physics.hold_at_contact,
        e_rule: e_rule(b, physics_has_lubrication)?,
    };
    check_roughness(&file, &kinds, &walls, physics_has_lubrication)?;
    let has_solid = kinds.iter().any(|k| matches!(k.material, Material::Solid { .. }));
    if has_solid && rule.st_critical <= EQ4_POLE {
        return Err(Invalid::new(
            "bounce.st_critical",
            format!(
                "must be > {EQ4_POLE:.3} with solid particles (the contact time of L06 eq. 4 \
                 diverges there), got {}",
                num(rule.st_critical)
            ),
        ));
    }

    // The run's cost, from counts, before any particle is placed: a scene whose run cannot fit
    // in memory is refused before it allocates its own particles.
    let (estimate, estimate_inputs) = super::estimate::estimate(
        &file,
        (duration, output_interval),
        physics.history.as_ref().map_or(0, |k| k.stored_modes()),
        &fluid.flow,
    );
    if !options.allow_large_memory {
        super::estimate::check_memory(&estimate, super::estimate::available_memory())?;
    }
    let mut particles = Particles::default();
    if physics.rotation {
        // The spin column, only in a scene with rotation (docs/physics.md §9).
        particles.omega = crate::particles::Column::new(1, glam::DVec3::ZERO, 0);
    }
    let origins = fill::add_particles(&file, &kinds, &walls, physics.rotation, &mut particles)?;
    fill::check_clear_of_walls(&origins, &particles, &walls)?;
    overlap::check_no_overlap(&origins, &particles)?;
    let injectors = flux::build_injectors(&file.injectors, &kinds, &walls, duration)?;
    if physics_has_lubrication {
        let injected = injectors.iter().map(|j| (j.kind, j.diameter.min_diameter()));
        let sizes = (0..particles.len()).map(|i| (particles.kind[i], particles.diameter[i]));
        check_roughness_below_radius(sizes.chain(injected), &kinds, &walls)?;
    }
    let outlets = flux::build_outlets(&file.outlets, &walls)?;

    let integrator = sim.integrator.unwrap_or(IntegratorKind::Rk2);
    let mut setup = Setup::new(kinds, walls, (fluid, physics), rule, (integrator, dt));
    setup.impact_location = sim.impact_location;
    setup.injectors = injectors;
    setup.outlets = outlets;
    let mut scene = Scene {
        path: Default::default(),
        source: source.to_string(),
        duration,
        output_interval,
        auto_step: None,
        setup,
        particles,
        estimate,
        estimate_inputs,
        checkpoint,
    };
    if sim.dt == DtSpec::Auto {
        let auto = auto_step(&scene, sim.accuracy.unwrap_or_default())
            .map_err(|message| Invalid::new("simulation.dt", message))?;
        scene.setup.dt = auto.dt;
        scene.setup.integrator = auto.integrator;
        scene.auto_step = Some(auto);
        fold_history_for_step(&mut scene.setup.physics, scene.setup.dt);
        if let Some(kernel) = &scene.setup.physics.history {
            scene.estimate = scene.estimate.clone().with_history_modes(kernel.stored_modes());
        }
    }
    // After `dt = "auto"` has chosen: its step is far inside the limit, and this says so.
    check_stable_step(&scene.setup, &scene.particles)?;
    if let Some(kernel) = &scene.setup.physics.history {
        // The memory itself is allocated when a run starts (`Simulation::new`), not here: a
        // scene that is only checked never holds it.
        check_history_window(kernel, scene.setup.dt)?;
    }
    if !options.allow_long_run {
        run_length(duration, output_interval, scene.setup.dt).map_err(|e| {
            let key = match e {
                TooLong::Frames(_) => "simulation.output_interval",
                TooLong::Steps(_) => "simulation.duration",
            };
            Invalid::new(key, e.to_string())
        })?;
    }
    Ok(scene)
}

/// The history window must hold at least one step (a memory shorter than Δt would forget the
/// step being taken), and its shortest resolved lag ([`SHORTEST_LAG`] of it) must stay below
/// Δt/1000, where the lumped short-lag term is exact: a window of at most 10⁷ Δt.
fn check_history_window(kernel: &MemoryKernel, dt: f64) -> Result<(), Invalid> {
    let key = "effects.history.window";
    if kernel.window < dt {
        return Err(Invalid::new(
            key,
            format!("must be at least the time step dt = {} s, got {} s", num(dt), num(kernel.window)),
        ));
    }
    let longest = 1e-3 * dt / SHORTEST_LAG;
    if kernel.window > longest {
        return Err(Invalid::new(
            key,
            format!(
                "must be at most 1e7 dt = {} s (the memory resolves lags down to 1e-10 of the window, \
                 which must stay below dt/1000), got {} s",
                num(longest),
                num(kernel.window)
            ),
        ));
    }
    Ok(())
}

fn build_fluid(f: &FluidSpec, base: &Path, source: &str) -> Result<Fluid, Invalid> {
    Ok(Fluid {
        density: check::non_negative_in("fluid.density", f.density, &FLUID_DENSITY)?,
        viscosity: check::non_negative_in("fluid.viscosity", f.viscosity, &VISCOSITY)?,
        gravity: check::magnitude_in("fluid.gravity", f.gravity, &GRAVITY)?,
        flow: flow::build_flow(&f.flow, base, source)?,
    })
}

fn build_kinds(specs: &[KindSpec]) -> Result<Vec<ParticleKind>, Invalid> {
    if specs.is_empty() {
        return Err(Invalid::new("kinds", "at least one particle kind is needed"));
    }
    let mut kinds: Vec<ParticleKind> = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        let key = |field: &str| format!("kinds[{i}].{field}");
        let name = &spec.name;
        let material = match spec.material {
            KindType::Solid => {
                forbid(&key("surface_tension"), spec.surface_tension.is_some(), "a solid (drops have it)")?;
                Material::Solid {
                    youngs_modulus: check::positive_in(
                        &key("youngs_modulus"),
                        required(&key("youngs_modulus"), spec.youngs_modulus, "a solid")?,
                        &YOUNGS_MODULUS,
                    )?,
                    poisson_ratio: poisson(
                        &key("poisson_ratio"),
                        required(&key("poisson_ratio"), spec.poisson_ratio, "a solid")?,
                    )?,
                }
            }
            KindType::Drop => {
                forbid(&key("youngs_modulus"), spec.youngs_modulus.is_some(), "a drop (solids have it)")?;
                forbid(&key("poisson_ratio"), spec.poisson_ratio.is_some(), "a drop (solids have it)")?;
                required(&key("restitution_max"), spec.restitution_max, "a drop")?;
                Material::Drop {
                    surface_tension: check::positive_in(
                        &key("surface_tension"),
                        required(&key("surface_tension"), spec.surface_tension, "a drop")?,
                        &SURFACE_TENSION,
                    )?,
                }
            }
        };
        let restitution_max = spec.restitution_max.unwrap_or(1.0);
        let density = spec.density;
        if name.trim().is_empty() {
            return Err(Invalid::new(key("name"), "must not be empty"));
        }
        if kinds.iter().any(|k| &k.name == name) {
            return Err(Invalid::new(key("name"), format!("duplicate kind name \"{name}\"")));
        }
        if kinds.len() >= u16::MAX as usize {
            return Err(Invalid::new("kinds", format!("at most {} kinds", u16::MAX)));
        }
        kinds.push(ParticleKind {
            name: name.clone(),
            density: check::positive_in(&key("density"), density, &DENSITY)?,
            restitution_max: check::in_range(&key("restitution_max"), restitution_max, 0.0, 1.0)?,
            material,
            roughness: spec
                .roughness
                .map(|v| check::positive_in(&key("roughness"), v, &ROUGHNESS))
                .transpose()?
                .unwrap_or(0.0),
            friction: friction_keys(
                &key(""),
                (spec.friction, spec.tangential_restitution, spec.rolling_friction),
            )?,
            // Set by the contact-time effect once the effects are built.
            held_at_contact: false,
        });
    }
    Ok(kinds)
}

/// The friction keys of a kind or a wall material **[ext]** (docs/physics.md §9), `prefix` the key
/// path up to the key's name (`kinds[0].`, `walls[1].material.`): `friction` (μ) 0 to 10,
/// `tangential_restitution` (β0) −1 to 1, `rolling_friction` (μ_r) 0 to 1.
pub(super) fn friction_keys(
    prefix: &str,
    (mu, beta0, rolling): (Option<f64>, Option<f64>, Option<f64>),
) -> Result<FrictionMaterial, Invalid> {
    let key = |f: &str| format!("{prefix}{f}");
    Ok(FrictionMaterial {
        friction: mu.map(|v| check::in_range(&key("friction"), v, 0.0, 10.0)).transpose()?,
        tangential_restitution: beta0
            .map(|v| check::in_range(&key("tangential_restitution"), v, -1.0, 1.0))
            .transpose()?,
        rolling_friction: rolling
            .map(|v| check::in_range(&key("rolling_friction"), v, 0.0, 1.0))
            .transpose()?,
    })
}

pub(super) fn poisson(key: &str, v: f64) -> Result<f64, Invalid> {
    check::finite(key, v)?;
    if v > -1.0 && v <= 0.5 {
        Ok(v)
    } else {
        Err(Invalid::new(key, format!("must be in (-1, 0.5], got {}", num(v))))
    }
}

/// An explicit integrator must be stable for the stiffest drag of the scene (`h λ` inside its
/// real-axis stability interval, see [`super::stiffness`]); otherwise the error names the
/// largest stable step and the exponential integrator, which is stable at any step.
fn check_stable_step(setup: &Setup, particles: &Particles) -> Result<(), Invalid> {
    let Setup { dt, integrator, ref kinds, .. } = *setup;
    check_stable_in_flow(setup)?;
    let Some(s) = stiffest_drag(&setup.physics, &setup.fluid, particles, &setup.injectors) else {
        return Ok(());
    };
    let limit = integrator.largest_stable_step(s.rate);
    if dt < limit {
        return Ok(());
    }
    Err(Invalid::new(
        "simulation.dt",
        format!(
            "{} s is not below the largest stable step of the {} integrator, {} s \
             ({:.3} τ, τ = {:.3e} s the shortest drag relaxation time, linearised, of kind \"{}\" \
             at d = {} m and slip speed {:.3e} m/s); use a smaller dt, or integrator = \
             \"exponential\", which is stable at any dt",
            num(dt),
            integrator.name(),
            round_down(limit),
            integrator.stability_interval(),
            1.0 / s.rate,
            kinds[s.kind].name,
            num(s.diameter),
            s.slip_speed,
        ),
    ))
}

/// In a field flow, a particle's position feeds back on its velocity at the rate
/// [`flow_rate`] (`|∇u|_max`, docs/physics.md §7): every scheme, the exponential one included (its
/// flow velocity is taken at a predicted midpoint, explicitly), must have `h` times that rate
/// inside its real-axis stability interval, 2 for the exponential scheme.
fn check_stable_in_flow(setup: &Setup) -> Result<(), Invalid> {
    let Setup { dt, integrator, .. } = *setup;
    let Some(rate) = flow_rate(&setup.physics, &setup.fluid) else { return Ok(()) };
    check_step_within_snapshots(setup)?;
    let interval = match integrator {
        IntegratorKind::Exponential => 2.0,
        _ => integrator.stability_interval(),
    };
    let limit = interval / rate;
    if dt < limit {
        return Ok(());
    }
    let gradient = setup.fluid.flow.field().map_or(0.0, |f| f.info.largest_gradient);
    Err(Invalid::new(
        "simulation.dt",
        format!(
            "{} s is not below the largest stable step of the {} integrator in the flow field, {} s \
             ({interval} / {:.3e} 1/s, the rate at which a particle following the flow feeds its position \
             back into its velocity: the field's largest velocity gradient |du_i/dx_j| = {:.3e} 1/s{}); \
             use a smaller dt, or dt = \"auto\"",
            num(dt),
            integrator.name(),
            round_down(limit),
            rate,
            gradient,
            if setup.physics.fluid_acceleration {
                ", times the square root of the largest fluid-acceleration gain"
            } else {
                ""
            },
        ),
    ))
}

/// In an unsteady field that acts on the particles, a step may not be longer than the shortest
/// interval between two snapshots: the flow is linear in time only between two of them, and
/// `∂u/∂t` (the fluid-acceleration effect) is the slope of the pair around the time asked, so a
/// longer step samples the series at points that skip whole snapshots and integrates an
/// aliased flow (a field of period 2e-7 s stepped at 1e-4 s bounced a bead 52 times where the
/// resolved run has no contact). Not a stability limit: the refusal is at the interval itself,
/// and `dt = "auto"` takes a fraction of it as one of its time scales.
fn check_step_within_snapshots(setup: &Setup) -> Result<(), Invalid> {
    let Some(field) = setup.fluid.flow.field() else { return Ok(()) };
    let s = super::stiffness::shortest_snapshot_interval(field);
    if setup.dt <= s.length {
        return Ok(());
    }
    Err(Invalid::new(
        "simulation.dt",
        format!(
            "{} s is longer than the shortest interval between the flow field's snapshots, {} s \
             (from t = {} s to {} s{}): a step would pass over snapshots, and the flow and its \
             time derivative would be sampled out of step with the series; use dt <= {} s, or \
             dt = \"auto\"",
            num(setup.dt),
            num(s.length),
            num(s.from),
            num(s.to),
            if field.period.is_some() && s.to > field.snapshots[field.snapshots.len() - 1].time {
                ", the wrap of the periodic series back to its first snapshot"
            } else {
                ""
            },
            num(s.length),
        ),
    ))
}

/// `x` rounded down to 3 significant digits, so that the value shown is itself stable.
fn round_down(x: f64) -> String {
    let scale = 10f64.powf(x.log10().floor() - 2.0);
    format!("{:.2e}", (x / scale).floor() * scale)
}

/// A particle may start touching a wall (gap 0) but not overlapping or behind it.
/// The bounce rule's restitution (docs/physics.md §3): L06's `ε(St)` or, with wall lubrication,
/// the `e` rule. Each without the other is refused: L06's `ε` already holds the fluid's losses
/// near the wall that lubrication computes (they would be counted twice), and the `e` rule
/// without lubrication has no St dependence at all.
fn e_rule(b: &BounceSpec, lubrication: bool) -> Result<Option<Option<f64>>, Invalid> {
    let rule = b.rule.unwrap_or(if lubrication { RuleSpec::E } else { RuleSpec::L06 });
    match (rule, lubrication) {
        (RuleSpec::E, false) => Err(Invalid::new(
            "bounce.rule",
            "\"e\" needs the wall_lubrication effect (without it the rebound would not depend on \
             the Stokes number at all), got \"e\"",
        )),
        (RuleSpec::L06, true) => Err(Invalid::new(
            "bounce.rule",
            "must be \"e\" with the wall_lubrication effect (L06's exp(-beta/St) already holds the \
             losses the lubrication computes: they would be counted twice), got \"l06\"",
        )),
        (RuleSpec::L06, false) => {
            forbid("bounce.e", b.e.is_some(), "the \"l06\" rule (it is the \"e\" rule's restitution)")?;
            Ok(None)
        }
        (RuleSpec::E, true) => {
            // The e rule has no exp(-beta/St) and no St_c: a value given for them would be
            // silently unused.
            let e_rule = "the \"e\" rule (it has no exp(-beta/St) and no St_c: its rebound depends on St \
                          through the lubrication)";
            forbid("bounce.beta", b.beta.is_some(), e_rule)?;
            forbid("bounce.st_critical", b.st_critical.is_some(), e_rule)?;
            Ok(Some(b.e.map(|e| check::in_range("bounce.e", e, 0.0, 1.0)).transpose()?))
        }
    }
}

/// `bounce.tangential_restitution` (`e_t`, 0 to 1; 1 when left out) is the tangential rule of
/// a scene without friction. With friction keys, Walton's impulse model replaces it, and a value
/// given would be silently unused: it is refused, with what to write instead.
fn tangential_rule(b: &BounceSpec, friction: bool) -> Result<f64, Invalid> {
    match (b.tangential_restitution, friction) {
        (None, _) => Ok(1.0),
        (Some(v), false) => check::in_range("bounce.tangential_restitution", v, 0.0, 1.0),
        (Some(v), true) => Err(Invalid::new(
            "bounce.tangential_restitution",
            format!(
                "is the tangential rule of a scene without friction; this scene gives friction keys, \
                 whose impulse model replaces it: remove it and give `tangential_restitution` (β0, \
                 -1 to 1) with `friction` in [[kinds]] or a wall's material, got {}",
                num(v)
            ),
        )),
    }
}

/// With wall lubrication, every particle kind and wall pair needs a contact gap `h_r > 0` (the
/// sum of the two roughnesses); without it, a roughness has no use and is refused.
fn check_roughness(
    file: &SceneFile,
    kinds: &[ParticleKind],
    walls: &[Wall],
    lubrication: bool,
) -> Result<(), Invalid> {
    if !lubrication {
        let unused = |key: String, v: Option<f64>| match v {
            Some(v) => Err(Invalid::new(
                key,
                format!(
                    "is used only by the wall_lubrication effect, which the scene does not name, got {}",
                    num(v)
                ),
            )),
            None => Ok(()),
        };
        for (i, k) in file.kinds.iter().enumerate() {
            unused(format!("kinds[{i}].roughness"), k.roughness)?;
        }
        for (i, w) in file.walls.iter().enumerate() {
            unused(format!("walls[{i}].material.roughness"), w.material.roughness)?;
        }
        return Ok(());
    }
    for (i, k) in kinds.iter().enumerate() {
        if let Some(w) = walls.iter().find(|w| k.roughness + w.material.roughness <= 0.0) {
            return Err(Invalid::new(
                format!("kinds[{i}].roughness"),
                format!(
                    "is needed with the wall_lubrication effect (contact is made at the particle's \
                     roughness plus the wall's, and wall \"{}\" has none), got none",
                    w.name
                ),
            ));
        }
    }
    Ok(())
}

/// The contact gap (the kind's roughness plus the roughest wall's) must be below the radius of
/// each particle, `(kind, diameter)`, initial or the smallest an injector can give.
fn check_roughness_below_radius(
    sizes: impl Iterator<Item = (u16, f64)>,
    kinds: &[ParticleKind],
    walls: &[Wall],
) -> Result<(), Invalid> {
    let wall_max = walls.iter().map(|w| w.material.roughness).fold(0.0, f64::max);
    for (k, d) in sizes {
        let k = k as usize;
        let (h_r, r) = (kinds[k].roughness + wall_max, 0.5 * d);
        if h_r >= r {
            return Err(Invalid::new(
                format!("kinds[{k}].roughness"),
                format!(
                    "must be below the radius of every particle of kind \"{}\" (with the roughest \
                     wall's {} m added: {} m), but a particle has radius {} m; got {}",
                    kinds[k].name,
                    num(wall_max),
                    num(h_r),
                    num(r),
                    num(kinds[k].roughness)
                ),
            ));
        }
    }
    Ok(())
}

/// The `[checkpoint]` table, checked.
fn checkpoint_keys(spec: &super::schema::CheckpointSpec) -> Result<super::CheckpointKeys, Invalid> {
    let every = spec.every.map(|v| check::positive("checkpoint.every", v)).transpose()?;
    let wall_minutes =
        spec.wall_minutes.map(|v| check::positive("checkpoint.wall_minutes", v)).transpose()?;
    let keep = match spec.keep {
        None => None,
        Some(k) if (1..=1_000_000).contains(&k) => Some(k as usize),
        Some(k) => {
            return Err(Invalid::new(
                "checkpoint.keep",
                format!("must be a whole number from 1 to 1000000, got {k}"),
            ));
        }
    };
    Ok(super::CheckpointKeys { every, wall_minutes, keep })
}
