//! `[[walls]]`: one builder per wall type. A wall type's keys are listed once, in
//! [`WallType::keys`]; its builder reads them (adding a shape: a variant of `WallType` and its
//! keys in `schema.rs`, a line in `keys`, a builder here — see docs/architecture.md).

use super::build::poisson;
use super::error::Invalid;
use super::error::check::{self, only, required};
use super::error::fmt::{num, vec3};
use super::ranges::{LENGTH, LENGTH_OR_ZERO, MESH_SCALE, ROUGHNESS, YOUNGS_MODULUS};
use super::schema::{MaterialSpec, Vec3Spec, WallSpec, WallType};
use crate::walls::{Cuboid, Cylinder, Plane, Shape, Wall, WallMaterial, annulus_mesh, load_mesh};
use std::path::Path;

impl WallType {
    /// The geometry keys of this type (besides `name`, `type` and `material`), and how error
    /// messages call it.
    fn keys(self) -> (&'static [&'static str], &'static str) {
        match self {
            WallType::Plane => (&["point", "normal"], "a plane"),
            WallType::Box => (&["min", "max", "inside"], "a box"),
            WallType::Cylinder => (&["base", "axis", "radius", "length"], "a cylinder"),
            WallType::Mesh => (&["file", "scale", "translate"], "a mesh"),
            WallType::Annulus => (
                &["center", "normal", "inner_radius", "outer_radius", "cone_height", "segments"],
                "an annulus",
            ),
        }
    }
}

/// One `[[walls]]` entry being built: its key path (`walls[i]`) and what messages call it.
struct Entry<'a> {
    spec: &'a WallSpec,
    key: String,
    what: &'static str,
}

impl Entry<'_> {
    /// The key path of field `f`.
    fn k(&self, f: &str) -> String {
        format!("{}.{f}", self.key)
    }

    /// A field this type needs.
    fn need<T>(&self, f: &str, v: Option<T>) -> Result<T, Invalid> {
        required(&self.k(f), v, self.what)
    }
}

/// Validates and builds the walls; mesh files are read relative to `base`.
pub(super) fn build_walls(specs: &[WallSpec], base: &Path) -> Result<Vec<Wall>, Invalid> {
    let mut walls: Vec<Wall> = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        let (allowed, what) = spec.shape.keys();
        let e = Entry { spec, key: format!("walls[{i}]"), what };
        only(&e.key, &spec.present(), allowed, what)?;
        let shape = match spec.shape {
            WallType::Plane => plane(&e)?,
            WallType::Box => cuboid(&e)?,
            WallType::Cylinder => cylinder(&e)?,
            WallType::Mesh => mesh(&e, base)?,
            WallType::Annulus => annulus(&e)?,
        };
        let name = &spec.name;
        if name.trim().is_empty() {
            return Err(Invalid::new(e.k("name"), "must not be empty"));
        }
        if walls.iter().any(|w| &w.name == name) {
            return Err(Invalid::new(e.k("name"), format!("duplicate wall name \"{name}\"")));
        }
        walls.push(Wall { name: name.clone(), material: build_material(&spec.material, &e.key)?, shape });
    }
    Ok(walls)
}

fn plane(e: &Entry) -> Result<Shape, Invalid> {
    let s = e.spec;
    Ok(Shape::Plane(Plane {
        point: check::point(&e.k("point"), e.need("point", s.point)?)?,
        normal: check::direction(&e.k("normal"), e.need("normal", s.normal)?)?,
    }))
}

fn cuboid(e: &Entry) -> Result<Shape, Invalid> {
    let s = e.spec;
    let (min, max) = (e.need("min", s.min)?, e.need("max", s.max)?);
    let (lo, hi) = (check::point(&e.k("min"), min)?, check::point(&e.k("max"), max)?);
    if !lo.cmplt(hi).all() {
        return Err(Invalid::new(
            e.k("max"),
            format!("must exceed min on every axis, got min {}, max {}", vec3(min.0), vec3(max.0)),
        ));
    }
    let inside =
        required(&e.k("inside"), s.inside, "a box (true: particles inside it; false: it is an obstacle)")?;
    Ok(Shape::Cuboid(Cuboid { min: lo, max: hi, inside }))
}

fn cylinder(e: &Entry) -> Result<Shape, Invalid> {
    let s = e.spec;
    let (lo, hi) = match s.length {
        Some(l) => (0.0, check::positive_in(&e.k("length"), l, &LENGTH)?),
        None => (f64::NEG_INFINITY, f64::INFINITY),
    };
    Ok(Shape::Cylinder(Cylinder {
        base: check::point(&e.k("base"), e.need("base", s.base)?)?,
        axis: check::direction(&e.k("axis"), s.axis.unwrap_or(Vec3Spec([0.0, 0.0, 1.0])))?,
        radius: check::positive_in(&e.k("radius"), e.need("radius", s.radius)?, &LENGTH)?,
        lo,
        hi,
    }))
}

fn mesh(e: &Entry, base: &Path) -> Result<Shape, Invalid> {
    let s = e.spec;
    let file = e.need("file", s.file.clone())?;
    let scale = check::positive_in(&e.k("scale"), s.scale.unwrap_or(1.0), &MESH_SCALE)?;
    let translate = check::point(&e.k("translate"), s.translate.unwrap_or_default())?;
    let mesh = load_mesh(&base.join(&file), scale, translate)
        .map_err(|err| Invalid::new(e.k("file"), err.to_string()))?;
    Ok(Shape::Mesh(Box::new(mesh)))
}

fn annulus(e: &Entry) -> Result<Shape, Invalid> {
    let s = e.spec;
    let center = check::point(&e.k("center"), e.need("center", s.center)?)?;
    let normal = check::direction(&e.k("normal"), e.need("normal", s.normal)?)?;
    let outer = check::positive_in(&e.k("outer_radius"), e.need("outer_radius", s.outer_radius)?, &LENGTH)?;
    let inner = check::non_negative_in(&e.k("inner_radius"), s.inner_radius.unwrap_or(0.0), &LENGTH_OR_ZERO)?;
    if inner >= outer {
        return Err(Invalid::new(
            e.k("inner_radius"),
            format!("must be < outer_radius {}, got {}", num(outer), num(inner)),
        ));
    }
    let segments = s.segments.unwrap_or(128);
    if !(3..=100_000).contains(&segments) {
        return Err(Invalid::new(e.k("segments"), format!("must be between 3 and 100000, got {segments}")));
    }
    let cone_height = check::signed_in(&e.k("cone_height"), s.cone_height.unwrap_or(0.0), &LENGTH_OR_ZERO)?;
    Ok(Shape::Mesh(Box::new(annulus_mesh(center, normal, inner, outer, cone_height, segments))))
}

fn build_material(m: &MaterialSpec, key: &str) -> Result<WallMaterial, Invalid> {
    let k = |f: &str| format!("{key}.material.{f}");
    Ok(WallMaterial {
        youngs_modulus: m
            .youngs_modulus
            .map(|v| check::positive_in(&k("youngs_modulus"), v, &YOUNGS_MODULUS))
            .transpose()?,
        poisson_ratio: m.poisson_ratio.map(|v| poisson(&k("poisson_ratio"), v)).transpose()?,
        restitution_max: m
            .restitution_max
            .map(|v| check::in_range(&k("restitution_max"), v, 0.0, 1.0))
            .transpose()?,
        roughness: m
            .roughness
            .map(|v| check::positive_in(&k("roughness"), v, &ROUGHNESS))
            .transpose()?
            .unwrap_or(0.0),
        friction: super::build::friction_keys(
            &k(""),
            (m.friction, m.tangential_restitution, m.rolling_friction),
        )?,
    })
}
