//! Contact events: one per contact, for the sinks.

/// What the bounce rule did at a contact (docs/physics.md §5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Other {
    /// A wall, by index into the simulation's walls.
    Wall(u32),
    /// Another particle, by id.
    Particle(u32),
}

/// One contact.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactEvent {
    /// Simulated time of the impact (s), located inside the step.
    pub time: f64,
    /// Id of the particle.
    pub id: u32,
    /// The wall or particle touched.
    pub other: Other,
    /// Normal approach speed `V∞` at contact (m/s).
    pub normal_speed: f64,
    /// Tangential speed of the contact point, relative to the wall or the other particle, just
    /// before the contact (m/s): `|v_ct|` of docs/physics.md §9, with the spin's part
    /// (`Ψ1 = tangential_speed / normal_speed`). **[ext]**
    pub tangential_speed: f64,
    /// Incidence angle (rad): of the centre's velocity relative to the wall or the other
    /// particle, from the normal (0 head-on, π/2 grazing). **[ext]**
    pub incidence_angle: f64,
    /// Stokes number of the impact.
    pub st: f64,
    /// Restitution applied (0 for a deposit).
    pub eps: f64,
    /// Contact time `t_c` (s) of L06 eq. 4 or 5; 0 for a deposit.
    pub contact_time: f64,
    /// Held, bounced or deposited.
    pub outcome: Outcome,
    /// Kinetic energy (J) just before the contact, of the particle (of both, for a pair), with
    /// the inertia of the force balance `(ρp + C_M ρ) π d³/6`, plus with rotation `½ I |ω|²`;
    /// a particle held at a wall counts 0. Kept for checks (the bounce rule never adds energy); not written to the outputs.
    pub energy_before: f64,
    /// Kinetic energy (J) right after the contact: at once for a rebound or a deposit, at
    /// release for a hold (the release velocities, before the forces act during the hold).
    pub energy_after: f64,
}

impl ContactEvent {
    /// True when the contact gave no kinetic energy, to round-off (a relative 1e-12).
    pub fn energy_not_gained(&self) -> bool {
        self.energy_after <= self.energy_before * (1.0 + 1e-12) + f64::MIN_POSITIVE
    }

    /// [`Self::energy_not_gained`], or a state already non-finite (which the commit stage takes
    /// out and reports).
    pub fn energy_not_gained_if_finite(&self) -> bool {
        !(self.energy_before.is_finite() && self.energy_after.is_finite()) || self.energy_not_gained()
    }
}

/// Kinetic energy `½ m |v|²` (J) of inertia `m` (kg) at `v` (m/s); 0 for an immobile body
/// (`m = ∞`, at rest).
pub(crate) fn kinetic_energy(m: f64, v: glam::DVec3) -> f64 {
    if m.is_finite() { 0.5 * m * v.length_squared() } else { 0.0 }
}
