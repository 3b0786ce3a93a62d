//! Integration tests: the physics against references: analytic cases, the paper's numbers and figures, the extensions (history, lubrication, fluid acceleration, friction, rotation), pairs, injectors and outlets.
//!
//! One test binary per theme, each file a module: 46 binaries of about 220 MB each made the
//! test build 11 GB and most of its time linking (issue 26). `cargo test --test physics NAME`
//! runs the tests whose path contains NAME (a file's name selects the file).

#[path = "../common/mod.rs"]
mod common;

mod accuracy_study;
mod analytic_stokes_settling;
mod analytic_vacuum_bounce;
mod broad_phase_polydisperse;
mod contact_rules;
mod feature_example;
mod flow_poiseuille;
mod fluid_acceleration;
mod friction_bed;
mod friction_impacts;
mod friction_lasting;
mod friction_lasting_energy;
mod heap;
mod history;
mod inject_outlets_counts;
mod lubrication_history;
mod outlets_residence;
mod pairs;
mod paper_fig6;
mod paper_numbers;
mod wall_lubrication;
