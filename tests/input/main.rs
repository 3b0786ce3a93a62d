//! Integration tests: what the engine reads: the command line, scene files (shipped, bad, adversarial), fills, meshes and CFD field files, and the docs' examples.
//!
//! One test binary per theme, each file a module: 46 binaries of about 220 MB each made the
//! test build 11 GB and most of its time linking (issue 26). `cargo test --test input NAME`
//! runs the tests whose path contains NAME (a file's name selects the file).

#[path = "../common/mod.rs"]
mod common;

mod checkpoint_refusals;
mod cli;
mod docs_examples;
mod field_bad_input;
mod field_errors;
mod field_formats;
mod mesh_walls;
mod scene_adversarial;
mod scene_fill;
mod scenes_bad;
mod scenes_shipped;
