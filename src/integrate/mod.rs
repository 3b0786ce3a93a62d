//! Time integrators of the free flight between contacts (docs/physics.md §1), one file each.
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
pub(crate) use exponential::{phi12, phi12_lanes};
pub use rk2::Rk2;
pub use rk4::Rk4;

use crate::effects::DragLaw;
use crate::fluid::FlowField;
use crate::numeric::lanes::{Real, Vector};
use glam::DVec3;
use serde::Deserialize;
use std::marker::PhantomData;

/// A particle's acceleration at one state, linearised in its velocity `v`:
/// `a = explicit + inv_tau (u − v)` (OpenFOAM's `forceSuSp` idea; docs/architecture.md).
/// Of one particle (`V = DVec3`) or of a lane group of four ([`crate::numeric::lanes::DVec3x4`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linear<V: Vector = DVec3> {
    /// Acceleration that does not depend on `v` (m/s²).
    pub explicit: V,
    /// Drag rate `1/τ = 3π μ d f(Re) / m_eff` (1/s); 0 without drag.
    pub inv_tau: V::Real,
    /// Fluid velocity the drag pulls towards (m/s).
    pub u: V,
}

impl<V: Vector> Linear<V> {
    /// The total acceleration at velocity `v` (m/s²).
    #[inline(always)]
    pub fn total(&self, v: V) -> V {
        self.explicit + (self.u - v) * self.inv_tau
    }
}

/// A force field for one particle, or for a lane group: the acceleration at a state.
pub trait ForceField<V: Vector = DVec3> {
    /// The linearised acceleration at position `x` (m) and velocity `v` (m/s).
    fn eval(&self, x: V, v: V) -> Linear<V>;
}

/// An integration scheme, as a type so that the hot loop is compiled for it.
pub trait Scheme: Copy + Send + Sync + 'static {
    /// Order of accuracy on smooth problems.
    const ORDER: u32;
    /// Real-axis stability interval: the scheme is stable on the linear decay `v' = −λ v` for
    /// `λ h` below this (∞ when it is stable for every step).
    const STABILITY_INTERVAL: f64;
    /// Under a constant acceleration the step moves a particle by `h v + θ h (v(h) − v)`: θ is
    /// the share of the step's change of velocity in its displacement. The lasting-contact
    /// solver moves a particle by θ h times the velocity it takes away, so that a particle it
    /// holds at rest ends the step where it began (contact/lasting/mod.rs).
    const DISPLACEMENT_SHARE: f64;
    /// Advances `(x, v)` by `h` (s) under `f`; returns the new `(x, v)`. Of one particle or of
    /// a lane group, with the same operations in the same order.
    fn advance<V: Vector, F: ForceField<V>>(self, f: &F, x: V, v: V, h: f64) -> (V, V);
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

/// The force on one particle (or on each of a lane group): its kind's constant acceleration
/// plus drag of law `D` in flow `F`.
#[derive(Debug, Clone, Copy)]
pub struct ParticleForce<D, F, V: Vector = DVec3> {
    /// Constant acceleration (m/s²): gravity, buoyancy over the inertia.
    pub accel: V,
    /// Stokes drag rate `18 μ / ((ρp + C_M ρ) d²)` (1/s).
    pub stokes_rate: V::Real,
    /// `ρ d / μ` (s/m): the Reynolds number per unit slip speed.
    pub re_per_speed: V::Real,
    /// `G = (1 + C_M) ρ / (ρp + C_M ρ)`: the acceleration per unit fluid acceleration `Du/Dt`
    /// (fluid-acceleration effect); read only when the flow [`FlowField::ACCELERATES`].
    pub fluid_gain: V::Real,
    /// The fluid velocity field.
    pub flow: F,
    /// The drag law.
    pub law: PhantomData<D>,
}

impl<D: DragLaw, F: FlowField, V: Vector> ForceField<V> for ParticleForce<D, F, V> {
    #[inline(always)]
    fn eval(&self, x: V, v: V) -> Linear<V> {
        // NOTE: `ACCELERATES` is a constant of the flow's type: every flow but a field with the
        // fluid-acceleration effect compiles this to `self.accel`, as before the effect existed.
        let explicit = if F::ACCELERATES {
            self.accel + self.flow.material_acceleration_of(x) * self.fluid_gain
        } else {
            self.accel
        };
        if !D::ACTIVE {
            return Linear { explicit, inv_tau: V::Real::splat(0.0), u: V::ZERO };
        }
        let u = self.flow.velocity_of(x);
        let re2 = self.re_per_speed * self.re_per_speed * (v - u).length_squared();
        Linear { explicit, inv_tau: self.stokes_rate * D::factor_of_squared(re2), u }
    }
}

/// A force field with the part pushing into a wall removed: a particle resting on a wall
/// (docs/physics.md §5.2) slides in the tangent plane of the unit normal `n`.
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

/// A force field with every part across a line removed: a particle resting in the crease of two
/// walls slides along their common tangent, the unit `t`.
#[derive(Debug, Clone, Copy)]
pub struct Along<'a, F> {
    /// The unconstrained field.
    pub inner: &'a F,
    /// Unit direction of the crease line.
    pub t: DVec3,
}

impl<F: ForceField> ForceField for Along<'_, F> {
    #[inline]
    fn eval(&self, x: DVec3, v: DVec3) -> Linear {
        let l = self.inner.eval(x, v);
        let t = self.t;
        Linear { explicit: l.explicit.dot(t) * t, inv_tau: l.inv_tau, u: l.u.dot(t) * t }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::{NoDrag, SchillerNaumann, Stokes};
    use crate::fluid::{Poiseuille, Quiescent, Uniform};
    use crate::numeric::lanes::{DVec3x4, F64x4, LANES};

    /// Stokes settling from rest in a uniform flow: the closed form of docs/physics.md §1.
    fn stokes_case() -> (ParticleForce<Stokes, Uniform>, impl Fn(f64) -> (DVec3, DVec3)) {
        let f = ParticleForce {
            accel: DVec3::new(0.3, 0.0, -2.0),
            stokes_rate: 1.0 / 0.05,
            re_per_speed: 0.0,
            fluid_gain: 0.0,
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

    /// `DISPLACEMENT_SHARE` is what each scheme does: from a velocity `v`, under a constant
    /// acceleration (no drag), the step moves a particle by `h v + θ h (v(h) − v)`.
    fn displacement_share_of<S: Scheme>(s: S) -> f64 {
        let f = ParticleForce::<NoDrag, Quiescent, DVec3> {
            accel: DVec3::new(0.0, 0.0, -5.9),
            stokes_rate: 0.0,
            re_per_speed: 0.0,
            fluid_gain: 0.0,
            flow: Quiescent,
            law: PhantomData,
        };
        let (x, v, h) = (DVec3::new(0.1, 0.2, 0.3), DVec3::new(0.01, 0.0, -0.02), 2e-4);
        let (x1, v1) = s.advance(&f, x, v, h);
        (x1 - x - v * h).z / (h * (v1 - v).z)
    }

    #[test]
    fn each_scheme_moves_a_particle_by_its_displacement_share_of_the_velocity_change() {
        for (name, theta, want) in [
            ("euler", displacement_share_of(Euler), Euler::DISPLACEMENT_SHARE),
            ("rk2", displacement_share_of(Rk2), Rk2::DISPLACEMENT_SHARE),
            ("rk4", displacement_share_of(Rk4), Rk4::DISPLACEMENT_SHARE),
            ("exponential", displacement_share_of(Exponential), Exponential::DISPLACEMENT_SHARE),
        ] {
            assert!((theta - want).abs() < 1e-9, "{name}: {theta}, declared {want}");
        }
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

    /// Four particles per group, as many groups as given: positions, velocities, kinds'
    /// accelerations and diameters drawn so that the groups hold zero slip (`Re = 0`, outside
    /// the power's table), creeping, intermediate and Newton-regime (`Re > 1000`) particles,
    /// alone and mixed.
    fn lane_groups(groups: usize) -> Vec<[(DVec3, DVec3, DVec3, f64); LANES]> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let vec = |scale: f64, rng: &mut rand_chacha::ChaCha8Rng| {
            DVec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                * scale
        };
        (0..groups)
            .map(|g| {
                std::array::from_fn(|lane| {
                    // Slip speeds from 0 and 1e-15 m/s to 30 m/s; in a group, either one
                    // regime or a mix.
                    let decade = if g % 3 == 0 { (g / 3) % 17 } else { rng.random_range(0..17) };
                    let speed =
                        if decade == 0 && lane % 2 == 0 { 0.0 } else { 3e-16 * 10f64.powi(decade as i32) };
                    let x = vec(0.05, &mut rng);
                    (x, vec(speed, &mut rng), vec(10.0, &mut rng), rng.random_range(1e-4..5e-3))
                })
            })
            .collect()
    }

    /// One step of every group by lanes, and of each particle alone: the same bits.
    fn lanes_match_one_by_one<S: Scheme, D: DragLaw, F: FlowField>(scheme: S, flow: F) {
        let (drag_rate, re_rate) = (1.8e-3, 2.5e6);
        for group in lane_groups(400) {
            let h = 1e-3;
            let field = |accel: DVec3, d: f64| ParticleForce::<D, F> {
                accel,
                stokes_rate: drag_rate / (d * d),
                re_per_speed: re_rate * d,
                fluid_gain: 0.0,
                flow,
                law: PhantomData,
            };
            let lanes = ParticleForce::<D, F, DVec3x4> {
                accel: DVec3x4::from_array(group.map(|p| p.2)),
                stokes_rate: F64x4::splat(drag_rate)
                    / (F64x4(group.map(|p| p.3)) * F64x4(group.map(|p| p.3))),
                re_per_speed: F64x4(group.map(|p| p.3)) * re_rate,
                fluid_gain: F64x4([0.0; LANES]),
                flow,
                law: PhantomData,
            };
            let (x, v) = (DVec3x4::from_array(group.map(|p| p.0)), DVec3x4::from_array(group.map(|p| p.1)));
            let (x1, v1) = scheme.advance(&lanes, x, v, h);
            let (x1, v1) = (x1.to_array(), v1.to_array());
            for (lane, p) in group.iter().enumerate() {
                let (xs, vs) = scheme.advance(&field(p.2, p.3), p.0, p.1, h);
                let same =
                    |a: DVec3, b: DVec3| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits);
                assert!(
                    same(x1[lane], xs) && same(v1[lane], vs),
                    "lane {lane} of {group:?}: {:?} vs {:?}",
                    (x1[lane], v1[lane]),
                    (xs, vs)
                );
            }
        }
    }

    fn lanes_match_one_by_one_for_every_law_and_flow<S: Scheme>(s: S) {
        let pipe = Poiseuille { point: DVec3::ZERO, axis: DVec3::Z, radius: 0.04, max_velocity: 0.3 };
        let uniform = Uniform(DVec3::new(0.0, 0.01, 0.2));
        lanes_match_one_by_one::<S, NoDrag, _>(s, Quiescent);
        lanes_match_one_by_one::<S, Stokes, _>(s, uniform);
        lanes_match_one_by_one::<S, SchillerNaumann, _>(s, Quiescent);
        lanes_match_one_by_one::<S, SchillerNaumann, _>(s, uniform);
        lanes_match_one_by_one::<S, SchillerNaumann, _>(s, pipe);
        lanes_match_one_by_one::<S, Stokes, _>(s, pipe);
    }

    #[test]
    fn euler_lane_groups_give_the_bits_of_one_particle_at_a_time() {
        lanes_match_one_by_one_for_every_law_and_flow(Euler);
    }

    #[test]
    fn rk2_lane_groups_give_the_bits_of_one_particle_at_a_time() {
        lanes_match_one_by_one_for_every_law_and_flow(Rk2);
    }

    #[test]
    fn rk4_lane_groups_give_the_bits_of_one_particle_at_a_time() {
        lanes_match_one_by_one_for_every_law_and_flow(Rk4);
    }

    #[test]
    fn exponential_lane_groups_give_the_bits_of_one_particle_at_a_time() {
        lanes_match_one_by_one_for_every_law_and_flow(Exponential);
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
