//! Contact events: one per contact, for the sinks.

/// What the bounce rule did at a contact (PHYSICS.md §5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// Held at the wall for `t_c`, then released at `ε V∞`.
    Held,
    /// Instantaneous rebound `v_n → −ε v_n`.
    Bounced,
    /// No rebound (`St < St_c`): the particle stays in contact.
    Deposited,
}

impl Outcome {
    /// Lower-case name written to outputs.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Held => "held",
            Outcome::Bounced => "bounced",
            Outcome::Deposited => "deposited",
        }
    }
}

/// What a particle touched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Other {
    /// A wall, by index into the simulation's walls.
    Wall(u32),
    /// Another particle, by id.
    Particle(u32),
}

/// One contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactEvent {
    /// Simulated time of the impact (s), located inside the step.
    pub time: f64,
    /// Id of the particle.
    pub id: u32,
    /// The wall or particle touched.
    pub other: Other,
    /// Normal approach speed `V∞` at contact (m/s).
    pub normal_speed: f64,
    /// Stokes number of the impact.
    pub st: f64,
    /// Restitution applied (0 for a deposit).
    pub eps: f64,
    /// Contact time `t_c` (s) of L06 eq. 4 or 5; 0 for a deposit.
    pub contact_time: f64,
    /// Held, bounced or deposited.
    pub outcome: Outcome,
}

/// A particle whose state became non-finite and was taken out of the simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LostParticle {
    /// Simulated time at the end of the step where it was found (s).
    pub time: f64,
    /// Its id.
    pub id: u32,
}
