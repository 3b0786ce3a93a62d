//! The carrier fluid: its properties and its velocity field.

use glam::DVec3;

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

/// The fluid velocity field, steady in time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Flow {
    /// `u = 0` everywhere.
    Quiescent,
    /// `u` = this constant vector (m/s) everywhere.
    Uniform(DVec3),
}

/// A steady velocity field evaluated in the hot loop; one zero-sized or tiny type per kind of
/// flow so that the integrators are compiled for it (no per-particle `match`).
pub trait FlowField: Copy + Send + Sync {
    /// Fluid velocity at `x` (m/s).
    fn velocity(&self, x: DVec3) -> DVec3;
}

/// [`Flow::Quiescent`] as a [`FlowField`].
#[derive(Debug, Clone, Copy)]
pub struct Quiescent;

impl FlowField for Quiescent {
    #[inline(always)]
    fn velocity(&self, _x: DVec3) -> DVec3 {
        DVec3::ZERO
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
}

impl Flow {
    /// Fluid velocity at `x` (m/s), for code outside the hot loop.
    pub fn velocity(&self, x: DVec3) -> DVec3 {
        match *self {
            Flow::Quiescent => Quiescent.velocity(x),
            Flow::Uniform(u) => Uniform(u).velocity(x),
        }
    }
}
