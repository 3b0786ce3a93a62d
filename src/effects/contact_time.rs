//! Contact time: particles are held at the wall for `t_c` before release (PHYSICS.md §5.3).

use super::{Effect, Physics};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// With this effect a rebounding particle is immobilised at the wall for its contact time
/// (L06 eq. 4 for solids, eq. 5 for drops) and then released at `ε V∞`; without it the rebound
/// is instantaneous. L06 §5: needed for millimetric drops in liquids, whose `t_c` is of the
/// order of the relaxation time. Scene table: `contact_time = {}`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactTime {}

impl Effect for ContactTime {
    fn name(&self) -> &'static str {
        "contact_time"
    }

    fn apply(&self, _fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        physics.hold_at_contact = true;
    }
}
