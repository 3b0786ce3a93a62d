//! What `wetbounce check` prints: the time scales and the bounce regime of each particle kind.

use super::Scene;
use crate::contact::Outcome;
use crate::contact::wall_impact;
use crate::correlations::{relaxation_time, terminal_velocity};
use crate::effects::DragLawKind;
use crate::pipeline::inject::SizeDistribution;
use crate::walls::WallMaterial;
use glam::DVec3;

/// Time scales and bounce regime of one particle kind at one diameter, at terminal velocity.
#[derive(Debug, Clone, PartialEq)]
pub struct KindReport {
    /// Kind name.
    pub kind: String,
    /// Diameter (m).
    pub diameter: f64,
    /// Terminal velocity (m/s); ∞ without drag.
    pub terminal_velocity: f64,
    /// True if it rises (lighter than the fluid).
    pub rising: bool,
    /// Reynolds number at terminal velocity.
    pub reynolds: f64,
    /// Stokes number of an impact at terminal velocity (L06 §2).
    pub stokes: f64,
    /// Restitution of that impact (0 if it does not rebound).
    pub eps: f64,
    /// Contact time of that impact (s), L06 eq. 4 or 5, against `wall` (0 if no rebound).
    pub contact_time: f64,
    /// Relaxation time at terminal velocity (s), L06 eq. 6.
    pub relaxation_time: f64,
    /// Whether an impact at terminal velocity rebounds (`St ≥ St_c`).
    pub bounces: bool,
    /// The wall whose material was used for the contact time (the first wall, or a rigid wall).
    pub wall: String,
}

/// One report per (kind, diameter) of the scene's initial particles and of its injectors'
/// smallest and largest sizes ([`scene_sizes`]), in order of appearance.
/// The drag law is the scene's, Schiller–Naumann if the scene has no drag effect.
pub fn kind_reports(scene: &Scene) -> Vec<KindReport> {
    scene_sizes(scene).into_iter().map(|(k, d)| kind_report(scene, k, d)).collect()
}

/// The (kind, diameter) pairs a scene can hold, in order of appearance: its initial
/// particles, then each injector's smallest and largest size (its only size if fixed).
pub fn scene_sizes(scene: &Scene) -> Vec<(u16, f64)> {
    let mut out: Vec<(u16, f64)> = Vec::new();
    let mut add = |k: u16, d: f64| {
        if !out.contains(&(k, d)) {
            out.push((k, d));
        }
    };
    for i in 0..scene.particles.len() {
        add(scene.particles.kind[i], scene.particles.diameter[i]);
    }
    for inj in &scene.setup.injectors {
        match inj.diameter {
            SizeDistribution::Fixed(d) => add(inj.kind, d),
            SizeDistribution::Uniform { min, max }
            | SizeDistribution::Normal { min, max, .. }
            | SizeDistribution::LogNormal { min, max, .. } => {
                add(inj.kind, min);
                add(inj.kind, max);
            }
        }
    }
    out
}

/// The report of a particle of kind `k` (index into the scene's kinds) and diameter `d` (m).
/// The drag law is the scene's, Schiller–Naumann if the scene has no drag effect.
pub fn kind_report(scene: &Scene, k: u16, d: f64) -> KindReport {
    let fluid = &scene.setup.fluid;
    let law = scene.setup.physics.drag.unwrap_or(DragLawKind::SchillerNaumann);
    let (material, wall) = scene
        .setup
        .walls
        .first()
        .map_or((WallMaterial::default(), "rigid wall".to_string()), |w| (w.material, w.name.clone()));
    let kind = &scene.setup.kinds[k as usize];
    let g = fluid.gravity.length();
    let tv = terminal_velocity(kind.density, fluid.density, d, fluid.viscosity, g, |re| law.factor(re));
    let impact =
        wall_impact(kind, d, &material, fluid, &scene.setup.rule, DVec3::new(0.0, 0.0, -tv.speed), DVec3::Z);
    let c_m = scene.setup.physics.added_mass_coefficient;
    KindReport {
        kind: kind.name.clone(),
        diameter: d,
        terminal_velocity: tv.speed,
        rising: tv.rising,
        reynolds: tv.reynolds,
        stokes: impact.st,
        eps: impact.eps,
        contact_time: impact.contact_time,
        relaxation_time: relaxation_time(
            kind.density,
            fluid.density,
            c_m,
            d,
            fluid.viscosity,
            law.factor(tv.reynolds),
        ),
        bounces: impact.outcome != Outcome::Deposited,
        wall,
    }
}
