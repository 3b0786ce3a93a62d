//! The stiffest drag of a scene, and the largest time step the explicit integrators are stable at.
//!
//! An explicit scheme is stable on the linear decay `v' = −λ v` only for `λ h` below its
//! real-axis stability interval (2 for Euler and RK2, 2.785 for RK4,
//! [`crate::integrate::IntegratorKind::largest_stable_step`]). For drag, `λ` is the
//! linearised rate along the slip, `(f + Re f') 18 μ / ((ρp + C_M ρ) d²)`
//! ([`crate::effects::DragLawKind::stiffness_factor`]), which grows with the slip speed under
//! Schiller–Naumann. It is evaluated at a bound on the slip speed, so that no particle of the
//! scene ever sees a larger rate: `W = w0 + 2 V_t`, with `w0` the starting slip (`|v0|` plus the
//! fastest fluid speed) and `V_t` the terminal slip speed. A stable scheme never lets the
//! distance to the terminal velocity grow (`|w − V_t| ≤ |w0 − V_t| ≤ w0 + V_t`), but it may
//! overshoot: from rest, a step near the limit lands close to `2 V_t` (the amplification factor
//! is near −1), where the Schiller–Naumann rate is higher — so neither `V_t` nor `max(w0, V_t)`
//! is a bound (the property test found a case, RK4 at 0.997 of a limit computed at `V_t`, that
//! diverged). Rebounds only lower the slip.

use crate::effects::Physics;
use crate::fluid::{Flow, Fluid};
use crate::particles::Particles;
use crate::pipeline::inject::{Injector, SizeDistribution};
use std::collections::HashMap;

/// The particle (kind and diameter) with the largest linearised drag rate in a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StiffestDrag {
    /// Kind index.
    pub kind: usize,
    /// Diameter (m).
    pub diameter: f64,
    /// The slip speed the rate is evaluated at (m/s): a bound on the slip.
    pub slip_speed: f64,
    /// Linearised drag rate `λ` (1/s); `1/λ` is the shortest relaxation time.
    pub rate: f64,
}

/// Fastest fluid speed anywhere (m/s).
pub fn max_flow_speed(flow: &Flow) -> f64 {
    match flow {
        Flow::Quiescent => 0.0,
        Flow::Uniform(u) => u.length(),
        Flow::Poiseuille(p) => p.max_velocity.abs(),
        Flow::Field(f) => f.0.info.speed_range.1,
    }
}

/// Terminal slip speed (m/s) of a particle of kind `k` and diameter `d` under its constant
/// acceleration: the root of `λ_Stokes f(Re(w)) w = |a|`, by bisection between 0 and the Stokes
/// speed (an upper bound since `f ≥ 1`). 0 without drag or without a constant force.
pub fn terminal_slip_speed(physics: &Physics, fluid: &Fluid, k: usize, d: f64) -> f64 {
    let Some(law) = physics.drag else { return 0.0 };
    let stokes_rate = physics.drag_rate(k, fluid) / (d * d);
    let accel = physics.body_acceleration(k).length();
    if stokes_rate.is_nan() || stokes_rate <= 0.0 || accel == 0.0 {
        return 0.0;
    }
    let re_per_speed = fluid.density * d / fluid.viscosity;
    let (mut lo, mut hi) = (0.0_f64, accel / stokes_rate);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if stokes_rate * law.factor(re_per_speed * mid) * mid > accel {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    hi
}

/// Linearised drag rate `λ` (1/s) of a particle of kind `k` and diameter `d` at slip speed `w`.
pub fn linearised_drag_rate(physics: &Physics, fluid: &Fluid, k: usize, d: f64, w: f64) -> f64 {
    let Some(law) = physics.drag else { return 0.0 };
    let re = if fluid.viscosity > 0.0 { fluid.density * w * d / fluid.viscosity } else { 0.0 };
    physics.drag_rate(k, fluid) / (d * d) * law.stiffness_factor(re)
}

/// The stiffest drag among the scene's initial particles and the sizes its injectors can draw
/// (their smallest, their largest and eight sizes in between), or `None` without drag.
pub fn stiffest_drag(
    physics: &Physics,
    fluid: &Fluid,
    particles: &Particles,
    injectors: &[Injector],
) -> Option<StiffestDrag> {
    physics.drag?;
    let u_max = max_flow_speed(&fluid.flow);
    // (kind, diameter) → largest starting slip speed.
    let mut start: HashMap<(u16, u64), f64> = HashMap::new();
    let mut note = |k: u16, d: f64, w: f64| {
        let e = start.entry((k, d.to_bits())).or_insert(0.0);
        *e = e.max(w);
    };
    for i in 0..particles.len() {
        note(particles.kind[i], particles.diameter[i], particles.vel[i].length() + u_max);
    }
    for inj in injectors {
        let w = inj.velocity.length() + u_max;
        match inj.diameter {
            SizeDistribution::Fixed(d) => note(inj.kind, d, w),
            SizeDistribution::Uniform { min, max }
            | SizeDistribution::Normal { min, max, .. }
            | SizeDistribution::LogNormal { min, max, .. } => {
                for j in 0..10 {
                    note(inj.kind, min * (max / min).powf(j as f64 / 9.0), w);
                }
            }
        }
    }
    let mut entries: Vec<_> = start.into_iter().collect();
    // HashMap order is arbitrary; ties must resolve the same way on every run.
    entries.sort_unstable_by_key(|&((k, bits), _)| (k, bits));
    entries
        .into_iter()
        .map(|((k, bits), w0)| {
            let (k, d) = (k as usize, f64::from_bits(bits));
            let w = w0 + 2.0 * terminal_slip_speed(physics, fluid, k, d);
            StiffestDrag {
                kind: k,
                diameter: d,
                slip_speed: w,
                rate: linearised_drag_rate(physics, fluid, k, d, w),
            }
        })
        .filter(|s| s.rate.is_finite())
        .max_by(|a, b| a.rate.total_cmp(&b.rate))
}

/// The time scales of a flow read from files (s), from what [`crate::fluid::field::FieldInfo`]
/// measured: `None` for the analytic flows. (Poiseuille's shear `2 u_max / R` is left out: its
/// velocity is along the axis and varies only across it, so a particle's position feeds back
/// on its velocity in one direction only, and the linearised flight has no eigenvalue from it.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlowScales {
    /// `Δx_min / |u|_max`: the time the fastest fluid takes to cross the smallest cell (s). An
    /// accuracy scale: the trilinear or barycentric interpolant is only continuous across a cell
    /// face, so a step that jumps cells averages its kinks away.
    pub crossing: f64,
    /// `1 / |∇u|_max`, the largest `|∂u_i/∂x_j|` over the cells: the flow's own rate (s). A
    /// stability scale: a particle that follows the flow (`τ |∇u| ≪ 1`) moves as `x' = u(x)`,
    /// whose linearisation has eigenvalues of size `|∇u|` (a compressional strain `−|∇u|`).
    pub shear: f64,
    /// The shortest interval between two successive snapshots of an unsteady field (s), the
    /// wrap from the last back to the first of a periodic series included; infinite for a
    /// steady field. An accuracy scale, and a limit on any step: the field is linear in time
    /// only between two snapshots, and `∂u/∂t` (fluid acceleration) is the slope of the pair
    /// around the time asked, so a step longer than an interval samples the series at points
    /// that miss whole snapshots, and integrates an aliased flow.
    pub snapshots: SnapshotInterval,
}

/// The shortest interval between successive snapshots of a field: its length (s) and the
/// times (s) of the two snapshots (for a periodic series' wrap, the last's and the first's
/// plus the period).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnapshotInterval {
    /// Its length (s); infinite for a steady field.
    pub length: f64,
    /// The time of the snapshot it starts at (s).
    pub from: f64,
    /// The time of the snapshot it ends at (s).
    pub to: f64,
}

/// [`FlowScales`] of `flow`, or `None` for an analytic flow; a still field has infinite ones.
pub fn flow_time_scales(flow: &Flow) -> Option<FlowScales> {
    let field = flow.field()?;
    let i = &field.info;
    let fast = i.speed_range.1;
    Some(FlowScales {
        crossing: if fast > 0.0 { i.spacing.0 / fast } else { f64::INFINITY },
        shear: if i.largest_gradient > 0.0 { 1.0 / i.largest_gradient } else { f64::INFINITY },
        snapshots: shortest_snapshot_interval(field),
    })
}

/// [`SnapshotInterval`] of `field`.
pub fn shortest_snapshot_interval(field: &crate::fluid::field::Field) -> SnapshotInterval {
    let times: Vec<f64> = field.snapshots.iter().map(|s| s.time).collect();
    let mut pairs: Vec<(f64, f64)> = times.windows(2).map(|w| (w[0], w[1])).collect();
    if let (Some(p), Some(&first), Some(&last)) = (field.period, times.first(), times.last()) {
        // After the last snapshot the series goes back to the first, at first + period.
        pairs.push((last, first + p));
    }
    pairs.into_iter().fold(
        SnapshotInterval { length: f64::INFINITY, from: f64::NAN, to: f64::NAN },
        |best, (from, to)| {
            if to - from < best.length { SnapshotInterval { length: to - from, from, to } } else { best }
        },
    )
}

/// The largest rate (1/s) at which a field flow feeds a particle's position back into its
/// velocity, for the stability of the explicit schemes: `|∇u|_max`, times `√G` (the largest
/// fluid-acceleration gain `(1 + C_M) ρ / (ρp + C_M ρ)` of the scene's kinds, when above 1)
/// with the fluid-acceleration effect, whose `G (u·∇)u` gives `x'' = G J² x` and so the rate
/// `√G |∇u|`. `None` without a field, or without drag and fluid acceleration (then the flow
/// does not act on the particles).
pub fn flow_rate(physics: &Physics, fluid: &Fluid) -> Option<f64> {
    let scales = flow_time_scales(&fluid.flow)?;
    if physics.drag.is_none() && !physics.fluid_acceleration {
        return None;
    }
    let gain =
        (0..physics.kinds.len()).map(|k| physics.fluid_acceleration_gain(k, fluid)).fold(1.0, f64::max);
    Some(gain.sqrt() / scales.shear)
}
