//! A field's cell hints: in a flow field on an unstructured grid, each particle remembers the
//! tetrahedron that held it at the end of the last step, and the next step's flow lookups walk
//! from there (docs/physics.md §7, `fluid::field::unstructured`). Not an effect a scene names:
//! [`super::Physics::build`] registers it for a field whose lookups walk.

use crate::fluid::SharedField;
use crate::particles::{Column, Feature, NO_TET, Next, Particles};
use rayon::prelude::*;
use std::collections::TryReserveError;

/// The cell-hint feature of one field.
#[derive(Debug, Clone)]
pub struct CellHints {
    field: SharedField,
}

impl CellHints {
    /// The hints of `field`'s tetrahedra.
    pub fn new(field: SharedField) -> Self {
        CellHints { field }
    }
}

impl Feature for CellHints {
    fn name(&self) -> &'static str {
        "cell_hints"
    }

    /// One tetrahedron per particle ([`Particles::tet`]), not known yet: found at the end of
    /// the first step.
    fn start(&self, p: &mut Particles) -> Result<(), TryReserveError> {
        if !p.tet.is_on() {
            p.tet = Column::try_new(1, NO_TET, p.len())?;
        }
        Ok(())
    }

    /// The tetrahedron holding each particle's end of the step, walking from its start's:
    /// before commit, so that the column is renumbered with the others.
    fn end_of_step(&self, p: &mut Particles, next: &mut Next, _h: f64) {
        let field = &self.field.0;
        let tets = p.tet.values_mut();
        tets.par_iter_mut().zip(next.pos.par_iter()).for_each(|(t, &x)| *t = field.tet_of(*t, x));
    }
}
