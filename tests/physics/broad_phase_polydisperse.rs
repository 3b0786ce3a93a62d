//! The broad phase with particles of very different sizes (issue 13, finding 5): one large bead
//! among many fines must not make the fines' neighbour list grow with the large bead's size, and
//! the hierarchical grid must miss no pair that can touch, for size ratios up to 100.

use glam::DVec3;
use proptest::prelude::*;
use proptest::test_runner::Config;
use wetbounce::contact::Neighbours;

/// `side³` fines of 100 µm on a cubic lattice at 120 µm (20 µm apart), and one 10 mm bead (100
/// fines' diameters) beside the lattice, 20 µm from the face `x = extent`, first in the columns
/// (index 0) as a scene's `[[particles]]` would be.
fn fines_and_one_large_bead(side: usize) -> (Vec<DVec3>, Vec<f64>) {
    let (fine, spacing, large) = (1e-4, 1.2e-4, 1e-2);
    let extent = side as f64 * spacing;
    let mut x =
        vec![DVec3::new(extent - 0.5 * spacing + 0.5 * (fine + large) + 2e-5, 0.5 * extent, 0.5 * extent)];
    let mut d = vec![large];
    for iz in 0..side {
        for iy in 0..side {
            for ix in 0..side {
                x.push(spacing * (DVec3::new(ix as f64, iy as f64, iz as f64) + 0.5));
                d.push(fine);
            }
        }
    }
    (x, d)
}

/// Issue 13, finding 5. With one grid sized by the largest bead (cell 15 mm, skin 5 mm) the
/// whole lattice fell in one cell: every fine was tested against every other one (2.4·10⁸
/// tests, ~11,000 per fine) and paired with nearly all of them (over 10⁸ pairs, gigabytes): this
/// test failed on the pair count. On the fines' own level (cell `d + s` = 150 µm: at most 2
/// lattice points per axis in a cell, so at most 8 fines in each of the 27 cells around a fine)
/// a fine makes at most 216 tests whatever the large bead's size, and one more against the large
/// bead when it is within the large bead's 27 cells: at most 217 per fine, and exactly one more
/// than without the large bead.
#[test]
fn one_bead_100_times_larger_beside_20000_fines_adds_one_distance_test_per_fine_and_no_fine_pair() {
    let side = 28;
    let (x, d) = fines_and_one_large_bead(side);
    let fines = x.len() - 1;
    assert!(fines >= 20_000);
    let mut nb = Neighbours::default();
    nb.update((&x, &x), &d, 0.0, 0.5);
    let mut alone = Neighbours::default();
    alone.update((&x[1..], &x[1..]), &d[1..], 0.0, 0.5);
    // The fines' reach is 100 µm + their own skin (50 µm): each fine pairs with the fines next
    // to it on the lattice (120 µm) and no farther one (170 µm on a diagonal).
    assert_eq!(alone.pairs.len(), 3 * side * side * (side - 1));
    // With the large bead: the same fine pairs, and the large bead with the fines within its
    // reach (10.1 mm / 2 + (5 mm + 50 µm) / 2), the fines nearest its face.
    let reach = 0.5 * (d[0] + d[1]) + 0.5 * (nb.skin_of(0) + nb.skin_of(1));
    let mut expected: Vec<[u32; 2]> =
        (1..x.len()).filter(|&j| (x[j] - x[0]).length() < reach).map(|j| [0, j as u32]).collect();
    assert!(!expected.is_empty() && expected.len() < fines);
    expected.extend(alone.pairs.iter().map(|&[i, j]| [i + 1, j + 1]));
    assert_eq!(nb.pairs, expected);
    let fines = fines as u64;
    assert_eq!(nb.distance_tests, alone.distance_tests + fines);
    assert!(nb.distance_tests <= 217 * fines, "{} distance tests for {fines} fines", nb.distance_tests);
}

/// Particles of random sizes, `ratio` (1 to 100) from the smallest to the largest, some of them
/// far from the others or on top of another, and how each moves per step.
#[derive(Debug, Clone)]
struct Cloud {
    x: Vec<DVec3>,
    d: Vec<f64>,
    /// Each particle's move per step (m).
    v: Vec<DVec3>,
    skin_fraction: f64,
}

fn cloud() -> impl Strategy<Value = Cloud> {
    let sizes = (-5.0f64..-2.0, 0.0f64..=2.0, 0.05f64..1.0);
    // How fast particles move: in their own diameters (0), all in the smallest one's (1: large
    // particles slow for their size, fines fast for theirs), or each either way (2).
    (2usize..120, sizes, 0u8..3).prop_flat_map(|(n, (log_d0, log_ratio, skin_fraction), units)| {
        let (d0, ratio) = (10f64.powf(log_d0), 10f64.powf(log_ratio));
        // A box a few large diameters wide: fines crowd, the large ones overlap many.
        let side = d0 * ratio * 3.0;
        // Per particle: size (0 the smallest, 1 the largest, both ends often), place, where it
        // goes (0: in the box, 1: far away, 2: on top of an earlier one, 3: a little apart from
        // the one before, so that gaps close within a few steps), move.
        let particle = (
            prop_oneof![Just(0.0), Just(1.0), 0.0f64..=1.0],
            (0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0),
            prop_oneof![4 => Just(0u8), 1 => Just(1u8), 1 => Just(2u8), 4 => Just(3u8)],
            (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            prop_oneof![2 => Just(0.0), 12 => 0.0f64..0.05, 1 => 0.0f64..2.0],
            any::<bool>(),
        );
        proptest::collection::vec(particle, n).prop_map(move |ps| {
            let mut x: Vec<DVec3> = Vec::new();
            let (mut d, mut v) = (Vec::new(), Vec::new());
            for (k, (size, (a, b, c), place, (vx, vy, vz), speed, own)) in ps.into_iter().enumerate() {
                let di = d0 * ratio.powf(size);
                let p = match place {
                    1 => DVec3::new(a, b, c) * side + DVec3::new(1e3, -1e6, 1e9) * side,
                    2 if k > 0 => x[(a * k as f64) as usize],
                    3 if k > 0 => {
                        // Up to twice the pair's skin beyond contact: half of them begin
                        // outside the list.
                        let gap = (0.5 * (d[k - 1] + di)) * (1.0 + 2.0 * skin_fraction * a);
                        x[k - 1] + gap * DVec3::new(b - 0.5, c - 0.5, a - 0.5).normalize_or(DVec3::X)
                    }
                    _ => DVec3::new(a, b, c) * side,
                };
                x.push(p);
                d.push(di);
                // Towards the one before if placed by it, else the middle of the box, so that
                // gaps close over the steps: mostly slow (up to 5 % of a diameter per step: a
                // list kept over steps), now and then up to 2 diameters (rebuilds, skins grown
                // to the moves).
                let own = units == 0 || (units == 2 && own);
                let target = if place == 3 && k > 0 { x[k - 1] } else { DVec3::splat(0.5 * side) };
                let towards = (target - p).normalize_or_zero() + 0.5 * DVec3::new(vx, vy, vz);
                v.push(towards * speed * if own { di } else { d0 });
            }
            Cloud { x, d, v, skin_fraction }
        })
    })
}

/// Every pair within `r_i + r_j + (s_i + s_j)/2` of each other, by testing them all.
fn brute_force(nb: &Neighbours, x: &[DVec3], d: &[f64]) -> Vec<[u32; 2]> {
    let mut pairs = Vec::new();
    for i in 0..x.len() {
        for j in i + 1..x.len() {
            let reach = 0.5 * (d[i] + d[j]) + 0.5 * (nb.skin_of(i) + nb.skin_of(j));
            if (x[j] - x[i]).length_squared() < reach * reach {
                pairs.push([i as u32, j as u32]);
            }
        }
    }
    pairs
}

/// The distance of closest approach of `i` and `j` moving straight from `a` to `b` (m).
fn closest_approach(a: &[DVec3], b: &[DVec3], i: usize, j: usize) -> f64 {
    let start = a[i] - a[j];
    let change = (b[i] - b[j]) - start;
    let lambda = (-start.dot(change) / change.length_squared()).clamp(0.0, 1.0);
    if lambda.is_finite() { (start + lambda * change).length() } else { start.length() }
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

proptest! {
    #![proptest_config(Config { cases: 1024, failure_persistence: None, ..Config::default() })]

    /// The list holds exactly the pairs a brute-force search finds, with each particle's skin
    /// its own level's (between its own `skin_fraction · d` and twice that), the same with one
    /// and two threads.
    #[test]
    fn finds_exactly_the_brute_force_pairs_for_size_ratios_up_to_100(c in cloud()) {
        let build = || {
            let mut nb = Neighbours::default();
            nb.update((&c.x, &c.x), &c.d, 0.0, c.skin_fraction);
            nb
        };
        let (one, two) = (in_pool(1, build), in_pool(2, build));
        prop_assert_eq!(&one.pairs, &two.pairs);
        prop_assert_eq!(one.distance_tests, two.distance_tests);
        prop_assert_eq!(&one.pairs, &brute_force(&one, &c.x, &c.d));
        for (i, &d) in c.d.iter().enumerate() {
            let s = one.skin_of(i);
            prop_assert!(s >= c.skin_fraction * d && s <= 2.0 * c.skin_fraction * d * (1.0 + 1e-12),
                "particle {i}: skin {s}, diameter {d}");
        }
    }

    /// Over steps of straight moves, every pair that comes within contact during a step is in
    /// the list of that step, and a rebuilt list is again exactly the brute-force pairs.
    #[test]
    fn every_pair_that_touches_in_a_step_is_in_that_steps_list(c in cloud()) {
        let mut nb = Neighbours::default();
        let mut x = c.x.clone();
        for _ in 0..16 {
            let next: Vec<DVec3> = x.iter().zip(&c.v).map(|(x, v)| *x + *v).collect();
            let step_move = x.iter().zip(&next).map(|(a, b)| (*b - *a).length()).fold(0.0, f64::max);
            let builds = nb.builds;
            nb.update((&x, &next), &c.d, step_move, c.skin_fraction);
            if nb.builds > builds {
                prop_assert_eq!(&nb.pairs, &brute_force(&nb, &x, &c.d));
            }
            for i in 0..x.len() {
                for j in i + 1..x.len() {
                    if closest_approach(&x, &next, i, j) <= 0.5 * (c.d[i] + c.d[j]) {
                        prop_assert!(nb.pairs.binary_search(&[i as u32, j as u32]).is_ok(),
                            "pair {i}, {j} touches in the step but is not in the list");
                    }
                }
            }
            x = next;
        }
    }
}

/// Two fines closing head-on at a steady speed beside a large bead at rest: whatever the speed
/// and the starting gap, the pair is in the list at every step in which they touch. The fines'
/// skin is 50 µm and the large bead's 5 mm, so only the fines' own moves may call a rebuild;
/// a bound that let them drift by more than half their own skin — or forgot the step of a
/// build — misses the contact for some of these speeds.
#[test]
fn fines_closing_head_on_beside_a_large_bead_are_listed_in_every_step_they_touch() {
    let (fine, large) = (1e-4, 1e-2);
    let d = [large, fine, fine];
    for gap_steps in 0..12 {
        for speed_steps in 1..40 {
            // Each fine moves `u` per step, 0.25 µm to 10 µm; the gap beyond contact starts at
            // 50 µm (the pair's skin) to 105 µm.
            let u = 2.5e-7 * speed_steps as f64;
            let gap = 5e-5 + 5e-6 * gap_steps as f64;
            let mut x = [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(0.02, 0.0, 0.0),
                DVec3::new(0.02 + fine + gap, 0.0, 0.0),
            ];
            let v = [DVec3::ZERO, DVec3::new(u, 0.0, 0.0), DVec3::new(-u, 0.0, 0.0)];
            let mut nb = Neighbours::default();
            for step in 0..(gap / (2.0 * u)) as usize + 3 {
                let next = [x[0] + v[0], x[1] + v[1], x[2] + v[2]];
                nb.update((&x, &next), &d, u, 0.5);
                if closest_approach(&x, &next, 1, 2) <= fine {
                    assert!(
                        nb.pairs.contains(&[1, 2]),
                        "u = {u}, gap = {gap}: the fines touch in step {step} but are not listed"
                    );
                }
                x = next;
            }
        }
    }
}
