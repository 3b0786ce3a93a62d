//! Which spheres already placed a new sphere may overlap, for placing particles one at a time
//! among others of any size (the random fill, the injectors).
//!
//! The spheres are binned by diameter into levels, level `k` holding the diameters in
//! `[2^k, 2^(k+1))` times `base`, each on a grid of cell `2^k base`. A query visits, level by
//! level, the cells within reach of the new sphere — or the level's spheres one by one, when
//! they are fewer than those cells. A fine thus looks at fines' cells and at the few cells of a
//! large sphere near it, not at cells sized by the largest sphere; and a large sphere among many
//! fines costs at most one pass over them.

use crate::contact::FastMap;
use glam::{DVec3, IVec3};

/// Most levels: a diameter 2^63 times `base` or more shares the top level (the query stays
/// correct, since it visits every cell within reach whatever the cell size; only slower).
const MAX_LEVEL: usize = 63;

/// Spheres placed so far, each with an item number the caller chooses (an index into its own
/// columns), binned by size (module doc).
#[derive(Debug, Clone)]
pub(crate) struct PlacedSpheres {
    /// The smallest diameter expected (m): level 0's lower end.
    base: f64,
    levels: Vec<Level>,
}

#[derive(Debug, Clone, Default)]
struct Level {
    /// Cell size (m).
    cell: f64,
    /// The largest radius placed on this level (m).
    r_max: f64,
    /// Centre, item.
    spheres: Vec<(DVec3, u32)>,
    /// Indices into `spheres`, per cell.
    cells: FastMap<IVec3, Vec<u32>>,
}

impl PlacedSpheres {
    /// No sphere yet; `base` (m, > 0) is the smallest diameter expected (a smaller one is put on
    /// level 0, whose cells are then larger than it: correct, only slower).
    pub(crate) fn new(base: f64) -> Self {
        PlacedSpheres { base, levels: Vec::new() }
    }

    /// Places a sphere of centre `x` (m) and radius `r` (m) as `item`.
    pub(crate) fn insert(&mut self, x: DVec3, r: f64, item: u32) {
        // ⌊log₂(2r / base)⌋ from the quotient's exponent bits: exact, the same on every machine.
        let exponent = ((2.0 * r / self.base).to_bits() >> 52) as i64 - 1023;
        let k = exponent.clamp(0, MAX_LEVEL as i64) as usize;
        if self.levels.len() <= k {
            self.levels.resize_with(k + 1, Level::default);
        }
        let level = &mut self.levels[k];
        if level.spheres.is_empty() {
            level.cell = self.base * 2f64.powi(k as i32);
        }
        level.r_max = level.r_max.max(r);
        let key = (x / level.cell).floor().as_ivec3();
        level.cells.entry(key).or_default().push(level.spheres.len() as u32);
        level.spheres.push((x, item));
    }

    /// Whether `clear(item)` holds for every placed sphere that may overlap a sphere of centre
    /// `x` (m) and radius `r` (m). Every placed sphere closer than `r` plus its radius is
    /// offered (some farther ones may be too): `clear` is the caller's exact test.
    pub(crate) fn all_clear(&self, x: DVec3, r: f64, mut clear: impl FnMut(u32) -> bool) -> bool {
        self.levels.iter().filter(|l| !l.spheres.is_empty()).all(|level| {
            // A hair wider than the reach: the box's ends are rounded.
            let reach = r + level.r_max;
            let reach = reach + 1e-9 * (reach + x.abs().max_element());
            // Saturated to `i32` as the spheres' own cells are, then widened: no overflow.
            let lo = ((x - reach) / level.cell).floor().as_ivec3().as_i64vec3();
            let hi = ((x + reach) / level.cell).floor().as_ivec3().as_i64vec3();
            let span = (hi - lo + 1).as_dvec3();
            if span.x * span.y * span.z > level.spheres.len() as f64 {
                return level.spheres.iter().all(|&(_, item)| clear(item));
            }
            (lo.z..=hi.z).all(|cz| {
                (lo.y..=hi.y).all(|cy| {
                    (lo.x..=hi.x).all(|cx| {
                        let cell = IVec3::new(cx as i32, cy as i32, cz as i32);
                        level
                            .cells
                            .get(&cell)
                            .is_none_or(|list| list.iter().all(|&s| clear(level.spheres[s as usize].1)))
                    })
                })
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: the items of the spheres within `r` plus their radius of `x`.
    fn overlapping(spheres: &[(DVec3, f64)], x: DVec3, r: f64) -> Vec<u32> {
        (0..spheres.len() as u32)
            .filter(|&i| (spheres[i as usize].0 - x).length() < spheres[i as usize].1 + r)
            .collect()
    }

    #[test]
    fn offers_every_overlapping_sphere_for_sizes_a_hundredfold_apart() {
        // A fixed pseudo-random sequence: fines of 100 µm, a few beads of 1 and 10 mm.
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut grid = PlacedSpheres::new(1e-4);
        let mut spheres = Vec::new();
        for i in 0..3000u32 {
            let d = match i % 100 {
                0 => 1e-2,
                1..=4 => 1e-3,
                _ => 1e-4 * (1.0 + next()),
            };
            let x = DVec3::new(next(), next(), next()) * 0.02;
            grid.insert(x, 0.5 * d, i);
            spheres.push((x, 0.5 * d));
        }
        for _ in 0..2000 {
            let r = if next() < 0.1 { 5e-3 } else { 5e-5 };
            let x = DVec3::new(next(), next(), next()) * 0.02;
            let expected = overlapping(&spheres, x, r);
            let mut offered = Vec::new();
            grid.all_clear(x, r, |i| {
                offered.push(i);
                true
            });
            assert!(expected.iter().all(|i| offered.contains(i)), "{expected:?} not all in {offered:?}");
            let clear = grid.all_clear(x, r, |i| !expected.contains(&i));
            assert_eq!(clear, expected.is_empty());
        }
    }
}
