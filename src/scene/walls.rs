//! `[[walls]]`: one table per wall shape. A shape's keys are listed once, in its struct in
//! `schema.rs`; the registry [`WallType::table`] maps each `type` to its struct, whose
//! [`Table::build`] here builds the shape (adding a shape: a variant of `WallType` and its
//! struct in `schema.rs`, a line in `table`, a builder here — see docs/architecture.md).

use super::build::poisson;
use super::error::Invalid;
use super::error::check::{self, required};
use super::error::fmt::{num, vec3};
use super::ranges::{LENGTH, LENGTH_OR_ZERO, MESH_SCALE, ROUGHNESS, YOUNGS_MODULUS};
use super::schema::{
    AnnulusSpec, BoxSpec, CylinderSpec, MaterialSpec, MeshSpec, PlaneSpec, Vec3Spec, WallSpec, WallType,
};
use super::table::{self, Entry, Place, Table, entry};
use crate::walls::{Cuboid, Cylinder, Plane, Shape, Wall, WallMaterial, annulus_mesh, load_mesh};
use std::path::Path;

impl WallType {
    /// The registry of wall shapes: each type's table.
    fn table(self) -> Entry<Shape> {
        match self {
            WallType::Plane => entry::<PlaneSpec, _>(),
            WallType::Box => entry::<BoxSpec, _>(),
            WallType::Cylinder => entry::<CylinderSpec, _>(),
            WallType::Mesh => entry::<MeshSpec, _>(),
            WallType::Annulus => entry::<AnnulusSpec, _>(),
        }
    }
}

/// Validates and builds the walls; mesh files are read relative to `base`, lines counted in
/// `source`.
pub(super) fn build_walls(specs: &[WallSpec], base: &Path, source: &str) -> Result<Vec<Wall>, Invalid> {
    let mut walls: Vec<Wall> = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        let key = format!("walls[{i}]");
        let shape = table::build(spec.shape, WallType::table, &spec.rest, key.clone(), source, base)?;
        let name = &spec.name;
        if name.trim().is_empty() {
            return Err(Invalid::new(format!("{key}.name"), "must not be empty"));
        }
        if walls.iter().any(|w| &w.name == name) {
            return Err(Invalid::new(format!("{key}.name"), format!("duplicate wall name \"{name}\"")));
        }
        walls.push(Wall { name: name.clone(), material: build_material(&spec.material, &key)?, shape });
    }
    Ok(walls)
}

impl Table<Shape> for PlaneSpec {
    const WHAT: &'static str = "a plane";
    fn build(self, e: &Place, _base: &Path) -> Result<Shape, Invalid> {
        Ok(Shape::Plane(Plane {
            point: check::point(&e.k("point"), self.point)?,
            normal: check::direction(&e.k("normal"), self.normal)?,
        }))
    }
}

impl Table<Shape> for BoxSpec {
    const WHAT: &'static str = "a box";
    fn build(self, e: &Place, _base: &Path) -> Result<Shape, Invalid> {
        let (min, max) = (self.min, self.max);
        let (lo, hi) = (check::point(&e.k("min"), min)?, check::point(&e.k("max"), max)?);
        if !lo.cmplt(hi).all() {
            return Err(Invalid::new(
                e.k("max"),
                format!("must exceed min on every axis, got min {}, max {}", vec3(min.0), vec3(max.0)),
            ));
        }
        let inside = required(
            &e.k("inside"),
            self.inside,
            "a box (true: particles inside it; false: it is an obstacle)",
        )?;
        Ok(Shape::Cuboid(Cuboid { min: lo, max: hi, inside }))
    }
}

impl Table<Shape> for CylinderSpec {
    const WHAT: &'static str = "a cylinder";
    fn build(self, e: &Place, _base: &Path) -> Result<Shape, Invalid> {
        let (lo, hi) = match self.length {
            Some(l) => (0.0, check::positive_in(&e.k("length"), l, &LENGTH)?),
            None => (f64::NEG_INFINITY, f64::INFINITY),
        };
        Ok(Shape::Cylinder(Cylinder {
            base: check::point(&e.k("base"), self.base)?,
            axis: check::direction(&e.k("axis"), self.axis.unwrap_or(Vec3Spec([0.0, 0.0, 1.0])))?,
            radius: check::positive_in(&e.k("radius"), self.radius, &LENGTH)?,
            lo,
            hi,
        }))
    }
}

impl Table<Shape> for MeshSpec {
    const WHAT: &'static str = "a mesh";
    fn build(self, e: &Place, base: &Path) -> Result<Shape, Invalid> {
        let scale = check::positive_in(&e.k("scale"), self.scale.unwrap_or(1.0), &MESH_SCALE)?;
        let translate = check::point(&e.k("translate"), self.translate.unwrap_or_default())?;
        let mesh = load_mesh(&base.join(&self.file), scale, translate)
            .map_err(|err| Invalid::new(e.k("file"), err.to_string()))?;
        Ok(Shape::Mesh(Box::new(mesh)))
    }
}

impl Table<Shape> for AnnulusSpec {
    const WHAT: &'static str = "an annulus";
    fn build(self, e: &Place, _base: &Path) -> Result<Shape, Invalid> {
        let center = check::point(&e.k("center"), self.center)?;
        let normal = check::direction(&e.k("normal"), self.normal)?;
        let outer = check::positive_in(&e.k("outer_radius"), self.outer_radius, &LENGTH)?;
        let inner =
            check::non_negative_in(&e.k("inner_radius"), self.inner_radius.unwrap_or(0.0), &LENGTH_OR_ZERO)?;
        if inner >= outer {
            return Err(Invalid::new(
                e.k("inner_radius"),
                format!("must be < outer_radius {}, got {}", num(outer), num(inner)),
            ));
        }
        let segments = self.segments.unwrap_or(128);
        if !(3..=100_000).contains(&segments) {
            return Err(Invalid::new(
                e.k("segments"),
                format!("must be between 3 and 100000, got {segments}"),
            ));
        }
        let cone_height =
            check::signed_in(&e.k("cone_height"), self.cone_height.unwrap_or(0.0), &LENGTH_OR_ZERO)?;
        Ok(Shape::Mesh(Box::new(annulus_mesh(center, normal, inner, outer, cone_height, segments))))
    }
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
