//! Run statistics for the end-of-run summary and `summary.json`: contacts overall and per
//! wall, residence times per outlet, injections per injector.

use super::{OutputError, Sink};
use crate::contact::{ContactEvent, Other, Outcome};
use crate::pipeline::Simulation;
use std::fmt;

/// Counts and means over all contact events of a run, in total and per wall.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Statistics {
    /// Every contact, with walls and between particles.
    pub all: ImpactTally,
    /// Contacts with each wall (indexed like the simulation's walls; grown as walls are hit).
    pub per_wall: Vec<ImpactTally>,
}

/// Counts per outcome, mean St and mean ε of a set of contacts (a whole run, or one wall).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ImpactTally {
    /// Impacts that held the particle.
    pub held: u64,
    /// Instantaneous rebounds.
    pub bounced: u64,
    /// Impacts without rebound.
    pub deposited: u64,
    /// Sum of the contact times of the held impacts (s): time particles spent held.
    pub held_time_s: f64,
    st_sum: f64,
    st_count: u64,
    eps_sum: f64,
}

impl ImpactTally {
    /// All impacts on the wall.
    pub fn impacts(&self) -> u64 {
        self.held + self.bounced + self.deposited
    }

    /// Mean Stokes number of the impacts with a finite one (NaN if none).
    pub fn mean_st(&self) -> f64 {
        self.st_sum / self.st_count as f64
    }

    /// Mean restitution of the rebounds (NaN if none).
    pub fn mean_eps(&self) -> f64 {
        self.eps_sum / (self.held + self.bounced) as f64
    }

    /// Adds one contact.
    pub fn add(&mut self, e: &ContactEvent) {
        match e.outcome {
            Outcome::Held => {
                self.held += 1;
                self.held_time_s += e.contact_time;
            }
            Outcome::Bounced => self.bounced += 1,
            Outcome::Deposited => self.deposited += 1,
        }
        if e.st.is_finite() {
            self.st_sum += e.st;
            self.st_count += 1;
        }
        if e.outcome != Outcome::Deposited {
            self.eps_sum += e.eps;
        }
    }
}

/// Count, mean, percentiles and histogram of a set of residence times (s).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Distribution {
    /// How many.
    pub count: usize,
    /// Mean (s); `None` when empty.
    pub mean: Option<f64>,
    /// Smallest (s).
    pub min: Option<f64>,
    /// 10th, 50th (median) and 90th percentiles (s), nearest-rank.
    pub p10: Option<f64>,
    /// Median (s).
    pub p50: Option<f64>,
    /// 90th percentile (s).
    pub p90: Option<f64>,
    /// Largest (s).
    pub max: Option<f64>,
    /// Histogram: `counts[k]` values in `[edges[k], edges[k+1])` (the last bin includes its upper
    /// edge); [`HISTOGRAM_BINS`] equal bins from `min` to `max`.
    pub histogram: Histogram,
}

/// Equal-width bins.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Histogram {
    /// Bin edges (s), one more than the counts.
    pub edges: Vec<f64>,
    /// Values per bin.
    pub counts: Vec<u64>,
}

/// Bins of the residence-time histograms.
pub const HISTOGRAM_BINS: usize = 20;

impl Distribution {
    /// The distribution of `values` (finite).
    pub fn of(values: &[f64]) -> Self {
        let mut v: Vec<f64> = values.to_vec();
        v.sort_by(f64::total_cmp);
        let n = v.len();
        // Nearest rank: the smallest value with at least q·n values at or below it.
        let pct = |q: f64| (n > 0).then(|| v[((q * n as f64).ceil() as usize).clamp(1, n) - 1]);
        let (lo, hi) = (v.first().copied(), v.last().copied());
        let histogram = match (lo, hi) {
            (Some(lo), Some(hi)) => {
                let width = (hi - lo) / HISTOGRAM_BINS as f64;
                let edges: Vec<f64> = (0..=HISTOGRAM_BINS).map(|k| lo + k as f64 * width).collect();
                let mut counts = vec![0; HISTOGRAM_BINS];
                for &x in &v {
                    let k = if width > 0.0 { ((x - lo) / width) as usize } else { 0 };
                    counts[k.min(HISTOGRAM_BINS - 1)] += 1;
                }
                Histogram { edges, counts }
            }
            _ => Histogram { edges: Vec::new(), counts: Vec::new() },
        };
        Distribution {
            count: n,
            mean: (n > 0).then(|| v.iter().sum::<f64>() / n as f64),
            min: lo,
            p10: pct(0.1),
            p50: pct(0.5),
            p90: pct(0.9),
            max: hi,
            histogram,
        }
    }
}

impl Statistics {
    /// All contacts.
    pub fn contacts(&self) -> u64 {
        self.all.impacts()
    }

    /// Adds one event to the total and, for a wall contact, to its wall.
    pub fn add(&mut self, e: &ContactEvent) {
        self.all.add(e);
        if let Other::Wall(w) = e.other {
            let w = w as usize;
            if self.per_wall.len() <= w {
                self.per_wall.resize(w + 1, ImpactTally::default());
            }
            self.per_wall[w].add(e);
        }
    }

    /// The contacts with wall `w` (all zero if it was never hit).
    pub fn wall(&self, w: usize) -> ImpactTally {
        self.per_wall.get(w).cloned().unwrap_or_default()
    }
}

impl Sink for Statistics {
    fn events(&mut self, _sim: &Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        events.iter().for_each(|e| self.add(e));
        Ok(())
    }

    fn mark(&mut self) -> Result<Option<super::SinkMark>, OutputError> {
        Ok(Some(super::SinkMark::Statistics(self.clone())))
    }
}

impl fmt::Display for Statistics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "contacts: {} (held {}, bounced {}, deposited {})",
            self.contacts(),
            self.all.held,
            self.all.bounced,
            self.all.deposited
        )?;
        if self.contacts() > 0 {
            write!(f, "; mean St {:.3}", self.all.mean_st())?;
        }
        if self.all.held + self.all.bounced > 0 {
            write!(f, ", mean ε of rebounds {:.3}", self.all.mean_eps())?;
        }
        Ok(())
    }
}
