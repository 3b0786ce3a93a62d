//! Particle kinds (materials) and the particle store, in columns.

use glam::DVec3;

/// What a particle is made of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// A solid sphere: elastic constants for the Hertz contact time (L06 eq. 3–4).
    Solid {
        /// Young's modulus `Ep` (Pa).
        youngs_modulus: f64,
        /// Poisson ratio `νp` (dimensionless).
        poisson_ratio: f64,
    },
    /// A liquid drop: interfacial tension for the mass–spring contact time (L06 eq. 5).
    Drop {
        /// Interfacial tension `σ` against the carrier fluid (N/m).
        surface_tension: f64,
    },
}

/// A named kind of particle: density, restitution in air and material.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleKind {
    /// Name used in scenes and outputs.
    pub name: String,
    /// Density `ρp` (kg/m³).
    pub density: f64,
    /// Restitution in air `ε_max` (dimensionless, 0..=1) against a wall that does not override it.
    pub restitution_max: f64,
    /// Solid or drop.
    pub material: Material,
}

/// Where a particle is in the bounce rule (PHYSICS.md §5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum State {
    /// Moving under the force balance.
    Free = 0,
    /// Immobilised at a wall for the contact time, then released at `ε V∞`.
    Held = 1,
    /// In lasting contact with a wall (St < St_c): slides, leaves when pulled away.
    Resting = 2,
}

impl State {
    /// The lower-case name written to outputs: `free`, `held`, `resting`.
    pub fn name(self) -> &'static str {
        match self {
            State::Free => "free",
            State::Held => "held",
            State::Resting => "resting",
        }
    }
}

/// No wall: the value of [`Particles::wall`] for a free particle.
pub const NO_WALL: u32 = u32::MAX;

/// All particles, one column per quantity, addressed by index (struct of arrays).
///
/// The index of a particle can change when particles are removed; `id` is its stable name.
#[derive(Debug, Clone, Default)]
pub struct Particles {
    /// Stable identifier, written to outputs.
    pub id: Vec<u32>,
    /// Index into the simulation's particle kinds.
    pub kind: Vec<u16>,
    /// Diameter `d` (m).
    pub diameter: Vec<f64>,
    /// Centre position (m).
    pub pos: Vec<DVec3>,
    /// Velocity (m/s).
    pub vel: Vec<DVec3>,
    /// Free, held or resting.
    pub state: Vec<State>,
    /// The wall a held or resting particle touches, [`NO_WALL`] otherwise.
    pub wall: Vec<u32>,
    /// Simulated time (s) at which a held particle is released, or was last released; a free
    /// particle's free flight in a step starts at `max(t, release_time)`.
    pub release_time: Vec<f64>,
    /// Velocity (m/s) a held particle gets at release: `ε V∞` along the normal plus `e_t` times
    /// the tangential velocity at impact.
    pub release_vel: Vec<DVec3>,
    /// Simulated time (s) at which the particle entered the simulation: 0 for the scene's
    /// initial particles, the injection time for injected ones. An outlet's residence time is
    /// the removal time minus this.
    pub born: Vec<f64>,
}

impl Particles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Appends a free particle and returns its index.
    pub fn push(&mut self, id: u32, kind: u16, diameter: f64, pos: DVec3, vel: DVec3) -> usize {
        self.id.push(id);
        self.kind.push(kind);
        self.diameter.push(diameter);
        self.pos.push(pos);
        self.vel.push(vel);
        self.state.push(State::Free);
        self.wall.push(NO_WALL);
        self.release_time.push(f64::NEG_INFINITY);
        self.release_vel.push(DVec3::ZERO);
        self.born.push(0.0);
        self.len() - 1
    }

    /// Keeps the particles with `keep[i]`, in their order.
    pub fn retain(&mut self, keep: &[bool]) {
        fn column<T>(c: &mut Vec<T>, keep: &[bool]) {
            let mut k = keep.iter();
            c.retain(|_| *k.next().expect("one flag per particle"));
        }
        column(&mut self.id, keep);
        column(&mut self.kind, keep);
        column(&mut self.diameter, keep);
        column(&mut self.pos, keep);
        column(&mut self.vel, keep);
        column(&mut self.state, keep);
        column(&mut self.wall, keep);
        column(&mut self.release_time, keep);
        column(&mut self.release_vel, keep);
        column(&mut self.born, keep);
    }
}

/// A lasting contact between particles `a < b` (indices): after an impact below `St_c`
/// (resting: they may not approach) or during a hold (they move together) **[ext]**.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairContact {
    /// Lower particle index.
    pub a: u32,
    /// Higher particle index.
    pub b: u32,
    /// `Some` during a hold.
    pub hold: Option<PairHold>,
    /// Normal force the contact carried in the last step (N, pushing the pair apart): the
    /// projection starts from it (warm start), so a bed carrying its own weight converges in a
    /// few sweeps instead of one sweep per layer.
    pub force: f64,
}

/// The release of a held pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairHold {
    /// When the hold ends (s).
    pub release_time: f64,
    /// Relative normal speed at release `ε Vn` (m/s), separating.
    pub normal_speed: f64,
    /// Relative tangential velocity `v_a − v_b` at release, `e_t` times that at impact (m/s).
    pub tangential: DVec3,
}

impl PairContact {
    /// A resting contact.
    pub fn resting(a: u32, b: u32) -> Self {
        PairContact { a, b, hold: None, force: 0.0 }
    }

    /// A hold until `release_time`.
    pub fn held(a: u32, b: u32, release_time: f64, normal_speed: f64, tangential: DVec3) -> Self {
        PairContact { a, b, hold: Some(PairHold { release_time, normal_speed, tangential }), force: 0.0 }
    }
}
