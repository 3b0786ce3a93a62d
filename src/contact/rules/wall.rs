//! The bounce rule of docs/physics.md §5 for one particle on a wall.

use crate::contact::Outcome;
use crate::correlations::{
    Restitution, drop_contact_time, immersed_solid_contact_time, restitution, stokes_number,
};
use crate::fluid::Fluid;
use crate::particles::{Material, ParticleKind};
use crate::walls::WallMaterial;
use glam::DVec3;

/// The scene's bounce parameters (docs/physics.md §3 and §5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BounceRule {
    /// `β` of `ε = ε_max exp(−β/St)`; 35 in L06.
    pub beta: f64,
    /// Critical Stokes number `St_c` below which there is no rebound; 10 by default.
    pub st_critical: f64,
    /// Tangential restitution `e_t` **[ext]**: tangential velocity kept at release; 1 default.
    pub tangential_restitution: f64,
    /// Walton's friction at impacts and Coulomb friction in lasting contacts **[ext]**
    /// (docs/physics.md §9): the scene gives friction keys. Then `tangential_restitution` is 1 and
    /// the materials' keys ([`super::friction::Friction::between`]) make the tangential rule.
    pub friction: bool,
    /// Hold rebounding particles at the wall for `t_c` (the contact-time effect).
    pub hold_at_contact: bool,
    /// The `e` rule **[ext]** (docs/physics.md §3, §8), with wall lubrication: the rebound is `e`
    /// times the speed at impact, `e` the scene's `bounce.e` (`Some`) or the dry restitution
    /// `ε_max` (`None`). `None` here: L06's `ε(St)`.
    pub e_rule: Option<Option<f64>>,
}

impl Default for BounceRule {
    fn default() -> Self {
        BounceRule {
            beta: 35.0,
            st_critical: 10.0,
            tangential_restitution: 1.0,
            friction: false,
            hold_at_contact: false,
            e_rule: None,
        }
    }
}

/// Under the `e` rule, an impact rebounds only if `e St_imp ≥ ln 2`, `St_imp` the Stokes number
/// of the impact speed. Leaving the wall at `V0` through the lubrication drag `6π μ a² V / h`
/// alone, a particle stops at `h = h_r exp(St0)`, `St0` the Stokes number of `V0`: below
/// `ln 2` the rebound would not lift it by its own roughness, and it rests instead (§5.2).
/// This ends the endless sequence of ever smaller rebounds of a particle settling onto the wall;
/// it is not L06's `St_c`, which the `e` rule does not use.
pub const E_RULE_LEAST_REBOUND_ST: f64 = std::f64::consts::LN_2;

/// What one impact on a wall gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Stokes number of the impact, from `V∞` (computed once per contact).
    pub st: f64,
    /// Restitution `ε` (0 for no rebound).
    pub eps: f64,
    /// Contact time `t_c` (s) from L06 eq. 4 (solids) or eq. 5 (drops); 0 for no rebound.
    pub contact_time: f64,
    /// Held, bounced or deposited.
    pub outcome: Outcome,
    /// Velocity after the impact (m/s): at once for a rebound, at release for a hold, the
    /// tangential part only for a deposit.
    pub velocity: DVec3,
}

/// Applies the bounce rule to a particle of `kind` and diameter `d` (m) hitting a wall of
/// `material` with velocity `v` (m/s); `n` is the wall's unit normal towards the particle.
///
/// `V∞ = −v·n` is the normal approach speed at contact: with no wall effect in the force
/// balance it is the speed before the particle feels the wall (docs/physics.md §2). With the `e`
/// rule (wall lubrication) it is the speed at impact, already slowed by the lubrication, and
/// `st` and `eps` in the result are of that speed (`eps = e`).
pub fn wall_impact(
    kind: &ParticleKind,
    d: f64,
    material: &WallMaterial,
    fluid: &Fluid,
    rule: &BounceRule,
    v: DVec3,
    n: DVec3,
) -> Impact {
    let vn = v.dot(n);
    let v_inf = (-vn).max(0.0);
    let tangential = v - vn * n;
    let st = stokes_number(kind.density, fluid.density, v_inf, d, fluid.viscosity);
    let eps_max = material.restitution_max.unwrap_or(kind.restitution_max);
    let rebound = match rule.e_rule {
        None => restitution(st, eps_max, rule.beta, rule.st_critical),
        Some(e) => {
            let e = e.unwrap_or(eps_max);
            if e * st >= E_RULE_LEAST_REBOUND_ST { Restitution::Rebound(e) } else { Restitution::NoRebound }
        }
    };
    match rebound {
        Restitution::NoRebound => {
            Impact { st, eps: 0.0, contact_time: 0.0, outcome: Outcome::Deposited, velocity: tangential }
        }
        Restitution::Rebound(eps) => Impact {
            st,
            eps,
            contact_time: contact_time(kind, d, material, fluid, v_inf, st),
            outcome: if rule.hold_at_contact && kind.held_at_contact {
                Outcome::Held
            } else {
                Outcome::Bounced
            },
            velocity: eps * v_inf * n + rule.tangential_restitution * tangential,
        },
    }
}

/// L06 eq. 5 for drops, eq. 4 for solids; a wall with no elastic constants is rigid.
fn contact_time(kind: &ParticleKind, d: f64, wall: &WallMaterial, fluid: &Fluid, v_imp: f64, st: f64) -> f64 {
    match kind.material {
        Material::Drop { surface_tension } => {
            drop_contact_time(kind.density, fluid.density, d, surface_tension)
        }
        Material::Solid { youngs_modulus, poisson_ratio } => immersed_solid_contact_time(
            kind.density,
            fluid.density,
            youngs_modulus,
            poisson_ratio,
            wall.youngs_modulus.unwrap_or(f64::INFINITY),
            wall.poisson_ratio.unwrap_or(0.0),
            d,
            v_imp,
            st,
        )
        // Only below St = 0.197, which the scene check keeps under St_c.
        .unwrap_or(0.0),
    }
}
