//! The broad phase's pairs: a Verlet neighbour list on a cell grid, rebuilt only when a particle has
//! moved more than half the skin since the last build.
//!
//! How far particles moved is bounded without a per-particle test in the common step: the sum of
//! each step's largest move bounds every particle's distance from its reference position. Only
//! when that bound reaches half the skin are the distances measured, particle by particle; the
//! list is rebuilt only if one of them really does.

use crate::contact::FastMap;
use glam::{DVec3, IVec3};
use rayon::prelude::*;

/// Candidate particle pairs within `r_i + r_j + skin` at the last build.
#[derive(Debug, Clone, Default)]
pub struct Neighbours {
    /// Pairs `(i, j)`, `i < j`, in increasing order.
    pub pairs: Vec<[u32; 2]>,
    /// Positions at the last build.
    reference: Vec<DVec3>,
    /// Extra distance (m) beyond contact kept in the list.
    skin: f64,
    /// Upper bound (m) on every particle's distance from its reference position at the end of
    /// the last step.
    drift: f64,
    /// Builds so far (for statistics and tests).
    pub builds: u64,
}

impl Neighbours {
    /// Forces a rebuild at the next [`Neighbours::update`] (particles added or removed).
    pub fn invalidate(&mut self) {
        self.reference.clear();
    }

    /// Makes the list valid for the moves of this step, from `start` to `end`; `step_move` is
    /// the largest of them, from the broad phase's pass over the particles. The list is rebuilt
    /// from `start` when a particle may have come within half the skin of leaving it. The skin
    /// is `skin_fraction` of the largest diameter, grown to four times the largest move of the
    /// step if that is larger (a fast particle is never missed).
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
        let valid = |moved: f64| 2.0 * step_move < self.skin && moved < 0.5 * self.skin;
        if self.reference.len() == n {
            if valid(self.drift + step_move) {
                self.drift += step_move;
                return;
            }
            // The bound is spent: measure.
            let reference = &self.reference;
            let moved = end
                .par_iter()
                .zip(reference)
                .with_min_len(4096)
                .map(|(x, r)| (*x - *r).length_squared())
                .reduce(|| 0.0, f64::max)
                .sqrt();
            if valid(moved) {
                self.drift = moved;
                return;
            }
        }
        let d_max = diameter.par_iter().copied().reduce(|| 0.0, f64::max);
        self.skin = (skin_fraction * d_max).max(4.0 * step_move).max(f64::MIN_POSITIVE);
        self.reference = start.to_vec();
        self.drift = step_move;
        self.pairs = build(start, diameter, d_max + self.skin, self.skin);
        self.builds += 1;
    }
}

/// All pairs closer than `r_i + r_j + skin`, on a grid of `cell`-sized cells.
fn build(x: &[DVec3], diameter: &[f64], cell: f64, skin: f64) -> Vec<[u32; 2]> {
    let key = |p: DVec3| (p / cell).floor().as_ivec3();
    let mut order: Vec<(IVec3, u32)> = x.par_iter().enumerate().map(|(i, p)| (key(*p), i as u32)).collect();
    order.par_sort_unstable_by_key(|&(c, i)| (c.x, c.y, c.z, i));
    let mut cells: FastMap<IVec3, (usize, usize)> = FastMap::default();
    let mut start = 0;
    for k in 1..=order.len() {
        if k == order.len() || order[k].0 != order[start].0 {
            cells.insert(order[start].0, (start, k));
            start = k;
        }
    }
    let per_particle: Vec<Vec<[u32; 2]>> = (0..x.len())
        .into_par_iter()
        .with_min_len(256)
        .map(|i| {
            let c = key(x[i]);
            let mut found = Vec::new();
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        // Wrapping: a cell index saturates for a position far beyond the cell
                        // size (the float-to-int cast saturates), and its neighbour must not
                        // overflow.
                        let Some(&(a, b)) = cells.get(&c.wrapping_add(IVec3::new(dx, dy, dz))) else {
                            continue;
                        };
                        for &(_, j) in &order[a..b] {
                            let j = j as usize;
                            if j > i {
                                let reach = 0.5 * (diameter[i] + diameter[j]) + skin;
                                if (x[j] - x[i]).length_squared() < reach * reach {
                                    found.push([i as u32, j as u32]);
                                }
                            }
                        }
                    }
                }
            }
            found.sort_unstable();
            found
        })
        .collect();
    per_particle.into_iter().flatten().collect()
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
                if (x[j] - x[i]).length() < 4e-3 + nb.skin {
                    brute.push([i as u32, j as u32]);
                }
            }
        }
        assert_eq!(nb.pairs, brute);
        assert!(!brute.is_empty());
    }
}
