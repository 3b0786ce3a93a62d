//! Recursive coordinate bisection: space cut into one domain per rank, each holding about the
//! same weight of particles (docs/distributed.md, "Domains").
//!
//! A set of weighted points is cut across the longest side of its bounding box where the
//! weight below the cut is the share of the ranks below it (`⌊k/2⌋` of `k`), and each side is
//! cut again until one rank is left. The cuts depend only on the points and their order, so
//! every rank that computes them from the same list finds the same domains.

use glam::DVec3;

/// The domains: a tree of cuts with one rank at each leaf.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Domains {
    nodes: Vec<Node>,
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
enum Node {
    /// Everything here belongs to this rank.
    Rank(u32),
    /// Points with `x[axis] < at` go to node `below`, the others to `above`.
    Cut { axis: u8, at: f64, below: u32, above: u32 },
}

impl Domains {
    /// The domains of `size` ranks for `points` (position and weight), each rank's share of
    /// the weight as equal as the points allow.
    pub fn bisect(points: &[(DVec3, f64)], size: usize) -> Self {
        let mut nodes = Vec::new();
        let mut order: Vec<usize> = (0..points.len()).collect();
        cut(points, &mut order, (0, size.max(1)), &mut nodes);
        Domains { nodes }
    }

    /// The rank whose domain holds `x`.
    pub fn owner(&self, x: DVec3) -> usize {
        let mut node = 0;
        loop {
            match self.nodes[node] {
                Node::Rank(r) => return r as usize,
                Node::Cut { axis, at, below, above } => {
                    node = if x[axis as usize] < at { below } else { above } as usize;
                }
            }
        }
    }
}

/// Cuts `order` (indices into `points`) among ranks `first..first + count`, pushing the nodes;
/// returns the index of the subtree's root.
fn cut(
    points: &[(DVec3, f64)],
    order: &mut [usize],
    (first, count): (usize, usize),
    nodes: &mut Vec<Node>,
) -> u32 {
    let me = nodes.len() as u32;
    if count == 1 {
        nodes.push(Node::Rank(first as u32));
        return me;
    }
    nodes.push(Node::Rank(first as u32));
    let (lo, hi) = order.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| {
        (lo.min(points[i].0), hi.max(points[i].0))
    });
    let extent = if order.is_empty() { DVec3::ZERO } else { hi - lo };
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    // By coordinate, then index (so the order is one on every rank): keys sorted in place
    // rather than comparisons through `points` (a million particles at the start).
    let mut keyed: Vec<(i64, usize)> = order.iter().map(|&i| (total_key(points[i].0[axis]), i)).collect();
    keyed.sort_unstable();
    for (o, (_, i)) in order.iter_mut().zip(keyed) {
        *o = i;
    }
    let below_ranks = count / 2;
    let total: f64 = order.iter().map(|&i| points[i].1).sum();
    let share = total * below_ranks as f64 / count as f64;
    // The upper side starts where the weight below is nearest the share, between two points
    // of different coordinates (points on one plane cannot be parted by a cut across it).
    let coordinate = |k: usize| points[order[k]].0[axis];
    let mut acc = 0.0;
    let mut split = 0;
    let mut best = f64::INFINITY;
    for k in 0..=order.len() {
        let between = k == 0 || k == order.len() || coordinate(k - 1) < coordinate(k);
        if between && (acc - share).abs() < best {
            (best, split) = ((acc - share).abs(), k);
        }
        if k < order.len() {
            acc += points[order[k]].1;
        }
    }
    let at = match split {
        0 => order.first().map_or(0.0, |_| coordinate(0)),
        k if k == order.len() => coordinate(k - 1) + 1.0,
        k => 0.5 * (coordinate(k - 1) + coordinate(k)),
    };
    let (lower, upper) = order.split_at_mut(split);
    let below = cut(points, lower, (first, below_ranks), nodes);
    let above = cut(points, upper, (first + below_ranks, count - below_ranks), nodes);
    nodes[me as usize] = Node::Cut { axis: axis as u8, at, below, above };
    me
}

/// An integer that orders as [`f64::total_cmp`] orders `x`.
fn total_key(x: f64) -> i64 {
    let bits = x.to_bits() as i64;
    bits ^ (((bits >> 63) as u64) >> 1) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lattice 10 points wide, in planes of 100 points 3 apart.
    fn grid(n: usize) -> Vec<(DVec3, f64)> {
        (0..n)
            .map(|i| (DVec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64 * 3.0), 1.0))
            .collect()
    }

    /// The lattice moved by a different small amount at each point: no two coordinates equal.
    fn jittered(n: usize) -> Vec<(DVec3, f64)> {
        let frac = |x: f64| x - x.floor();
        grid(n)
            .into_iter()
            .enumerate()
            .map(|(i, (x, w))| {
                let i = i as f64;
                (x + 0.1 * DVec3::new(frac(i * 0.618_034), frac(i * 0.414_214), frac(i * 0.732_051)), w)
            })
            .collect()
    }

    fn counts(points: &[(DVec3, f64)], size: usize) -> Vec<usize> {
        let d = Domains::bisect(points, size);
        let mut counts = vec![0usize; size];
        for (x, _) in points {
            counts[d.owner(*x)] += 1;
        }
        counts
    }

    #[test]
    fn the_sort_key_orders_as_total_cmp() {
        let xs = [-f64::INFINITY, -2.5, -1e-300, -0.0, 0.0, 1e-300, 3.0, f64::INFINITY];
        for a in xs {
            for b in xs {
                assert_eq!(total_key(a).cmp(&total_key(b)), a.total_cmp(&b), "{a} {b}");
            }
        }
    }

    #[test]
    fn bisection_gives_every_rank_an_equal_share_of_equal_points() {
        let points = jittered(1000);
        for size in [1, 2, 3, 4, 7, 16] {
            let counts = counts(&points, size);
            let (lo, hi) = (*counts.iter().min().unwrap(), *counts.iter().max().unwrap());
            // A cut misses its share by half a point at most, at each of ⌈log₂ 16⌉ levels.
            assert!(hi - lo <= 4, "{size} ranks: {counts:?}");
        }
    }

    #[test]
    fn a_cut_never_parts_points_of_one_plane_and_falls_between_planes() {
        // 1000 lattice points in 10 planes of 100 (across z, the longest side): 3 ranks get
        // whole planes, the shares nearest a third.
        assert_eq!(counts(&grid(1000), 3), vec![300, 300, 400]);
        assert_eq!(counts(&grid(1000), 2), vec![500, 500]);
    }

    #[test]
    fn a_heavy_point_takes_a_domain_of_its_own() {
        let mut points = grid(100);
        points[0].1 = 100.0;
        let d = Domains::bisect(&points, 2);
        let owner0 = d.owner(points[0].0);
        let with0 = points.iter().filter(|(x, _)| d.owner(*x) == owner0).count();
        // Only with the nine points of its own lattice line, which no cut across x can part.
        assert_eq!(with0, 10, "the heavy point shares its domain with {} others", with0 - 1);
    }

    #[test]
    fn fewer_points_than_ranks_leave_ranks_empty_without_failing() {
        let points = vec![(DVec3::ZERO, 1.0), (DVec3::X, 1.0)];
        let d = Domains::bisect(&points, 5);
        assert_ne!(d.owner(DVec3::ZERO), d.owner(DVec3::X));
        assert!(Domains::bisect(&[], 3).owner(DVec3::ONE) < 3);
    }
}
