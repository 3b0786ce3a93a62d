//! The broad phase's pairs: a Verlet neighbour list on a hierarchy of cell grids, rebuilt only
//! when a particle has moved more than half its skin since the last build.
//!
//! **Levels.** Particles are binned by diameter: level `k` holds the diameters in
//! `[2^k, 2^(k+1))` times the smallest. Each level has its own skin, `skin_fraction` times the
//! largest diameter it holds (grown to four times the largest move of the step in it), and its
//! own cell grid. A pair is kept when `|x_i − x_j| < r_i + r_j + (s_i + s_j)/2`, `s` the skin of
//! each one's level; the list then holds every pair that can touch while no particle has moved
//! half its own skin. A fine's skin is thus a fine's, never the largest bead's: one sphere among
//! fines neither makes the fines' list longer nor their cells coarser.
//!
//! **Cells.** A level's cell is the largest reach between one of its particles and one of its
//! own or a finer level, so a particle finds all its partners at a coarser (or its own) level in
//! the 27 cells around it. Each particle looks at its own level (partners of a higher index) and
//! at every coarser level (clipped to the cells that level occupies), so each pair is found once,
//! from its finer member. With one level (diameters within a factor 2: every shipped scene)
//! this is the uniform grid of cell `d_max + skin`, as before.
//!
//! **Drift.** How far particles moved is bounded without a per-particle test in the common
//! step: the sum of each step's largest move bounds every particle's distance from its reference
//! position, and is compared with half the smallest skin (less, for a level of a larger skin,
//! the difference of the two halves — see [`Neighbours::update`]). Only when that bound is spent
//! are the distances measured, level by level against each level's skin; the list is rebuilt
//! only if one of them really is too far.

use crate::contact::FastMap;
use glam::{DVec3, I64Vec3, IVec3};
use rayon::prelude::*;

/// Most levels: a diameter 2^63 times the smallest or more shares the top level (correct still,
/// since a level's cell is sized by what it holds; only slower).
const MAX_LEVEL: u8 = 63;
/// Particles per task of the build: fixed, so that the work and the order of its results do
/// not depend on the thread count.
const CHUNK: usize = 256;

/// Candidate particle pairs within `r_i + r_j + (s_i + s_j)/2` at the last build, `s` the skin of
/// each particle's size level (module doc).
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Neighbours {
    /// Pairs `(i, j)`, `i < j`, in increasing order.
    pub pairs: Vec<[u32; 2]>,
    /// Positions at the last build.
    reference: Vec<DVec3>,
    /// Each particle's level at the last build; empty when every particle is on level 0.
    level: Vec<u8>,
    /// Each level's skin (m): extra distance beyond contact kept in the list; +∞ for a level
    /// holding no particle.
    skins: Vec<f64>,
    /// The smallest and the largest skin of a level holding particles (m).
    skin_min: f64,
    skin_max: f64,
    /// Upper bound (m) on every particle's distance from its reference position at the end of
    /// the last step, less half the difference between its level's skin and the smallest one.
    drift: f64,
    /// Builds so far (for statistics and tests).
    pub builds: u64,
    /// Distance tests made by the last build (for statistics and tests: a measure of its work
    /// that does not depend on timing or on the thread count).
    pub distance_tests: u64,
}

impl Neighbours {
    /// Forces a rebuild at the next [`Neighbours::update`] (particles added or removed).
    pub fn invalidate(&mut self) {
        self.reference.clear();
    }

    /// The skin (m) particle `i` had at the last build: its pairs reach
    /// `r_i + r_j + (skin_of(i) + skin_of(j))/2`. Panics if `i` was not in the last build of two
    /// particles or more.
    pub fn skin_of(&self, i: usize) -> f64 {
        if self.level.is_empty() { self.skins[0] } else { self.skins[self.level[i] as usize] }
    }

    /// Makes the list valid for the moves of this step, from `start` to `end`; `step_move` is
    /// the largest of them, from the broad phase's pass over the particles. The list is rebuilt
    /// from `start` when a particle may have come within half its skin of leaving it. A level's
    /// skin is `skin_fraction` of its largest diameter, grown to four times the largest move in
    /// the level this step if that is larger (a fast particle is never missed).
    ///
    /// With skins `s_k` differing between levels, one number still carries the bound:
    /// `drift` bounds `|x_i − x_i,ref| − (s_k − s_min)/2` for every particle `i` of level `k`;
    /// every particle stays within half its own skin while `drift + step_move < s_min/2`.
    pub fn update(
        &mut self,
        (start, end): (&[DVec3], &[DVec3]),
        diameter: &[f64],
        step_move: f64,
        skin_fraction: f64,
    ) {
        let n = start.len();
        if n < 2 {
            self.pairs.clear();
            self.reference = start.to_vec();
            self.drift = step_move;
            return;
        }
        if self.reference.len() == n {
            if 2.0 * step_move < self.skin_min && self.drift + step_move < 0.5 * self.skin_min {
                self.drift += step_move;
                return;
            }
            // The bound is spent: measure. (A particle moving more than half the largest skin
            // in one step asks for a rebuild, which grows its level's skin to fit its moves.)
            if 2.0 * step_move < self.skin_max
                && let Some(drift) = self.measure(end)
            {
                self.drift = drift;
                return;
            }
        }
        self.rebuild((start, end), diameter, step_move, skin_fraction);
    }

    /// The bound `drift` from every particle's distance to its reference at `end`, or `None` when
    /// one of them is half its skin away or more.
    fn measure(&self, end: &[DVec3]) -> Option<f64> {
        let reference = &self.reference;
        if self.level.is_empty() {
            let moved = end
                .par_iter()
                .zip(reference)
                .with_min_len(4096)
                .map(|(x, r)| (*x - *r).length_squared())
                .reduce(|| 0.0, f64::max)
                .sqrt();
            return (moved < 0.5 * self.skins[0]).then_some(moved);
        }
        let levels = self.skins.len();
        let moved = end
            .par_iter()
            .zip(reference)
            .zip(&self.level)
            .with_min_len(4096)
            .fold(
                || vec![0.0; levels],
                |mut m, ((x, r), &k)| {
                    let k = k as usize;
                    m[k] = f64::max(m[k], (*x - *r).length_squared());
                    m
                },
            )
            .reduce(|| vec![0.0; levels], max_each);
        let mut drift = f64::NEG_INFINITY;
        for (m, &s) in moved.iter().zip(&self.skins) {
            let m = m.sqrt();
            if m >= 0.5 * s {
                return None;
            }
            drift = drift.max(m - 0.5 * (s - self.skin_min));
        }
        Some(drift)
    }

    /// Rebuilds the list from `start`: levels, skins, grids, pairs.
    fn rebuild(
        &mut self,
        (start, end): (&[DVec3], &[DVec3]),
        diameter: &[f64],
        step_move: f64,
        skin_fraction: f64,
    ) {
        let (d_min, d_max) = diameter
            .par_iter()
            .map(|&d| (d, d))
            .reduce(|| (f64::INFINITY, 0.0), |a, b| (a.0.min(b.0), a.1.max(b.1)));
        let skin_of =
            |d_max: f64, moved: f64| (skin_fraction * d_max).max(4.0 * moved).max(f64::MIN_POSITIVE);
        let top = level_of(d_max, d_min);
        // Per level: the largest diameter, the largest move of the step, whether it holds any.
        let (held, cells) = if top == 0 {
            self.level.clear();
            self.skins = vec![skin_of(d_max, step_move)];
            self.drift = step_move;
            (vec![true], vec![d_max + self.skins[0]])
        } else {
            self.level = diameter.par_iter().map(|&d| level_of(d, d_min)).collect();
            let levels = top as usize + 1;
            let per_level = (&self.level, diameter, start, end)
                .into_par_iter()
                .with_min_len(4096)
                .fold(
                    || vec![(0.0f64, 0.0f64, false); levels],
                    |mut m, (&k, &d, a, b)| {
                        let m_k = &mut m[k as usize];
                        *m_k = (m_k.0.max(d), f64::max(m_k.1, (*b - *a).length_squared()), true);
                        m
                    },
                )
                .reduce(
                    || vec![(0.0f64, 0.0f64, false); levels],
                    |mut a, b| {
                        for (a, b) in a.iter_mut().zip(b) {
                            *a = (a.0.max(b.0), a.1.max(b.1), a.2 || b.2);
                        }
                        a
                    },
                );
            self.skins = per_level
                .iter()
                .map(|&(d, moved, held)| if held { skin_of(d, moved.sqrt()) } else { f64::INFINITY })
                .collect();
            let skin_min = self.skins.iter().copied().fold(f64::INFINITY, f64::min);
            // After the build every particle is its step's move from its reference.
            self.drift = per_level
                .iter()
                .zip(&self.skins)
                .filter(|((_, _, held), _)| *held)
                .map(|(&(_, moved, _), &s)| moved.sqrt() - 0.5 * (s - skin_min))
                .fold(f64::NEG_INFINITY, f64::max);
            // A level's cell: the largest reach between one of its particles and one of its own
            // level or a finer one.
            let mut widest_below: f64 = 0.0;
            let cells = per_level
                .iter()
                .zip(&self.skins)
                .map(|(&(d, _, held), &s)| {
                    if !held {
                        return 0.0;
                    }
                    widest_below = widest_below.max(d + s);
                    0.5 * (d + s + widest_below)
                })
                .collect();
            (per_level.iter().map(|l| l.2).collect(), cells)
        };
        let occupied = || self.skins.iter().zip(&held).filter(|(_, h)| **h).map(|(s, _)| *s);
        self.skin_min = occupied().fold(f64::INFINITY, f64::min);
        self.skin_max = occupied().fold(0.0, f64::max);
        self.reference = start.to_vec();
        let level = &self.level;
        let level_of_particle = |i: usize| level.get(i).map_or(0, |&k| k as usize);
        let (pairs, tests) = build(start, diameter, &self.skins, &cells, &level_of_particle);
        self.pairs = pairs;
        self.distance_tests = tests;
        self.builds += 1;
    }
}

/// Every pair `[i, j]`, `i < j`, in increasing order, whose surfaces are closer than `skin`:
/// the list's build on one level (one grid of cell `d_max + skin`), for a search with a skin of
/// its own (the clusters of ranks).
pub fn pairs_within(x: &[DVec3], diameter: &[f64], skin: f64) -> Vec<[u32; 2]> {
    let d_max = diameter.iter().copied().fold(0.0, f64::max);
    // `0.5 (s + s)` is `s` exactly: the reach is `(d_i + d_j)/2 + skin`.
    build(x, diameter, &[skin], &[(d_max + skin).max(f64::MIN_POSITIVE)], &|_| 0).0
}

/// The level of diameter `d` when the smallest is `d_min`: `⌊log₂(d / d_min)⌋`, read from the
/// quotient's exponent bits (exact, the same on every machine), at most [`MAX_LEVEL`].
fn level_of(d: f64, d_min: f64) -> u8 {
    let exponent = ((d / d_min).to_bits() >> 52) as i64 - 1023;
    exponent.clamp(0, MAX_LEVEL as i64) as u8
}

fn max_each(mut a: Vec<f64>, b: Vec<f64>) -> Vec<f64> {
    for (a, b) in a.iter_mut().zip(b) {
        *a = a.max(b);
    }
    a
}

/// What one chunk of particles found: the pairs with a partner of higher index, in order; those
/// found from the higher index, in no order; the distance tests made.
type ChunkPairs = (Vec<[u32; 2]>, Vec<[u32; 2]>, u64);

/// One level's grid: the cells it occupies, each a range of the sorted particle order.
struct Grid {
    cell: f64,
    cells: FastMap<IVec3, (u32, u32)>,
    /// The smallest and largest cell coordinates it occupies.
    lo: I64Vec3,
    hi: I64Vec3,
}

/// All pairs closer than `r_i + r_j + (s_i + s_j)/2`, each level on a grid of its `cells`-sized
/// cells (`cells[k]` is 0 for a level holding no particle); and the distance tests made.
fn build(
    x: &[DVec3],
    diameter: &[f64],
    skins: &[f64],
    cells: &[f64],
    level: &(impl Fn(usize) -> usize + Sync),
) -> (Vec<[u32; 2]>, u64) {
    let key = |p: DVec3, cell: f64| (p / cell).floor().as_ivec3();
    let mut order: Vec<(u8, IVec3, u32)> = x
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let k = level(i);
            (k as u8, key(*p, cells[k]), i as u32)
        })
        .collect();
    order.par_sort_unstable_by_key(|&(k, c, i)| (k, c.x, c.y, c.z, i));
    let mut grids: Vec<Option<Grid>> = (0..cells.len()).map(|_| None).collect();
    let mut start = 0;
    for end in 1..=order.len() {
        if end == order.len() || (order[end].0, order[end].1) != (order[start].0, order[start].1) {
            let (k, c, _) = order[start];
            let grid = grids[k as usize].get_or_insert_with(|| Grid {
                cell: cells[k as usize],
                cells: FastMap::default(),
                lo: c.as_i64vec3(),
                hi: c.as_i64vec3(),
            });
            grid.cells.insert(c, (start as u32, end as u32));
            (grid.lo, grid.hi) = (grid.lo.min(c.as_i64vec3()), grid.hi.max(c.as_i64vec3()));
            start = end;
        }
    }
    let chunks: Vec<ChunkPairs> = (0..x.len().div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            // Pairs with a partner of higher index, in order; those found from the higher
            // index (a finer particle's partner on a coarser level) apart.
            let (mut forward, mut backward, mut tests) = (Vec::new(), Vec::new(), 0u64);
            let mut partners: Vec<u32> = Vec::new();
            for i in chunk * CHUNK..x.len().min((chunk + 1) * CHUNK) {
                let own = level(i);
                partners.clear();
                for (k, grid) in grids.iter().enumerate().skip(own) {
                    let Some(grid) = grid else { continue };
                    // The 27 cells around, clipped to those the level occupies (in 64 bits: a
                    // cell index saturates for a position far beyond the cell size).
                    let c = key(x[i], grid.cell).as_i64vec3();
                    let (lo, hi) = ((c - 1).max(grid.lo), (c + 1).min(grid.hi));
                    for cz in lo.z..=hi.z {
                        for cy in lo.y..=hi.y {
                            for cx in lo.x..=hi.x {
                                let cell = IVec3::new(cx as i32, cy as i32, cz as i32);
                                let Some(&(a, b)) = grid.cells.get(&cell) else { continue };
                                for &(_, _, j) in &order[a as usize..b as usize] {
                                    let j = j as usize;
                                    if k == own && j <= i {
                                        continue;
                                    }
                                    tests += 1;
                                    let reach =
                                        0.5 * (diameter[i] + diameter[j]) + 0.5 * (skins[own] + skins[k]);
                                    if (x[j] - x[i]).length_squared() < reach * reach {
                                        if j > i {
                                            partners.push(j as u32);
                                        } else {
                                            backward.push([j as u32, i as u32]);
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
                partners.sort_unstable();
                forward.extend(partners.iter().map(|&j| [i as u32, j]));
            }
            (forward, backward, tests)
        })
        .collect();
    let tests = chunks.iter().map(|c| c.2).sum();
    let total = chunks.iter().map(|c| c.0.len()).sum();
    let mut forward = Vec::with_capacity(total);
    let mut backward = Vec::new();
    for (f, b, _) in chunks {
        forward.extend_from_slice(&f);
        backward.extend_from_slice(&b);
    }
    if backward.is_empty() {
        return (forward, tests);
    }
    // Unique pairs: the unstable sort gives the one order.
    backward.par_sort_unstable();
    (merge(&forward, &backward), tests)
}

/// The sorted union of two sorted lists with no pair in common.
fn merge(a: &[[u32; 2]], b: &[[u32; 2]]) -> Vec<[u32; 2]> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] < b[j] {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_exactly_the_pairs_a_brute_force_search_finds() {
        let x: Vec<DVec3> = (0..400)
            .map(|i| {
                let f = i as f64;
                DVec3::new((f * 0.37).sin(), (f * 0.71).cos(), (f * 0.13).sin()) * 0.05
            })
            .collect();
        let d = vec![4e-3; x.len()];
        let mut nb = Neighbours::default();
        nb.update((&x, &x), &d, 0.0, 0.5);
        let mut brute = Vec::new();
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                if (x[j] - x[i]).length() < 4e-3 + nb.skin_of(i) {
                    brute.push([i as u32, j as u32]);
                }
            }
        }
        assert_eq!(nb.pairs, brute);
        assert!(!brute.is_empty());
    }
}
