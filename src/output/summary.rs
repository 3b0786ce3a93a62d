//! The table printed at the end of a run.

use super::Statistics;
use super::statistics::{Distribution, ImpactTally};
use crate::particles::State;
use crate::pipeline::Simulation;
use crate::run::RunReport;
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
    /// Taken out by outlets.
    pub removed_by_outlets: usize,
    /// Added by injectors.
    pub injected: u64,
    /// Injections skipped because no clear place was found (never placed overlapping).
    pub injection_skipped: u64,
    /// Each wall's name and impacts, in scene order.
    pub walls: Vec<(String, ImpactTally)>,
    /// Each outlet's name and residence-time distribution (s), in scene order.
    pub outlets: Vec<(String, Distribution)>,
    /// Each injector's name and (due, injected, skipped) counts, in scene order.
    pub injectors: Vec<(String, [u64; 3])>,
}

impl RunSummary {
    /// The summary of a run that ended with `sim` in this state.
    pub fn new(sim: &Simulation, report: &RunReport, stats: &Statistics) -> Self {
        let count = |s: State| sim.world.particles.state.iter().filter(|&&x| x.code() == s.code()).count();
        RunSummary {
            time: report.time,
            steps: report.steps,
            wall_time_s: report.wall_time.as_secs_f64(),
            interrupted: report.interrupted,
            stats: stats.clone(),
            alive: sim.world.particles.len(),
            free: count(State::Free),
            held: count(State::Held),
            resting: count(State::Resting),
            lost: sim.record.lost.len(),
            removed_by_outlets: sim.record.removed.iter().map(Vec::len).sum(),
            injected: sim.world.injection.iter().map(|i| i.injected).sum(),
            injection_skipped: sim.world.injection.iter().map(|i| i.skipped).sum(),
            walls: sim
                .setup
                .walls
                .iter()
                .enumerate()
                .map(|(w, wall)| (wall.name.clone(), stats.wall(w)))
                .collect(),
            outlets: sim
                .setup
                .outlets
                .iter()
                .zip(&sim.record.removed)
                .map(|(o, removed)| {
                    let times: Vec<f64> = removed.iter().map(|r| r.residence_time).collect();
                    (o.name.clone(), Distribution::of(&times))
                })
                .collect(),
            injectors: sim
                .setup
                .injectors
                .iter()
                .zip(&sim.world.injection)
                .map(|(i, s)| (i.name.clone(), [s.due, s.injected, s.skipped]))
                .collect(),
        }
    }

    /// Particles taken out of the simulation, for any reason.
    pub fn removed(&self) -> usize {
        self.lost + self.removed_by_outlets
    }

    /// Particles that were ever in the simulation: `alive + removed = initial + injected`.
    pub fn total(&self) -> usize {
        self.alive + self.removed()
    }

    /// The content of `DIR/summary.json`: this table, with every wall's impacts, every outlet's
    /// residence-time distribution and every injector's counts. SI units; a mean of nothing is
    /// `null`.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        let num = |x: f64| if x.is_finite() { json!(x) } else { serde_json::Value::Null };
        // One wall's impacts, or all of them, with their count under `count`.
        let tally = |st: &ImpactTally, count: &str| {
            let mut m = serde_json::Map::new();
            m.insert(count.into(), json!(st.impacts()));
            m.insert("held".into(), json!(st.held));
            m.insert("bounced".into(), json!(st.bounced));
            m.insert("deposited".into(), json!(st.deposited));
            m.insert("mean_st".into(), num(st.mean_st()));
            m.insert("mean_eps".into(), num(st.mean_eps()));
            m
        };
        let s = &self.stats.all;
        let walls: Vec<_> = self
            .walls
            .iter()
            .map(|(name, st)| {
                let mut w = tally(st, "impacts");
                w.insert("name".into(), json!(name));
                w.insert("held_time_s".into(), json!(st.held_time_s));
                w
            })
            .collect();
        let outlets: Vec<_> =
            self.outlets.iter().map(|(name, d)| json!({ "name": name, "residence_time_s": d })).collect();
        let injectors: Vec<_> = self
            .injectors
            .iter()
            .map(|(name, [due, injected, skipped])| {
                json!({ "name": name, "due": due, "injected": injected, "skipped": skipped })
            })
            .collect();
        json!({
            "time_s": self.time,
            "steps": self.steps,
            "wall_time_s": self.wall_time_s,
            "interrupted": self.interrupted,
            "particles": {
                "alive": self.alive,
                "free": self.free,
                "held": self.held,
                "deposited": self.resting,
                "removed": self.removed(),
                "removed_by_outlets": self.removed_by_outlets,
                "lost_non_finite": self.lost,
                "injected": self.injected,
                "injection_skipped": self.injection_skipped,
            },
            "impacts": tally(s, "total"),
            "walls": walls,
            "outlets": outlets,
            "injectors": injectors,
        })
    }
}

impl fmt::Display for RunSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.stats.all;
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
            s.impacts(),
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
        if self.injected + self.injection_skipped > 0 {
            writeln!(
                f,
                "  injected           {} ({} skipped: no clear place)",
                self.injected, self.injection_skipped
            )?;
        }
        if self.outlets.is_empty() {
            write!(f, "  removed            {} ({} non-finite)", self.removed(), self.lost)?;
        } else {
            write!(
                f,
                "  removed            {} ({} by outlets, {} non-finite)",
                self.removed(),
                self.removed_by_outlets,
                self.lost
            )?;
        }
        for (name, w) in self.walls.iter().filter(|(_, w)| w.impacts() > 0) {
            write!(
                f,
                "\n  wall {name:<13} {} impacts (held {}, bounced {}, deposited {}), mean St {}, mean ε {}, held {:.3} s",
                w.impacts(),
                w.held,
                w.bounced,
                w.deposited,
                opt(w.mean_st()),
                opt(w.mean_eps()),
                w.held_time_s
            )?;
        }
        for (name, d) in &self.outlets {
            let s = |x: Option<f64>| x.map_or("-".into(), |x| format!("{x:.3}"));
            write!(
                f,
                "\n  outlet {name:<11} {} removed, residence time mean {} s (p10 {}, median {}, p90 {})",
                d.count,
                s(d.mean),
                s(d.p10),
                s(d.p50),
                s(d.p90)
            )?;
        }
        Ok(())
    }
}
