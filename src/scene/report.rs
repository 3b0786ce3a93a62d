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

/// What `wetbounce check` says about a flow field: the files, the grid, the velocities and
/// their time scales, the grid spacing against the particle sizes, and the walls, injectors
/// and particles that lie outside the field. Empty for an analytic flow.
pub fn field_report(scene: &Scene) -> Vec<String> {
    use crate::fluid::field::Grid;
    use crate::pipeline::inject::Region;
    use crate::walls::{Drawable, Solid};
    let Some(f) = scene.setup.fluid.flow.field() else { return Vec::new() };
    let i = &f.info;
    let mut out = Vec::new();
    let files: Vec<String> = i.files.iter().map(|p| p.display().to_string()).collect();
    out.push(format!("flow field: {} ({}), array {}", files.join(", "), i.format, i.array));
    let kind = match &f.grid {
        Grid::Structured(g) => {
            let [nx, ny, nz] = g.dims();
            format!("structured grid of {nx} × {ny} × {nz} nodes, trilinear")
        }
        Grid::Unstructured(g) => {
            format!(
                "unstructured grid of {} cells ({} tetrahedra around their centres), barycentric",
                g.cells(),
                g.tets.len()
            )
        }
    };
    out.push(format!("  {kind}; {} cells, {} nodes with a value", i.cells, i.nodes));
    let (lo, hi) = i.bounds;
    match f.axisymmetric {
        Some(a) => out.push(format!(
            "  axisymmetric (r, z) table about the axis through {} along {}: r = {:.6} … {:.6} m, z = {:.6} … {:.6} m",
            a.point, a.axis, lo.x, hi.x, lo.z, hi.z
        )),
        // Each coordinate by `num`: `{}` would write a coordinate of 1e300 as 301 digits.
        None => out.push(format!(
            "  bounds: {} … {} m",
            super::error::fmt::vec3(lo.to_array()),
            super::error::fmt::vec3(hi.to_array())
        )),
    }
    let (slow, fast) = i.speed_range;
    let (dx_min, dx_max) = i.spacing;
    out.push(format!(
        "  speed |u| = {slow:.4e} … {fast:.4e} m/s; grid spacing (cell size) {dx_min:.4e} … {dx_max:.4e} m"
    ));
    let crossing = if fast > 0.0 { dx_min / fast } else { f64::INFINITY };
    let shear = if i.largest_gradient > 0.0 { 1.0 / i.largest_gradient } else { f64::INFINITY };
    out.push(format!(
        "  time scales: smallest spacing / largest speed = {crossing:.4e} s, 1 / largest |∂u_i/∂x_j| = {shear:.4e} s; dt = {:.4e} s is {:.3} of the shorter",
        scene.setup.dt,
        scene.setup.dt / crossing.min(shear)
    ));
    if f.snapshots.len() > 1 {
        let (t0, t1) = (f.snapshots[0].time, f.snapshots[f.snapshots.len() - 1].time);
        let period = f.period.map_or("held at the ends".to_string(), |p| format!("periodic, period {p} s"));
        let s = super::stiffness::shortest_snapshot_interval(f);
        out.push(format!(
            "  {} snapshots from t = {t0} to {t1} s, linear in time, {period}; shortest interval {:.4e} s \
             (dt is {:.3} of it)",
            f.snapshots.len(),
            s.length,
            scene.setup.dt / s.length
        ));
    }
    out.push(format!("  outside the field: {}", f.outside.name()));
    for (k, d) in scene_sizes(scene) {
        out.push(format!(
            "  {} of d = {:.4} mm: d / spacing = {:.3} … {:.3}{}",
            scene.setup.kinds[k as usize].name,
            d * 1e3,
            d / dx_max,
            d / dx_min,
            if d > dx_min {
                " (the particle spans cells: the flow is taken at its centre, without Faxén corrections)"
            } else {
                ""
            }
        ));
    }
    // Walls, injector regions and particles outside the field, by sampled points. A point
    // counts as outside beyond a millionth of the field's size (points on the boundary).
    let tolerance = 1e-6 * (hi - lo).length();
    let outside = |points: &[DVec3]| -> (usize, Option<DVec3>) {
        let bad: Vec<DVec3> = points.iter().copied().filter(|&p| f.distance_outside(p) > tolerance).collect();
        (bad.len(), bad.first().copied())
    };
    let mut report = |what: String, points: Vec<DVec3>| {
        let (n, first) = outside(&points);
        if let Some(p) = first {
            out.push(format!(
                "  warning: {what}: {n} of {} sampled points lie outside the field, e.g. {p}",
                points.len()
            ));
        }
    };
    let ring = |c: DVec3, e1: DVec3, e2: DVec3, r: f64| -> Vec<DVec3> {
        (0..16)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 16.0;
                c + r * (a.cos() * e1 + a.sin() * e2)
            })
            .collect()
    };
    for w in &scene.setup.walls {
        let points = match w.shape.solid(DVec3::ZERO, 1.0) {
            Solid::Triangles { vertices, .. } => vertices,
            Solid::Cuboid { center, size, rotation } => (0..8)
                .map(|c| {
                    let s = DVec3::new(
                        if c & 1 == 0 { -0.5 } else { 0.5 },
                        if c & 2 == 0 { -0.5 } else { 0.5 },
                        if c & 4 == 0 { -0.5 } else { 0.5 },
                    );
                    center + rotation * (s * size)
                })
                .collect(),
            Solid::Cylinder { center, radius, length, rotation } => {
                let (e1, e2, ez) = (rotation * DVec3::X, rotation * DVec3::Y, rotation * DVec3::Z);
                let mut p = ring(center - 0.5 * length * ez, e1, e2, radius);
                p.extend(ring(center + 0.5 * length * ez, e1, e2, radius));
                p
            }
        };
        if w.shape.bounds().is_none() && !matches!(w.shape.solid(DVec3::ZERO, 1.0), Solid::Cylinder { .. }) {
            continue; // a plane has no extent to check
        }
        report(format!("wall \"{}\"", w.name), points);
    }
    for j in &scene.setup.injectors {
        let points = match j.region {
            Region::Disk { center, radius, e1, e2, .. } => {
                let mut p = ring(center, e1, e2, radius);
                p.push(center);
                p
            }
            Region::Box { min, max } => (0..8)
                .map(|c| {
                    DVec3::new(
                        if c & 1 == 0 { min.x } else { max.x },
                        if c & 2 == 0 { min.y } else { max.y },
                        if c & 4 == 0 { min.z } else { max.z },
                    )
                })
                .collect(),
        };
        report(format!("injector \"{}\" region", j.name), points);
    }
    report("initial particles".to_string(), scene.particles.pos.clone());
    out
}
