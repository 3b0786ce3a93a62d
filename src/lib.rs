//! # wetbounce
//!
//! Particles — solid beads and liquid drops — moving through a liquid or a gas and bouncing on
//! walls as immersed particles do, following Legendre, Zenit, Daniel & Guiraud, Chem. Eng. Sci.
//! 61 (2006) 3543–3549. The physics is specified in `docs/physics.md` (cited as
//! "docs/physics.md §N"); this crate's rooms, from the bottom up (a lower one never names a
//! higher one):
//!
//! - [`files`]: the rule every file read follows (a regular file, under a size cap);
//! - [`agree`]: what the ranks of a run split over MPI agree on inside a step;
//! - [`numeric`]: four particles at once (lane groups) and fixed powers by tables;
//! - [`correlations`]: the paper's formulas as pure functions;
//! - [`particles`], [`fluid`], [`walls`]: what the world is made of;
//! - [`effects`]: the force terms a scene can name (gravity, buoyancy, drag, added mass) and
//!   the hold at contact;
//! - [`integrate`]: Euler, RK2, RK4 and an exponential integrator;
//! - [`flight`]: one particle's path between contacts, compiled for the scene's physics;
//! - [`contact`]: every contact — detection, the events inside a step, the bounce rules, the
//!   contacts that last;
//! - [`pipeline`]: [`Simulation`] (its [`World`], [`Setup`] and [`Record`]) and its
//!   stage-ordered `step()`;
//! - [`scene`]: the TOML scene format, validated with errors that name file, key and value;
//! - [`output`]: sinks for trajectories and contact events;
//! - [`run`]: the driver that steps a simulation and feeds the sinks;
//! - [`ranks`]: one run on several MPI ranks, identical to one process.
#![warn(missing_docs)]

pub mod agree;
pub mod contact;
pub mod correlations;
pub mod effects;
pub mod files;
pub mod flight;
pub mod fluid;
pub mod heap;
pub mod integrate;
pub mod numeric;
pub mod output;
pub mod particles;
pub mod pipeline;
pub mod ranks;
pub mod run;
pub mod scene;
pub mod walls;

pub use contact::{ContactEvent, Other, Outcome};
pub use pipeline::{Record, Setup, Simulation, World};
pub use scene::{Scene, SceneError};
