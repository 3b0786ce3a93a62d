//! `fluid.flow`: one table per flow type. A type's keys are listed once, in its struct in
//! `schema.rs`; the registry [`FlowType::table`] maps each `type` to its struct, whose
//! [`Table::build`] builds the flow (here; a field's in `field.rs`).

use super::error::Invalid;
use super::error::check;
use super::ranges::{LENGTH, SPEED};
use super::schema::{FieldSpec, FlowSpec, FlowType, PoiseuilleSpec, QuiescentSpec, UniformSpec, Vec3Spec};
use super::table::{self, Entry, Place, Table, entry};
use crate::fluid::{Flow, Poiseuille};
use std::path::Path;

impl FlowType {
    /// The registry of flows: each type's table.
    fn table(self) -> Entry<Flow> {
        match self {
            FlowType::Quiescent => entry::<QuiescentSpec, _>(),
            FlowType::Uniform => entry::<UniformSpec, _>(),
            FlowType::Poiseuille => entry::<PoiseuilleSpec, _>(),
            FlowType::Field => entry::<FieldSpec, _>(),
        }
    }
}

/// Validates and builds the flow; field files are read relative to `base`, lines counted in
/// `source`.
pub(super) fn build_flow(f: &FlowSpec, base: &Path, source: &str) -> Result<Flow, Invalid> {
    table::build(f.flow, FlowType::table, &f.rest, "fluid.flow".into(), source, base)
}

impl Table<Flow> for QuiescentSpec {
    const WHAT: &'static str = "a quiescent flow";
    fn build(self, _at: &Place, _base: &Path) -> Result<Flow, Invalid> {
        Ok(Flow::Quiescent)
    }
}

impl Table<Flow> for UniformSpec {
    const WHAT: &'static str = "a uniform flow";
    fn build(self, at: &Place, _base: &Path) -> Result<Flow, Invalid> {
        Ok(Flow::Uniform(check::magnitude_in(&at.k("velocity"), self.velocity, &SPEED)?))
    }
}

impl Table<Flow> for PoiseuilleSpec {
    const WHAT: &'static str = "a poiseuille flow";
    fn build(self, at: &Place, _base: &Path) -> Result<Flow, Invalid> {
        let k = |f: &str| at.k(f);
        let point = check::point(&k("point"), self.point)?;
        let axis = check::direction(&k("axis"), self.axis.unwrap_or(Vec3Spec([0.0, 0.0, 1.0])))?;
        let radius = check::positive_in(&k("radius"), self.radius, &LENGTH)?;
        let max_velocity = match (self.mean_velocity, self.max_velocity) {
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
        Ok(Flow::Poiseuille(Poiseuille { point, axis, radius, max_velocity }))
    }
}
