//! From the parsed file to a validated [`Scene`].

use super::Scene;
use super::error::{Invalid, SceneError, check};
use super::fill;
use super::schema::*;
use crate::contact::BounceRule;
use crate::effects::{Physics, build_effect};
use crate::fluid::{Flow, Fluid};
use crate::particles::{Material, ParticleKind, Particles};
use crate::walls::{Cuboid, Cylinder, Plane, Shape, Surface, Wall, WallMaterial, load_mesh};
use glam::DVec3;
use std::path::Path;

/// The largest Stokes number at which L06 eq. 4 diverges: `0.85^10`.
const EQ4_POLE: f64 = 0.196_874_404_3;

/// Parses TOML into the schema; errors carry the key path and the line and column.
pub(super) fn parse(source: &str, path: &Path) -> Result<SceneFile, SceneError> {
    let located = |key: String, e: &toml::de::Error| {
        let at = e.span().map(|s| {
            let before = &source[..s.start.min(source.len())];
            let line = before.matches('\n').count() + 1;
            let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
            format!(" (line {line}, column {col})")
        });
        SceneError::Parse {
            file: path.to_path_buf(),
            key,
            message: format!("{}{}", e.message().trim_end(), at.unwrap_or_default()),
        }
    };
    let de =
        toml::de::Deserializer::parse(source).map_err(|e| located("(top level)".into(), &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let key = e.path().to_string();
        let key = if key == "." {
            "(top level)".to_string()
        } else {
            key
        };
        located(key, e.inner())
    })
}

pub(super) fn build(file: SceneFile, base: &Path, source: &str) -> Result<Scene, Invalid> {
    let sim = &file.simulation;
    let dt = check::positive("simulation.dt", sim.dt)?;
    let duration = check::positive("simulation.duration", sim.duration)?;
    let output_interval = check::positive("simulation.output_interval", sim.output_interval)?;

    let fluid = build_fluid(&file.fluid)?;
    let kinds = build_kinds(&file.kinds)?;
    let walls = build_walls(&file.walls, base)?;

    let mut effects = Vec::new();
    for (name, table) in &file.effects {
        let key = format!("effects.{name}");
        let table = match table {
            toml::Value::Table(_) => table.clone(),
            other => {
                return Err(Invalid::new(
                    key,
                    format!("must be a table such as {{}}, got {other}"),
                ));
            }
        };
        effects.push(build_effect(name, table).map_err(|m| Invalid::new(key, m))?);
    }
    let physics = Physics::build(&fluid, &kinds, &effects);
    if physics.drag.is_some() && fluid.viscosity <= 0.0 {
        return Err(Invalid::new(
            "fluid.viscosity",
            format!("must be > 0 with the drag effect, got {}", fluid.viscosity),
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
    let has_solid = kinds
        .iter()
        .any(|k| matches!(k.material, Material::Solid { .. }));
    if has_solid && rule.st_critical <= EQ4_POLE {
        return Err(Invalid::new(
            "bounce.st_critical",
            format!(
                "must be > {EQ4_POLE:.3} with solid particles (the contact time of L06 eq. 4 \
                 diverges there), got {}",
                rule.st_critical
            ),
        ));
    }

    let mut particles = Particles::default();
    let origins = fill::add_particles(&file, &kinds, &mut particles)?;
    check_clear_of_walls(&origins, &particles, &walls)?;

    Ok(Scene {
        path: Default::default(),
        source: source.to_string(),
        dt,
        duration,
        output_interval,
        integrator: sim.integrator,
        fluid,
        kinds,
        walls,
        physics,
        rule,
        particles,
    })
}

fn build_fluid(f: &FluidSpec) -> Result<Fluid, Invalid> {
    Ok(Fluid {
        density: check::non_negative("fluid.density", f.density)?,
        viscosity: check::non_negative("fluid.viscosity", f.viscosity)?,
        gravity: check::vector("fluid.gravity", f.gravity)?,
        flow: match f.flow {
            FlowSpec::Quiescent => Flow::Quiescent,
            FlowSpec::Uniform { velocity } => {
                Flow::Uniform(check::vector("fluid.flow.velocity", velocity)?)
            }
        },
    })
}

fn build_kinds(specs: &[KindSpec]) -> Result<Vec<ParticleKind>, Invalid> {
    if specs.is_empty() {
        return Err(Invalid::new(
            "kinds",
            "at least one particle kind is needed",
        ));
    }
    let mut kinds: Vec<ParticleKind> = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        let key = |field: &str| format!("kinds[{i}].{field}");
        let (name, density, restitution_max, material) = match spec {
            KindSpec::Solid {
                name,
                density,
                restitution_max,
                youngs_modulus,
                poisson_ratio,
            } => (
                name,
                density,
                restitution_max,
                Material::Solid {
                    youngs_modulus: check::positive(&key("youngs_modulus"), *youngs_modulus)?,
                    poisson_ratio: poisson(&key("poisson_ratio"), *poisson_ratio)?,
                },
            ),
            KindSpec::Drop {
                name,
                density,
                restitution_max,
                surface_tension,
            } => (
                name,
                density,
                restitution_max,
                Material::Drop {
                    surface_tension: check::positive(&key("surface_tension"), *surface_tension)?,
                },
            ),
        };
        if name.trim().is_empty() {
            return Err(Invalid::new(key("name"), "must not be empty"));
        }
        if kinds.iter().any(|k| &k.name == name) {
            return Err(Invalid::new(
                key("name"),
                format!("duplicate kind name \"{name}\""),
            ));
        }
        if kinds.len() >= u16::MAX as usize {
            return Err(Invalid::new("kinds", format!("at most {} kinds", u16::MAX)));
        }
        kinds.push(ParticleKind {
            name: name.clone(),
            density: check::positive(&key("density"), *density)?,
            restitution_max: check::in_range(&key("restitution_max"), *restitution_max, 0.0, 1.0)?,
            material,
        });
    }
    Ok(kinds)
}

fn poisson(key: &str, v: f64) -> Result<f64, Invalid> {
    check::finite(key, v)?;
    if v > -1.0 && v <= 0.5 {
        Ok(v)
    } else {
        Err(Invalid::new(key, format!("must be in (-1, 0.5], got {v}")))
    }
}

fn build_material(m: &MaterialSpec, key: &str) -> Result<WallMaterial, Invalid> {
    let k = |f: &str| format!("{key}.material.{f}");
    Ok(WallMaterial {
        youngs_modulus: m
            .youngs_modulus
            .map(|v| check::positive(&k("youngs_modulus"), v))
            .transpose()?,
        poisson_ratio: m
            .poisson_ratio
            .map(|v| poisson(&k("poisson_ratio"), v))
            .transpose()?,
        restitution_max: m
            .restitution_max
            .map(|v| check::in_range(&k("restitution_max"), v, 0.0, 1.0))
            .transpose()?,
    })
}

fn build_walls(specs: &[WallSpec], base: &Path) -> Result<Vec<Wall>, Invalid> {
    let mut walls: Vec<Wall> = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        let key = format!("walls[{i}]");
        let k = |f: &str| format!("{key}.{f}");
        let (name, material, shape) = match spec {
            WallSpec::Plane {
                name,
                point,
                normal,
                material,
            } => (
                name,
                material,
                Shape::Plane(Plane {
                    point: check::vector(&k("point"), *point)?,
                    normal: check::direction(&k("normal"), *normal)?,
                }),
            ),
            WallSpec::Box {
                name,
                min,
                max,
                inside,
                material,
            } => {
                let (lo, hi) = (
                    check::vector(&k("min"), *min)?,
                    check::vector(&k("max"), *max)?,
                );
                if !lo.cmplt(hi).all() {
                    return Err(Invalid::new(
                        k("max"),
                        format!("must exceed min on every axis, got min {min:?}, max {max:?}"),
                    ));
                }
                (
                    name,
                    material,
                    Shape::Cuboid(Cuboid {
                        min: lo,
                        max: hi,
                        inside: *inside,
                    }),
                )
            }
            WallSpec::Cylinder {
                name,
                base: b,
                axis,
                radius,
                length,
                material,
            } => {
                let hi = match length {
                    Some(l) => check::positive(&k("length"), *l)?,
                    None => f64::INFINITY,
                };
                let lo = if length.is_some() {
                    0.0
                } else {
                    f64::NEG_INFINITY
                };
                (
                    name,
                    material,
                    Shape::Cylinder(Cylinder {
                        base: check::vector(&k("base"), *b)?,
                        axis: check::direction(&k("axis"), *axis)?,
                        radius: check::positive(&k("radius"), *radius)?,
                        lo,
                        hi,
                    }),
                )
            }
            WallSpec::Mesh {
                name,
                file,
                scale,
                translate,
                material,
            } => {
                let scale = check::positive(&k("scale"), *scale)?;
                let translate = check::vector(&k("translate"), *translate)?;
                let mesh = load_mesh(&base.join(file), scale, translate)
                    .map_err(|e| Invalid::new(k("file"), e.to_string()))?;
                (name, material, Shape::Mesh(Box::new(mesh)))
            }
        };
        if name.trim().is_empty() {
            return Err(Invalid::new(k("name"), "must not be empty"));
        }
        if walls.iter().any(|w| &w.name == name) {
            return Err(Invalid::new(
                k("name"),
                format!("duplicate wall name \"{name}\""),
            ));
        }
        walls.push(Wall {
            name: name.clone(),
            material: build_material(material, &key)?,
            shape,
        });
    }
    Ok(walls)
}

/// A particle may start touching a wall (gap 0) but not overlapping or behind it.
fn check_clear_of_walls(
    origins: &fill::Origins,
    p: &Particles,
    walls: &[Wall],
) -> Result<(), Invalid> {
    for i in 0..p.len() {
        let r = 0.5 * p.diameter[i];
        for wall in walls {
            let g = wall.shape.gap(p.pos[i], r);
            if g.gap < -1e-9 * r {
                let x: DVec3 = p.pos[i];
                return Err(Invalid::new(
                    fill::origin_key(origins, i),
                    format!(
                        "particle at [{}, {}, {}] (d = {} m) starts inside wall \"{}\": it overlaps by {:.3e} m",
                        x.x, x.y, x.z, p.diameter[i], wall.name, -g.gap
                    ),
                ));
            }
        }
    }
    Ok(())
}
