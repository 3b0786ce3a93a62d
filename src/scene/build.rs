//! From the parsed file to a validated [`Scene`].

use super::accuracy::auto_step;
use super::error::check::{self, forbid, only, required};
use super::error::fmt::{num, shorten_long_numbers, vec3};
use super::error::{Invalid, SceneError};
use super::ranges::{
    self, DENSITY, FLUID_DENSITY, GRAVITY, LENGTH, SPEED, SURFACE_TENSION, TIME, VISCOSITY, YOUNGS_MODULUS,
};
use super::run_length::{TooLong, run_length};
use super::schema::*;
use super::stiffness::stiffest_drag;
use super::{LoadOptions, Scene};
use super::{fill, flux, walls};
use crate::contact::BounceRule;
use crate::effects::{Physics, build_effect};
use crate::fluid::{Flow, Fluid, Poiseuille};
use crate::integrate::IntegratorKind;
use crate::particles::{Material, ParticleKind, Particles};
use crate::pipeline::Setup;
use crate::walls::{Surface, Wall};
use glam::DVec3;
use std::path::Path;

/// The largest Stokes number at which L06 eq. 4 diverges: `0.85^10`.
const EQ4_POLE: f64 = 0.196_874_404_3;

/// Parses TOML into the schema; errors carry the key path and the line and column.
pub(super) fn parse(source: &str, path: &Path) -> Result<SceneFile, SceneError> {
    let located = |key: String, e: &toml::de::Error| {
        let at = e.span().map(|s| {
            let start = s.start.min(source.len());
            let before = &source[..start];
            let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
            format!(" (line {}, column {col})", line_of(source, start))
        });
        SceneError::Parse {
            file: path.to_path_buf(),
            key,
            message: shorten_long_numbers(&format!("{}{}", e.message().trim_end(), at.unwrap_or_default())),
        }
    };
    let de = toml::de::Deserializer::parse(source).map_err(|e| located("(top level)".into(), &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let key = e.path().to_string();
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
    source[..at.min(source.len())].matches('\n').count() + 1
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

    let fluid = build_fluid(&file.fluid)?;
    let kinds = build_kinds(&file.kinds)?;
    let walls = walls::build_walls(&file.walls, base)?;

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
        effects.push(effect);
    }
    let physics = Physics::build(&fluid, &kinds, &effects);
    if file.effects.contains_key("added_mass") {
        // The effect checks the sign itself; the range is the scene's (ranges.rs).
        ranges::ADDED_MASS.check("effects.added_mass.coefficient", physics.added_mass_coefficient)?;
    }
    if physics.drag.is_some() && fluid.viscosity <= 0.0 {
        return Err(Invalid::new(
            "fluid.viscosity",
            format!("must be > 0 with the drag effect, got {}", num(fluid.viscosity)),
        ));
    }

    let b = &file.bounce;
    let rule = BounceRule {
        beta: check::non_negative("bounce.beta", b.beta)?,
        st_critical: check::non_negative("bounce.st_critical", b.st_critical)?,
        tangential_restitution: check::in_range(
            "bounce.tangential_restitution",
            b.tangential_restitution,
            0.0,
            1.0,
        )?,
        hold_at_contact: physics.hold_at_contact,
    };
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

    let mut particles = Particles::default();
    let origins = fill::add_particles(&file, &kinds, &walls, &mut particles)?;
    check_clear_of_walls(&origins, &particles, &walls)?;
    let injectors = flux::build_injectors(&file.injectors, &kinds, duration)?;
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
    };
    if sim.dt == DtSpec::Auto {
        let auto = auto_step(&scene, sim.accuracy.unwrap_or_default())
            .map_err(|message| Invalid::new("simulation.dt", message))?;
        scene.setup.dt = auto.dt;
        scene.setup.integrator = auto.integrator;
        scene.auto_step = Some(auto);
    }
    // After `dt = "auto"` has chosen: its step is far inside the limit, and this says so.
    check_stable_step(&scene.setup, &scene.particles)?;
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

fn build_fluid(f: &FluidSpec) -> Result<Fluid, Invalid> {
    Ok(Fluid {
        density: check::non_negative_in("fluid.density", f.density, &FLUID_DENSITY)?,
        viscosity: check::non_negative_in("fluid.viscosity", f.viscosity, &VISCOSITY)?,
        gravity: check::magnitude_in("fluid.gravity", f.gravity, &GRAVITY)?,
        flow: build_flow(&f.flow)?,
    })
}

fn build_flow(f: &FlowSpec) -> Result<Flow, Invalid> {
    let k = |field: &str| format!("fluid.flow.{field}");
    let (allowed, what): (&[&str], &str) = match f.flow {
        FlowType::Quiescent => (&[], "a quiescent flow"),
        FlowType::Uniform => (&["velocity"], "a uniform flow"),
        FlowType::Poiseuille => {
            (&["point", "axis", "radius", "mean_velocity", "max_velocity"], "a poiseuille flow")
        }
    };
    let present = [
        ("velocity", f.velocity.is_some()),
        ("point", f.point.is_some()),
        ("axis", f.axis.is_some()),
        ("radius", f.radius.is_some()),
        ("mean_velocity", f.mean_velocity.is_some()),
        ("max_velocity", f.max_velocity.is_some()),
    ];
    only("fluid.flow", &present, allowed, what)?;
    Ok(match f.flow {
        FlowType::Quiescent => Flow::Quiescent,
        FlowType::Uniform => {
            let v = required(&k("velocity"), f.velocity, what)?;
            Flow::Uniform(check::magnitude_in(&k("velocity"), v, &SPEED)?)
        }
        FlowType::Poiseuille => {
            let point = check::point(&k("point"), required(&k("point"), f.point, what)?)?;
            let axis = check::direction(&k("axis"), f.axis.unwrap_or(Vec3Spec([0.0, 0.0, 1.0])))?;
            let radius = check::positive_in(&k("radius"), required(&k("radius"), f.radius, what)?, &LENGTH)?;
            let max_velocity = match (f.mean_velocity, f.max_velocity) {
                (Some(mean), None) => 2.0 * check::signed_in(&k("mean_velocity"), mean, &SPEED)?,
                (None, Some(max)) => check::signed_in(&k("max_velocity"), max, &SPEED)?,
                (Some(_), Some(_)) => {
                    return Err(Invalid::new(
                        k("max_velocity"),
                        "give either mean_velocity or max_velocity, not both (max = 2 × mean)",
                    ));
                }
                (None, None) => {
                    return Err(Invalid::new(
                        k("mean_velocity"),
                        "missing: a poiseuille flow needs mean_velocity or max_velocity",
                    ));
                }
            };
            Flow::Poiseuille(Poiseuille { point, axis, radius, max_velocity })
        }
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
        });
    }
    Ok(kinds)
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

/// `x` rounded down to 3 significant digits, so that the value shown is itself stable.
fn round_down(x: f64) -> String {
    let scale = 10f64.powf(x.log10().floor() - 2.0);
    format!("{:.2e}", (x / scale).floor() * scale)
}

/// A particle may start touching a wall (gap 0) but not overlapping or behind it.
fn check_clear_of_walls(origins: &fill::Origins, p: &Particles, walls: &[Wall]) -> Result<(), Invalid> {
    for i in 0..p.len() {
        let r = 0.5 * p.diameter[i];
        for wall in walls {
            let g = wall.shape.gap(p.pos[i], r);
            if g.gap < -1e-9 * r {
                let x: DVec3 = p.pos[i];
                return Err(Invalid::new(
                    fill::origin_key(origins, i),
                    format!(
                        "particle at {} (d = {} m) starts inside wall \"{}\": it overlaps by {:.3e} m",
                        vec3(x.to_array()),
                        num(p.diameter[i]),
                        wall.name,
                        -g.gap
                    ),
                ));
            }
        }
    }
    Ok(())
}
