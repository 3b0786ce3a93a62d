//! One run on several ranks (MPI), giving the files one process gives (docs/distributed.md).
//!
//! **Design.** Each rank owns whole *clusters* ([`clusters`]): sets of particles close enough
//! to touch before the next re-clustering, linked also by their lasting contacts. No contact
//! then crosses a rank, and each rank steps its particles with the single-process step,
//! unchanged: what does not cross a rank is computed exactly as in one process. Its particles
//! are kept in id order, the order of one process, so every order-dependent loop of the step
//! (islands, Gauss–Seidel sweeps, events) visits them in the same relative order. What spans
//! the ranks is agreed:
//!
//! - inside a step, the few decisions over *all* contacts (whether another projection round or
//!   sweep is needed) through [`crate::agree::Agree`], by a reduction;
//! - after each step ([`Split`], a [`Steps`] of the run loop): the step's events, lost particles
//!   and outlet removals go to rank 0, merged into one process's order (events by island, an
//!   island by its lowest id; the others by id); injectors draw on every rank from the same
//!   generator, against the particles near them gathered from every rank, and rank 0 takes
//!   the new particles; a particle outside an `outside = "error"` field stops every rank;
//! - at a frame, rank 0 gathers every particle, in id order, and writes the same files as one
//!   process;
//! - clusters are found again ([`clusters::recluster`]) when particles were injected or when a
//!   particle may come within half the cluster skin of its reference; the domains
//!   ([`bisection`]) are cut again when the ranks' counts drift apart. During the step the
//!   ranks check that no particle went farther than the skin allows; if one did (a jump far
//!   larger than the last step's moves), the run stops with an error rather than miss a contact.
//!
//! A run started without `mpirun`, or with one rank, does not come here: it is the plain run.

pub mod bisection;
pub mod clusters;
pub mod comm;
mod drift;
#[cfg(feature = "mpi")]
pub mod mpi;
mod parcel;

use crate::contact::ContactEvent;
use crate::fluid::field::{Outside, OutsideField};
use crate::particles::NO_TET;
use crate::pipeline::inject::{self, Injector, InjectorState};
use crate::pipeline::outlets::Removal;
use crate::pipeline::{LostParticle, Simulation};
use crate::run::Steps;
use bisection::Domains;
use clusters::{Balance, Clustering, recluster};
use comm::{Comm, all_gather, decode, encode, exchange};
use drift::{Agreeing, realign};
use glam::DVec3;
use parcel::Parcel;
use std::cell::Cell;

/// The cluster skin holds at least this many of the last step's largest moves: the clusters
/// are then found again no more often than every `(MOVES_IN_SKIN/2 − 4)/2` steps (the drift
/// bound grows by twice the move a step, and four moves are kept for the next step). 32 rather
/// than 16 halved the column's re-clusterings (1317 to 659 in 8000 steps) and took its run on 2
/// ranks from 31.4 s to 27.8 s, though its largest cluster grew from 599 drops to 729.
pub const MOVES_IN_SKIN: f64 = 32.0;

/// Imbalance (largest rank's count over the mean, less one) past which the domains are cut
/// again at a re-clustering.
pub const REBALANCE_THRESHOLD: f64 = 0.1;

/// A run's part on this rank, and what the ranks share: a [`Steps`] for the run loop
/// ([`crate::run::Driver::run_with`]), which holds on rank 0 the simulation the sinks read.
pub struct Split<'c> {
    comm: &'c dyn Comm,
    /// This rank's particles, stepped by the single-process step (without the injectors).
    local: Simulation,
    /// The scene's injectors and their state: the same on every rank.
    injectors: Vec<Injector>,
    injection: Vec<InjectorState>,
    next_id: u32,
    domains: Domains,
    balance: Balance,
    /// The cluster skin `S` (m) of the last clustering, and each particle's id and position
    /// then (the ids only to follow removals).
    skin: f64,
    reference: Vec<DVec3>,
    reference_ids: Vec<u32>,
    /// A bound on every particle's distance from its reference (m), over the ranks.
    drift: f64,
    /// The largest free-flight move of the last step, over the ranks (m).
    last_move: f64,
    /// How many events, lost particles and removals of `local` are handed on already.
    handed: (usize, Vec<usize>),
    /// Why the run stopped on its own, if it did.
    failure: Option<String>,
    /// What the re-clusterings did.
    pub report: SplitReport,
}

/// How the run was split, for the end-of-run table.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SplitReport {
    /// Ranks.
    pub ranks: usize,
    /// Rank 0's threads (each rank's, unless `--threads` was set differently per rank); 0 when
    /// not known (`wetbounce check --ranks`, which runs no rank).
    pub threads: usize,
    /// Re-clusterings, and those that cut the domains again.
    pub reclusterings: u64,
    /// Re-clusterings that cut the domains again.
    pub rebalances: u64,
    /// Particles that changed rank, over the run.
    pub moved: u64,
    /// The last clustering.
    pub last: Clustering,
    /// The largest imbalance after a re-clustering (largest count over the mean, less one).
    pub worst_imbalance: f64,
}

impl SplitReport {
    /// Lines for the end-of-run table.
    pub fn lines(&self) -> Vec<String> {
        let c = &self.last;
        vec![
            format!(
                "ranks: {}{} (particles per rank at the last re-clustering: {:?}; worst imbalance {:.0} %)",
                self.ranks,
                match self.threads {
                    0 => String::new(),
                    1 => " × 1 thread".to_string(),
                    t => format!(" × {t} threads"),
                },
                c.counts,
                100.0 * self.worst_imbalance
            ),
            format!(
                "clusters: {} at the last re-clustering, the largest {} particles; {} re-clusterings, {} rebalances, {} particles moved between ranks",
                c.clusters, c.largest, self.reclusterings, self.rebalances, self.moved
            ),
        ]
    }
}

/// What the inflow of a step did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Injected {
    /// Nothing was due, or nothing could be placed.
    None,
    /// New particles joined their clusters on their ranks.
    Joined,
    /// New particles link clusters of different ranks: the clusters are found again.
    Linking,
}

/// What a rank hands rank 0 after a step.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
struct News {
    /// The step's events, each with its island's lowest id.
    events: Vec<(u32, ContactEvent)>,
    lost: Vec<LostParticle>,
    removed: Vec<Vec<Removal>>,
    left_field: Option<OutsideField>,
}

impl<'c> Split<'c> {
    /// Splits `sim` (the whole simulation, built from the scene on every rank alike) over the
    /// ranks of `comm`; `sim` stays the simulation the run loop holds (rank 0's sinks read it).
    pub fn new(comm: &'c dyn Comm, sim: &Simulation) -> Result<Self, std::collections::TryReserveError> {
        let mut setup = sim.setup.clone();
        let injectors = std::mem::take(&mut setup.injectors);
        let mut world = sim.world.clone();
        let injection = std::mem::take(&mut world.injection);
        // Every rank holds the whole world here: each keeps at once the particles of its domain
        // in a bisection of them all (a lasting contact's particles with its lowest one's), so
        // that the first clustering is shared out too.
        let p = &world.particles;
        let points: Vec<(DVec3, f64)> = p.pos.iter().map(|x| (*x, 1.0)).collect();
        let domains = Domains::bisect(&points, comm.size());
        let mut held = clusters::Sets::new(p.len());
        for c in &world.lasting {
            held.join(c.a as usize, c.b as usize);
        }
        let keep: Vec<bool> =
            (0..p.len()).map(|i| domains.owner(p.pos[held.root(i)]) == comm.rank()).collect();
        let kept_ids: Vec<u32> = (0..p.len()).filter(|&i| keep[i]).map(|i| p.id[i]).collect();
        crate::contact::lasting::remove_particles(&mut world.particles, &keep, &mut world.lasting);
        world.wall_contacts.retain(|w| kept_ids.binary_search(&w.id).is_ok());
        world.neighbours.invalidate();
        let removed = vec![Vec::new(); setup.outlets.len()];
        let local = Simulation::restore(setup, world, (Vec::new(), removed.clone(), None))?;
        let next_id = sim.world.next_id;
        let mut split = Split {
            comm,
            local,
            injectors,
            injection,
            next_id,
            domains,
            balance: Balance::default(),
            skin: 0.0,
            reference: Vec::new(),
            reference_ids: Vec::new(),
            drift: 0.0,
            last_move: 0.0,
            handed: (0, vec![0; removed.len()]),
            failure: None,
            report: SplitReport {
                ranks: comm.size(),
                threads: rayon::current_num_threads(),
                ..SplitReport::default()
            },
        };
        split.recluster(false);
        Ok(split)
    }

    /// Why the run stopped before its end on its own (a particle jumped farther than the
    /// clusters allow), if it did.
    pub fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }

    /// This rank's part of the run.
    pub fn local(&self) -> &Simulation {
        &self.local
    }

    /// Finds the clusters again with a skin fitted to the last step's moves.
    fn recluster(&mut self, rebalance: bool) {
        let setup = &self.local.setup;
        // The largest particle there is or may come (an injector's).
        let injected = self.injectors.iter().map(|i| i.diameter.max_diameter()).fold(0.0, f64::max);
        let d_max =
            self.comm.max(self.local.world.particles.diameter.iter().copied().fold(injected, f64::max));
        // Twice the neighbour list's skin, and room for many moves like the last step's.
        self.skin = (2.0 * setup.skin_fraction * d_max).max(MOVES_IN_SKIN * self.last_move);
        let bounds = (&mut self.domains, &mut self.balance);
        let done =
            recluster(self.comm, &mut self.local.world, bounds, (self.skin, REBALANCE_THRESHOLD, rebalance));
        self.reference = self.local.world.particles.pos.clone();
        self.reference_ids = self.local.world.particles.id.clone();
        self.drift = 0.0;
        let total: usize = done.counts.iter().sum();
        let mean = total as f64 / done.counts.len() as f64;
        let worst = done.counts.iter().copied().max().unwrap_or(0) as f64;
        let r = &mut self.report;
        r.reclusterings += 1;
        r.rebalances += done.rebalanced as u64;
        r.moved += done.moved as u64;
        if mean > 0.0 {
            r.worst_imbalance = r.worst_imbalance.max(worst / mean - 1.0);
        }
        r.last = done;
    }

    /// After a step: the news to rank 0, merged into `view`.
    fn hand_on(&mut self, view: &mut Simulation) {
        let record = &mut self.local.record;
        let news = News {
            events: record.event_islands.iter().copied().zip(record.events.iter().copied()).collect(),
            lost: record.lost[self.handed.0..].to_vec(),
            removed: record.removed.iter().zip(&self.handed.1).map(|(r, &k)| r[k..].to_vec()).collect(),
            left_field: record.left_field.take(),
        };
        record.events.clear();
        record.event_islands.clear();
        self.handed = (record.lost.len(), record.removed.iter().map(Vec::len).collect());
        let mut outgoing = vec![News::default(); self.comm.size()];
        outgoing[0] = news;
        let came: Vec<News> = exchange(self.comm, &outgoing);
        if self.comm.rank() != 0 {
            return;
        }
        let mut events: Vec<(u32, ContactEvent)> =
            came.iter().flat_map(|n| n.events.iter().copied()).collect();
        // Stable: each rank's events are in its islands' order already.
        events.sort_by_key(|e| e.0);
        view.record.events.extend(events.into_iter().map(|e| e.1));
        let mut lost: Vec<LostParticle> = came.iter().flat_map(|n| n.lost.iter().copied()).collect();
        lost.sort_by_key(|l| l.id);
        view.record.lost.extend(lost);
        for (k, removed) in view.record.removed.iter_mut().enumerate() {
            let mut r: Vec<Removal> = came.iter().flat_map(|n| n.removed[k].iter().copied()).collect();
            r.sort_by_key(|r| r.id);
            removed.extend(r);
        }
        if view.record.left_field.is_none() {
            view.record.left_field = came.iter().filter_map(|n| n.left_field).min_by_key(|l| l.id);
        }
    }

    /// Stage 7's inflow for the whole run: every rank draws, against the particles near each
    /// injector gathered from every rank (with the rank each came from), so every rank adds the
    /// same particles. Each new particle joins the cluster of the particles within the cluster
    /// skin of it, and goes to their rank (to the owner of its domain when it touches none);
    /// when new particles link clusters of different ranks, the clusters must be found again.
    fn inject(&mut self, view: &mut Simulation, t1: f64) -> Injected {
        let due = self.injectors.iter().zip(&self.injection).any(|(inj, s)| inj.due_by(t1) > s.due);
        if !due {
            return Injected::None;
        }
        let p = &self.local.world.particles;
        let d_max = self.comm.max(p.diameter.iter().copied().fold(0.0, f64::max));
        let skin = self.skin;
        let near: Vec<usize> = (0..p.len())
            .filter(|&i| {
                self.injectors.iter().any(|inj| {
                    let (lo, hi) = inj.region_bounds();
                    // Within reach of a new particle: for its placing, and for its cluster.
                    let margin = DVec3::splat(0.5 * (inj.diameter.max_diameter() + d_max) + skin);
                    p.pos[i].cmpge(lo - margin).all() && p.pos[i].cmple(hi + margin).all()
                })
            })
            .collect();
        let parts: Vec<crate::particles::Particles> = all_gather(self.comm, &p.select(&near));
        let mut around = p.select(&[]);
        let mut rank_of = Vec::new();
        for (r, part) in parts.iter().enumerate() {
            around.append(part);
            rank_of.extend(std::iter::repeat_n(r, part.len()));
        }
        let mut order: Vec<usize> = (0..around.len()).collect();
        order.sort_unstable_by_key(|&i| around.id[i]);
        let mut around = around.select(&order);
        let rank_of: Vec<usize> = order.iter().map(|&i| rank_of[i]).collect();
        let before = around.len();
        let walls = &self.local.setup.walls;
        if !inject::run(&self.injectors, &mut self.injection, walls, &mut around, &mut self.next_id, t1) {
            return Injected::None;
        }
        let fresh = around.select(&(before..around.len()).collect::<Vec<_>>());
        if self.comm.rank() == 0 {
            self.check_new_inside_field(view, &fresh, t1);
        }
        // The new particles' clusters: linked among themselves, and to the ranks they touch.
        let links = clusters::close_pairs(&around.pos, &around.diameter, skin, around.len());
        let mut sets = clusters::Sets::new(fresh.len());
        let mut touched: Vec<Vec<usize>> = vec![Vec::new(); fresh.len()];
        for &[a, b] in &links {
            let (a, b) = (a as usize, b as usize);
            match (a >= before, b >= before) {
                (true, true) => sets.join(a - before, b - before),
                (false, true) => touched[b - before].push(rank_of[a]),
                (true, false) => touched[a - before].push(rank_of[b]),
                (false, false) => {}
            }
        }
        let mut ranks_of_set: Vec<Vec<usize>> = vec![Vec::new(); fresh.len()];
        for (k, t) in touched.iter().enumerate() {
            let root = sets.root(k);
            ranks_of_set[root].extend(t);
        }
        let mut destination = Vec::with_capacity(fresh.len());
        for k in 0..fresh.len() {
            let root = sets.root(k);
            let ranks = &mut ranks_of_set[root];
            ranks.sort_unstable();
            ranks.dedup();
            destination.push(match ranks[..] {
                [] => self.domains.owner(fresh.pos[root]),
                [r] => r,
                _ => return self.place_all_on_root(fresh),
            });
        }
        let mine: Vec<usize> = (0..fresh.len()).filter(|&k| destination[k] == self.comm.rank()).collect();
        if !mine.is_empty() {
            let joining = fresh.select(&mine);
            self.reference.extend_from_slice(&joining.pos);
            self.reference_ids.extend_from_slice(&joining.id);
            self.local.world.particles.append(&joining);
            self.local.world.neighbours.invalidate();
        }
        Injected::Joined
    }

    /// New particles that link clusters of several ranks: rank 0 takes them all, and the
    /// clusters are found again.
    fn place_all_on_root(&mut self, fresh: crate::particles::Particles) -> Injected {
        if self.comm.rank() == 0 {
            self.local.world.particles.append(&fresh);
            self.local.world.neighbours.invalidate();
        }
        Injected::Linking
    }

    /// One process checks the particles just injected against an `outside = "error"` field
    /// with the others: rank 0 does it for them.
    fn check_new_inside_field(&self, view: &mut Simulation, fresh: &crate::particles::Particles, t1: f64) {
        let Some(field) = self.local.setup.fluid.flow.field() else { return };
        if field.outside != Outside::Error || view.record.left_field.is_some() {
            return;
        }
        let unknown = |i: usize| fresh.tet.values().get(i).is_none_or(|&t| t == NO_TET);
        view.record.left_field = (0..fresh.len())
            .find(|&i| unknown(i) && !field.contains(fresh.pos[i]))
            .map(|i| OutsideField { id: fresh.id[i], position: fresh.pos[i], time: t1 });
    }
}

impl Steps for Split<'_> {
    fn advance(&mut self, view: &mut Simulation, target: f64) {
        let steps = self.local.world.steps;
        let agree = Agreeing {
            comm: self.comm,
            reference: &self.reference,
            drift: self.drift,
            half_skin: 0.5 * self.skin,
            flown: Cell::new((0.0, 0.0)),
        };
        self.local.advance_agreeing(target, &agree);
        let (moved, reach) = agree.flown.get();
        let t1 = self.local.world.time;
        view.world.time = t1;
        view.world.steps = self.local.world.steps;
        if self.local.world.steps == steps {
            return;
        }
        if reach > 0.5 * self.skin && self.failure.is_none() {
            self.failure = Some(format!(
                "at t = {t1:.6e} s a particle may have moved {reach:.3e} m from where it was when the \
                 ranks last shared out the particles, more than half the cluster skin ({:.3e} m): a \
                 contact across ranks could have been missed, so the run stops here. A smaller time \
                 step, or fewer ranks, avoids it",
                0.5 * self.skin
            ));
        }
        self.last_move = moved;
        self.hand_on(view);
        // The particles' references follow removals (lost, outlets): ids in order on both sides.
        let p = &self.local.world.particles;
        if p.len() != self.reference.len() {
            (self.reference, self.reference_ids) = realign(&p.id, (&self.reference_ids, &self.reference));
        }
        let injected = self.inject(view, t1);
        // The drift bound grows by the step's move (twice: contacts may turn a path); when the
        // next step could spend it, it is measured, and the clusters found again if need be.
        self.drift += 2.0 * moved;
        if self.drift + 4.0 * self.last_move >= 0.5 * self.skin {
            let p = &self.local.world.particles;
            let drift =
                p.pos.iter().zip(&self.reference).map(|(x, r)| (*x - *r).length()).fold(0.0, f64::max);
            self.drift = self.comm.max(drift);
        }
        if injected == Injected::Linking || self.drift + 4.0 * self.last_move >= 0.5 * self.skin {
            self.recluster(false);
        }
    }

    fn before_frame(&mut self, view: &mut Simulation) {
        self.gather(view, false);
    }

    fn checkpointing(&mut self, due: bool) -> bool {
        self.comm.any(due)
    }

    fn before_checkpoint(&mut self, view: &mut Simulation) {
        self.gather(view, true);
    }

    fn stopping(&mut self, asked: bool) -> bool {
        self.comm.any(asked || self.failure.is_some())
    }
}

impl Split<'_> {
    /// Gathers every rank's particles into `view` on rank 0, in id order; with `whole`, also
    /// the lasting contacts and the walls' forces: the world one process would hold, which a
    /// checkpoint saves (its neighbour list left to be built again: it changes no result).
    fn gather(&mut self, view: &mut Simulation, whole: bool) {
        let world = &self.local.world;
        let mine = || {
            if whole {
                Parcel::of(world)
            } else {
                Parcel { particles: world.particles.clone(), ..Parcel::default() }
            }
        };
        // Rank 0 keeps its own part as it is (encoding it to itself cost as much as the rest).
        let me = self.comm.rank();
        let mut outgoing = vec![Vec::new(); self.comm.size()];
        if me != 0 {
            outgoing[0] = encode(&mine());
        }
        let received = self.comm.exchange(outgoing);
        if me != 0 {
            return;
        }
        let parts: Vec<Parcel> =
            std::iter::once(mine()).chain(received.iter().skip(1).map(|b| decode(b))).collect();
        let merged = Parcel::merge(parts.into_iter().filter(|p| !p.particles.is_empty()).collect());
        if whole {
            view.world.lasting = merged.renumbered();
            view.world.wall_contacts = merged.walls;
            view.world.neighbours = Default::default();
        }
        // With no particle anywhere, the store keeps its features' columns.
        view.world.particles = if merged.particles.id.is_empty() {
            self.local.world.particles.select(&[])
        } else {
            merged.particles
        };
        view.world.injection.clone_from(&self.injection);
        view.world.next_id = self.next_id;
    }
}
