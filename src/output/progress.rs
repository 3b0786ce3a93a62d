//! The progress bar on standard error: simulated time of total, particles alive, steps/s, time
//! left.
//!
//! The rate and the time left are measured over the last few seconds of wall time, not since
//! the start (nor by indicatif's own estimate, which weighs a long past): a run whose injectors
//! keep adding particles gets slower as it goes, and an average over its cheap beginning showed
//! 17 s left with 35 s to go.

use super::{OutputError, Sink};
use crate::pipeline::Simulation;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use std::collections::VecDeque;
use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Simulated time is tracked in microseconds: the bar's integer position.
const TICKS_PER_S: f64 = 1e6;
/// Wall time over which the rate is measured.
const WINDOW: Duration = Duration::from_secs(5);
/// Wall time between two samples of the rate.
const SAMPLE_EVERY: Duration = Duration::from_millis(200);

/// A [`Sink`] that draws an indicatif bar while the run goes on, and clears it at the end.
pub struct Progress {
    bar: ProgressBar,
    /// Steps per second over the window, as `f64` bits.
    rate: Arc<AtomicU64>,
    /// Seconds left at the window's rate, as `f64` bits (NaN before the first measurement).
    left: Arc<AtomicU64>,
    alive: Arc<AtomicU64>,
    duration: f64,
    /// (wall time, simulated time, steps) every [`SAMPLE_EVERY`], over the last [`WINDOW`].
    samples: VecDeque<(Instant, f64, u64)>,
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
        let rate = Arc::new(AtomicU64::new(0.0f64.to_bits()));
        let left = Arc::new(AtomicU64::new(f64::NAN.to_bits()));
        let alive = Arc::new(AtomicU64::new(0));
        let bar = ProgressBar::with_draw_target(Some(ticks(duration)), target);
        let (r, l, a) = (rate.clone(), left.clone(), alive.clone());
        let style = ProgressStyle::with_template(
            "{bar:30} t = {sim} s  {alive} particles  {rate} steps/s  {left} left",
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
        .with_key("rate", move |_: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(w, "{:.0}", f64::from_bits(r.load(Ordering::Relaxed)));
        })
        .with_key("left", move |_: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(w, "{}", time_left(f64::from_bits(l.load(Ordering::Relaxed))));
        });
        bar.set_style(style);
        Progress { bar, rate, left, alive, duration, samples: VecDeque::new() }
    }

    /// Records a sample at most every [`SAMPLE_EVERY`] and updates the rate and the time left
    /// from the oldest sample within [`WINDOW`].
    fn measure(&mut self, now: Instant, time: f64, steps: u64) {
        if self.samples.back().is_some_and(|&(at, _, _)| now.duration_since(at) < SAMPLE_EVERY) {
            return;
        }
        self.samples.push_back((now, time, steps));
        while self.samples.len() > 2 && now.duration_since(self.samples[1].0) >= WINDOW {
            self.samples.pop_front();
        }
        let (at, t0, n0) = self.samples[0];
        let wall = now.duration_since(at).as_secs_f64();
        if wall <= 0.0 || time <= t0 {
            return;
        }
        let rate = (steps - n0) as f64 / wall;
        let left = (self.duration - time).max(0.0) * wall / (time - t0);
        self.rate.store(rate.to_bits(), Ordering::Relaxed);
        self.left.store(left.to_bits(), Ordering::Relaxed);
    }
}

/// Seconds left as `12 s`, `3 min 05 s`, `2 h 01 min`, or `?` before a measurement.
fn time_left(s: f64) -> String {
    if !s.is_finite() {
        return "?".into();
    }
    let s = s.round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, s % 3600 / 60),
    }
}

fn ticks(t: f64) -> u64 {
    (t.max(0.0) * TICKS_PER_S).round() as u64
}

impl Sink for Progress {
    fn step(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        if !self.bar.is_hidden() {
            self.measure(Instant::now(), sim.world.time, sim.world.steps);
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_left_follows_the_recent_rate_of_a_run_that_slows_down() {
        let mut p = Progress::with_target(100.0, ProgressDrawTarget::hidden());
        let start = Instant::now();
        // 10 s of wall time at 1 simulated second per wall second, then 10 s at 0.1.
        let mut t = 0.0;
        for k in 1..=200 {
            t += if k <= 100 { 0.1 } else { 0.01 };
            p.measure(start + Duration::from_millis(100 * k), t, 10 * k);
        }
        let left = f64::from_bits(p.left.load(Ordering::Relaxed));
        // 89 simulated seconds at 0.1 per wall second: 890 s. A whole-run average says 162 s.
        assert!((left - (100.0 - t) / 0.1).abs() < 1.0, "{left}");
    }

    #[test]
    fn time_left_reads_in_seconds_minutes_and_hours() {
        assert_eq!(time_left(f64::NAN), "?");
        assert_eq!(time_left(17.2), "17 s");
        assert_eq!(time_left(185.0), "3 min 05 s");
        assert_eq!(time_left(7260.0), "2 h 01 min");
    }
}
