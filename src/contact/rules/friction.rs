//! Friction at an impact **[ext]** (docs/physics.md §9): the rigid-body impulse model with Coulomb
//! friction `μ` and tangential restitution `β0` (Walton 1993; Maw, Barber & Fawcett 1976; as
//! Joseph & Hunt 2004 use it for immersed oblique impacts). The normal impulse is the bounce
//! rule's (L06's `ε`, or `e` under the `e` rule, 0 for a deposit); this file adds the tangential
//! impulse at the contact point, and the spin it gives.

use crate::particles::FrictionMaterial;
use glam::DVec3;

/// `β0` when no surface of a contact gives one: a sticking impact ends with no slip at the
/// contact point and no tangential elasticity (Foerster et al. 1994 measured 0.3–0.4 for glass;
/// a scene that wants the elastic reversal says so).
pub const DEFAULT_TANGENTIAL_RESTITUTION: f64 = 0.0;

/// The friction of one contact, the two surfaces' keys combined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Friction {
    /// Coulomb friction coefficient `μ`.
    pub mu: f64,
    /// Tangential restitution `β0` (−1 to 1).
    pub beta0: f64,
    /// Rolling friction coefficient `μ_r`.
    pub rolling: f64,
}

impl Friction {
    /// The friction between two surfaces: `μ` and `μ_r` are the geometric means of the two
    /// values (so a frictionless surface, `μ = 0`, makes a frictionless contact whatever the
    /// other — as the pair restitution `ε_max = sqrt(ε_a ε_b)`), `β0` the arithmetic mean (it
    /// may be negative). A surface that does not give a key leaves it to the other; when neither
    /// does, `μ = μ_r = 0` and `β0` = [`DEFAULT_TANGENTIAL_RESTITUTION`].
    pub fn between(a: &FrictionMaterial, b: &FrictionMaterial) -> Friction {
        let combine = |x: Option<f64>, y: Option<f64>, mean: fn(f64, f64) -> f64, none: f64| match (x, y) {
            (Some(x), Some(y)) => mean(x, y),
            (Some(v), None) | (None, Some(v)) => v,
            (None, None) => none,
        };
        let geometric = |x: f64, y: f64| (x * y).sqrt();
        let arithmetic = |x: f64, y: f64| 0.5 * (x + y);
        Friction {
            mu: combine(a.friction, b.friction, geometric, 0.0),
            beta0: combine(
                a.tangential_restitution,
                b.tangential_restitution,
                arithmetic,
                DEFAULT_TANGENTIAL_RESTITUTION,
            ),
            rolling: combine(a.rolling_friction, b.rolling_friction, geometric, 0.0),
        }
    }
}

/// One body at an impact: inverse translational inertia (1/kg; 0 for a wall or a particle held
/// at one), inverse moment of inertia (1/(kg m²); 0 likewise), radius (m: the lever arm from
/// its centre to the contact point), velocity (m/s) and spin (rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spinning {
    /// `1/m`, with `m` the inertia of the force balance `(ρp + C_M ρ) Vp`.
    pub inv_mass: f64,
    /// `1/I`, `I = (2/5) ρp Vp a²`.
    pub inv_moment: f64,
    /// Radius `a` (m).
    pub radius: f64,
    /// Velocity (m/s).
    pub v: DVec3,
    /// Angular velocity (rad/s).
    pub omega: DVec3,
}

impl Spinning {
    /// A wall: immobile, not spinning.
    pub const WALL: Spinning =
        Spinning { inv_mass: 0.0, inv_moment: 0.0, radius: 0.0, v: DVec3::ZERO, omega: DVec3::ZERO };
}

/// What the tangential part of an impact does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tangential {
    /// Tangential impulse on `a` (N s); `b` gets its opposite.
    pub impulse: DVec3,
    /// Contact point's tangential velocity of `a` relative to `b` before the impact (m/s).
    pub slip: DVec3,
    /// Whether the impact sticks (`v_ct' = −β0 v_ct`) rather than slides.
    pub sticking: bool,
}

impl Tangential {
    /// Applies the impulse to `a` and `b` (normal from `a` to `b`): velocities and spins after.
    pub fn apply(&self, a: &Spinning, b: &Spinning, n: DVec3) -> [(DVec3, DVec3); 2] {
        let j = self.impulse;
        [
            (a.v + j * a.inv_mass, a.omega + (a.radius * n).cross(j) * a.inv_moment),
            (b.v - j * b.inv_mass, b.omega + (b.radius * n).cross(j) * b.inv_moment),
        ]
    }
}

/// Contact point velocity of `a` relative to `b`, touching with unit normal `n` from `a` to `b`:
/// `(v_a + ω_a × a_a n) − (v_b + ω_b × (−a_b n))`.
pub fn contact_velocity(a: &Spinning, b: &Spinning, n: DVec3) -> DVec3 {
    (a.v + a.omega.cross(a.radius * n)) - (b.v + b.omega.cross(-b.radius * n))
}

/// Walton's tangential impulse for bodies `a` and `b` touching with unit normal `n` from `a` to
/// `b`, approaching at normal speed `vn ≥ 0` and separating at `e vn` (the bounce rule's normal
/// restitution; 0 for a deposit).
///
/// A tangential impulse `J` changes the contact point's relative tangential velocity by `c J`,
/// `c = 1/m_a + 1/m_b + a_a²/I_a + a_b²/I_b`; the normal impulse is `J_n = (1 + e) vn / (1/m_a
/// + 1/m_b)`. The impact **sticks** when `(1 + β0) |v_ct| ≤ μ c J_n` — for one solid sphere on a
/// wall, with no added mass, `c J_n = (7/2)(1 + e)|vn|`: the 7/2 of docs/physics.md §9 — and then
/// `v_ct' = −β0 v_ct`; otherwise it **slides**: `|J| = μ J_n` against `v_ct`, and `|v_ct|` drops
/// by `μ c J_n`. In a liquid `m` carries the added mass and `I` does not (a sphere's added mass
/// has no rotational part), so `c J_n / (1 + e) vn` is `1 + (5/2)(ρp + C_M ρ)/ρp` rather than 7/2.
/// Either way `|v_ct'| ≤ |v_ct|`: the impulse never adds energy.
pub fn tangential_impulse(a: &Spinning, b: &Spinning, n: DVec3, vn: f64, e: f64, f: &Friction) -> Tangential {
    let u = contact_velocity(a, b, n);
    let slip = u - u.dot(n) * n;
    let c = a.inv_mass + b.inv_mass + a.radius * a.radius * a.inv_moment + b.radius * b.radius * b.inv_moment;
    let w = a.inv_mass + b.inv_mass;
    if c == 0.0 || w == 0.0 {
        return Tangential { impulse: DVec3::ZERO, slip, sticking: true };
    }
    let normal_impulse = (1.0 + e) * vn.max(0.0) / w;
    let speed = slip.length();
    let limit = f.mu * normal_impulse;
    if (1.0 + f.beta0) * speed <= limit * c {
        Tangential { impulse: -(1.0 + f.beta0) * slip / c, slip, sticking: true }
    } else {
        Tangential { impulse: -limit * slip / speed, slip, sticking: false }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn materials_combine_by_geometric_mean_and_beta0_by_average() {
        let a = FrictionMaterial {
            friction: Some(0.4),
            tangential_restitution: Some(0.2),
            rolling_friction: None,
        };
        let b = FrictionMaterial {
            friction: Some(0.1),
            tangential_restitution: Some(-0.4),
            rolling_friction: Some(0.01),
        };
        let f = Friction::between(&a, &b);
        assert!((f.mu - 0.2).abs() < 1e-15 && (f.beta0 + 0.1).abs() < 1e-15 && f.rolling == 0.01);
        let none = Friction::between(&FrictionMaterial::default(), &FrictionMaterial::default());
        assert_eq!(none, Friction { mu: 0.0, beta0: DEFAULT_TANGENTIAL_RESTITUTION, rolling: 0.0 });
    }
}
