//! `dt = "auto"`: the time step and integrator chosen from an accuracy setting and the scene's
//! own time scales.
//!
//! For every particle kind and diameter the scene can hold (its initial particles, and the
//! smallest and largest size of each injector) three time scales are computed at terminal
//! velocity, with the same functions as `wetbounce check`:
//!
//! - the relaxation time `t_r` (L06 eq. 6), over which the velocity changes;
//! - the time to cross a diameter, `d / V_t`, over which the distance to a wall changes by a
//!   particle size (what the impact's location is resolved against);
//! - the contact time `t_c` (L06 eq. 4 or 5) when rebounding particles are held, since the
//!   motion right after a release is a new relaxation towards `V_t`.
//!
//! In a flow read from files two more time scales count (docs/physics.md §7,
//! [`super::stiffness::FlowScales`]): the time the fastest fluid takes to cross the smallest
//! cell, `Δx_min / |u|_max`, over which the interpolated velocity a particle sees changes by a
//! cell's worth (accuracy), and `1 / |∇u|_max`, the flow's own rate (accuracy, and the stability
//! limit the loader checks). An unsteady field adds the shortest interval between two successive
//! snapshots (the wrap from the last back to the first of a periodic series included), over
//! which the flow and its `∂u/∂t` change from one pair of snapshots to the next.
//!
//! The smallest of them all, `T`, sets `Δt = T / N`, with `N` and the integrator fixed per
//! setting. `N` was calibrated with the work–precision study (`docs/accuracy.md`) so that on
//! the study's cases each setting delivers the error it promises:
//!
//! | setting | integrator | `Δt` | error on the study's cases |
//! | --- | --- | --- | --- |
//! | `fast` | exponential | `T/4` | ≤ 1 % |
//! | `balanced` | rk4 | `T/25` | ≤ 0.1 % |
//! | `precise` | rk4 | `T/100` | ≤ 0.01 % |
//!
//! The largest error of the study's cases decides `N`: the column's mean residence time,
//! which converges at first order whatever the integrator, because outlets remove a drop at
//! the end of the step in which it crosses and resting drops leave a wall at a step's start.

use super::Scene;
use super::report::{kind_report, scene_sizes};
use super::stiffness::flow_time_scales;
use crate::integrate::IntegratorKind;
use serde::Deserialize;

/// `simulation.accuracy`: how accurate a `dt = "auto"` scene should be.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Accuracy {
    /// About 1 % on positions, impact times and speeds.
    Fast,
    /// About 0.1 %.
    #[default]
    Balanced,
    /// About 0.01 %.
    Precise,
}

impl Accuracy {
    /// Every setting, coarsest first.
    pub const ALL: [Accuracy; 3] = [Accuracy::Fast, Accuracy::Balanced, Accuracy::Precise];

    /// The scene-file name.
    pub fn name(self) -> &'static str {
        match self {
            Accuracy::Fast => "fast",
            Accuracy::Balanced => "balanced",
            Accuracy::Precise => "precise",
        }
    }

    /// The error (relative) the setting is documented to deliver on the study's cases.
    pub fn target_error(self) -> f64 {
        match self {
            Accuracy::Fast => 1e-2,
            Accuracy::Balanced => 1e-3,
            Accuracy::Precise => 1e-4,
        }
    }

    /// The integrator and the number of steps per smallest time scale.
    pub fn scheme(self) -> (IntegratorKind, f64) {
        match self {
            Accuracy::Fast => (IntegratorKind::Exponential, 4.0),
            Accuracy::Balanced => (IntegratorKind::Rk4, 25.0),
            Accuracy::Precise => (IntegratorKind::Rk4, 100.0),
        }
    }
}

/// What `dt = "auto"` chose, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct AutoStep {
    /// The setting.
    pub accuracy: Accuracy,
    /// The integrator it picks.
    pub integrator: IntegratorKind,
    /// The time step (s).
    pub dt: f64,
    /// The smallest time scale `T` (s).
    pub time_scale: f64,
    /// Which time scale it is, of which kind and diameter, in words.
    pub limited_by: String,
}

/// The time step and integrator of `accuracy` for `scene`, or why there is none (the message
/// for `simulation.dt`).
pub fn auto_step(scene: &Scene, accuracy: Accuracy) -> Result<AutoStep, String> {
    if scene.setup.physics.drag.is_none() {
        return Err("\"auto\" needs the drag effect (the time scales are the relaxation time and the \
                    terminal velocity's); give dt in s"
            .into());
    }
    let mut best: Option<(f64, String)> = None;
    for (k, d) in scene_sizes(scene) {
        let r = kind_report(scene, k, d);
        let who = format!("{} d = {:.3} mm", r.kind, d * 1e3);
        let mut scales = vec![
            (r.relaxation_time, format!("relaxation time t_r of {who}")),
            (d / r.terminal_velocity, format!("time to cross a diameter d/V_t of {who}")),
        ];
        if scene.setup.rule.hold_at_contact && scene.setup.kinds[k as usize].held_at_contact && r.bounces {
            scales.push((r.contact_time, format!("contact time t_c of {who}")));
        }
        for (t, why) in scales {
            if t.is_finite() && t > 0.0 && best.as_ref().is_none_or(|(b, _)| t < *b) {
                best = Some((t, why));
            }
        }
    }
    if let Some(f) = flow_time_scales(&scene.setup.fluid.flow) {
        let s = f.snapshots;
        let scales = [
            (
                f.crossing,
                "time for the fastest fluid to cross the smallest cell of the flow field, dx_min/|u|_max"
                    .to_string(),
            ),
            (
                f.shear,
                "inverse of the largest velocity gradient of the flow field, 1/|du_i/dx_j|_max".to_string(),
            ),
            (
                s.length,
                format!(
                    "shortest interval between the flow field's snapshots, from t = {} s to {} s",
                    s.from, s.to
                ),
            ),
        ];
        for (t, why) in scales {
            if t.is_finite() && t > 0.0 && best.as_ref().is_none_or(|(b, _)| t < *b) {
                best = Some((t, why));
            }
        }
    }
    let (time_scale, limited_by) = best.ok_or_else(|| {
        "\"auto\" found no finite time scale (no particles or injectors, or no gravity to set a \
         terminal velocity); give dt in s"
            .to_string()
    })?;
    let (integrator, n) = accuracy.scheme();
    Ok(AutoStep { accuracy, integrator, dt: time_scale / n, time_scale, limited_by })
}
