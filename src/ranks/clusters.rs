//! Clusters: the particles that may touch each other before the next re-clustering, which a
//! rank owns whole (docs/distributed.md, "Clusters").
//!
//! Two particles are linked when their surfaces are closer than the cluster skin `S`, or when
//! they share a lasting contact; a cluster is a connected set of links. While no particle has
//! moved `S/2` from where it was at the clustering, no two clusters can touch: every contact of
//! the step is inside one cluster, on one rank, and is computed there exactly as one process
//! computes it. A cluster's owner is the rank whose domain ([`Domains`]) holds its
//! lowest-id particle.
//!
//! [`recluster`] finds the clusters across ranks: each rank links its own particles, and the
//! particles other ranks sent it as *ghosts* (those within reach of its particles' bounding
//! box); the links that cross ranks are gathered to every rank, which joins the clusters they
//! link in the same way; then every particle moves to its cluster's owner, with its lasting
//! contacts and its walls' last forces.

use super::bisection::Domains;
use super::comm::{Comm, all_gather, exchange};
use super::parcel::Parcel;
use crate::contact::FastMap;
use crate::contact::detect::neighbours::pairs_within;
use crate::pipeline::World;
use glam::DVec3;

/// Pairs `[i, j]`, `i < j`, of `x` whose surfaces are closer than `skin`, none between two
/// points at or above `ghosts` (the ghosts link only to this rank's particles).
pub fn close_pairs(x: &[DVec3], diameter: &[f64], skin: f64, ghosts: usize) -> Vec<[u32; 2]> {
    let mut pairs = pairs_within(x, diameter, skin);
    pairs.retain(|&[i, _]| (i as usize) < ghosts);
    pairs
}

/// Union–find whose root is the lowest member (so a set's root does not depend on the order of
/// the unions).
#[derive(Debug, Clone)]
pub struct Sets {
    parent: Vec<u32>,
}

impl Sets {
    /// `n` sets of one.
    pub fn new(n: usize) -> Self {
        Sets { parent: (0..n as u32).collect() }
    }

    /// The lowest member of `i`'s set.
    pub fn root(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.parent[r] as usize != r {
            r = self.parent[r] as usize;
        }
        let mut k = i;
        while self.parent[k] as usize != r {
            let up = self.parent[k] as usize;
            self.parent[k] = r as u32;
            k = up;
        }
        r
    }

    /// Joins the sets of `a` and `b`.
    pub fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb) as u32;
        }
    }
}

/// The same, on labels that are particle ids (sparse): the root is the lowest id.
#[derive(Debug, Default)]
struct IdSets {
    parent: FastMap<u32, u32>,
}

impl IdSets {
    fn root(&mut self, i: u32) -> u32 {
        let mut r = i;
        while let Some(&up) = self.parent.get(&r) {
            if up == r {
                break;
            }
            r = up;
        }
        if r != i {
            self.parent.insert(i, r);
        }
        r
    }

    fn join(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.parent.insert(ra.max(rb), ra.min(rb));
            self.parent.entry(ra.min(rb)).or_insert(ra.min(rb));
        }
    }
}

/// A particle sent to another rank to find the links that cross ranks.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
struct Ghost {
    id: u32,
    pos: DVec3,
    diameter: f64,
}

/// What a rank tells every other of its clusters' links across ranks.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
struct Border {
    /// `(cluster, ghost)`: a cluster of this rank (its lowest id) linked to another rank's
    /// particle.
    links: Vec<(u32, u32)>,
    /// `(particle, cluster)` for each of this rank's particles sent as a ghost.
    ghosts: Vec<(u32, u32)>,
    /// Where the lowest particle of each cluster named in `links` is.
    keys: Vec<(u32, DVec3)>,
}

/// A cluster's part on one rank, for a new bisection: its cluster, its particles here, and
/// where the cluster's lowest particle is when it is here.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
struct Part {
    cluster: u32,
    count: u32,
    key: Option<DVec3>,
}

/// The imbalance the last cut of the domains left (largest count over the mean, less one).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Balance {
    /// Right after the last cut.
    pub after_cut: f64,
    /// Particles in the run then.
    pub total_at_cut: usize,
}

/// What a re-clustering found and did, for the end-of-run table.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Clustering {
    /// Clusters in the whole run.
    pub clusters: usize,
    /// Particles of the largest cluster.
    pub largest: usize,
    /// Particles that changed rank.
    pub moved: usize,
    /// Whether the domains were cut again (the imbalance passed the threshold).
    pub rebalanced: bool,
    /// Particles on each rank after it.
    pub counts: Vec<usize>,
}

/// Finds the clusters of every rank's particles with skin `skin` (m), moves each cluster to its
/// owner (cutting the domains again when `rebalance` says so, or when the largest count passes
/// the mean by more than `threshold` beyond what the last cut left: `balance`), and leaves this
/// rank's particles in id order.
pub fn recluster(
    comm: &dyn Comm,
    world: &mut World,
    (domains, balance): (&mut Domains, &mut Balance),
    (skin, threshold, rebalance): (f64, f64, bool),
) -> Clustering {
    let (me, size) = (comm.rank(), comm.size());
    let p = &world.particles;
    let n = p.len();
    let d_max = comm.max(p.diameter.iter().copied().fold(0.0, f64::max));
    let reach = d_max + skin;
    // 1. Ghosts: this rank's particles within reach of each other rank's bounding box.
    let own_box = (n > 0).then(|| {
        p.pos.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), x| (lo.min(*x), hi.max(*x)))
    });
    let boxes: Vec<Option<(DVec3, DVec3)>> = all_gather(comm, &own_box);
    let mut outgoing: Vec<Vec<Ghost>> = vec![Vec::new(); size];
    let mut sent = vec![false; n];
    for (r, b) in boxes.iter().enumerate() {
        let Some((lo, hi)) = b.filter(|_| r != me) else { continue };
        for (i, sent) in sent.iter_mut().enumerate() {
            if p.pos[i].cmpge(lo - reach).all() && p.pos[i].cmple(hi + reach).all() {
                outgoing[r].push(Ghost { id: p.id[i], pos: p.pos[i], diameter: p.diameter[i] });
                *sent = true;
            }
        }
    }
    let ghosts: Vec<Ghost> = exchange(comm, &outgoing).concat();
    // 2. Links among this rank's particles and to the ghosts; clusters here.
    let mut x = p.pos.clone();
    let mut d = p.diameter.clone();
    x.extend(ghosts.iter().map(|g| g.pos));
    d.extend(ghosts.iter().map(|g| g.diameter));
    let pairs = close_pairs(&x, &d, skin, n);
    let mut sets = Sets::new(n);
    for &[a, b] in pairs.iter().filter(|[_, b]| (*b as usize) < n) {
        sets.join(a as usize, b as usize);
    }
    for c in &world.lasting {
        sets.join(c.a as usize, c.b as usize);
    }
    let label: Vec<u32> = (0..n).map(|i| p.id[sets.root(i)]).collect();
    // 3. Links across ranks, joined the same way on every rank.
    let mut border = Border::default();
    for &[a, b] in pairs.iter().filter(|[_, b]| (*b as usize) >= n) {
        border.links.push((label[a as usize], ghosts[b as usize - n].id));
    }
    border.links.sort_unstable();
    border.links.dedup();
    border.ghosts = (0..n).filter(|&i| sent[i]).map(|i| (p.id[i], label[i])).collect();
    let index_of = |id: u32| p.id.binary_search(&id).expect("a cluster's label is one of its particles");
    let mut keys: Vec<u32> = border.links.iter().map(|l| l.0).collect();
    keys.dedup();
    border.keys = keys.iter().map(|&c| (c, p.pos[index_of(c)])).collect();
    let borders: Vec<Border> = all_gather(comm, &border);
    let mut cluster_of_ghost: FastMap<u32, u32> = FastMap::default();
    let mut key_of: FastMap<u32, DVec3> = FastMap::default();
    for b in &borders {
        cluster_of_ghost.extend(b.ghosts.iter().copied());
        key_of.extend(b.keys.iter().copied());
    }
    let mut joined = IdSets::default();
    for b in &borders {
        for &(cluster, ghost) in &b.links {
            joined.join(cluster, cluster_of_ghost[&ghost]);
        }
    }
    // 4. Each particle's cluster in the whole run, and where that cluster's key particle is.
    let whole: Vec<u32> = label.iter().map(|&l| joined.root(l)).collect();
    let key = |c: u32| key_of.get(&c).copied().unwrap_or_else(|| p.pos[index_of(c)]);
    // 5. Owners; the domains cut again when the counts are uneven (or asked).
    let mut parts: Vec<Part> = Vec::new();
    let mut count_of: FastMap<u32, u32> = FastMap::default();
    for &c in &whole {
        *count_of.entry(c).or_default() += 1;
    }
    let mut clusters_here: Vec<u32> = count_of.keys().copied().collect();
    clusters_here.sort_unstable();
    parts.extend(clusters_here.iter().map(|&c| Part {
        cluster: c,
        count: count_of[&c],
        key: p.id.binary_search(&c).ok().map(|i| p.pos[i]),
    }));
    let counted = |domains: &Domains| {
        let mut counts = vec![0usize; size];
        for part in &parts {
            counts[domains.owner(key(part.cluster))] += part.count as usize;
        }
        counts
    };
    let counts: Vec<usize> = all_gather(comm, &counted(domains)).iter().fold(vec![0; size], |mut t, c| {
        for (t, c) in t.iter_mut().zip(c) {
            *t += c;
        }
        t
    });
    let total: usize = counts.iter().sum();
    let mean = total as f64 / size as f64;
    let imbalance = if total > 0 { *counts.iter().max().unwrap_or(&0) as f64 / mean - 1.0 } else { 0.0 };
    // The largest cluster: those of one rank counted there, those across ranks summed.
    let across: Vec<(u32, u32)> = parts
        .iter()
        .filter(|part| joined.parent.contains_key(&part.cluster))
        .map(|part| (part.cluster, part.count))
        .collect();
    let mut across_sums: FastMap<u32, usize> = FastMap::default();
    for (c, k) in all_gather(comm, &across).into_iter().flatten() {
        *across_sums.entry(c).or_default() += k as usize;
    }
    let local_largest = parts
        .iter()
        .filter(|part| !joined.parent.contains_key(&part.cluster))
        .map(|part| part.count)
        .max()
        .unwrap_or(0);
    let largest =
        (comm.max(local_largest as f64) as usize).max(across_sums.values().copied().max().unwrap_or(0));
    let clusters_total: usize =
        all_gather(comm, &parts.iter().filter(|p| p.key.is_some()).count()).iter().sum();
    // Cut again when the counts drift apart — not when a cut cannot help (one cluster larger
    // than a rank's share stays uneven whatever the cuts): only past the imbalance the last cut
    // left, by the threshold.
    // (A cut made for a run that has since grown or shrunk by more than the threshold — an
    // injector filling the column — is no guide.)
    let stale = (total as f64 - balance.total_at_cut as f64).abs() > threshold * balance.total_at_cut as f64;
    let floor = if stale { threshold } else { threshold.max(balance.after_cut + threshold) };
    let rebalanced = size > 1 && (rebalance || imbalance > floor);
    if rebalanced {
        let all_parts: Vec<Vec<Part>> = all_gather(comm, &parts);
        let mut whole_clusters: FastMap<u32, (u32, Option<DVec3>)> = FastMap::default();
        for part in all_parts.iter().flatten() {
            let e = whole_clusters.entry(part.cluster).or_insert((0, None));
            e.0 += part.count;
            e.1 = e.1.or(part.key);
        }
        let mut list: Vec<(u32, (u32, Option<DVec3>))> = whole_clusters.into_iter().collect();
        list.sort_unstable_by_key(|e| e.0);
        let points: Vec<(DVec3, f64)> = list
            .iter()
            .map(|(_, (count, key))| (key.expect("every cluster's key is on a rank"), *count as f64))
            .collect();
        *domains = Domains::bisect(&points, size);
    }
    // 6. Every particle to its cluster's owner.
    let owner: Vec<usize> = whole.iter().map(|&c| domains.owner(key(c))).collect();
    let moved_here = owner.iter().filter(|&&o| o != me).count();
    let moved = comm.max(moved_here as f64) as usize;
    if moved > 0 {
        migrate(comm, world, &owner);
    }
    let counts: Vec<usize> = all_gather(comm, &world.particles.len());
    let moved_total: usize = all_gather(comm, &moved_here).iter().sum();
    if rebalanced {
        let mean = total as f64 / size as f64;
        balance.after_cut =
            if total > 0 { *counts.iter().max().unwrap_or(&0) as f64 / mean - 1.0 } else { 0.0 };
        balance.total_at_cut = total;
    }
    Clustering { clusters: clusters_total, largest, moved: moved_total, rebalanced, counts }
}

/// Sends each particle to `owner[i]`, with its lasting contacts (both particles of one go to
/// the same rank: they are one cluster) and its walls' last forces; keeps the particles in id
/// order.
fn migrate(comm: &dyn Comm, world: &mut World, owner: &[usize]) {
    let (me, size) = (comm.rank(), comm.size());
    let mut rows: Vec<Vec<usize>> = vec![Vec::new(); size];
    for (i, &o) in owner.iter().enumerate() {
        rows[o].push(i);
    }
    let parcels: Vec<Parcel> = (0..size)
        .map(|r| {
            if r == me || rows[r].is_empty() {
                Parcel::default()
            } else {
                Parcel::to_rank(world, owner, r, &rows[r])
            }
        })
        .collect();
    let kept = Parcel::to_rank(world, owner, me, &rows[me]);
    let received: Vec<Parcel> = exchange(comm, &parcels);
    // Kept first, then what came, in rank order: a cluster's own lasting contacts keep their
    // order (the only order that matters: contacts of different clusters never meet).
    let parts = std::iter::once(kept).chain(received.into_iter().filter(|r| !r.particles.is_empty()));
    let merged = Parcel::merge(parts.collect());
    world.lasting = merged.renumbered();
    world.particles = merged.particles;
    world.wall_contacts = merged.walls;
    world.neighbours.invalidate();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_pairs_are_those_a_search_of_every_pair_finds_and_never_two_ghosts() {
        let x: Vec<DVec3> = (0..300)
            .map(|i| {
                DVec3::new((i as f64 * 0.37).sin(), (i as f64 * 0.71).cos(), (i as f64 * 0.13).sin()) * 0.03
            })
            .collect();
        let d: Vec<f64> = (0..300).map(|i| 2e-3 + 1e-3 * (i % 3) as f64).collect();
        let ghosts = 250;
        let pairs = close_pairs(&x, &d, 1e-3, ghosts);
        let mut brute = Vec::new();
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                if (i < ghosts || j < ghosts) && (x[j] - x[i]).length() < 0.5 * (d[i] + d[j]) + 1e-3 {
                    brute.push([i as u32, j as u32]);
                }
            }
        }
        assert_eq!(pairs, brute);
        assert!(!brute.is_empty());
    }

    #[test]
    fn a_set_is_named_by_its_lowest_member_whatever_the_order_of_the_joins() {
        let mut a = Sets::new(6);
        a.join(5, 3);
        a.join(3, 1);
        a.join(4, 2);
        let mut b = Sets::new(6);
        b.join(1, 3);
        b.join(2, 4);
        b.join(3, 5);
        for i in 0..6 {
            assert_eq!(a.root(i), b.root(i));
        }
        assert_eq!((a.root(5), a.root(4), a.root(0)), (1, 2, 0));
    }
}
