//! Measures the engine state per particle: heap bytes held by a `Simulation` of N particles
//! after a few steps (columns, scratch, neighbour list), with no output sinks.
//!
//! Run: `cargo run --release --bin memory -- [N] [history]` (default 1,000,000). The beads sit
//! on a cubic lattice at 3 d spacing in a box of water, with gravity, buoyancy, Stokes drag and
//! pair collisions on — the dilute benchmark scene scaled to N; with `history`, also the history
//! effect at its defaults. It prints the bytes the loaded scene holds (what `wetbounce check`
//! allocates) and those of the running simulation (the scene's particles moved into it, as
//! `wetbounce run` does).

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use wetbounce::Scene;

/// The system allocator, counting the bytes currently allocated.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; only a counter is added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        // SAFETY: same layout as requested by the caller.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: `ptr` was allocated by `alloc` above with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn main() {
    let n: usize = std::env::args().nth(1).map_or(1_000_000, |s| {
        s.parse().unwrap_or_else(|_| {
            eprintln!("error: N must be a whole number, got {s}");
            std::process::exit(2)
        })
    });
    let history = std::env::args().nth(2).is_some_and(|a| a == "history");
    let side = (n as f64).cbrt().ceil() as usize;
    let (d, spacing) = (2.5e-3, 7.5e-3);
    let extent = side as f64 * spacing;
    let text = format!(
        r#"
[simulation]
dt = 8.77e-6
duration = 1.0
output_interval = 1.0
integrator = "euler"
[fluid]
density = 1000.0
viscosity = 0.1
[effects]
gravity = {{}}
buoyancy = {{}}
drag = {{ law = "stokes" }}
{history}
[[kinds]]
name = "glass"
type = "solid"
density = 2540.0
youngs_modulus = 6e7
poisson_ratio = 0.23
[[walls]]
name = "box"
type = "box"
min = [0.0, 0.0, 0.0]
max = [{extent}, {extent}, {top}]
inside = true
[[lattice]]
kind = "glass"
diameter = {d}
min = [0.0, 0.0, 0.0]
max = [{extent}, {extent}, {extent}]
spacing = {spacing}
"#,
        top = extent * 1.2,
        history = if history { "history = {}" } else { "" }
    );
    let before = LIVE.load(Ordering::Relaxed);
    let mut scene = Scene::from_str(&text, Path::new("memory.toml")).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    let loaded = LIVE.load(Ordering::Relaxed).saturating_sub(before);
    let estimate = scene.estimate.bytes_per_particle;
    let mut sim = scene.take_simulation().unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    drop(scene);
    for _ in 0..3 {
        sim.step(8.77e-6);
    }
    let bytes = LIVE.load(Ordering::Relaxed).saturating_sub(before);
    let count = sim.world.particles.len();
    println!(
        "N = {count}{}: loaded scene {:.1} bytes per particle; running: {:.1} MB of engine state, {:.1} bytes \
         per particle (estimate used by check: {estimate:.0})",
        if history { " with history" } else { "" },
        loaded as f64 / count as f64,
        bytes as f64 / 1e6,
        bytes as f64 / count as f64
    );
}
