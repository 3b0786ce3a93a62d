//! The simulation and its step.
//!
//! A [`Simulation`] is three things kept apart: the [`World`] a step changes (time, particles,
//! lasting contacts, neighbour list, injectors' draws), the [`Setup`] a scene fixes (walls,
//! kinds, fluid, effects, rules, time step, injectors and outlets) and the [`Record`] a run
//! collects (contact events, lost particles, outlet removals, stage times).
//!
//! [`Simulation::step`] runs these stages, in this order ([`StepWith::run`] reads as this
//! list):
//!
//! 1. **release** — contacts that end: pair holds ([`contact::release_pairs`]); holds at walls
//!    and resting particles pulled off their wall ([`contact::release_at_wall`], in the pass
//!    below). The only stage that writes the state at the start of the step: it rewrites where
//!    those particles' paths begin;
//! 2. **free flight** — every particle over its part of the step with the scene's effects only
//!    ([`crate::flight::Kernel::free_flight`]); resting particles slide along their wall;
//! 3. **broad phase** — the particles whose straight move may touch a wall
//!    ([`contact::touches_wall`]) and the neighbour pairs that may touch
//!    ([`contact::candidate_pairs`]); 1, 2 and the walls' part of 3 run as one parallel pass
//!    over the particles ([`particle_pass`]), so each particle's data is read once;
//! 4. **contacts in the step** — narrow phase and response alternate: the first contact on the
//!    paths is located inside the step, the bounce rule applied, the rest of the step
//!    integrated from the contact point ([`contact::resolve_in_step`], islands in parallel);
//! 5. **lasting contacts** — pairs held together or resting on each other
//!    ([`contact::keep_lasting`]);
//!
//!    5½. **features** — each stateful feature's end of step and its part of the step's
//!    contacts ([`crate::particles::feature`]; a field's cell hints find each particle's
//!    tetrahedron here);
//! 6. **commit** — the new state replaces the old; a particle whose state is no longer finite
//!    is taken out and recorded ([`commit`]);
//! 7. **outflow and inflow** — outlets take out the particles that left through them
//!    ([`outlets`]), injectors add the particles due ([`inject`], serial and seeded);
//! 8. **emit** — the step's contact events wait in [`Record::events`] for the output sinks
//!    (the driver, [`crate::run`], hands them on).
//!
//! Stages 2–5 read the particles as they were at the start of the step and write their state
//! at its end into [`Next`]; stage 6 swaps it in. Each stage's doc says what it writes.

mod commit;
pub mod inject;
pub mod outlets;
mod particle_pass;

pub use commit::LostParticle;

use crate::agree::{Agree, Alone};
use crate::contact::{
    self, BounceRule, ContactEvent, ImpactLocation, LastingContact, Neighbours, Other, WallContact,
};
use crate::effects::Physics;
use crate::flight::{Kernel, Motion, StepFlow, WithMotion, dispatch};
use crate::fluid::Fluid;
use crate::fluid::field::{Outside, OutsideField};
use crate::integrate::IntegratorKind;
use crate::particles::{Features, NO_TET, Next, ParticleKind, Particles, Touch, feature};
use crate::walls::Wall;
use inject::{Injector, InjectorState};
use outlets::{Outlet, Removal};
use std::time::{Duration, Instant};

/// What a scene fixes: nothing here changes while the simulation runs.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Time step `Δt` (s).
    pub dt: f64,
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
    /// Whether particles collide with each other (off: they pass through each other).
    pub pair_collisions: bool,
    /// Verlet skin as a fraction of the largest diameter of each size level (diameters within a
    /// factor 2; `contact::Neighbours`).
    pub skin_fraction: f64,
    /// Injectors (stage 7).
    pub injectors: Vec<Injector>,
    /// Outlets (stage 7).
    pub outlets: Vec<Outlet>,
}

impl Setup {
    /// A setup with these parts, particles colliding with each other, impacts located inside
    /// the step, no injector and no outlet.
    pub fn new(
        kinds: Vec<ParticleKind>,
        walls: Vec<Wall>,
        (fluid, physics): (Fluid, Physics),
        rule: BounceRule,
        (integrator, dt): (IntegratorKind, f64),
    ) -> Self {
        Setup {
            dt,
            kinds,
            walls,
            fluid,
            physics,
            rule,
            integrator,
            impact_location: ImpactLocation::InStep,
            pair_collisions: true,
            skin_fraction: 0.5,
            injectors: Vec::new(),
            outlets: Vec::new(),
        }
    }
}

impl Setup {
    /// How the outputs name what a particle touched: the wall's name or the other particle's
    /// id, and the kind, `"wall"` or `"particle"`.
    pub fn name_of(&self, other: Other) -> (String, &'static str) {
        match other {
            Other::Wall(w) => (self.walls[w as usize].name.clone(), "wall"),
            Other::Particle(id) => (id.to_string(), "particle"),
        }
    }
}

/// What a step changes.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct World {
    /// Simulated time (s).
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// The particles.
    pub particles: Particles,
    /// Lasting contacts between particles (holds, and pairs that met below `St_c`).
    pub lasting: Vec<LastingContact>,
    /// With friction: the forces the walls carried on the particles in the last step (the
    /// warm start of the lasting-contact solver's wall rows), sorted by particle id.
    pub wall_contacts: Vec<WallContact>,
    /// Verlet neighbour list for particle–particle contacts.
    pub neighbours: Neighbours,
    /// Each injector's counts and random draws, like [`Setup::injectors`].
    pub injection: Vec<InjectorState>,
    /// Id of the next injected particle: above every id in use, so ids are never reused.
    pub next_id: u32,
}

/// What a run collects.
#[derive(Debug, Clone, Default)]
pub struct Record {
    /// Contact events of the steps since the sinks last drained them.
    pub events: Vec<ContactEvent>,
    /// For each of `events`, the id of the lowest particle of the island it came from: the
    /// order in which a run split over ranks merges its ranks' events into one process's
    /// (islands in the order of their lowest particle, `crate::ranks`).
    pub event_islands: Vec<u32>,
    /// Particles taken out because their state became non-finite.
    pub lost: Vec<LostParticle>,
    /// What each outlet removed, in removal order, like [`Setup::outlets`].
    pub removed: Vec<Vec<Removal>>,
    /// The first particle found outside a flow field whose policy is `outside = "error"`
    /// (checked at the end of every step, in index order); the driver stops the run on it.
    pub left_field: Option<OutsideField>,
    /// Time spent per stage.
    pub stage_times: StageTimes,
}

/// Wall time spent in each stage of [`Simulation::step`], summed over steps (numbered as in
/// the module documentation).
#[derive(Debug, Clone, Copy, Default)]
pub struct StageTimes {
    /// 1–3 (walls): the pass over the particles, and the end of pair holds.
    pub particle_pass: Duration,
    /// 3 (pairs): the Verlet list and the candidate pairs.
    pub broad_phase: Duration,
    /// 4: contacts in the step.
    pub in_step: Duration,
    /// 5: lasting contacts between particles.
    pub lasting: Duration,
    /// 6: commit.
    pub commit: Duration,
    /// 7: outlets and injectors.
    pub inflow_outflow: Duration,
}

/// A stopwatch read at the end of each stage: the time since the last reading goes to that
/// stage's timer.
struct Laps(Instant);

impl Laps {
    fn lap(&mut self, timer: &mut Duration) {
        let now = Instant::now();
        *timer += now - self.0;
        self.0 = now;
    }
}

/// Per-step scratch, reused between steps: the state at the end of the step, and the broad
/// phase's candidates.
#[derive(Debug, Clone, Default)]
struct Scratch {
    next: Next,
    wall_candidates: Vec<u32>,
    pair_candidates: Vec<[u32; 2]>,
}

/// A simulation: the world, the setup it runs under, and what it has recorded.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// What a step changes.
    pub world: World,
    /// What the scene fixes.
    pub setup: Setup,
    /// What the run collects.
    pub record: Record,
    scratch: Scratch,
}

impl Simulation {
    /// A simulation at time 0 of `particles` under `setup`.
    pub fn new(setup: Setup, particles: Particles) -> Self {
        Simulation::try_new(setup, particles).unwrap_or_else(|e| panic!("{e}"))
    }

    /// [`Simulation::new`], with the stateful features' columns (the history memory, its
    /// end-of-step copy: the large ones) reserved first, so that a machine that cannot give
    /// them is an error rather than an abort.
    pub fn try_new(
        setup: Setup,
        mut particles: Particles,
    ) -> Result<Self, std::collections::TryReserveError> {
        // Each feature turns its columns on, when a run starts: a scene that is only checked
        // never holds them.
        feature::start_all(&setup.physics.features, &mut particles)?;
        let mut end_of_step = Vec::new();
        end_of_step.try_reserve_exact(particles.memory.values().len())?;
        let next_id = particles.id.iter().max().map_or(0, |&i| i + 1);
        let world = World {
            particles,
            injection: setup.injectors.iter().map(Injector::start).collect(),
            next_id,
            ..World::default()
        };
        let record = Record { removed: vec![Vec::new(); setup.outlets.len()], ..Record::default() };
        let mut scratch = Scratch::default();
        scratch.next.memory = end_of_step;
        Ok(Simulation { world, setup, record, scratch })
    }

    /// A simulation that goes on from a checkpoint: its `world` and what its run had recorded
    /// (`lost`, `removed`, `left_field`), under `setup` — rebuilt from the same scene. The
    /// features' columns come with the world; the step's end-of-step copies are reserved first,
    /// as in [`Simulation::try_new`].
    pub fn restore(
        setup: Setup,
        mut world: World,
        (lost, removed, left_field): (Vec<LostParticle>, Vec<Vec<Removal>>, Option<OutsideField>),
    ) -> Result<Self, std::collections::TryReserveError> {
        feature::start_all(&setup.physics.features, &mut world.particles)?;
        let mut end_of_step = Vec::new();
        end_of_step.try_reserve_exact(world.particles.memory.values().len())?;
        let record = Record { lost, removed, left_field, ..Record::default() };
        let mut scratch = Scratch::default();
        scratch.next.memory = end_of_step;
        Ok(Simulation { world, setup, record, scratch })
    }

    /// Steps with `Δt` until `t_end`, shortening the last step to land on it exactly, so that
    /// outputs fall on their nominal times whatever `Δt`.
    ///
    /// The steps run inside rayon's pool, so the serial stages between the parallel ones run on
    /// a worker rather than on a further thread that competes with the pool for the cores.
    pub fn advance_to(&mut self, t_end: f64) {
        rayon::scope(|_| self.advance_agreeing(t_end, &Alone));
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

    /// [`Simulation::advance_to`] on the calling thread, each step asking `agree` what spans
    /// the ranks of a run split over MPI (`crate::ranks`; one process passes [`Alone`]).
    pub fn advance_agreeing(&mut self, t_end: f64, agree: &dyn Agree) {
        let dt = self.setup.dt;
        // A sliver left by round-off (the sum of n steps misses t_end by ~n·ε·t) is no step. It
        // is judged against the time's own round-off, not against Δt: a span far shorter than
        // Δt (an output interval below Δt) is a whole step, never a sliver.
        let sliver = (1e-6 * dt).min(1024.0 * f64::EPSILON * t_end.abs());
        while self.world.time < t_end {
            let remaining = t_end - self.world.time;
            if remaining <= sliver {
                self.world.time = t_end;
                break;
            }
            let h = if remaining < 1.000_001 * dt { remaining } else { dt };
            self.step_agreeing(h, agree);
            if h == remaining {
                self.world.time = t_end;
            }
        }
    }

    /// Advances every particle by `h` (s): the stages listed in the module documentation.
    pub fn step(&mut self, h: f64) {
        self.step_agreeing(h, &Alone);
    }

    /// [`Simulation::step`], asking `agree` what spans the ranks of a run split over MPI.
    pub fn step_agreeing(&mut self, h: f64, agree: &dyn Agree) {
        let Simulation { world, setup, record, scratch } = self;
        let setup = &*setup;
        let (integrator, drag, flow) = (setup.integrator, setup.physics.drag, &setup.fluid.flow);
        let mid_step = world.time + 0.5 * h;
        let accelerating = setup.physics.fluid_acceleration;
        let flow = StepFlow { flow, time: mid_step, accelerating };
        dispatch(integrator, drag, flow, StepWith { world, setup, record, scratch, h, agree });
    }
}

/// One step of `h`, for whichever [`Motion`] the scene's integrator, drag law and flow make.
struct StepWith<'a> {
    world: &'a mut World,
    setup: &'a Setup,
    record: &'a mut Record,
    scratch: &'a mut Scratch,
    h: f64,
    agree: &'a dyn Agree,
}

impl WithMotion for StepWith<'_> {
    type Out = ();

    /// The stages of the module documentation, in order.
    fn run<M: Motion>(self, motion: &M) {
        let StepWith { world, setup, record, scratch, h, agree } = self;
        let span = (world.time, world.time + h);
        let mut laps = Laps(Instant::now());
        // The events of this step are those from here on (stage 4 records the first).
        let first_event = record.events.len();
        // A caller that drained `events` (the sinks) left their islands: dropped with them.
        record.event_islands.truncate(first_event);
        // 1.–5. The flight kernel reads two columns for the whole step while stage 1 rewrites
        // where paths start in the store: the history memory and, in a field on an
        // unstructured grid, the tetrahedra at the start of the step (empty without them). It
        // holds a share of them (`Column::share`), gone at the end of the block, so that 5½
        // and commit write them without a copy.
        let suspect = {
            let lent = (world.particles.memory.share(), world.particles.tet.share());
            let parts = (&mut *world, setup, &mut *record, &mut *scratch);
            move_and_collide(motion, parts, (&lent.0, &lent.1), (span, agree), &mut laps)
        };
        // 5½. The stateful features' end of step (a field's cell hints: the tetrahedron that
        // holds each particle's end of the step), then their part of each contact.
        let touches = touches(&world.particles, &record.events[first_event..], &setup.physics.features);
        feature::end_of_step(&setup.physics.features, &mut world.particles, &mut scratch.next, h, &touches);
        // 6. Commit.
        let mut renumbered = commit::run(
            (&mut world.particles, &setup.physics.features),
            &mut scratch.next,
            suspect,
            span.1,
            &mut record.lost,
            &mut world.lasting,
        );
        laps.lap(&mut record.stage_times.commit);
        // 7. Outflow, then inflow.
        renumbered |= outflow_and_inflow(world, setup, record, first_event, span.1);
        if renumbered {
            world.neighbours.invalidate();
        }
        check_inside_field(world, setup, record, span.1);
        laps.lap(&mut record.stage_times.inflow_outflow);
        // 8. Emit: the step's events wait in `record.events` for the sinks.
        world.time = span.1;
        world.steps += 1;
    }
}

/// Stages 1–5 over `(t0, t1)`: release, free flight and broad phase (one pass over the
/// particles), contacts in the step, lasting contacts; the state at the end of the step in
/// `scratch.next`. The flight kernel reads `start_memory` and `tets`, shares of the store's
/// columns (see [`StepWith::run`]). Returns true when a particle's new state may not be finite.
fn move_and_collide<M: Motion>(
    motion: &M,
    (world, setup, record, scratch): (&mut World, &Setup, &mut Record, &mut Scratch),
    (start_memory, tets): (&[f64], &[u32]),
    ((t0, t1), agree): ((f64, f64), &dyn Agree),
    laps: &mut Laps,
) -> bool {
    let h = t1 - t0;
    let flight = Kernel::new(motion, &setup.physics, &setup.fluid, &setup.kinds, &setup.walls, t0 + 0.5 * h)
        .remembering(&setup.physics, &setup.fluid, start_memory, setup.physics.history.as_ref(), h)
        .walking_from(tets);
    let ctx = contact::Ctx::new(
        &flight,
        &setup.physics,
        &setup.kinds,
        &setup.fluid,
        &setup.rule,
        setup.impact_location,
    );
    let times = &mut record.stage_times;
    let p = &mut world.particles;
    // 1. Release (pairs; at walls inside the pass).
    contact::release_pairs(&ctx, p, &mut world.lasting, t1);
    // 1.–3. (walls): one pass over the particles.
    let pass = particle_pass::run(&flight, p, (t0, t1), &mut scratch.next, &mut scratch.wall_candidates);
    if flight.rotation() {
        particle_pass::spin(&flight, p, h, &mut scratch.next);
    }
    agree.flown(pass.step_move, (&p.pos, &scratch.next.pos));
    laps.lap(&mut times.particle_pass);
    // 3. Broad phase (pairs).
    scratch.pair_candidates.clear();
    if setup.pair_collisions {
        let verlet = (pass.step_move, setup.skin_fraction);
        let (next, lasting) = (&scratch.next, &world.lasting);
        contact::candidate_pairs(
            p,
            next,
            &mut world.neighbours,
            verlet,
            lasting,
            &mut scratch.pair_candidates,
        );
    }
    let neighbour_pairs: &[[u32; 2]] = if setup.pair_collisions { &world.neighbours.pairs } else { &[] };
    laps.lap(&mut times.broad_phase);
    // 4. Contacts in the step.
    let candidates = (&scratch.wall_candidates[..], &scratch.pair_candidates[..]);
    let (next, lasting) = (&mut scratch.next, &mut world.lasting);
    let events = (&mut record.events, &mut record.event_islands);
    let mut suspect = pass.suspect;
    suspect |= contact::resolve_in_step(&ctx, p, (t0, t1), candidates, next, events, lasting);
    laps.lap(&mut times.in_step);
    // 5. Lasting contacts.
    let wall_contacts = &mut world.wall_contacts;
    suspect |= contact::keep_lasting(&ctx, agree, p, next, lasting, neighbour_pairs, wall_contacts, h);
    laps.lap(&mut times.lasting);
    suspect
}

/// The step's contacts (`events`) as the features see them, with the index of each particle;
/// none without a feature.
fn touches(p: &Particles, events: &[ContactEvent], features: &Features) -> Vec<Touch> {
    if features.is_empty() {
        return Vec::new();
    }
    // Ids rise with the index (injected ids are new, removal keeps the order), unless a program
    // made the particles otherwise: then the index is looked for.
    let index = |id: u32| p.id.binary_search(&id).ok().or_else(|| p.id.iter().position(|&i| i == id));
    events
        .iter()
        .filter_map(|e| {
            Some(Touch {
                index: index(e.id)?,
                time: e.time,
                normal_speed: e.normal_speed,
                st: e.st,
                eps: e.eps,
                wall: matches!(e.other, Other::Wall(_)),
            })
        })
        .collect()
}

/// Stage 7 at `t1`: the outlets take out the particles that left through them, then the
/// injectors add those due — a particle injected in this step is not judged by an outlet
/// before it has moved. The step's events are those of `record.events` from `first_event` on
/// (a caller may step several times before handing events on). Returns true when particles
/// were renumbered.
fn outflow_and_inflow(
    world: &mut World,
    setup: &Setup,
    record: &mut Record,
    first_event: usize,
    t1: f64,
) -> bool {
    let (p, lasting) = (&mut world.particles, &mut world.lasting);
    let step_events = &record.events[first_event..];
    let mut renumbered = outlets::run(&setup.outlets, &mut record.removed, p, step_events, t1, lasting);
    renumbered |=
        inject::run(&setup.injectors, &mut world.injection, &setup.walls, p, &mut world.next_id, t1);
    renumbered
}

/// A flow field whose outside is an error: the first particle (in index order) left outside
/// it after the outlets have taken theirs, recorded in `record.left_field` (the driver stops
/// the run). Inside the step an integrator stage that strays outside got the nearest point's
/// velocity.
fn check_inside_field(world: &World, setup: &Setup, record: &mut Record, t1: f64) {
    let Some(field) = setup.fluid.flow.field() else { return };
    if field.outside != Outside::Error || record.left_field.is_some() {
        return;
    }
    let p = &world.particles;
    // A particle with a tetrahedron is inside: only the others are looked up.
    let unknown = |i: usize| p.tet.values().get(i).is_none_or(|&t| t == NO_TET);
    record.left_field = (0..p.len())
        .find(|&i| unknown(i) && !field.contains(p.pos[i]))
        .map(|i| OutsideField { id: p.id[i], position: p.pos[i], time: t1 });
}
