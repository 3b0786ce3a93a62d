//! Contact time: particles are held at the wall for `t_c` before release (docs/physics.md §5.3).

use super::{Effect, EffectError, Physics};
use crate::fluid::Fluid;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// With this effect a rebounding particle is immobilised at the wall for its contact time
/// (L06 eq. 4 for solids, eq. 5 for drops) and then released at `ε V∞`; without it the rebound
/// is instantaneous. L06 §5: needed for millimetric drops in liquids, whose `t_c` is of the
/// order of the relaxation time. Scene table: `contact_time = {}` (every kind), or
/// `contact_time = { kinds = ["toluene"] }` (only those: the beads of a mixed scene keep their
/// instantaneous rebound, and `dt = "auto"` is not bound by their microsecond Hertz time).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactTime {
    /// The kinds held at contact, by name; `None`: every kind.
    #[serde(default)]
    pub kinds: Option<Vec<String>>,
}

impl ContactTime {
    /// Whether a particle of `kind` is held at contact.
    pub fn holds(&self, kind: &ParticleKind) -> bool {
        self.kinds.as_ref().is_none_or(|names| names.contains(&kind.name))
    }
}

impl Effect for ContactTime {
    fn name(&self) -> &'static str {
        "contact_time"
    }

    fn apply(&self, _fluid: &Fluid, kinds: &[ParticleKind], physics: &mut Physics) {
        physics.hold_at_contact = true;
        physics.held_kinds = kinds.iter().map(|k| self.holds(k)).collect();
    }

    fn check(&self, kinds: &[ParticleKind]) -> Result<(), EffectError> {
        let Some(names) = &self.kinds else { return Ok(()) };
        if names.is_empty() {
            return Err(EffectError::new(
                "kinds",
                "must name at least one kind (leave it out for every kind)",
            ));
        }
        for (i, name) in names.iter().enumerate() {
            if !kinds.iter().any(|k| &k.name == name) {
                let valid: Vec<&str> = kinds.iter().map(|k| k.name.as_str()).collect();
                return Err(EffectError::new(
                    format!("kinds[{i}]"),
                    format!("unknown kind \"{name}\"; kinds are: {}", valid.join(", ")),
                ));
            }
        }
        Ok(())
    }
}
