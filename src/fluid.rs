//! The carrier fluid: its properties and its velocity field.

pub mod field;

use crate::numeric::lanes::Vector;
use glam::DVec3;
use std::sync::Arc;

/// The fluid the particles move through. SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Fluid {
    /// Density `ρ` (kg/m³); 0 for vacuum.
    pub density: f64,
    /// Dynamic viscosity `μ` (Pa·s); 0 for vacuum or an inviscid fluid.
    pub viscosity: f64,
    /// Gravity vector `g` (m/s²).
    pub gravity: DVec3,
    /// Velocity field `u(x)` of the fluid.
    pub flow: Flow,
}

/// The fluid velocity field.
#[derive(Debug, Clone, PartialEq)]
pub enum Flow {
    /// `u = 0` everywhere.
    Quiescent,
    /// `u` = this constant vector (m/s) everywhere.
    Uniform(DVec3),
    /// Laminar Poiseuille flow in a straight circular pipe (see [`Poiseuille`]).
    Poiseuille(Poiseuille),
    /// A field read from CFD files (see [`field::Field`]), shared: cloning the flow clones
    /// the handle, not the data.
    Field(SharedField),
}

/// A [`field::Field`] behind an `Arc`; two are equal when they are the same field.
#[derive(Debug, Clone)]
pub struct SharedField(pub Arc<field::Field>);

impl PartialEq for SharedField {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// A steady velocity field evaluated in the hot loop; one zero-sized or tiny type per kind of
/// flow so that the integrators are compiled for it (no per-particle `match`).
pub trait FlowField: Copy + Send + Sync {
    /// Fluid velocity at `x` (m/s).
    fn velocity(&self, x: DVec3) -> DVec3;
    /// Fluid velocity at one point or a lane group of points (m/s): [`FlowField::velocity`] of
    /// each, unless the flow has a cheaper lane form.
    #[inline(always)]
    fn velocity_of<V: Vector>(&self, x: V) -> V {
        x.map_points(|x| self.velocity(x))
    }
    /// Whether the flow's lookups can start from a particle's remembered tetrahedron
    /// ([`FlowField::hinted`]): only a field flow (on an unstructured grid, which the field
    /// knows; [`field::Field::walks`]).
    const HINTED: bool = false;
    /// The flow with its lookups walking from tetrahedron `tet` of an unstructured field
    /// ([`field::unstructured`]): one particle's flow. The value is the same whatever `tet` is
    /// (up to rounding); other flows have nothing to look up.
    #[inline(always)]
    fn hinted(self, _tet: u32) -> Self {
        self
    }
    /// Whether the flow has a material acceleration to evaluate: true only for a field read
    /// with the fluid-acceleration effect ([`field::Accelerating`]), so that every other flow
    /// compiles the force without it.
    const ACCELERATES: bool = false;
    /// The fluid's material acceleration `Du/Dt = ∂u/∂t + (u·∇)u` at `x` (m/s²), for the
    /// fluid-acceleration effect (docs/physics.md §7.2); zero unless [`FlowField::ACCELERATES`].
    #[inline(always)]
    fn material_acceleration(&self, _x: DVec3) -> DVec3 {
        DVec3::ZERO
    }
    /// [`FlowField::material_acceleration`] of one point or a lane group of points (m/s²).
    #[inline(always)]
    fn material_acceleration_of<V: Vector>(&self, x: V) -> V {
        x.map_points(|x| self.material_acceleration(x))
    }
}

/// [`Flow::Quiescent`] as a [`FlowField`].
#[derive(Debug, Clone, Copy)]
pub struct Quiescent;

impl FlowField for Quiescent {
    #[inline(always)]
    fn velocity(&self, _x: DVec3) -> DVec3 {
        DVec3::ZERO
    }
    #[inline(always)]
    fn velocity_of<V: Vector>(&self, _x: V) -> V {
        V::ZERO
    }
}

/// [`Flow::Uniform`] as a [`FlowField`].
#[derive(Debug, Clone, Copy)]
pub struct Uniform(pub DVec3);

impl FlowField for Uniform {
    #[inline(always)]
    fn velocity(&self, _x: DVec3) -> DVec3 {
        self.0
    }
    #[inline(always)]
    fn velocity_of<V: Vector>(&self, _x: V) -> V {
        V::splat(self.0)
    }
}

/// Fully developed laminar flow in a circular pipe of radius `R` around the axis through
/// `point` along unit `axis`: `u = u_max (1 − ρ²/R²) axis` at distance `ρ < R` from the axis,
/// 0 outside (the pipe wall and beyond). The mean velocity over the section is `u_max / 2`.
///
/// The flow is steady and unidirectional, and `u` varies only across the axis, so the
/// convective acceleration `(u·∇)u` is zero as well as `∂u/∂t`: `Du/Dt = 0` everywhere, and
/// the added-mass and fluid-acceleration terms need no extra code (docs/physics.md §1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Poiseuille {
    /// A point on the pipe's axis (m).
    pub point: DVec3,
    /// Unit direction of the axis; the flow goes along it when `max_velocity > 0`.
    pub axis: DVec3,
    /// Pipe radius `R` (m).
    pub radius: f64,
    /// Centre-line velocity `u_max` (m/s), signed along `axis`.
    pub max_velocity: f64,
}

impl FlowField for Poiseuille {
    #[inline(always)]
    fn velocity(&self, x: DVec3) -> DVec3 {
        let rel = x - self.point;
        let along = rel.dot(self.axis);
        let rho2 = (rel - along * self.axis).length_squared();
        let shape = (1.0 - rho2 / (self.radius * self.radius)).max(0.0);
        (self.max_velocity * shape) * self.axis
    }
}

impl Flow {
    /// Fluid velocity at `x` (m/s) at time `t` (s), for code outside the hot loop.
    pub fn velocity(&self, x: DVec3, t: f64) -> DVec3 {
        match self {
            Flow::Quiescent => Quiescent.velocity(x),
            Flow::Uniform(u) => Uniform(*u).velocity(x),
            Flow::Poiseuille(p) => p.velocity(x),
            Flow::Field(f) => f.0.velocity(x, t),
        }
    }

    /// The field read from files, if the flow is one.
    pub fn field(&self) -> Option<&field::Field> {
        match self {
            Flow::Field(f) => Some(&f.0),
            _ => None,
        }
    }

    /// The field of a field flow, as its shared handle (cloning it clones the handle).
    pub fn shared_field(&self) -> Option<&SharedField> {
        match self {
            Flow::Field(f) => Some(f),
            _ => None,
        }
    }

    /// Half the fluid's vorticity `½ ∇×u` at `x` (rad/s) **[ext]**: the spin a torque-free
    /// sphere takes in the flow (docs/physics.md §9). Zero in a quiescent or uniform flow; in the
    /// pipe, with `u = u_max (1 − ρ²/R²) e` and `ρ` the distance from the axis,
    /// `∇×u = ∇u_z × e = −(2 u_max / R²) ρ⃗ × e`, so `½ ∇×u = (u_max / R²) e × ρ⃗` inside the
    /// pipe and 0 outside (where the flow is taken as still). In a field, the curl of the
    /// interpolant at time `t` (s) by central differences (see [`field::Field::half_vorticity`]).
    pub fn half_vorticity(&self, x: DVec3, t: f64) -> DVec3 {
        match self {
            Flow::Quiescent | Flow::Uniform(_) => DVec3::ZERO,
            Flow::Field(f) => f.0.half_vorticity(x, t),
            Flow::Poiseuille(p) => {
                let rel = x - p.point;
                let across = rel - rel.dot(p.axis) * p.axis;
                let r2 = p.radius * p.radius;
                if across.length_squared() > r2 {
                    DVec3::ZERO
                } else {
                    (p.max_velocity / r2) * p.axis.cross(across)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poiseuille_is_parabolic_inside_and_still_outside() {
        let p = Poiseuille { point: DVec3::ZERO, axis: DVec3::Z, radius: 0.02, max_velocity: -0.1 };
        assert_eq!(p.velocity(DVec3::new(0.0, 0.0, 5.0)), DVec3::new(0.0, 0.0, -0.1));
        let half = p.velocity(DVec3::new(0.01, 0.0, -3.0));
        assert!((half.z + 0.075).abs() < 1e-15 && half.x == 0.0 && half.y == 0.0);
        assert_eq!(p.velocity(DVec3::new(0.0, 0.03, 0.0)), DVec3::ZERO);
    }

    #[test]
    fn poiseuille_half_vorticity_matches_a_central_difference_curl() {
        let p =
            Poiseuille { point: DVec3::new(0.01, 0.0, 0.0), axis: DVec3::Z, radius: 0.02, max_velocity: 0.3 };
        let flow = Flow::Poiseuille(p);
        let x = DVec3::new(0.017, -0.004, 0.2);
        let h = 1e-6;
        let d = |e: DVec3| (p.velocity(x + h * e) - p.velocity(x - h * e)) / (2.0 * h);
        let (dx, dy, dz) = (d(DVec3::X), d(DVec3::Y), d(DVec3::Z));
        let curl = DVec3::new(dy.z - dz.y, dz.x - dx.z, dx.y - dy.x);
        let half = flow.half_vorticity(x, 0.0);
        assert!((half - 0.5 * curl).length() < 1e-6 * curl.length(), "{half} vs {}", 0.5 * curl);
        assert_eq!(Flow::Uniform(DVec3::X).half_vorticity(x, 0.0), DVec3::ZERO);
    }
}
