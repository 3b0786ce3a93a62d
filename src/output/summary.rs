//! The table printed at the end of a run.

use super::Statistics;
use crate::particles::State;
use crate::pipeline::Simulation;
use crate::pipeline::run::RunReport;
use std::fmt;

/// What a run did, for the end-of-run table: steps and wall time, impacts per outcome, mean St
/// and ε, and where the particles ended.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Simulated time reached (s).
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Wall-clock time (s).
    pub wall_time_s: f64,
    /// Whether Ctrl-C stopped the run early.
    pub interrupted: bool,
    /// Contact statistics.
    pub stats: Statistics,
    /// Particles still in the simulation.
    pub alive: usize,
    /// Of those: free, held, resting (deposited).
    pub free: usize,
    /// Held at a wall for their contact time.
    pub held: usize,
    /// Resting on a wall after an impact below `St_c`.
    pub resting: usize,
    /// Taken out because their state became non-finite.
    pub lost: usize,
    // NOTE: removals by outlets go here as a field of their own (and in `removed()`) once the
    // engine counts them.
}

impl RunSummary {
    /// The summary of a run that ended with `sim` in this state.
    pub fn new(sim: &Simulation, report: &RunReport, stats: &Statistics) -> Self {
        let count = |s: State| sim.particles.state.iter().filter(|&&x| x == s).count();
        RunSummary {
            time: report.time,
            steps: report.steps,
            wall_time_s: report.wall_time.as_secs_f64(),
            interrupted: report.interrupted,
            stats: stats.clone(),
            alive: sim.particles.len(),
            free: count(State::Free),
            held: count(State::Held),
            resting: count(State::Resting),
            lost: sim.lost.len(),
        }
    }

    /// Particles taken out of the simulation, for any reason.
    pub fn removed(&self) -> usize {
        self.lost
    }
}

impl fmt::Display for RunSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.stats;
        let opt = |x: f64| if x.is_finite() { format!("{x:.3}") } else { "-".into() };
        let rate = if self.wall_time_s > 0.0 { self.steps as f64 / self.wall_time_s } else { 0.0 };
        writeln!(
            f,
            "  simulated time     {:.6} s{}",
            self.time,
            if self.interrupted { " (interrupted)" } else { "" }
        )?;
        writeln!(f, "  steps              {} ({:.0} steps/s)", self.steps, rate)?;
        writeln!(f, "  wall time          {:.3} s", self.wall_time_s)?;
        writeln!(
            f,
            "  impacts            {} (held {}, bounced {}, deposited {})",
            s.contacts(),
            s.held,
            s.bounced,
            s.deposited
        )?;
        writeln!(f, "  mean St            {}", opt(s.mean_st()))?;
        writeln!(f, "  mean ε of rebounds {}", opt(s.mean_eps()))?;
        writeln!(
            f,
            "  particles          {} in the simulation: {} free, {} held, {} deposited (resting)",
            self.alive, self.free, self.held, self.resting
        )?;
        write!(f, "  removed            {} ({} non-finite)", self.removed(), self.lost)
    }
}
