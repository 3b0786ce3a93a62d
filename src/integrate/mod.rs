//! Time integrators of the free flight between contacts (PHYSICS.md §1), one file each.
//!
//! Every scheme advances one particle's `(x, v)` over a step `h` under a [`ForceField`] that
//! returns the acceleration in linearised form ([`Linear`]): an explicit part plus a drag rate
//! towards the fluid velocity. The explicit Runge–Kutta schemes use only the total; the
//! [`Exponential`] scheme integrates the drag part exactly.

mod euler;
mod exponential;
mod rk2;
mod rk4;

pub use euler::Euler;
pub use exponential::Exponential;
pub use rk2::Rk2;
pub use rk4::Rk4;

use crate::effects::DragLaw;
use crate::fluid::FlowField;
use glam::DVec3;
use serde::Deserialize;
use std::marker::PhantomData;

/// A particle's acceleration at one state, linearised in its velocity `v`:
/// `a = explicit + inv_tau (u − v)` (OpenFOAM's `forceSuSp` idea, ARCHITECTURE.md rule 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linear {
    /// Acceleration that does not depend on `v` (m/s²).
    pub explicit: DVec3,
    /// Drag rate `1/τ = 3π μ d f(Re) / m_eff` (1/s); 0 without drag.
    pub inv_tau: f64,
    /// Fluid velocity the drag pulls towards (m/s).
    pub u: DVec3,
}

impl Linear {
    /// The total acceleration at velocity `v` (m/s²).
    #[inline(always)]
    pub fn total(&self, v: DVec3) -> DVec3 {
        self.explicit + self.inv_tau * (self.u - v)
    }
}

/// A force field for one particle: the acceleration at a state.
pub trait ForceField {
    /// The linearised acceleration at position `x` (m) and velocity `v` (m/s).
    fn eval(&self, x: DVec3, v: DVec3) -> Linear;
}

/// An integration scheme, as a type so that the hot loop is compiled for it.
pub trait Scheme: Copy + Send + Sync + 'static {
    /// Order of accuracy on smooth problems.
    const ORDER: u32;
    /// Real-axis stability interval: the scheme is stable on the linear decay `v' = −λ v` for
    /// `λ h` below this (∞ when it is stable for every step).
    const STABILITY_INTERVAL: f64;
    /// Advances `(x, v)` by `h` (s) under `f`; returns the new `(x, v)`.
    fn advance<F: ForceField>(self, f: &F, x: DVec3, v: DVec3, h: f64) -> (DVec3, DVec3);
}

/// The integrator a scene chooses (`simulation.integrator`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorKind {
    /// Forward Euler, order 1.
    Euler,
    /// Heun's two-stage Runge–Kutta (explicit trapezoidal rule), order 2: L06's integrator.
    Rk2,
    /// Classical four-stage Runge–Kutta, order 4.
    Rk4,
    /// Exponential integrator, exact for the linear drag part, order 2 otherwise.
    Exponential,
}

impl IntegratorKind {
    /// The scene-file name.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Euler => "euler",
            IntegratorKind::Rk2 => "rk2",
            IntegratorKind::Rk4 => "rk4",
            IntegratorKind::Exponential => "exponential",
        }
    }
}

impl IntegratorKind {
    /// The real-axis stability interval of the scheme ([`Scheme::STABILITY_INTERVAL`]).
    pub fn stability_interval(self) -> f64 {
        match self {
            IntegratorKind::Euler => Euler::STABILITY_INTERVAL,
            IntegratorKind::Rk2 => Rk2::STABILITY_INTERVAL,
            IntegratorKind::Rk4 => Rk4::STABILITY_INTERVAL,
            IntegratorKind::Exponential => Exponential::STABILITY_INTERVAL,
        }
    }

    /// The largest stable step (s) of this scheme for a particle relaxing at `rate` (1/s, the
    /// linearised drag rate `λ = 1/τ`): `interval / λ`, strict (`h` must stay below it). ∞ for
    /// the exponential scheme and for `rate = 0` (no drag: the explicit schemes then integrate
    /// a constant force, exactly or with bounded error, at any step).
    pub fn largest_stable_step(self, rate: f64) -> f64 {
        if rate > 0.0 { self.stability_interval() / rate } else { f64::INFINITY }
    }
}

/// The force on one particle: its kind's constant acceleration plus drag of law `D` in flow `F`.
#[derive(Debug, Clone, Copy)]
pub struct ParticleForce<D, F> {
    /// Constant acceleration (m/s²): gravity, buoyancy over the inertia.
    pub accel: DVec3,
    /// Stokes drag rate `18 μ / ((ρp + C_M ρ) d²)` (1/s).
    pub stokes_rate: f64,
    /// `ρ d / μ` (s/m): the Reynolds number per unit slip speed.
    pub re_per_speed: f64,
    /// The fluid velocity field.
    pub flow: F,
    /// The drag law.
    pub law: PhantomData<D>,
}

impl<D: DragLaw, F: FlowField> ForceField for ParticleForce<D, F> {
    #[inline(always)]
    fn eval(&self, x: DVec3, v: DVec3) -> Linear {
        if !D::ACTIVE {
            return Linear { explicit: self.accel, inv_tau: 0.0, u: DVec3::ZERO };
        }
        let u = self.flow.velocity(x);
        let re2 = self.re_per_speed * self.re_per_speed * (v - u).length_squared();
        Linear { explicit: self.accel, inv_tau: self.stokes_rate * D::factor_of_squared(re2), u }
    }
}

/// A force field with the part pushing into a wall removed: a particle resting on a wall
/// (PHYSICS.md §5.2) slides in the tangent plane of the unit normal `n`.
#[derive(Debug, Clone, Copy)]
pub struct Tangential<'a, F> {
    /// The unconstrained field.
    pub inner: &'a F,
    /// Unit normal of the wall at the contact, pointing towards the particle.
    pub n: DVec3,
}

impl<F: ForceField> ForceField for Tangential<'_, F> {
    #[inline]
    fn eval(&self, x: DVec3, v: DVec3) -> Linear {
        let l = self.inner.eval(x, v);
        let n = self.n;
        Linear { explicit: l.explicit - l.explicit.dot(n) * n, inv_tau: l.inv_tau, u: l.u - l.u.dot(n) * n }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::Stokes;
    use crate::fluid::Uniform;

    /// Stokes settling from rest in a uniform flow: the closed form of PHYSICS.md §1.
    fn stokes_case() -> (ParticleForce<Stokes, Uniform>, impl Fn(f64) -> (DVec3, DVec3)) {
        let f = ParticleForce {
            accel: DVec3::new(0.3, 0.0, -2.0),
            stokes_rate: 1.0 / 0.05,
            re_per_speed: 0.0,
            flow: Uniform(DVec3::new(0.1, 0.0, 0.0)),
            law: PhantomData,
        };
        let tau = 0.05;
        let vt = f.flow.0 + f.accel * tau;
        let exact = move |t: f64| {
            let decay = (-t / tau).exp();
            (vt * t - vt * tau * (1.0 - decay), vt * (1.0 - decay))
        };
        (f, exact)
    }

    fn error_at_end<S: Scheme>(s: S, steps: usize) -> f64 {
        let (f, exact) = stokes_case();
        let t_end = 0.2;
        let h = t_end / steps as f64;
        let (mut x, mut v) = (DVec3::ZERO, DVec3::ZERO);
        for _ in 0..steps {
            (x, v) = s.advance(&f, x, v, h);
        }
        let (xe, ve) = exact(t_end);
        (x - xe).length() / xe.length() + (v - ve).length() / ve.length()
    }

    fn observed_order<S: Scheme>(s: S) -> f64 {
        let coarse = error_at_end(s, 40);
        let fine = error_at_end(s, 80);
        (coarse / fine).log2()
    }

    #[test]
    fn euler_converges_at_first_order_on_stokes_settling() {
        let p = observed_order(Euler);
        assert!((p - 1.0).abs() < 0.1, "order {p}");
    }

    #[test]
    fn rk2_converges_at_second_order_on_stokes_settling() {
        let p = observed_order(Rk2);
        assert!((p - 2.0).abs() < 0.1, "order {p}");
    }

    #[test]
    fn rk4_converges_at_fourth_order_on_stokes_settling() {
        let p = observed_order(Rk4);
        assert!((p - 4.0).abs() < 0.15, "order {p}");
    }

    #[test]
    fn exponential_is_exact_for_linear_stokes_drag_at_any_step() {
        for steps in [1, 3, 40] {
            let e = error_at_end(Exponential, steps);
            assert!(e < 1e-13, "{steps} steps: relative error {e}");
        }
    }
}
