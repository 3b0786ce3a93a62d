//! Particle kinds (materials) and the particle store, in columns.

mod column;
pub mod feature;

pub use column::Column;
pub use feature::{Feature, Features, Touch};

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
    /// Surface roughness `h_r` (m) **[ext]**: with the `wall_lubrication` effect, contact with
    /// a wall is made at this gap plus the wall's roughness (docs/physics.md §8); 0 when not given.
    pub roughness: f64,
    /// Friction keys of the kind **[ext]** (docs/physics.md §9); all `None` when not given.
    pub friction: FrictionMaterial,
    /// Held at a wall (or in a pair) for its contact time when it rebounds: the contact-time
    /// effect names it, or names no kind (docs/physics.md §5.3). False without the effect.
    pub held_at_contact: bool,
}

/// The friction keys of one surface (a particle kind or a wall) **[ext]**, docs/physics.md §9: each
/// `None` when the scene does not give it. How two surfaces' values combine is
/// `contact::rules::friction::Friction::between`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrictionMaterial {
    /// Coulomb friction coefficient `μ` (dimensionless, ≥ 0).
    pub friction: Option<f64>,
    /// Tangential restitution `β0` of Walton's impulse model (dimensionless, −1 to 1): the
    /// contact point's tangential velocity after a sticking impact is `−β0` times that before.
    pub tangential_restitution: Option<f64>,
    /// Rolling friction coefficient `μ_r` (dimensionless, ≥ 0): a lasting contact resists
    /// rolling with a torque up to `μ_r R N`.
    pub rolling_friction: Option<f64>,
}

impl FrictionMaterial {
    /// True when the surface names any friction key.
    pub fn named(&self) -> bool {
        self.friction.is_some() || self.tangential_restitution.is_some() || self.rolling_friction.is_some()
    }
}

/// Where a particle is in the bounce rule (docs/physics.md §5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[repr(u8)]
pub enum State {
    /// Moving under the force balance.
    Free = 0,
    /// Immobilised at a wall ([`Particles::wall`]) for the contact time, then released at
    /// `ε V∞`.
    Held = 1,
    /// In lasting contact with a wall (St < St_c): slides, leaves when pulled away.
    Resting = 2,
    /// Held against another particle for the pair's contact time **[ext]**: it moves, with its
    /// partner at their common velocity, and has no wall.
    PairHeld = 3,
}

impl State {
    /// The lower-case name written to outputs: `free`, `held`, `resting`. Outputs do not tell
    /// a hold at a wall from a hold in a pair: both are `held`.
    pub fn name(self) -> &'static str {
        match self {
            State::Free => "free",
            State::Held | State::PairHeld => "held",
            State::Resting => "resting",
        }
    }

    /// The number written to outputs (the MCAP's `state` field): 0 free, 1 held (at a wall or
    /// in a pair), 2 resting.
    pub fn code(self) -> u8 {
        match self {
            State::PairHeld => State::Held as u8,
            s => s as u8,
        }
    }

    /// Held, at a wall or in a pair.
    pub fn is_held(self) -> bool {
        matches!(self, State::Held | State::PairHeld)
    }
}

/// No wall: the value of [`Particles::wall`] for a free particle.
pub const NO_WALL: u32 = u32::MAX;

/// All particles, one column per quantity, addressed by index (struct of arrays).
///
/// The index of a particle can change when particles are removed; `id` is its stable name.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
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
    /// Angular velocity `ω` (rad/s) **[ext]**: a column only in a scene with rotation
    /// (docs/physics.md §9), off otherwise (read it with [`Particles::spin`], zero then).
    pub omega: Column<DVec3>,
    /// Free, held or resting.
    pub state: Vec<State>,
    /// The wall a held ([`State::Held`]) or resting particle touches, [`NO_WALL`] otherwise.
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
    /// With the history effect **[ext]** only (off otherwise): each particle's memory of its
    /// past accelerations, the modes `F_k = ∫ e^{−λ_k (t − s)} dw/ds ds` of the slip `w` (m/s
    /// each; docs/physics.md §10), [`Column::width`] = 3 × modes numbers per particle by
    /// component: the `x` of every mode, then every `y`, then every `z`, so that the flight's
    /// loops over the modes run over contiguous numbers (`flight::remembered`).
    pub memory: Column<f64>,
    /// With a flow field on an unstructured grid only (off otherwise): the grid's tetrahedron
    /// that held each particle at the end of the last step, where the next step's flow lookups
    /// walk from ([`crate::fluid::field::unstructured`]); [`NO_TET`] when outside or not known
    /// yet.
    pub tet: Column<u32>,
    /// The columns a feature made for itself ([`Particles::add_column`]), with its name: pushed,
    /// retained and committed with the others (docs/architecture.md, "Features that own their
    /// state").
    pub columns: Vec<(String, Column<f64>)>,
}

/// No tetrahedron ([`Particles::tet`]): outside the grid, or not looked up yet.
pub const NO_TET: u32 = u32::MAX;

impl Particles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Particle `i`'s angular velocity (rad/s): zero in a scene without rotation.
    pub fn spin(&self, i: usize) -> DVec3 {
        self.omega.values().get(i).copied().unwrap_or(DVec3::ZERO)
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
        // The features' columns (a new particle remembers nothing, as if it had moved at its
        // velocity forever; its tetrahedron is not known yet).
        self.omega.push();
        self.memory.push();
        self.tet.push();
        for (_, c) in &mut self.columns {
            c.push();
        }
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
        self.omega.retain(keep);
        self.memory.retain(keep);
        self.tet.retain(keep);
        for (_, c) in &mut self.columns {
            c.retain(keep);
        }
    }

    /// The particles `rows` (indices, in the order given), every column with them: what a rank
    /// sends of its particles, and how one process's order is rebuilt from the ranks' parts
    /// (`crate::ranks`).
    pub fn select(&self, rows: &[usize]) -> Particles {
        fn column<T: Copy>(c: &[T], rows: &[usize]) -> Vec<T> {
            rows.iter().map(|&i| c[i]).collect()
        }
        Particles {
            id: column(&self.id, rows),
            kind: column(&self.kind, rows),
            diameter: column(&self.diameter, rows),
            pos: column(&self.pos, rows),
            vel: column(&self.vel, rows),
            omega: self.omega.select(rows),
            state: column(&self.state, rows),
            wall: column(&self.wall, rows),
            release_time: column(&self.release_time, rows),
            release_vel: column(&self.release_vel, rows),
            born: column(&self.born, rows),
            memory: self.memory.select(rows),
            tet: self.tet.select(rows),
            columns: self.columns.iter().map(|(n, c)| (n.clone(), c.select(rows))).collect(),
        }
    }

    /// Appends `other`'s particles after these: a store of the same scene (the same features'
    /// columns, in the same order).
    pub fn append(&mut self, other: &Particles) {
        self.id.extend_from_slice(&other.id);
        self.kind.extend_from_slice(&other.kind);
        self.diameter.extend_from_slice(&other.diameter);
        self.pos.extend_from_slice(&other.pos);
        self.vel.extend_from_slice(&other.vel);
        self.omega.append(&other.omega);
        self.state.extend_from_slice(&other.state);
        self.wall.extend_from_slice(&other.wall);
        self.release_time.extend_from_slice(&other.release_time);
        self.release_vel.extend_from_slice(&other.release_vel);
        self.born.extend_from_slice(&other.born);
        self.memory.append(&other.memory);
        self.tet.append(&other.tet);
        for ((_, c), (_, o)) in self.columns.iter_mut().zip(&other.columns) {
            c.append(o);
        }
    }

    /// A feature's own column `name`, `width` values per particle, a new particle's `fresh`:
    /// made for the particles there are (all `fresh`) unless it exists. Returns its slot, the
    /// index of [`Particles::columns`] and [`Next::columns`] it has.
    pub fn add_column(
        &mut self,
        name: &str,
        width: usize,
        fresh: f64,
    ) -> Result<usize, std::collections::TryReserveError> {
        if let Some(slot) = self.column_slot(name) {
            return Ok(slot);
        }
        self.columns.push((name.to_string(), Column::try_new(width, fresh, self.len())?));
        Ok(self.columns.len() - 1)
    }

    /// The slot of the feature column `name`, if it was made.
    pub fn column_slot(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|(n, _)| *n == name)
    }

    /// The feature column `name`, if it was made.
    pub fn column(&self, name: &str) -> Option<&Column<f64>> {
        self.columns.iter().find(|(n, _)| *n == name).map(|(_, c)| c)
    }
}

/// The particles' state at the end of the step being computed. The rule of the step: stage 1
/// (release) rewrites the start of the paths whose contacts end, in [`Particles`]; every later
/// stage reads [`Particles`] (the state at the start of the step) and writes here; commit
/// swaps this in ([`Particles::commit`]).
#[derive(Debug, Clone, Default)]
pub struct Next {
    /// Centre position (m).
    pub pos: Vec<DVec3>,
    /// Velocity (m/s).
    pub vel: Vec<DVec3>,
    /// Angular velocity (rad/s): sized only in a scene with rotation, empty otherwise.
    pub omega: Vec<DVec3>,
    /// Free, held, pair-held or resting.
    pub state: Vec<State>,
    /// The wall of a held or resting particle, [`NO_WALL`] otherwise.
    pub wall: Vec<u32>,
    /// Holds at a wall that began in the step (few: kept as a list, not as full columns).
    pub holds: Vec<WallHold>,
    /// With the history effect: each particle's memory at the end of the step (written by
    /// the particle pass and, for the particles whose path a contact restarted, by stage 4).
    pub memory: Vec<f64>,
    /// The end-of-step values of the features' own columns, like [`Particles::columns`]
    /// (stage 5½ fills them).
    pub columns: Vec<Vec<f64>>,
}

/// A hold at a wall that began in the step: when particle `index` is released, and at what
/// velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallHold {
    /// Particle index.
    pub index: u32,
    /// Release time (s).
    pub release_time: f64,
    /// Velocity at release (m/s).
    pub release_vel: DVec3,
}

impl Next {
    /// Sizes the columns for `n` particles (their values are all written by the step) and
    /// forgets the last step's holds. The spin column is sized only with `rotation`: a scene
    /// without it never touches it.
    pub fn resize(&mut self, n: usize, rotation: bool) {
        self.pos.resize(n, DVec3::ZERO);
        self.vel.resize(n, DVec3::ZERO);
        self.omega.resize(if rotation { n } else { 0 }, DVec3::ZERO);
        self.state.resize(n, State::Free);
        self.wall.resize(n, NO_WALL);
        self.holds.clear();
    }

    /// The end-of-step values of the feature column in `slot` ([`Particles::add_column`]), to
    /// write: `width` per particle, as the column.
    pub fn column_mut(&mut self, slot: usize) -> &mut [f64] {
        &mut self.columns[slot]
    }
}

impl Particles {
    /// The step's results replace the state: the columns of `next` are swapped in (its own
    /// become scratch for the next step), every feature's too, and the holds begun in the step
    /// are recorded. What a feature does to its values after that is its
    /// [`Feature::commit`].
    pub fn commit(&mut self, next: &mut Next) {
        std::mem::swap(&mut self.pos, &mut next.pos);
        std::mem::swap(&mut self.vel, &mut next.vel);
        // Only a scene with rotation sized (and wrote) the step's spins.
        if self.omega.is_on() {
            self.omega.swap_values(&mut next.omega);
        }
        std::mem::swap(&mut self.state, &mut next.state);
        std::mem::swap(&mut self.wall, &mut next.wall);
        if self.memory.is_on() {
            self.memory.swap_values(&mut next.memory);
        }
        for ((_, c), values) in self.columns.iter_mut().zip(&mut next.columns) {
            c.swap_values(values);
        }
        for h in next.holds.drain(..) {
            self.release_time[h.index as usize] = h.release_time;
            self.release_vel[h.index as usize] = h.release_vel;
        }
    }
}
