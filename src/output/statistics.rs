//! Run statistics for the end-of-run summary.

use super::{OutputError, Sink};
use crate::pipeline::{ContactEvent, Outcome, Simulation};
use std::fmt;

/// Counts and means over all contact events of a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Statistics {
    /// Contacts that held the particle.
    pub held: u64,
    /// Instantaneous rebounds.
    pub bounced: u64,
    /// Contacts without rebound.
    pub deposited: u64,
    /// Sum of the finite Stokes numbers, and how many there were.
    st_sum: f64,
    st_count: u64,
    /// Sum of ε over rebounds (held or bounced).
    eps_sum: f64,
}

impl Statistics {
    /// All contacts.
    pub fn contacts(&self) -> u64 {
        self.held + self.bounced + self.deposited
    }

    /// Mean Stokes number of the contacts with a finite one (NaN if none).
    pub fn mean_st(&self) -> f64 {
        self.st_sum / self.st_count as f64
    }

    /// Mean restitution of the rebounds (NaN if none).
    pub fn mean_eps(&self) -> f64 {
        self.eps_sum / (self.held + self.bounced) as f64
    }

    /// Adds one event.
    pub fn add(&mut self, e: &ContactEvent) {
        match e.outcome {
            Outcome::Held => self.held += 1,
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

impl Sink for Statistics {
    fn events(&mut self, _sim: &Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        events.iter().for_each(|e| self.add(e));
        Ok(())
    }
}

impl fmt::Display for Statistics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "contacts: {} (held {}, bounced {}, deposited {})",
            self.contacts(),
            self.held,
            self.bounced,
            self.deposited
        )?;
        if self.contacts() > 0 {
            write!(f, "; mean St {:.3}", self.mean_st())?;
        }
        if self.held + self.bounced > 0 {
            write!(f, ", mean ε of rebounds {:.3}", self.mean_eps())?;
        }
        Ok(())
    }
}
