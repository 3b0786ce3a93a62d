//! Integration tests: numerical stability (docs/stability.md): corners, creases, tunnelling, stiff drag, non-finite states, property and fuzz tests, regressions, results independent of the thread count.
//!
//! One test binary per theme, each file a module: 46 binaries of about 220 MB each made the
//! test build 11 GB and most of its time linking (issue 26). `cargo test --test stability NAME`
//! runs the tests whose path contains NAME (a file's name selects the file).

#[path = "../common/mod.rs"]
mod common;

mod determinism_threads;
mod ranks_identity;
mod regress_simultaneous_contacts;
mod regress_step_counts;
mod stability_bubble;
mod stability_collapse;
mod stability_corners;
mod stability_dense_pour;
mod stability_edge_starts;
mod stability_fuzz_input;
mod stability_long_run;
mod stability_non_finite;
mod stability_properties;
mod stability_stiff_drag;
mod stability_tunnelling;
