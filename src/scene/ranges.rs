//! The ranges a scene's physical values must lie in: one table, here, documented in
//! `docs/scene-format.md` (§1, "Ranges").
//!
//! Why ranges at all: a value far outside any physical range is a typo or an attack, and it
//! does not fail where it is given. A diameter of 1e-300 m gives a particle volume of 0 and a
//! NaN acceleration at the first step; a fluid density of 1e300 kg/m³ overflows the buoyancy;
//! a speed of 1e155 m/s overflows the kinetic energy (v² > 1.8e308); a direction of 1e200 has
//! an infinite squared length. Each bound below is wide — several orders of magnitude beyond
//! the materials and flows the model is meant for — and far inside the range where products of
//! the values (ρ d³, v², d²/μ, ρ g d³, E d²) stay finite and normal in double precision, so that
//! an accepted scene cannot overflow or underflow in its first step for want of a check.

use super::error::Invalid;
use super::error::fmt::num;

/// The accepted range of one kind of quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Range {
    /// What the values are, plural ("densities"), for messages.
    pub quantity: &'static str,
    /// SI unit, for messages ("kg/m³"; "" for a pure number).
    pub unit: &'static str,
    /// Smallest magnitude accepted (> 0).
    pub min: f64,
    /// Largest magnitude accepted.
    pub max: f64,
    /// Whether 0 is accepted too, below `min`, and what it means there ("a vacuum"; "" to say
    /// nothing). `None` when it is not, or when `min` is 0 anyway.
    pub zero: Option<&'static str>,
}

/// Particle densities. From 1e-6 kg/m³ (far below any gas bubble; air is 1.2) to 1e5 (four
/// times osmium, the densest element).
pub(crate) const DENSITY: Range =
    Range { quantity: "densities", unit: "kg/m³", min: 1e-6, max: 1e5, zero: None };

/// The fluid's density: as particle densities, or 0 for a vacuum.
pub(crate) const FLUID_DENSITY: Range = Range { zero: Some("a vacuum"), ..DENSITY };

/// Dynamic viscosities: from 1e-7 Pa·s (ten times below any gas: hydrogen has 9e-6) to 1e6
/// (a hundred thousand times honey), or 0 (an inviscid fluid).
pub(crate) const VISCOSITY: Range =
    Range { quantity: "viscosities", unit: "Pa·s", min: 1e-7, max: 1e6, zero: Some("an inviscid fluid") };

/// Particle diameters: from 0.1 µm (the edge of continuum drag) to 10 m.
pub(crate) const DIAMETER: Range =
    Range { quantity: "particle diameters", unit: "m", min: 1e-7, max: 10.0, zero: None };

/// Sizes of walls and regions (radii, lengths, spacings, a cone's height): up to 10 km; the
/// smallest 1 nm, below the smallest particle.
pub(crate) const LENGTH: Range = Range { quantity: "lengths", unit: "m", min: 1e-9, max: 1e4, zero: None };

/// Sizes that may also be 0 (a disk region's radius: a point; an annulus's hole: a disc; a
/// flat annulus's cone height).
pub(crate) const LENGTH_OR_ZERO: Range = Range { zero: Some(""), ..LENGTH };

/// Coordinates (every component of a point, a corner, a translation): within ±10 km of the
/// origin. (This keeps every product of lengths finite; it does not make a scene accurate:
/// at 10 km a position's round-off is 2e-12 m, so small particles belong near the origin.)
pub(crate) const COORDINATE: Range =
    Range { quantity: "coordinates", unit: "m", min: 0.0, max: 1e4, zero: None };

/// Speeds (the length of a velocity, a flow's speed): up to 10 km/s, beyond any flow of
/// liquids or gases and any particle the model is meant for (hypervelocity impacts).
pub(crate) const SPEED: Range = Range { quantity: "speeds", unit: "m/s", min: 0.0, max: 1e4, zero: None };

/// The length of gravity: up to 1e5 m/s² (10,000 g, a laboratory centrifuge).
pub(crate) const GRAVITY: Range =
    Range { quantity: "accelerations of gravity", unit: "m/s²", min: 0.0, max: 1e5, zero: None };

/// Interfacial tensions of drops: from 1e-7 N/m (below the ultra-low tensions of surfactant
/// systems, 1e-6) to 10 N/m (five times molten iron's 1.9).
pub(crate) const SURFACE_TENSION: Range =
    Range { quantity: "surface tensions", unit: "N/m", min: 1e-7, max: 10.0, zero: None };

/// Young's moduli of particles and walls: from 1 kPa (soft gels) to 1e13 Pa (ten times
/// diamond's 1.2e12).
pub(crate) const YOUNGS_MODULUS: Range =
    Range { quantity: "Young's moduli", unit: "Pa", min: 1e3, max: 1e13, zero: None };

/// Times (the time step, the duration, the output interval, an injector's start and stop):
/// from 1 ps to 1e9 s (31 years).
pub(crate) const TIME: Range = Range { quantity: "times", unit: "s", min: 1e-12, max: 1e9, zero: None };

/// Times that may also be 0 (an injector's start).
pub(crate) const TIME_OR_ZERO: Range = Range { zero: Some("the start of the run"), ..TIME };

/// A mesh's scale (m per file unit): from 1e-6 (files in µm) to 1e6.
pub(crate) const MESH_SCALE: Range =
    Range { quantity: "mesh scales", unit: "m per file unit", min: 1e-6, max: 1e6, zero: None };

/// The added-mass coefficient: up to 10 (a sphere far from walls has 0.5, touching one 0.73).
pub(crate) const ADDED_MASS: Range =
    Range { quantity: "added-mass coefficients", unit: "", min: 0.0, max: 10.0, zero: None };

/// Surface roughnesses of particles and walls (the gap at which contact is made with wall
/// lubrication): from 0.1 nm (an atomic step) to 10 cm; it must also be below the radius of
/// every particle of the kind (checked on its own).
pub(crate) const ROUGHNESS: Range =
    Range { quantity: "roughnesses", unit: "m", min: 1e-10, max: 0.1, zero: None };

/// Every range, for the test that checks `docs/scene-format.md` lists them.
#[cfg(test)]
pub(crate) const ALL: [&Range; 16] = [
    &DENSITY,
    &FLUID_DENSITY,
    &VISCOSITY,
    &DIAMETER,
    &LENGTH,
    &LENGTH_OR_ZERO,
    &COORDINATE,
    &SPEED,
    &GRAVITY,
    &SURFACE_TENSION,
    &YOUNGS_MODULUS,
    &TIME,
    &TIME_OR_ZERO,
    &MESH_SCALE,
    &ADDED_MASS,
    &ROUGHNESS,
];

impl Range {
    /// `1e-6 to 1e5 kg/m³`, or `0 (a vacuum) or 1e-6 to 1e5 kg/m³`, or `at most 1e4 m/s`.
    pub fn describe(&self) -> String {
        let unit = if self.unit.is_empty() { String::new() } else { format!(" {}", self.unit) };
        if self.min == 0.0 {
            return format!("at most {}{unit}", num(self.max));
        }
        let span = format!("{} to {}{unit}", num(self.min), num(self.max));
        match self.zero {
            Some("") => format!("0 or {span}"),
            Some(meaning) => format!("0 ({meaning}) or {span}"),
            None => span,
        }
    }

    /// Whether `v` (≥ 0) is in the range.
    pub fn contains(&self, v: f64) -> bool {
        (v == 0.0 && (self.zero.is_some() || self.min == 0.0)) || (self.min..=self.max).contains(&v)
    }

    /// `v` (finite, of the sign the key needs, checked before) if it is in the range.
    pub fn check(&self, key: &str, v: f64) -> Result<f64, Invalid> {
        if self.contains(v) {
            Ok(v)
        } else {
            Err(Invalid::new(
                key,
                format!("must be {} (the range of {}), got {}", self.describe(), self.quantity, num(v)),
            ))
        }
    }

    /// Checks a magnitude `m` (≥ 0) of a value shown as `shown`.
    pub fn check_magnitude(&self, key: &str, m: f64, shown: &str) -> Result<f64, Invalid> {
        if self.contains(m) {
            Ok(m)
        } else {
            let range = self.describe();
            Err(Invalid::new(
                key,
                format!("must be {range} in magnitude (the range of {}), got {shown}", self.quantity),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_range_is_documented_in_scene_format_md_as_the_messages_write_it() {
        let doc = include_str!("../../docs/scene-format.md");
        for range in ALL {
            let shown = range.describe();
            assert!(
                doc.contains(&shown),
                "docs/scene-format.md lacks the range of {}: {shown}",
                range.quantity
            );
        }
    }

    #[test]
    fn bounds_are_ordered_and_zero_is_accepted_only_where_it_has_a_meaning() {
        for range in ALL {
            assert!(range.min < range.max, "{}", range.quantity);
            assert_eq!(range.contains(0.0), range.zero.is_some() || range.min == 0.0, "{}", range.quantity);
            assert!(
                range.contains(range.min) && range.contains(range.max) && !range.contains(range.max * 1.0001)
            );
        }
        assert!(!DENSITY.contains(0.0) && FLUID_DENSITY.contains(0.0));
    }
}
