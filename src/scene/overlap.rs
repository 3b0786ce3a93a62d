//! Initial particles must not overlap one another.
//!
//! `[[particles]]` and `[[lattice]]` entries were never checked against each other: two
//! lattices offset by half a spacing started 13 % overlapped, and two coincident beads in
//! vacuum with ε = 1 lost 80 % of their energy in micro-bounces while the contact solver pulled
//! them apart. Touching is allowed (gap 0, as for walls); overlapping by more than round-off is
//! not: centres closer than `(1 − 10⁻⁹)(rᵢ + rⱼ)`, less an allowance of 10⁻¹⁵ of the larger
//! coordinate for the round-off of positions computed as `min + spacing·(i + ½)`.
//!
//! The check is a cell grid with one level per power of two of the diameters: a particle of
//! diameter d goes to the level whose cells are the smallest power-of-two multiple of the
//! smallest diameter that is ≥ d. Each pair is looked at from the finer of its two levels:
//! within a level, a cell and the 13 cells after it (a sweep over the sorted cells, no hash
//! map); towards each coarser level, the 27 cells around the particle there (binary search).
//! Any two overlapping particles are at most one cell of the coarser level apart, so nothing
//! is missed, and a few large particles do not put all the small ones in one cell. A cell of
//! side s holds at most 64 particles that do not overlap (their diameters exceed s/2), so the
//! work is linear in the number of particles until pairs do overlap; the count of overlapping
//! pairs stops at [`MAX_PAIRS_COUNTED`].

use super::error::Invalid;
use super::error::fmt::{num, vec3};
use super::fill::{Origins, describe, origin_key};
use crate::particles::Particles;
use glam::DVec3;
use std::ops::Range;

/// Relative tolerance on the sum of radii: closer than `(1 − TOLERANCE)(rᵢ + rⱼ)` overlaps.
const TOLERANCE: f64 = 1e-9;

/// Allowance for the round-off of the positions themselves, relative to the larger coordinate.
const POSITION_ROUND_OFF: f64 = 1e-15;

/// A cell of one level: `(level, z, y, x)`, sorted so that a row of cells (same level, z and
/// y) is contiguous.
type Key = (u8, i64, i64, i64);

/// The particles of one cell: `entries[start..end]`.
#[derive(Debug, Clone, Copy)]
struct Run {
    key: Key,
    start: usize,
    end: usize,
}

/// Most overlapping pairs counted. Beyond it the search stops, so that a scene of many
/// coincident particles (each cell holding thousands) costs no more than this many tests more
/// than a clean one; the message then says "at least".
const MAX_PAIRS_COUNTED: usize = 1_000_000;

/// The overlapping pairs met so far: how many, and the one to name: the pair whose later
/// particle was created first, and among those the earliest partner.
struct Search<'a> {
    p: &'a Particles,
    pairs: usize,
    first: Option<(usize, usize, f64)>,
}

impl Search<'_> {
    fn test(&mut self, a: usize, b: usize) {
        let (earlier, later) = if a < b { (a, b) } else { (b, a) };
        let (p, xa, xb) = (self.p, self.p.pos[a], self.p.pos[b]);
        let reach = 0.5 * (p.diameter[a] + p.diameter[b]);
        let allowance = TOLERANCE * reach + POSITION_ROUND_OFF * xa.abs().max(xb.abs()).max_element();
        let depth = reach - (xa - xb).length();
        if depth > allowance {
            self.pairs += 1;
            if self.first.is_none_or(|(l, e, _)| (later, earlier) < (l, e)) {
                self.first = Some((later, earlier, depth));
            }
        }
    }

    /// Tests `i` against every particle of `cells`.
    fn against(&mut self, i: usize, cells: &[Run], entries: &[(Key, u32)]) {
        for cell in cells {
            for e in &entries[cell.start..cell.end] {
                self.test(i, e.1 as usize);
            }
        }
    }

    fn done(&self) -> bool {
        self.pairs >= MAX_PAIRS_COUNTED
    }
}

/// Refuses initial particles that overlap one another, naming both (their scene entries and
/// positions), the overlap and how many pairs overlap in all.
pub(super) fn check_no_overlap(origins: &Origins, p: &Particles) -> Result<(), Invalid> {
    let n = p.len();
    if n < 2 {
        return Ok(());
    }
    let d_min = p.diameter.iter().copied().fold(f64::INFINITY, f64::min);
    let level_of = |d: f64| {
        let mut l = (d / d_min).log2().ceil().max(0.0) as i32;
        while d_min * 2f64.powi(l) < d {
            l += 1;
        }
        l as u8
    };
    // Cell sizes are d_min times powers of two, so a particle's cell at a coarser level is its
    // cell at its own level shifted right: dividing by a power of two is exact.
    let key = |x: DVec3, l: u8| -> Key {
        let c = (x / (d_min * 2f64.powi(l as i32))).floor();
        (l, c.z as i64, c.y as i64, c.x as i64)
    };
    // Sorted by cell, and within a cell by index.
    let mut entries: Vec<(Key, u32)> =
        (0..n).map(|i| (key(p.pos[i], level_of(p.diameter[i])), i as u32)).collect();
    entries.sort_unstable();
    let mut runs: Vec<Run> = Vec::new();
    for (k, e) in entries.iter().enumerate() {
        match runs.last_mut() {
            Some(run) if run.key == e.0 => run.end = k + 1,
            _ => runs.push(Run { key: e.0, start: k, end: k + 1 }),
        }
    }
    // Each level present, with its runs.
    let mut levels: Vec<(u8, Range<usize>)> = Vec::new();
    for (k, run) in runs.iter().enumerate() {
        match levels.last_mut() {
            Some((l, r)) if *l == run.key.0 => r.end = k + 1,
            _ => levels.push((run.key.0, k..k + 1)),
        }
    }

    let mut search = Search { p, pairs: 0, first: None };
    sweep(&mut search, &entries, &runs, &levels);
    let Some((b, a, depth)) = search.first else { return Ok(()) };
    let smaller = p.diameter[a].min(p.diameter[b]);
    let more = match search.pairs {
        1 => String::new(),
        k if search.done() => format!("; at least {k} pairs overlap"),
        k => format!("; {k} pairs overlap in all"),
    };
    Err(Invalid::new(
        origin_key(origins, b),
        format!(
            "{} at {} (d = {} m) overlaps {} at {} (d = {} m) by {depth:.3e} m, {:.0} % of the smaller \
             diameter{more}; particles may start touching (gap 0) but not overlapping",
            describe(origins, b),
            vec3(p.pos[b].to_array()),
            num(p.diameter[b]),
            describe(origins, a),
            vec3(p.pos[a].to_array()),
            num(p.diameter[a]),
            100.0 * depth / smaller,
        ),
    ))
}

/// Tests every pair of particles that may overlap, once, until the search is done.
fn sweep(search: &mut Search, entries: &[(Key, u32)], runs: &[Run], levels: &[(u8, Range<usize>)]) {
    let members = |run: &Run| entries[run.start..run.end].iter().map(|e| e.1 as usize);
    // The runs of the cells from `from` to `to` (keys, inclusive) among `within`, found by
    // binary search: among one level's runs, so that a few large particles are found among
    // few runs, not among the million small ones.
    let between = |within: &Range<usize>, from: Key, to: Key| {
        let level = &runs[within.clone()];
        let lo = level.partition_point(|r| r.key < from);
        let hi = level.partition_point(|r| r.key <= to);
        within.start + lo..within.start + hi.max(lo)
    };
    // One cursor per row of cells after the current one (same level): y + 1 in the same z
    // plane, and y − 1, y, y + 1 in the next one. Keys shifted by a fixed offset keep their
    // order, so each cursor only moves forward: the sweep is linear.
    const ROWS: [(i64, i64); 4] = [(0, 1), (1, -1), (1, 0), (1, 1)];
    let mut cursors = [0usize; 4];
    // Per coarser level, the last coarse cell looked up and the runs of its 3 × 3 rows of
    // neighbours: consecutive cells of a row often share their coarse cell, and the binary
    // searches are most of the cost with several sizes.
    let mut memo: Vec<Option<(Key, [Range<usize>; 9])>> = vec![None; levels.len()];
    for (ci, run) in runs.iter().enumerate() {
        let (level, z, y, x) = run.key;
        let next = runs.get(ci + 1).filter(|r| r.key == (level, z, y, x + 1));
        for (k, i) in members(run).enumerate() {
            for j in members(run).skip(k + 1) {
                search.test(i, j);
            }
            if let Some(next) = next {
                search.against(i, std::slice::from_ref(next), entries);
            }
            if search.done() {
                return;
            }
        }
        for (cursor, (dz, dy)) in cursors.iter_mut().zip(ROWS) {
            let (from, to) = ((level, z + dz, y + dy, x - 1), (level, z + dz, y + dy, x + 1));
            while *cursor < runs.len() && runs[*cursor].key < from {
                *cursor += 1;
            }
            let end = *cursor + runs[*cursor..].iter().take_while(|r| r.key <= to).count();
            for i in members(run) {
                search.against(i, &runs[*cursor..end], entries);
                if search.done() {
                    return;
                }
            }
        }
        // Towards each coarser level: the 27 cells around the run's cell there.
        for (li, (coarser, within)) in levels.iter().enumerate().filter(|(_, (l, _))| *l > level) {
            let coarser = *coarser;
            let shift = u32::from(coarser - level);
            let c = (coarser, z >> shift, y >> shift, x >> shift);
            let rows = match &memo[li] {
                Some((k, rows)) if *k == c => rows.clone(),
                _ => {
                    let rows: [Range<usize>; 9] = std::array::from_fn(|r| {
                        let (dz, dy) = (r as i64 / 3 - 1, r as i64 % 3 - 1);
                        between(
                            within,
                            (coarser, c.1 + dz, c.2 + dy, c.3 - 1),
                            (coarser, c.1 + dz, c.2 + dy, c.3 + 1),
                        )
                    });
                    memo[li] = Some((c, rows.clone()));
                    rows
                }
            };
            // Most small particles have no large one near them.
            if rows.iter().all(|r| r.is_empty()) {
                continue;
            }
            for i in members(run) {
                for r in &rows {
                    search.against(i, &runs[r.clone()], entries);
                }
                if search.done() {
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Particles at `xs` with diameters `ds`, all from one `[[particles]]`-like group each.
    fn particles(xs: &[DVec3], ds: &[f64]) -> (Origins, Particles) {
        let mut p = Particles::default();
        let mut origins = Origins::new();
        for (i, (&x, &d)) in xs.iter().zip(ds).enumerate() {
            origins.push((i, format!("particles[{i}].position")));
            p.push(i as u32, 0, d, x, DVec3::ZERO);
        }
        (origins, p)
    }

    /// The same rule, pair by pair.
    fn brute_force(p: &Particles) -> usize {
        let mut pairs = 0;
        for a in 0..p.len() {
            for b in a + 1..p.len() {
                let reach = 0.5 * (p.diameter[a] + p.diameter[b]);
                let allowance =
                    TOLERANCE * reach + POSITION_ROUND_OFF * p.pos[a].abs().max(p.pos[b].abs()).max_element();
                if reach - (p.pos[a] - p.pos[b]).length() > allowance {
                    pairs += 1;
                }
            }
        }
        pairs
    }

    #[test]
    fn touching_particles_pass_and_the_first_overlapping_pair_is_named() {
        let xs = [DVec3::ZERO, DVec3::new(2e-3, 0.0, 0.0), DVec3::new(1e-3, 0.0, 0.0)];
        let (origins, p) = particles(&xs[..2], &[2e-3, 2e-3]);
        assert_eq!(check_no_overlap(&origins, &p), Ok(()));
        let (origins, p) = particles(&xs, &[2e-3, 2e-3, 2e-3]);
        let e = check_no_overlap(&origins, &p).unwrap_err();
        assert_eq!(e.key, "particles[2].position");
        assert!(
            e.message.starts_with("particles[2] at [0.001, 0, 0] (d = 0.002 m) overlaps particles[0]"),
            "{}",
            e.message
        );
        assert!(
            e.message.contains("by 1.000e-3 m, 50 % of the smaller diameter; 2 pairs overlap in all"),
            "{}",
            e.message
        );
    }

    #[test]
    fn many_coincident_particles_stop_the_count_and_say_at_least() {
        let n = 1500; // 1.1e6 pairs
        let (origins, p) = particles(&vec![DVec3::ZERO; n], &vec![1e-3; n]);
        let e = check_no_overlap(&origins, &p).unwrap_err();
        assert!(e.message.starts_with("particles[1] at [0, 0, 0]"), "{}", e.message);
        // Counted up to the end of the particle's cells after the limit: a lower bound.
        let at_least =
            e.message.split("at least ").nth(1).and_then(|t| t.split(' ').next()?.parse::<usize>().ok());
        assert!(at_least.is_some_and(|k| (MAX_PAIRS_COUNTED..n * (n - 1) / 2).contains(&k)), "{}", e.message);
    }

    /// `n³` touching particles of diameter `d` from `lo`, as a lattice entry makes them.
    fn lattice(p: &mut Particles, origins: &mut Origins, n: usize, d: f64, lo: DVec3) {
        origins.push((p.len(), format!("lattice[{}]", origins.len())));
        for iz in 0..n {
            for iy in 0..n {
                for ix in 0..n {
                    let x = lo + d * (DVec3::new(ix as f64, iy as f64, iz as f64) + 0.5);
                    p.push(p.len() as u32, 0, d, x, DVec3::ZERO);
                }
            }
        }
    }

    /// The timing of docs/stability.md (finding 9): `cargo test --release --lib
    /// scene::overlap::tests::a_million -- --ignored --nocapture`.
    #[test]
    #[ignore = "timing, run by hand"]
    fn a_million_touching_particles_of_one_or_three_sizes() {
        let time = |p: &Particles, origins: &Origins| {
            let t = std::time::Instant::now();
            assert_eq!(check_no_overlap(origins, p), Ok(()));
            t.elapsed().as_secs_f64()
        };
        let (mut p, mut origins) = (Particles::default(), Origins::new());
        lattice(&mut p, &mut origins, 100, 1e-3, DVec3::ZERO);
        println!("10^6 touching beads of one size: {:.3} s", time(&p, &origins));
        // Above them, touching layers of beads 10 and 100 times larger.
        lattice(&mut p, &mut origins, 10, 1e-2, DVec3::new(0.0, 0.0, 0.1));
        lattice(&mut p, &mut origins, 1, 1e-1, DVec3::new(0.0, 0.0, 0.2));
        println!("the same with 1001 beads 10 and 100 times larger: {:.3} s", time(&p, &origins));
        // Two such lattices offset by half a spacing: every bead overlaps 8 others.
        lattice(&mut p, &mut origins, 100, 1e-3, DVec3::splat(5e-4));
        let t = std::time::Instant::now();
        let e = check_no_overlap(&origins, &p).unwrap_err();
        println!("and one more offset by half a spacing: {:.3} s, {}", t.elapsed().as_secs_f64(), e.message);
    }

    proptest! {
        /// The grid finds every overlapping pair the brute force does, for diameters spanning
        /// four powers of ten (so several levels) and particles placed touching, overlapping or
        /// apart.
        #[test]
        fn grid_agrees_with_brute_force(
            spec in prop::collection::vec((0.0f64..0.02, 0.0f64..0.02, 0.0f64..0.02, -6.0f64..-2.0, 0usize..4), 2..60),
        ) {
            let mut xs: Vec<DVec3> = Vec::new();
            let mut ds: Vec<f64> = Vec::new();
            for &(x, y, z, e, how) in &spec {
                let d = 10f64.powf(e);
                let mut at = DVec3::new(x, y, z);
                if let (Some(&prev), Some(&dp), true) = (xs.last(), ds.last(), how > 0) {
                    // Touching the previous one, slightly overlapping it, or slightly apart.
                    let f = [1.0, 1.0 - 1e-6, 1.0 + 1e-6][how - 1];
                    at = prev + DVec3::new(f * 0.5 * (dp + d), 0.0, 0.0);
                }
                xs.push(at);
                ds.push(d);
            }
            let (origins, p) = particles(&xs, &ds);
            let expected = brute_force(&p);
            match check_no_overlap(&origins, &p) {
                Ok(()) => prop_assert_eq!(expected, 0),
                Err(e) => {
                    prop_assert!(expected > 0);
                    let all = if expected > 1 { format!("{expected} pairs overlap in all") } else { "overlapping".into() };
                    prop_assert!(e.message.contains(&all), "{} vs {}", expected, e.message);
                }
            }
        }
    }
}
