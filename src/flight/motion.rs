//! The free-flight machinery compiled for one (integrator, drag law, flow), and the one
//! `match` that picks it per step — so the per-particle loops carry no branch on effects.

use crate::effects::{DragLaw, DragLawKind, NoDrag, SchillerNaumann, Stokes};
use crate::fluid::{self, Flow, FlowField};
use crate::integrate::{Euler, Exponential, ForceField, IntegratorKind, ParticleForce, Rk2, Rk4, Scheme};
use crate::numeric::lanes::Vector;
use std::marker::PhantomData;

/// Free flight of one particle: its force field and the integrator.
pub trait Motion: Sync {
    /// The force field of one particle (`V = DVec3`) or of a lane group.
    type Field<V: Vector>: ForceField<V> + Send + Sync;
    /// Whether free flight runs by lane groups ([`crate::effects::DragLaw::LANE_GROUPS`]).
    const LANE_GROUPS: bool;
    /// Whether the flow has a material acceleration the force reads ([`FlowField::ACCELERATES`]):
    /// only a field with the fluid-acceleration effect.
    const ACCELERATES: bool;
    /// Whether the flow's lookups can walk from a particle's remembered tetrahedron
    /// ([`FlowField::HINTED`]).
    const HINTED: bool;
    /// The integrator's [`Scheme::DISPLACEMENT_SHARE`].
    const DISPLACEMENT_SHARE: f64;
    /// The field of one particle, its flow's lookups walking from tetrahedron `tet`
    /// ([`FlowField::hinted`]).
    fn hinted(field: Self::Field<glam::DVec3>, tet: u32) -> Self::Field<glam::DVec3>;
    /// The field of a particle with constant acceleration `accel` (m/s²), Stokes drag rate
    /// `stokes_rate` (1/s), Reynolds number per unit slip speed `re_per_speed` (s/m) and
    /// acceleration per unit fluid acceleration `fluid_gain` (read only if `ACCELERATES`).
    fn field<V: Vector>(
        &self,
        accel: V,
        stokes_rate: V::Real,
        re_per_speed: V::Real,
        fluid_gain: V::Real,
    ) -> Self::Field<V>;
    /// One integrator step of `h` (s) under `f`.
    fn advance<V: Vector, G: ForceField<V>>(&self, f: &G, x: V, v: V, h: f64) -> (V, V);
}

/// [`Motion`] for integrator `S`, drag law `D` and flow `F`.
#[derive(Debug, Clone, Copy)]
pub struct Mover<S, D, F> {
    scheme: S,
    flow: F,
    law: PhantomData<D>,
}

impl<S: Scheme, D: DragLaw, F: FlowField> Motion for Mover<S, D, F> {
    type Field<V: Vector> = ParticleForce<D, F, V>;
    const LANE_GROUPS: bool = D::LANE_GROUPS;
    const ACCELERATES: bool = F::ACCELERATES;
    const HINTED: bool = F::HINTED;
    const DISPLACEMENT_SHARE: f64 = S::DISPLACEMENT_SHARE;

    #[inline(always)]
    fn hinted(field: Self::Field<glam::DVec3>, tet: u32) -> Self::Field<glam::DVec3> {
        ParticleForce { flow: field.flow.hinted(tet), ..field }
    }

    #[inline(always)]
    fn field<V: Vector>(
        &self,
        accel: V,
        stokes_rate: V::Real,
        re_per_speed: V::Real,
        fluid_gain: V::Real,
    ) -> Self::Field<V> {
        ParticleForce { accel, stokes_rate, re_per_speed, fluid_gain, flow: self.flow, law: PhantomData }
    }

    #[inline(always)]
    fn advance<V: Vector, G: ForceField<V>>(&self, f: &G, x: V, v: V, h: f64) -> (V, V) {
        self.scheme.advance(f, x, v, h)
    }
}

/// Work to run with a concrete [`Motion`].
pub trait WithMotion {
    /// What the work returns.
    type Out;
    /// Runs the work.
    fn run<M: Motion>(self, motion: &M) -> Self::Out;
}

/// The flow of a step as [`dispatch`] reads it: the scene's flow, the time (s) an unsteady flow
/// is taken at (the middle of the step), and whether the fluid-acceleration effect is on.
#[derive(Debug, Clone, Copy)]
pub struct StepFlow<'a> {
    /// The scene's flow.
    pub flow: &'a Flow,
    /// The time (s) an unsteady field is read at.
    pub time: f64,
    /// With the fluid-acceleration effect: a field flow is compiled with its material
    /// acceleration ([`crate::fluid::field::Accelerating`]). The analytic flows have none.
    pub accelerating: bool,
}

/// Runs `work` with the [`Motion`] of this integrator, drag law and flow.
pub fn dispatch<W: WithMotion>(
    integrator: IntegratorKind,
    drag: Option<DragLawKind>,
    flow: StepFlow<'_>,
    work: W,
) -> W::Out {
    match integrator {
        IntegratorKind::Euler => by_drag(Euler, drag, flow, work),
        IntegratorKind::Rk2 => by_drag(Rk2, drag, flow, work),
        IntegratorKind::Rk4 => by_drag(Rk4, drag, flow, work),
        IntegratorKind::Exponential => by_drag(Exponential, drag, flow, work),
    }
}

fn by_drag<S: Scheme, W: WithMotion>(s: S, drag: Option<DragLawKind>, flow: StepFlow<'_>, w: W) -> W::Out {
    match drag {
        None => by_flow::<S, NoDrag, W>(s, flow, w),
        Some(DragLawKind::Stokes) => by_flow::<S, Stokes, W>(s, flow, w),
        Some(DragLawKind::SchillerNaumann) => by_flow::<S, SchillerNaumann, W>(s, flow, w),
    }
}

fn by_flow<S: Scheme, D: DragLaw, W: WithMotion>(scheme: S, step: StepFlow<'_>, w: W) -> W::Out {
    let StepFlow { flow, time, accelerating } = step;
    match flow {
        Flow::Quiescent => w.run(&Mover::<S, D, _> { scheme, flow: fluid::Quiescent, law: PhantomData }),
        Flow::Uniform(u) => w.run(&Mover::<S, D, _> { scheme, flow: fluid::Uniform(*u), law: PhantomData }),
        Flow::Poiseuille(p) => w.run(&Mover::<S, D, _> { scheme, flow: *p, law: PhantomData }),
        Flow::Field(f) if accelerating => {
            w.run(&Mover::<S, D, _> { scheme, flow: f.0.accelerating(time), law: PhantomData })
        }
        // A structured grid's lookup is compiled apart from an unstructured grid's walk.
        Flow::Field(f) => match f.0.structured_at(time) {
            Some(flow) => w.run(&Mover::<S, D, _> { scheme, flow, law: PhantomData }),
            None => w.run(&Mover::<S, D, _> { scheme, flow: f.0.at(time), law: PhantomData }),
        },
    }
}
