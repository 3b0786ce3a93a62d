//! An island's contacts in time order: a priority queue of events, each resolved by the
//! bounce rule, and only the changed particles' events computed again.

use super::super::Ctx;
use super::track::Track;
use crate::contact::{ContactEvent, LastingContact};
use crate::flight::Motion;
use crate::particles::Particles;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Events resolved per particle of an island in one step before the rest is left to the
/// lasting-contact stage (only a jammed cluster with a huge step reaches it).
const MAX_EVENTS_PER_PARTICLE: usize = 32;

/// What an island hands back.
pub(crate) struct IslandResult<M: Motion> {
    pub tracks: Vec<Track<M>>,
    pub events: Vec<ContactEvent>,
    pub lasting: Vec<LastingContact>,
}

/// What a queued event is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Subject {
    /// Track `track` reaches wall `wall`.
    Wall { track: usize, wall: usize },
    /// Pair `pair` (a position in the island's pairs) touches.
    Pair { pair: usize },
}

/// A queued event: when, what, and the versions of the tracks it was computed from (an event
/// computed before one of its tracks changed course is stale). The max-heap pops the earliest
/// time first (by `Reverse`); at equal times the derived order decides (pairs before walls,
/// higher indices first): any fixed order, so that ties resolve the same way on every run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Queued {
    time: Reverse<Time>,
    subject: Subject,
    versions: [u32; 2],
}

impl<'a, M: Motion> Ctx<'a, M> {
    /// Resolves an island: `tracks` sorted by particle index, `pairs` as positions in `tracks`.
    ///
    /// Events wait in a priority queue by time; an event computed before one of its particles
    /// changed course is stale (its version is old) and skipped, and only the changed
    /// particles' events are recomputed — so a dense island costs in proportion to its events.
    pub(crate) fn resolve_island(
        &self,
        p: &Particles,
        mut tracks: Vec<Track<M>>,
        pairs: &[[usize; 2]],
        t1: f64,
    ) -> IslandResult<M> {
        let mut events = Vec::new();
        let mut lasting: Vec<LastingContact> = Vec::new();
        let mut settled = vec![false; pairs.len()];
        let mut version = vec![0u32; tracks.len()];
        let mut pairs_of: Vec<Vec<usize>> = vec![Vec::new(); tracks.len()];
        for (q, &[a, b]) in pairs.iter().enumerate() {
            pairs_of[a].push(q);
            pairs_of[b].push(q);
        }
        let mut queue: BinaryHeap<Queued> = BinaryHeap::new();
        let wall_entry = |tracks: &[Track<M>], version: &[u32], k: usize| {
            self.next_wall_event(&tracks[k], t1).map(|(w, t)| Queued {
                time: Reverse(Time(t)),
                subject: Subject::Wall { track: k, wall: w },
                versions: [version[k], 0],
            })
        };
        let pair_entry = |tracks: &[Track<M>], version: &[u32], q: usize| {
            let [a, b] = pairs[q];
            self.next_pair_event(&tracks[a], &tracks[b], t1).map(|t| Queued {
                time: Reverse(Time(t)),
                subject: Subject::Pair { pair: q },
                versions: [version[a], version[b]],
            })
        };
        for k in 0..tracks.len() {
            queue.extend(wall_entry(&tracks, &version, k));
        }
        for q in 0..pairs.len() {
            queue.extend(pair_entry(&tracks, &version, q));
        }
        let mut budget = MAX_EVENTS_PER_PARTICLE * tracks.len();
        while let Some(Queued { time: Reverse(Time(t)), subject, versions: [va, vb] }) = queue.pop() {
            let changed: Vec<usize> = match subject {
                Subject::Wall { track, wall } => {
                    if version[track] != va {
                        continue;
                    }
                    self.wall_event(p, &mut tracks[track], (wall, t), t1, &mut events);
                    vec![track]
                }
                Subject::Pair { pair } => {
                    let [a, b] = pairs[pair];
                    if settled[pair] || version[a] != va || version[b] != vb {
                        continue;
                    }
                    let (lo, hi) = tracks.split_at_mut(b);
                    if let Some(c) = self.pair_event(p, (&mut lo[a], &mut hi[0]), t, t1, &mut events) {
                        settled[pair] = true;
                        lasting.push(c);
                    }
                    vec![a, b]
                }
            };
            budget -= 1;
            if budget == 0 {
                break;
            }
            for &k in &changed {
                version[k] += 1;
            }
            for &k in &changed {
                queue.extend(wall_entry(&tracks, &version, k));
                for &q in &pairs_of[k] {
                    if !settled[q] {
                        queue.extend(pair_entry(&tracks, &version, q));
                    }
                }
            }
        }
        IslandResult { tracks, events, lasting }
    }
}

/// A time with a total order, for the event queue.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Time(f64);

impl Eq for Time {}

impl PartialOrd for Time {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Time {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}
