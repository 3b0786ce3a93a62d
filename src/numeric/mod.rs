//! Arithmetic below the physics: four particles at once ([`lanes`]), sums along one particle's
//! array by lanes of four ([`lane_sums`]), and `x^p` for a fixed `p` by tables ([`FixedPower`]). This room names no other room of the engine; the correlations,
//! flows and integrators above it are written once over its [`lanes::Vector`].

pub mod lane_sums;
pub mod lanes;
mod power;

pub use power::FixedPower;

/// A number as every message writes it, one rule for the engine (`{}` writes 1e300 as 301
/// digits, and `{:e}` 0.001 as `1e-3`): the shortest text that reads back as `v`, plain from
/// 1e-4 up to 1e4 (`0.001`, `2500`, `-0.00089`), scientific outside (`1e300`, `1e4`,
/// `6.3e10`, `1e-7`); `NaN`, `inf`, `-inf`.
pub fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e4).contains(&a) { format!("{v}") } else { format!("{v:e}") }
}
