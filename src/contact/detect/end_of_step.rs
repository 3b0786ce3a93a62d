//! End-of-step impact detection: the cheap alternative to locating the impact inside the step,
//! offered only so that the accuracy study (`tools/plots/src/accuracy_study.rs`,
//! `docs/accuracy.md`) can measure what locating it inside the step buys.
//!
//! docs/physics.md §5.5 asks for the contact inside the step; many codes instead test for overlap
//! at the end of the step and apply the response there. This reproduces that: a wall contact
//! exists only if the particle overlaps the wall at the step's end, it is dated at the step's
//! end, the particle is pushed back along the wall's normal to touch it, and the bounce rule
//! uses the velocity it has there. A path that enters and leaves a wall inside one step is
//! missed, as in those codes.

use serde::Deserialize;

/// Where a wall contact is placed in time (`simulation.impact_location`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ImpactLocation {
    /// On the integrator's path inside the step (docs/physics.md §5.5; the default).
    #[default]
    InStep,
    /// At the end of the step, if the particle overlaps the wall there.
    EndOfStep,
}

impl ImpactLocation {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            ImpactLocation::InStep => "in_step",
            ImpactLocation::EndOfStep => "end_of_step",
        }
    }
}

/// The time of a wall contact detected at the end of a stretch of path `[t, t1]`, given the
/// gap (m) and the normal velocity (m/s, positive away from the wall) at `t1`: `t1` if the
/// particle overlaps the wall there while moving into it, else none. The velocity test keeps
/// a particle just pushed back to the wall (gap 0 up to round-off) and moving away from it
/// from being detected again.
#[inline]
pub fn detect_at_end(end_gap: f64, normal_velocity: f64, t1: f64) -> Option<f64> {
    (end_gap < 0.0 && normal_velocity < 0.0).then_some(t1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contact_only_when_overlapping_at_the_end() {
        assert_eq!(detect_at_end(-1e-6, -0.1, 0.3), Some(0.3));
        assert_eq!(detect_at_end(0.0, -0.1, 0.3), None);
        assert_eq!(detect_at_end(1e-6, -0.1, 0.3), None);
    }

    #[test]
    fn no_contact_when_leaving_the_wall() {
        assert_eq!(detect_at_end(-1e-18, 0.1, 0.3), None);
    }
}
