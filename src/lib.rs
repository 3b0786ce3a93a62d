//! # wetbounce
//!
//! Particles — solid beads and liquid drops — moving through a liquid or a gas and bouncing on
//! walls as immersed particles do, following Legendre, Zenit, Daniel & Guiraud, Chem. Eng. Sci.
//! 61 (2006) 3543–3549. The physics is specified in `PHYSICS.md`; this crate's modules follow
//! its sections:
//!
//! - [`correlations`]: the paper's formulas as pure functions;
//! - [`effects`]: the force terms a scene can name (gravity, buoyancy, drag, added mass) and
//!   the hold at contact;
//! - [`integrate`]: Euler, RK2, RK4 and an exponential integrator;
//! - [`walls`] and [`contact`]: where and how a particle meets a wall, and the bounce rule;
//! - [`pipeline`]: [`Simulation`] and its stage-ordered `step()`;
//! - [`scene`]: the TOML scene format, validated with errors that name file, key and value;
//! - [`output`]: sinks for trajectories and contact events.
#![warn(missing_docs)]

pub mod contact;
pub mod correlations;
pub mod effects;
pub mod fluid;
pub mod integrate;
pub mod lanes;
pub mod output;
pub mod particles;
pub mod pipeline;
pub mod scene;
pub mod walls;

pub use pipeline::{ContactEvent, Other, Outcome, Simulation};
pub use scene::{Scene, SceneError};
