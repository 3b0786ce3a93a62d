//! Integration tests: what a run writes: MCAP, VTK, stopping on a signal, a full disk.
//!
//! One test binary per theme, each file a module: 46 binaries of about 220 MB each made the
//! test build 11 GB and most of its time linking (issue 26). `cargo test --test output NAME`
//! runs the tests whose path contains NAME (a file's name selects the file).

#[path = "../common/mod.rs"]
mod common;
#[path = "../outputs_common/mod.rs"]
mod outputs_common;

mod checkpoint_resume;
mod output_disk_full;
mod output_interrupt;
mod output_mcap;
mod output_vtk;
