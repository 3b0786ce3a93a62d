//! The bounce rule for two particles **[ext]** (docs/physics.md §2, §4 and §5, pair extensions).

use super::wall::BounceRule;
use crate::contact::Outcome;
use crate::correlations::{
    ADDED_MASS_FAR, ADDED_MASS_WALL, Restitution, hertz_pair_contact_time, pair_stokes_number, restitution,
    sphere_volume, spring_pair_contact_time,
};
use crate::fluid::Fluid;
use crate::particles::{Material, ParticleKind};
use glam::DVec3;

/// One particle of a colliding pair.
#[derive(Debug, Clone, Copy)]
pub struct PairBody<'a> {
    /// Its kind.
    pub kind: &'a ParticleKind,
    /// Diameter (m).
    pub d: f64,
    /// Inertia in the force balance (kg): `(ρp + C_M ρ) Vp`; ∞ for a particle held at a wall.
    pub inertia: f64,
    /// Velocity at contact (m/s).
    pub v: DVec3,
}

impl PairBody<'_> {
    fn immobile(&self) -> bool {
        self.inertia.is_infinite()
    }

    /// Mass of L06 §2 for the Stokes number, `(ρp + C_M∞ ρ) Vp` (kg).
    fn stokes_mass(&self, rho: f64) -> f64 {
        if self.immobile() {
            f64::INFINITY
        } else {
            (self.kind.density + ADDED_MASS_FAR * rho) * sphere_volume(self.d)
        }
    }

    /// Mass of L06 eq. 5 for the spring analogy, `(ρp + C_Mwall ρ) Vp` (kg).
    fn wall_mass(&self, rho: f64) -> f64 {
        if self.immobile() {
            f64::INFINITY
        } else {
            (self.kind.density + ADDED_MASS_WALL * rho) * sphere_volume(self.d)
        }
    }
}

/// What one pair impact gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairImpact {
    /// Relative normal approach speed `Vn` (m/s).
    pub normal_speed: f64,
    /// Pair Stokes number `St = m* Vn / (6π μ a*²)`.
    pub st: f64,
    /// Restitution (0 for no rebound).
    pub eps: f64,
    /// Pair contact time (s); 0 for no rebound.
    pub contact_time: f64,
    /// Held, bounced or deposited.
    pub outcome: Outcome,
    /// Velocities right after the impact (m/s): rebounded, or with the relative normal velocity
    /// removed (deposit), or both at the centre-of-mass velocity (hold).
    pub va: DVec3,
    /// See `va`.
    pub vb: DVec3,
    /// For a hold: the relative velocity `va − vb` to give at release, `−ε Vn n + e_t u_t`.
    pub release_relative: DVec3,
}

/// The bounce rule on the relative motion of particles `a` and `b` touching with unit normal
/// `n` pointing from `a` to `b`: St from the reduced mass and radius, `ε = ε_max exp(−β/St)`
/// with `ε_max = sqrt(ε_max,a ε_max,b)` **[ext]**, contact time from Hertz (two solids) or two
/// springs in series (a drop involved), and momentum-conserving velocity changes.
pub fn pair_impact(a: &PairBody, b: &PairBody, n: DVec3, fluid: &Fluid, rule: &BounceRule) -> PairImpact {
    let u = a.v - b.v;
    let vn = u.dot(n).max(0.0);
    let ut = u - u.dot(n) * n;
    let (ra, rb) = (0.5 * a.d, 0.5 * b.d);
    let rho = fluid.density;
    let st = pair_stokes_number(a.stokes_mass(rho), b.stokes_mass(rho), ra, rb, vn, fluid.viscosity);
    let eps_max = (a.kind.restitution_max * b.kind.restitution_max).sqrt();
    // Impulse per unit of relative-velocity change: va += wa J, vb −= wb J.
    let (wa, wb) = (1.0 / a.inertia, 1.0 / b.inertia);
    let towards = |target: DVec3| {
        let j = (target - u) / (wa + wb);
        (a.v + wa * j, b.v - wb * j)
    };
    match restitution(st, eps_max, rule.beta, rule.st_critical) {
        Restitution::NoRebound => {
            let (va, vb) = towards(u - u.dot(n) * n);
            PairImpact {
                normal_speed: vn,
                st,
                eps: 0.0,
                contact_time: 0.0,
                outcome: Outcome::Deposited,
                va,
                vb,
                release_relative: DVec3::ZERO,
            }
        }
        Restitution::Rebound(eps) => {
            let rebound = -eps * vn * n + rule.tangential_restitution * ut;
            let contact_time = pair_contact_time(a, b, rho, st, vn);
            // A pair is held when either kind is: the contact time is then the softer one's
            // (a drop's spring), which is what the effect names a kind for.
            let held = rule.hold_at_contact && (a.kind.held_at_contact || b.kind.held_at_contact);
            let (outcome, (va, vb)) = if held {
                (Outcome::Held, towards(DVec3::ZERO))
            } else {
                (Outcome::Bounced, towards(rebound))
            };
            PairImpact { normal_speed: vn, st, eps, contact_time, outcome, va, vb, release_relative: rebound }
        }
    }
}

/// Hertz for two solids, with the effective modulus, reduced radius and reduced mass; two
/// springs `16π σ / 5` in series for drops (a solid is the stiffer spring, taken as rigid).
fn pair_contact_time(a: &PairBody, b: &PairBody, rho: f64, _st: f64, vn: f64) -> f64 {
    match (a.kind.material, b.kind.material) {
        (
            Material::Solid { youngs_modulus: ea, poisson_ratio: na },
            Material::Solid { youngs_modulus: eb, poisson_ratio: nb },
        ) => {
            let compliance = (1.0 - na * na) / ea + (1.0 - nb * nb) / eb;
            let m = reduce(a.stokes_mass(rho), b.stokes_mass(rho));
            let r = reduce(0.5 * a.d, 0.5 * b.d);
            hertz_pair_contact_time(m, r, compliance, vn)
        }
        (ma, mb) => {
            let sigma = |m: Material| match m {
                Material::Drop { surface_tension } => surface_tension,
                Material::Solid { .. } => f64::INFINITY,
            };
            spring_pair_contact_time(a.wall_mass(rho), b.wall_mass(rho), sigma(ma), sigma(mb))
        }
    }
}

fn reduce(x: f64, y: f64) -> f64 {
    if y.is_infinite() {
        x
    } else if x.is_infinite() {
        y
    } else {
        x * y / (x + y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drop_kind() -> ParticleKind {
        ParticleKind {
            name: "toluene".into(),
            density: 860.0,
            restitution_max: 0.91,
            material: Material::Drop { surface_tension: 0.026 },
            roughness: 0.0,
            friction: Default::default(),
            held_at_contact: true,
        }
    }

    #[test]
    fn head_on_equal_drops_rebound_symmetrically_conserving_momentum() {
        let kind = drop_kind();
        let fluid = Fluid {
            density: 997.0,
            viscosity: 0.89e-3,
            gravity: DVec3::ZERO,
            flow: crate::fluid::Flow::Quiescent,
        };
        let m = (860.0 + 0.5 * 997.0) * sphere_volume(2.5e-3);
        let a = PairBody { kind: &kind, d: 2.5e-3, inertia: m, v: DVec3::new(0.1, 0.0, 0.0) };
        let b = PairBody { kind: &kind, d: 2.5e-3, inertia: m, v: DVec3::new(-0.1, 0.0, 0.0) };
        let r = pair_impact(&a, &b, DVec3::X, &fluid, &BounceRule::default());
        assert_eq!(r.outcome, Outcome::Bounced);
        assert!((r.va + r.vb).length() < 1e-16);
        assert!((r.va.x + r.eps * 0.1).abs() < 1e-15, "{r:?}");
        assert!(r.st > 10.0);
    }
}
