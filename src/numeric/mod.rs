//! Arithmetic below the physics: four particles at once ([`lanes`]) and `x^p` for a fixed `p`
//! by tables ([`FixedPower`]). This room names no other room of the engine; the correlations,
//! flows and integrators above it are written once over its [`lanes::Vector`].

pub mod lanes;
mod power;

pub use power::FixedPower;
