//! Drag: `−3π μ d f(Re) (v − u)` (docs/physics.md §1), Stokes or Schiller–Naumann.

use super::{Effect, Physics};
use crate::correlations::{
    drag_factor_schiller_naumann, drag_factor_schiller_naumann_of_squared, schiller_naumann_stiffness_factor,
};
use crate::fluid::Fluid;
use crate::numeric::lanes::Real;
use crate::particles::ParticleKind;
use serde::Deserialize;

/// Which `f(Re)` the drag uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DragLawKind {
    /// `f = 1`: Stokes drag, linear in the slip velocity.
    Stokes,
    /// `f = 1 + 0.15 Re^0.687`, Newton regime above Re = 1000 (the paper's law).
    SchillerNaumann,
}

impl DragLawKind {
    /// `f(Re)` of this law.
    pub fn factor(self, re: f64) -> f64 {
        match self {
            DragLawKind::Stokes => Stokes::factor(re),
            DragLawKind::SchillerNaumann => SchillerNaumann::factor(re),
        }
    }

    /// `d(Re f)/dRe`: the drag's rate of growth with the slip speed relative to Stokes drag,
    /// which sets the stability of the explicit integrators (1 for Stokes drag).
    pub fn stiffness_factor(self, re: f64) -> f64 {
        match self {
            DragLawKind::Stokes => 1.0,
            DragLawKind::SchillerNaumann => schiller_naumann_stiffness_factor(re),
        }
    }
}

/// The drag effect. Scene table: `drag = { law = "schiller_naumann" }` (default) or
/// `drag = { law = "stokes" }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Drag {
    /// The drag law; default `schiller_naumann`.
    #[serde(default = "default_law")]
    pub law: DragLawKind,
}

fn default_law() -> DragLawKind {
    DragLawKind::SchillerNaumann
}

impl Effect for Drag {
    fn name(&self) -> &'static str {
        "drag"
    }

    fn apply(&self, _fluid: &Fluid, _kinds: &[ParticleKind], physics: &mut Physics) {
        physics.drag = Some(self.law);
    }
}

/// A drag law as a type, so the hot loop is compiled once per law (no per-particle branch).
pub trait DragLaw: Copy + Send + Sync + 'static {
    /// False only for [`NoDrag`]: the drag term is then left out entirely.
    const ACTIVE: bool;
    /// Whether free flight under this law is faster by lane groups of four particles
    /// ([`crate::numeric::lanes`]) than one by one *without AVX2* (with AVX2 lane groups pay for every
    /// law and are always used). Measured with SSE2 only on the peer's beads
    /// (`tools/step_rate`, 1 thread): with Schiller–Naumann's power, lane groups are 1.1–1.7×
    /// faster (Euler to RK2); with linear (Stokes) drag, the few operations per particle do not
    /// pay for moving the particles into lanes and back (2–13 % slower).
    const LANE_GROUPS: bool = false;
    /// `f(Re)`, the drag relative to Stokes drag.
    fn factor(re: f64) -> f64;
    /// `f(Re)` from `Re²`, of one particle or a lane group: what the hot loop calls, since
    /// `Re² = (ρ d/μ)² |w|²` needs no square root (one square root less on each force
    /// evaluation's chain of dependent operations).
    #[inline(always)]
    fn factor_of_squared<R: Real>(re2: R) -> R {
        re2.map(|r| Self::factor(r.sqrt()))
    }
}

/// No drag effect in the scene.
#[derive(Debug, Clone, Copy)]
pub struct NoDrag;
/// Stokes drag, `f = 1`.
#[derive(Debug, Clone, Copy)]
pub struct Stokes;
/// Schiller–Naumann drag with the Newton regime above Re = 1000.
#[derive(Debug, Clone, Copy)]
pub struct SchillerNaumann;

impl DragLaw for NoDrag {
    const ACTIVE: bool = false;
    #[inline(always)]
    fn factor(_re: f64) -> f64 {
        0.0
    }
}

impl DragLaw for Stokes {
    const ACTIVE: bool = true;
    #[inline(always)]
    fn factor(_re: f64) -> f64 {
        1.0
    }
}

impl DragLaw for SchillerNaumann {
    const ACTIVE: bool = true;
    const LANE_GROUPS: bool = true;
    #[inline(always)]
    fn factor(re: f64) -> f64 {
        drag_factor_schiller_naumann(re)
    }
    #[inline(always)]
    fn factor_of_squared<R: Real>(re2: R) -> R {
        drag_factor_schiller_naumann_of_squared(re2)
    }
}
