//! The progress bar on standard error: simulated time of total, particles alive, steps/s, ETA.

use super::{OutputError, Sink};
use crate::pipeline::Simulation;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// Simulated time is tracked in microseconds: the bar's integer position.
const TICKS_PER_S: f64 = 1e6;

/// A [`Sink`] that draws an indicatif bar while the run goes on, and clears it at the end.
pub struct Progress {
    bar: ProgressBar,
    steps: Arc<AtomicU64>,
    alive: Arc<AtomicU64>,
}

impl Progress {
    /// A bar for a run of `duration` (s), drawn on stderr unless `quiet` or stderr is not a
    /// terminal (a log file or a pipe gets no control characters).
    pub fn new(duration: f64, quiet: bool) -> Self {
        let visible = !quiet && std::io::stderr().is_terminal();
        Self::with_target(
            duration,
            if visible { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() },
        )
    }

    /// A bar drawn to `target`.
    pub fn with_target(duration: f64, target: ProgressDrawTarget) -> Self {
        let steps = Arc::new(AtomicU64::new(0));
        let alive = Arc::new(AtomicU64::new(0));
        let bar = ProgressBar::with_draw_target(Some(ticks(duration)), target);
        let (s, a) = (steps.clone(), alive.clone());
        let style = ProgressStyle::with_template(
            "{bar:30} t = {sim} s  {alive} particles  {rate} steps/s  ETA {eta}",
        )
        .expect("the template is fixed and valid")
        .progress_chars("=> ")
        .with_key("sim", |st: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(
                w,
                "{:.4}/{:.4}",
                st.pos() as f64 / TICKS_PER_S,
                st.len().unwrap_or(0) as f64 / TICKS_PER_S
            );
        })
        .with_key("alive", move |_: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(w, "{}", a.load(Ordering::Relaxed));
        })
        .with_key("rate", move |st: &ProgressState, w: &mut dyn std::fmt::Write| {
            let secs = st.elapsed().as_secs_f64();
            let n = s.load(Ordering::Relaxed) as f64;
            let _ = write!(w, "{:.0}", if secs > 0.0 { n / secs } else { 0.0 });
        });
        bar.set_style(style);
        Progress { bar, steps, alive }
    }
}

fn ticks(t: f64) -> u64 {
    (t.max(0.0) * TICKS_PER_S).round() as u64
}

impl Sink for Progress {
    fn step(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        self.steps.store(sim.world.steps, Ordering::Relaxed);
        self.alive.store(sim.world.particles.len() as u64, Ordering::Relaxed);
        // indicatif redraws at most ~20 times a second, so this is cheap per step.
        self.bar.set_position(ticks(sim.world.time));
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.bar.finish_and_clear();
        Ok(())
    }
}
