//! Pure correlation functions of `docs/physics.md`, each citing its source.
//!
//! Every function is a plain function of SI numbers: no scene, no state. The doc comment of
//! each gives the formula, the source with its equation number, the range of validity and the
//! units. Legendre, Zenit, Daniel & Guiraud, Chem. Eng. Sci. 61 (2006) 3543–3549 is cited as
//! **L06**; extensions that are ours are marked **[ext]**.

mod contact_time;
mod drag;
mod drag_stiffness;
mod faddeeva;
mod history;
mod restitution;
mod rotation;
mod stokes;
mod terminal;
mod wall_hindrance;

pub use contact_time::{
    drop_contact_time, hertz_contact_time, hertz_pair_contact_time, immersed_solid_contact_time,
    immersed_solid_correction, spring_pair_contact_time,
};
pub use drag::{drag_factor_schiller_naumann, drag_factor_schiller_naumann_of_squared, reynolds_number};
pub use drag_stiffness::schiller_naumann_stiffness_factor;
pub use history::{
    ExponentialSum, HistorySettling, VAN_HINSBERG_A, VAN_HINSBERG_T, basset_coefficient,
    history_settling_velocity,
};
pub use restitution::{Restitution, restitution};
pub use rotation::{rotational_stokes_torque, sphere_moment_of_inertia, spin_relaxation_rate_d2};
pub use stokes::{pair_stokes_number, relaxation_time, stokes_number};
pub use terminal::{TerminalVelocity, terminal_velocity};
pub use wall_hindrance::{
    ADDED_MASS_CONTACT, NORMAL_GAP_CONSTANT, PARALLEL_GAP_CONSTANT, added_mass_normal,
    added_mass_normal_and_slope, added_mass_normal_exact, brenner_normal_exact, faxen_parallel,
    oneill_parallel_exact, wall_factor_normal, wall_factor_parallel,
};

/// Added-mass coefficient of a sphere far from walls, `C_M∞ = 1/2` (L06 §2).
pub const ADDED_MASS_FAR: f64 = 0.5;
/// Added-mass coefficient of a sphere touching a wall, `C_Mwall = 0.73` (L06 §3).
pub const ADDED_MASS_WALL: f64 = 0.73;

/// Volume of a sphere of diameter `d` (m) in m³: `π d³ / 6`.
pub fn sphere_volume(d: f64) -> f64 {
    std::f64::consts::PI * d * d * d / 6.0
}
