//! The simulation and its step.
//!
//! [`Simulation::step`] runs these stages, in this order, each in its own file:
//!
//! 1. **release** ([`release`]): held particles whose contact time ends inside the step are
//!    released at `ε V∞`; resting particles whose net force points away from their wall leave it;
//! 2. **free flight** ([`free_flight`]): every free particle is integrated over its part of the
//!    step with the scene's effects only, resting particles slide along their wall (parallel);
//! 3. **broad phase** ([`broad_phase`]): the particles whose swept path may touch a wall;
//! 4. **narrow phase** and 5. **response** ([`wall_contacts`]), alternating per particle: the
//!    first contact on the path is located inside the step, the bounce rule applied, and the
//!    rest of the step integrated from the contact point, until the step is used up (parallel
//!    over particles, results written back in particle order);
//! 6. **commit** ([`commit`]): the new states replace the old; a particle whose state is no
//!    longer finite is taken out and reported; then **outlets** ([`outlets`]) take out the
//!    particles that left through them (recording their residence times) and **injectors**
//!    ([`inject`]) add the particles due in the step, clear of walls and other particles
//!    (serial and seeded, so independent of the thread count);
//! 7. **emit**: the step's contact events wait in [`Simulation::events`] for the output sinks
//!    (the [`run`] driver drains them and writes frames at the output times).

mod broad_phase;
mod commit;
mod contacts;
mod events;
mod free_flight;
pub mod inject;
mod motion;
pub mod neighbours;
pub mod outlets;
mod particle_pass;
mod persistent;
mod release;
pub mod run;

pub use events::{ContactEvent, LostParticle, Other, Outcome};
pub use motion::{Motion, WithMotion, dispatch};

use crate::contact::{BounceRule, ImpactLocation};
use crate::effects::Physics;
use crate::fluid::Fluid;
use crate::integrate::IntegratorKind;
use crate::lanes::{DVec3x4, F64x4, LANES, each};
use crate::particles::{NO_WALL, PairContact, ParticleKind, Particles, State};
use crate::walls::Wall;
use glam::DVec3;
use neighbours::Neighbours;
use std::time::{Duration, Instant};

/// Hash map of the per-step stages: foldhash with a fixed seed — fast on small integer keys,
/// and the same on every run (only lookups are used; no result depends on iteration order).
pub(crate) type FastMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;
/// Hash set of the per-step stages (see [`FastMap`]).
pub(crate) type FastSet<K> = std::collections::HashSet<K, foldhash::fast::FixedState>;

/// Wall time spent in each stage of [`Simulation::step`], summed over steps.
#[derive(Debug, Clone, Copy, Default)]
pub struct StageTimes {
    /// Stages 1, 2 and the walls' part of 3: one fused pass over the particles (release, free
    /// flight, wall candidates), plus the end of pair holds.
    pub particles: Duration,
    /// Stage 3 for pairs: the Verlet list and the candidate pairs.
    pub pairs: Duration,
    /// Stages 4 and 5: events in time order.
    pub contacts: Duration,
    /// Stage 5b: lasting contacts between particles.
    pub persistent: Duration,
    /// Stage 6.
    pub commit: Duration,
    /// Stage 6: outlets and injectors.
    pub inflow_outflow: Duration,
}

/// Per-step scratch columns, reused between steps.
#[derive(Debug, Clone, Default)]
struct Scratch {
    next_pos: Vec<DVec3>,
    next_vel: Vec<DVec3>,
    next_state: Vec<State>,
    candidates: Vec<u32>,
    pair_candidates: Vec<[u32; 2]>,
}

/// Everything a simulation is: the world state and the fixed parameters of the scene.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// Simulated time (s).
    pub time: f64,
    /// Time step `Δt` (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// The particles.
    pub particles: Particles,
    /// Particle kinds, indexed by [`Particles::kind`].
    pub kinds: Vec<ParticleKind>,
    /// Static walls.
    pub walls: Vec<Wall>,
    /// Carrier fluid.
    pub fluid: Fluid,
    /// What the scene's effects make of the physics.
    pub physics: Physics,
    /// Bounce parameters.
    pub rule: BounceRule,
    /// Time integrator.
    pub integrator: IntegratorKind,
    /// Where wall contacts are placed in time: inside the step (default) or at its end.
    pub impact_location: ImpactLocation,
    /// Contact events of the steps since the sinks last drained them.
    pub events: Vec<ContactEvent>,
    /// Particles taken out because their state became non-finite.
    pub lost: Vec<LostParticle>,
    /// Time spent per stage.
    pub stage_times: StageTimes,
    /// Lasting contacts between particles (holds, and pairs that met below `St_c`).
    pub pair_contacts: Vec<PairContact>,
    /// Verlet neighbour list for particle–particle contacts.
    pub neighbours: Neighbours,
    /// Whether particles collide with each other (off: they pass through each other).
    pub pair_collisions: bool,
    /// Verlet skin as a fraction of the largest diameter.
    pub skin_fraction: f64,
    /// Injectors (stage 6), with their counts.
    pub injectors: Vec<inject::Injector>,
    /// Outlets (stage 6), with the particles they removed.
    pub outlets: Vec<outlets::Outlet>,
    /// Id of the next injected particle: above every id in use, so ids are never reused.
    pub next_id: u32,
    scratch: Scratch,
}

/// The read-only context of the per-particle stages.
pub(crate) struct Ctx<'a, M> {
    pub motion: &'a M,
    pub walls: &'a [Wall],
    pub kinds: &'a [ParticleKind],
    pub fluid: &'a Fluid,
    pub rule: &'a BounceRule,
    pub impact_location: ImpactLocation,
    kind_accel: Vec<DVec3>,
    kind_drag_rate: Vec<f64>,
    inertia_density: Vec<f64>,
    re_rate: f64,
}

impl<'a, M: Motion> Ctx<'a, M> {
    /// The force field of a particle of kind `k` and diameter `d`.
    #[inline(always)]
    pub fn field(&self, k: usize, d: f64) -> M::Field<DVec3> {
        self.motion.field(self.kind_accel[k], self.kind_drag_rate[k] / (d * d), self.re_rate * d)
    }

    /// [`Ctx::field`] of a lane group: kinds `k`, diameters `d`.
    #[inline(always)]
    pub fn field_lanes(&self, k: [u16; LANES], d: F64x4) -> M::Field<DVec3x4> {
        let accel = DVec3x4::from_array(each(k, |k| self.kind_accel[k as usize]));
        let drag_rate = F64x4(each(k, |k| self.kind_drag_rate[k as usize]));
        self.motion.field(accel, drag_rate / (d * d), d * self.re_rate)
    }
}

/// A stretch of one particle's motion inside a step: from time `t`, state `(x, v)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    pub t: f64,
    pub x: DVec3,
    pub v: DVec3,
    pub state: State,
    pub wall: u32,
}

/// Where a segment ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Flight {
    pub x: DVec3,
    pub v: DVec3,
    pub state: State,
}

/// Gap (in particle radii) beyond which a sliding particle has lost its wall: it went over a
/// convex edge, or its neighbours lifted it. Below it the particle is put back on the wall. The
/// same hysteresis as for lasting pair contacts, so that a particle in a bed does not leave and
/// land again at every step.
const FALL_AWAY: f64 = 1e-3;

/// Integrates one segment over `h` (s): free flight, sliding on the wall, or nothing (held).
#[inline]
pub(crate) fn fly<M: Motion>(ctx: &Ctx<M>, field: &M::Field<DVec3>, r: f64, seg: &Segment, h: f64) -> Flight {
    match seg.state {
        // Held at a wall: immobilised.
        State::Held if seg.wall != NO_WALL => Flight { x: seg.x, v: seg.v, state: State::Held },
        // Free, or held by another particle (the pair is kept together afterwards).
        State::Free | State::Held => {
            let (x, v) = ctx.motion.advance(field, seg.x, seg.v, h);
            Flight { x, v, state: seg.state }
        }
        State::Resting => {
            use crate::walls::Surface;
            let wall = &ctx.walls[seg.wall as usize].shape;
            let n = wall.gap(seg.x, r).normal;
            let slide = crate::integrate::Tangential { inner: field, n };
            let (x, v) = ctx.motion.advance(&slide, seg.x, seg.v - seg.v.dot(n) * n, h);
            let g = wall.gap(x, r);
            if g.gap > FALL_AWAY * r {
                Flight { x, v, state: State::Free }
            } else {
                let n1 = g.normal;
                let (x, v) = (x - g.gap * n1, v - v.dot(n1) * n1);
                // A resting particle ignores contacts with its own wall, so sliding along one
                // face must not take it through another face of that wall (into a box's corner,
                // across a mesh's crease): it stops there.
                let (x, v, _) = crate::walls::push_out(wall, x, v, r);
                Flight { x, v, state: State::Resting }
            }
        }
    }
}

impl Simulation {
    /// A simulation at time 0 with these parts. `dt` is the time step (s).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        particles: Particles,
        kinds: Vec<ParticleKind>,
        walls: Vec<Wall>,
        fluid: Fluid,
        physics: Physics,
        rule: BounceRule,
        integrator: IntegratorKind,
        dt: f64,
    ) -> Self {
        let next_id = particles.id.iter().max().map_or(0, |&i| i + 1);
        Simulation {
            time: 0.0,
            dt,
            steps: 0,
            particles,
            kinds,
            walls,
            fluid,
            physics,
            rule,
            integrator,
            impact_location: ImpactLocation::InStep,
            events: Vec::new(),
            lost: Vec::new(),
            stage_times: StageTimes::default(),
            pair_contacts: Vec::new(),
            neighbours: Neighbours::default(),
            pair_collisions: true,
            skin_fraction: 0.5,
            injectors: Vec::new(),
            outlets: Vec::new(),
            next_id,
            scratch: Scratch::default(),
        }
    }

    /// Steps with `Δt` until `t_end`, shortening the last step to land on it exactly, so that
    /// outputs fall on their nominal times whatever `Δt`.
    ///
    /// The steps run inside rayon's pool, so the serial stages between the parallel ones run on
    /// a worker rather than on a further thread that competes with the pool for the cores.
    pub fn advance_to(&mut self, t_end: f64) {
        rayon::scope(|_| self.advance_to_in_pool(t_end));
    }

    /// Takes `n` steps of `h` (s), inside rayon's pool like [`Simulation::advance_to`]: what a
    /// benchmark should time (a step called from outside the pool pays for handing the work to
    /// the pool's threads and back).
    pub fn run_steps(&mut self, n: usize, h: f64) {
        rayon::scope(|_| {
            for _ in 0..n {
                self.step(h);
            }
        });
    }

    fn advance_to_in_pool(&mut self, t_end: f64) {
        while self.time < t_end {
            let remaining = t_end - self.time;
            // A sliver left by round-off (the sum of many steps misses t_end by ~n·ε·t) is no step.
            if remaining <= 1e-6 * self.dt {
                self.time = t_end;
                break;
            }
            let h = if remaining < 1.000_001 * self.dt { remaining } else { self.dt };
            self.step(h);
            if h == remaining {
                self.time = t_end;
            }
        }
    }

    /// Advances every particle by `h` (s): the stages listed in the module documentation.
    pub fn step(&mut self, h: f64) {
        let (integrator, drag, flow) = (self.integrator, self.physics.drag, self.fluid.flow);
        dispatch(integrator, drag, flow, StepWith { sim: self, h });
    }

    fn ctx<'a, M: Motion>(&'a self, motion: &'a M) -> Ctx<'a, M> {
        let n = self.kinds.len();
        let mu = self.fluid.viscosity;
        Ctx {
            motion,
            walls: &self.walls,
            kinds: &self.kinds,
            fluid: &self.fluid,
            rule: &self.rule,
            impact_location: self.impact_location,
            kind_accel: (0..n).map(|k| self.physics.body_acceleration(k)).collect(),
            kind_drag_rate: (0..n).map(|k| self.physics.drag_rate(k, &self.fluid)).collect(),
            inertia_density: self.physics.kinds.iter().map(|k| k.inertia_density).collect(),
            re_rate: if mu > 0.0 { self.fluid.density / mu } else { 0.0 },
        }
    }
}

struct StepWith<'a> {
    sim: &'a mut Simulation,
    h: f64,
}

impl WithMotion for StepWith<'_> {
    type Out = ();

    fn run<M: Motion>(self, motion: &M) {
        let StepWith { sim, h } = self;
        let (t0, t1) = (sim.time, sim.time + h);
        let mut scratch = std::mem::take(&mut sim.scratch);
        let mut particles = std::mem::take(&mut sim.particles);
        let mut contacts = std::mem::take(&mut sim.pair_contacts);
        let mut neighbours = std::mem::take(&mut sim.neighbours);
        let mut times = sim.stage_times;
        let mut events = std::mem::take(&mut sim.events);
        {
            let ctx = sim.ctx(motion);
            let clock = Instant::now();
            // 1. (pairs; the walls' part is fused below)
            persistent::release(&ctx, &mut particles, &mut contacts, t1);
            // 1. + 2. + 3. (walls), one pass over the particles.
            let pass = particle_pass::run(&ctx, &mut particles, t0, t1, &mut scratch);
            let c1 = Instant::now();
            // 3. (pairs)
            if sim.pair_collisions {
                broad_phase::pairs(
                    &particles,
                    &mut scratch,
                    &mut neighbours,
                    pass.step_move,
                    sim.skin_fraction,
                    &contacts,
                );
            }
            let pairs: &[[u32; 2]] = if sim.pair_collisions { &neighbours.pairs } else { &[] };
            let c3 = Instant::now();
            // 4. + 5.
            let first_event = events.len();
            let mut suspect = pass.suspect;
            suspect |= contacts::run(&ctx, &mut particles, t0, t1, &mut scratch, &mut events, &mut contacts);
            let c3b = Instant::now();
            suspect |= persistent::run(&ctx, &particles, &mut scratch, &mut contacts, pairs, h);
            let c4 = Instant::now();
            // 6.
            if commit::run(
                &mut particles,
                &mut scratch,
                (&pass.fell, suspect),
                t1,
                &mut sim.lost,
                &mut contacts,
            ) {
                neighbours.invalidate();
            }
            let c5 = Instant::now();
            // 6. (continued) Outlets, then injectors: a particle injected in this step is not
            // judged by an outlet before it has moved.
            let removed =
                outlets::run(&mut sim.outlets, &mut particles, &events[first_event..], t1, &mut contacts);
            let added = inject::run(&mut sim.injectors, &sim.walls, &mut particles, &mut sim.next_id, t1);
            if removed || added {
                neighbours.invalidate();
            }
            times.inflow_outflow += c5.elapsed();
            times.particles += c1 - clock;
            times.pairs += c3 - c1;
            times.contacts += c3b - c3;
            times.persistent += c4 - c3b;
            times.commit += c5 - c4;
        }
        // 7. Events stay in `sim.events` for the sinks.
        sim.particles = particles;
        sim.pair_contacts = contacts;
        sim.neighbours = neighbours;
        sim.scratch = scratch;
        sim.events = events;
        sim.stage_times = times;
        sim.time = t1;
        sim.steps += 1;
    }
}
