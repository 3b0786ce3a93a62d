use super::structured::{Axis, Structured};
use super::unstructured::{Unstructured, hexahedron_corners};
use super::*;
use crate::numeric::lanes::LANES;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A smooth field with every component varying along every axis.
fn analytic(p: DVec3) -> DVec3 {
    DVec3::new((2.0 * p.x).sin() * p.y.cos(), (p.x + p.z).cos() + p.y * p.y, p.y.sin() * p.z * p.z - p.x)
}

fn steady(grid: Grid, values: Vec<DVec3>, outside: Outside, axisymmetric: Option<Axisymmetric>) -> Field {
    let snapshots = vec![Snapshot { time: 0.0, values }];
    Field::new(grid, snapshots, None, outside, axisymmetric, FieldInfo::default())
}

/// Point data of `analytic` on an `n`-cell image of the unit cube.
fn image(n: usize, f: impl Fn(DVec3) -> DVec3) -> Field {
    let nodes: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
    let axes = [0, 1, 2].map(|_| Axis::new(nodes.clone(), 0.0, 1.0));
    let mut values = Vec::new();
    for &z in &nodes {
        for &y in &nodes {
            for &x in &nodes {
                values.push(f(DVec3::new(x, y, z)));
            }
        }
    }
    steady(Grid::Structured(Structured { axes }), values, Outside::Error, None)
}

/// The unit cube in `n³` hexahedra (VTK order), interior points moved by up to `jitter` of a
/// cell so that the cells are not boxes; or each hexahedron in six tetrahedra.
fn cube_mesh(n: usize, jitter: f64, tets: bool) -> (Vec<DVec3>, Vec<(u8, Vec<u64>)>) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let h = 1.0 / n as f64;
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u64;
    let mut points = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let mut p = DVec3::new(i as f64, j as f64, k as f64) * h;
                let interior = |a: usize| a > 0 && a < n;
                if interior(i) && interior(j) && interior(k) {
                    p += DVec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    ) * (jitter * h);
                }
                points.push(p);
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let v = hexahedron_corners(i, j, k).map(|(a, b, c)| id(a, b, c));
                if tets {
                    // Kuhn's six tetrahedra along the diagonal 0–6.
                    for path in [[1, 2], [3, 2], [1, 5], [4, 5], [3, 7], [4, 7]] {
                        cells.push((10u8, vec![v[0], v[path[0]], v[path[1]], v[6]]));
                    }
                } else {
                    cells.push((12u8, v.to_vec()));
                }
            }
        }
    }
    (points, cells)
}

fn mesh_field(n: usize, jitter: f64, tets: bool, f: impl Fn(DVec3) -> DVec3) -> Field {
    let (points, cells) = cube_mesh(n, jitter, tets);
    let mesh = Unstructured::new(points, &cells).unwrap();
    let values = mesh.nodes[..mesh.points].iter().map(|&p| f(p)).collect::<Vec<_>>();
    // Centres: the mean of the cell's vertex values, as the reader does for point data.
    let mut all = values.clone();
    for c in 0..mesh.cells() {
        let v = &mesh.cell_points[mesh.cell_offsets[c] as usize..mesh.cell_offsets[c + 1] as usize];
        all.push(v.iter().map(|&i| values[i as usize]).sum::<DVec3>() / v.len() as f64);
    }
    steady(Grid::Unstructured(mesh), all, Outside::Error, None)
}

/// Largest error against `analytic` over random points of `[lo, hi]³`.
fn max_error(field: &Field, lo: f64, hi: f64) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let f = field.at(0.0);
    (0..400)
        .map(|_| {
            let p = DVec3::new(rng.random_range(lo..hi), rng.random_range(lo..hi), rng.random_range(lo..hi));
            (f.velocity(p) - analytic(p)).length()
        })
        .fold(0.0, f64::max)
}

/// The observed orders between successive halvings of the grid spacing.
fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect()
}

#[test]
fn trilinear_field_is_second_order_in_grid_spacing() {
    let errors: Vec<f64> = [8, 16, 32].iter().map(|&n| max_error(&image(n, analytic), 0.0, 1.0)).collect();
    for p in orders(&errors) {
        assert!((1.8..2.3).contains(&p), "errors {errors:?}, orders {:?}", orders(&errors));
    }
}

#[test]
fn trilinear_field_reproduces_a_trilinear_field_exactly() {
    let f = |p: DVec3| DVec3::new(1.0 + 2.0 * p.x - p.y + 0.5 * p.x * p.y * p.z, p.z, -3.0 * p.y * p.z);
    let field = image(5, f);
    let at = field.at(0.0);
    for p in [DVec3::new(0.13, 0.77, 0.5), DVec3::new(1.0, 0.0, 0.31), DVec3::splat(0.999)] {
        assert!((at.velocity(p) - f(p)).length() < 1e-14);
    }
}

#[test]
fn cell_data_on_a_structured_grid_is_second_order_up_to_its_faces() {
    // Cell data: values at the centres; the half cell at each face is reached by extending
    // the outer cells' lines.
    let field = |n: usize| {
        let points: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
        let centres: Vec<f64> = points.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
        let axes = [0, 1, 2].map(|_| Axis::new(centres.clone(), 0.0, 1.0));
        let mut values = Vec::new();
        for &z in &centres {
            for &y in &centres {
                for &x in &centres {
                    values.push(analytic(DVec3::new(x, y, z)));
                }
            }
        }
        steady(Grid::Structured(Structured { axes }), values, Outside::Error, None)
    };
    let errors: Vec<f64> = [8, 16, 32].iter().map(|&n| max_error(&field(n), 0.0, 1.0)).collect();
    for p in orders(&errors) {
        // At least second order (the coarse grids converge a little faster).
        assert!((1.8..2.6).contains(&p), "errors {errors:?}");
    }
}

#[test]
fn tetrahedral_field_is_second_order_in_cell_size() {
    let errors: Vec<f64> =
        [4, 8, 16].iter().map(|&n| max_error(&mesh_field(n, 0.0, true, analytic), 0.0, 1.0)).collect();
    for p in orders(&errors) {
        assert!((1.7..2.4).contains(&p), "errors {errors:?}, orders {:?}", orders(&errors));
    }
}

#[test]
fn hexahedral_field_is_second_order_in_cell_size_on_distorted_cells() {
    let errors: Vec<f64> =
        [4, 8, 16].iter().map(|&n| max_error(&mesh_field(n, 0.2, false, analytic), 0.0, 1.0)).collect();
    for p in orders(&errors) {
        assert!((1.7..2.4).contains(&p), "errors {errors:?}, orders {:?}", orders(&errors));
    }
}

#[test]
fn unstructured_field_reproduces_a_linear_field_exactly() {
    let f = |p: DVec3| DVec3::new(1.0 + 2.0 * p.x - p.y, 3.0 * p.z, -p.x + 0.5 * p.y);
    for tets in [false, true] {
        let field = mesh_field(3, 0.25, tets, f);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let at = field.at(0.0);
        for _ in 0..200 {
            let p = DVec3::new(rng.random(), rng.random(), rng.random());
            assert!((at.velocity(p) - f(p)).length() < 1e-12, "tets {tets} at {p}");
            assert!(field.contains(p));
        }
    }
}

#[test]
fn outside_policies_give_an_error_flag_zero_or_the_nearest_value() {
    let f = |p: DVec3| DVec3::new(p.x, 2.0 * p.y, 1.0);
    let mut field = image(4, f);
    let out = DVec3::new(1.5, 0.5, -0.25);
    assert!(!field.contains(out));
    field.outside = Outside::Nearest;
    assert!((field.velocity(out, 0.0) - DVec3::new(1.0, 1.0, 1.0)).length() < 1e-14);
    field.outside = Outside::Zero;
    assert_eq!(field.velocity(out, 0.0), DVec3::ZERO);
    let mut mesh = mesh_field(3, 0.0, true, f);
    assert!(!mesh.contains(out));
    mesh.outside = Outside::Nearest;
    assert!((mesh.velocity(out, 0.0) - DVec3::new(1.0, 1.0, 1.0)).length() < 1e-12);
    mesh.outside = Outside::Zero;
    assert_eq!(mesh.velocity(out, 0.0), DVec3::ZERO);
}

#[test]
fn axisymmetric_table_turns_its_radial_velocity_about_the_axis() {
    // u_r = r, u_θ = 0.5 r, u_z = 1 − r² on r = 0 … 1, z = −1 … 1, axis along x through (0, 2, 0).
    let r: Vec<f64> = (0..=20).map(|i| i as f64 / 20.0).collect();
    let z: Vec<f64> = (0..=4).map(|i| -1.0 + i as f64 / 2.0).collect();
    let mut values = Vec::new();
    for _ in &z {
        for &r in &r {
            values.push(DVec3::new(r, 0.5 * r, 1.0 - r * r));
        }
    }
    let axes = [Axis::new(r, 0.0, 1.0), Axis::new(vec![0.0], 0.0, 0.0), Axis::new(z, -1.0, 1.0)];
    let frame = Axisymmetric { point: DVec3::new(0.0, 2.0, 0.0), axis: DVec3::X };
    let field = steady(Grid::Structured(Structured { axes }), values, Outside::Error, Some(frame));
    let p = DVec3::new(0.3, 2.0, 0.5); // r = 0.5 along +z from the axis
    let u = field.velocity(p, 0.0);
    // e_r = +z, e_θ = x × z = −y.
    let expected = DVec3::new(1.0 - 0.25, -0.25, 0.5);
    assert!((u - expected).length() < 2e-3, "{u}"); // the table's linear error in u_z
    assert_eq!(field.velocity(DVec3::new(0.7, 2.0, 0.0), 0.0).z, 0.0);
    assert!(field.contains(DVec3::new(-0.9, 2.6, 0.79)));
    assert!(!field.contains(DVec3::new(0.0, 2.0, 1.01)));
    assert!(!field.contains(DVec3::new(1.2, 2.0, 0.0)));
}

#[test]
fn time_series_is_linear_in_time_and_periodic_when_asked() {
    let grid = || {
        let axes = [0, 1, 2].map(|_| Axis::new(vec![0.0, 1.0], 0.0, 1.0));
        Grid::Structured(Structured { axes })
    };
    let snap = |time: f64, u: f64| Snapshot { time, values: vec![DVec3::new(u, 0.0, 0.0); 8] };
    let series = vec![snap(1.0, 0.0), snap(2.0, 10.0), snap(4.0, 20.0)];
    let p = DVec3::splat(0.5);
    let field = Field::new(grid(), series.clone(), None, Outside::Error, None, FieldInfo::default());
    let u = |f: &Field, t: f64| f.velocity(p, t).x;
    assert_eq!(u(&field, 0.0), 0.0); // held before the first
    assert_eq!(u(&field, 1.5), 5.0);
    assert_eq!(u(&field, 3.0), 15.0);
    assert_eq!(u(&field, 9.0), 20.0); // held after the last
    let periodic = Field::new(grid(), series, Some(4.0), Outside::Error, None, FieldInfo::default());
    assert_eq!(u(&periodic, 4.5), 10.0); // halfway from the last (t = 4) back to the first (t = 5)
    assert_eq!(u(&periodic, 6.0), 10.0); // t = 6 is t = 2
    assert_eq!(u(&periodic, 0.0), 20.0); // t = 0 is t = 4, the last snapshot
}

/// The structured grids' lookup of the hot loop ([`StructuredAt`], which [`Field::velocity`]
/// uses) against the sum over the stencil ([`FieldAt`]), bit for bit: image data and a
/// rectilinear grid of cell data, an axis of one node (also as an axisymmetric table), points
/// inside, on node planes and outside, each outside policy, one snapshot and two blended in time.
#[test]
fn structured_lookup_is_the_stencils_sum_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let even = |n: usize, lo: f64, hi: f64| -> Vec<f64> {
        (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect()
    };
    let mut uneven: Vec<f64> = (0..9).map(|i| (i as f64 / 8.0).powf(1.5)).collect();
    uneven[3] += 0.01;
    let grids = [
        [
            Axis::new(even(7, -0.3, 0.4), -0.3, 0.4),
            Axis::new(even(5, 0.0, 1.0), 0.0, 1.0),
            Axis::new(even(6, 1.0, 2.5), 1.0, 2.5),
        ],
        // Cell data: the extent half a cell beyond the outer nodes.
        [
            Axis::new(uneven.clone(), -0.05, 1.1),
            Axis::new(even(4, 0.0, 1.0), -0.1, 1.1),
            Axis::new(uneven, 0.0, 1.0),
        ],
        [
            Axis::new(even(5, 0.0, 1.0), 0.0, 1.0),
            Axis::new(vec![0.5], 0.5, 0.5),
            Axis::new(even(3, 0.0, 1.0), 0.0, 1.0),
        ],
    ];
    let bits = |u: DVec3| u.to_array().map(f64::to_bits);
    for axes in grids {
        let g = Structured { axes };
        let nodes: usize = g.dims().iter().product();
        let lo = DVec3::new(g.axes[0].lo, g.axes[1].lo, g.axes[2].lo);
        let hi = DVec3::new(g.axes[0].hi, g.axes[1].hi, g.axes[2].hi);
        let mut snap = |time: f64| Snapshot {
            time,
            values: (0..nodes).map(|_| DVec3::new(rng.random(), rng.random(), rng.random()) - 0.5).collect(),
        };
        let series = vec![snap(0.0), snap(1.0)];
        let frames = if g.dims()[1] == 1 {
            vec![
                None,
                Some(Axisymmetric { point: DVec3::new(0.1, -0.2, 0.3), axis: DVec3::new(0.6, 0.0, 0.8) }),
            ]
        } else {
            vec![None]
        };
        for outside in [Outside::Error, Outside::Zero, Outside::Nearest] {
            for &frame in &frames {
                let grid = Grid::Structured(g.clone());
                let field = Field::new(grid, series.clone(), None, outside, frame, FieldInfo::default());
                for _ in 0..500 {
                    // Up to a quarter of the box's size beyond it on every side; some points on
                    // a node plane.
                    let xs: [DVec3; LANES] = std::array::from_fn(|_| {
                        let mut x = lo
                            + (hi - lo) * (1.5 * DVec3::new(rng.random(), rng.random(), rng.random()) - 0.25);
                        if rng.random_bool(0.2) {
                            x.x = g.axes[0].nodes[rng.random_range(0..g.axes[0].nodes.len())];
                        }
                        x
                    });
                    for t in [0.0, 0.3, 1.0] {
                        // The lane group's lookup too.
                        let lanes = field.structured_at(t).expect("a structured grid");
                        let lanes = lanes.velocity_of(DVec3x4::from_array(xs)).to_array();
                        for (x, lane) in xs.into_iter().zip(lanes) {
                            let stencil = field.at(t).velocity(x);
                            assert_eq!(bits(field.velocity(x, t)), bits(stencil), "{x} at t = {t}");
                            assert_eq!(bits(lane), bits(stencil), "{x} at t = {t}, in a lane group");
                        }
                    }
                }
            }
        }
    }
}

mod walk {
    use super::*;
    use proptest::prelude::*;
    use rand::Rng;
    use std::sync::OnceLock;

    /// A tetrahedral and a hexahedral grid of the unit cube, distorted, with `analytic` on them.
    fn grids() -> &'static [Field; 2] {
        static GRIDS: OnceLock<[Field; 2]> = OnceLock::new();
        GRIDS.get_or_init(|| [mesh_field(5, 0.25, true, analytic), mesh_field(5, 0.25, false, analytic)])
    }

    fn tets(field: &Field) -> &Unstructured {
        match &field.grid {
            Grid::Unstructured(g) => g,
            Grid::Structured(_) => unreachable!("an unstructured test grid"),
        }
    }

    #[test]
    fn every_inner_face_has_one_neighbour_across_it_and_it_points_back() {
        for (field, kind) in grids().iter().zip(["tetrahedra", "hexahedra"]) {
            let g = tets(field);
            let n = g.neighbours();
            // The cube's six sides, 5 × 5 faces of a cell each, two triangles a face (a
            // hexahedron's face cut in two, or the faces of two tetrahedral cells).
            let boundary = n.iter().flatten().filter(|&&t| t == NO_TET).count();
            assert_eq!(boundary, 6 * 25 * 2, "{kind}");
            for (t, across) in n.iter().enumerate() {
                for &u in across.iter().filter(|&&u| u != NO_TET) {
                    assert!(n[u as usize].contains(&(t as u32)), "{t} → {u} and back");
                }
            }
        }
    }

    #[test]
    fn a_walk_from_a_neighbouring_tetrahedron_finds_the_trees_tetrahedron() {
        let field = &grids()[1];
        let g = tets(field);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..200 {
            let p = DVec3::new(rng.random(), rng.random(), rng.random());
            let found = g.tet_of(NO_TET, p);
            assert_ne!(found, NO_TET, "{p} is inside");
            // A point a fifth of a cell away, walked to from the first one's tetrahedron.
            let q = (p + DVec3::new(rng.random(), rng.random(), rng.random()) * 0.04).min(DVec3::ONE);
            let walked = g.tet_of(found, q);
            let mine = g.tet_of(NO_TET, q);
            let l = |t: u32| field.at(0.0).hinted(t).velocity(q);
            assert_ne!(walked, NO_TET);
            assert!((l(walked) - l(mine)).length() <= 1e-12, "{q}: {walked} vs {mine}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// Whichever tetrahedron the lookup starts from (none: the search tree), it gives the
        /// tree's value, inside the grid and outside it (the nearest point's), up to rounding
        /// on a face shared by two tetrahedra.
        #[test]
        fn walking_from_any_tetrahedron_gives_the_search_trees_value(
            grid in 0usize..2,
            x in -0.05f64..1.05,
            y in -0.05f64..1.05,
            z in -0.05f64..1.05,
            start in any::<prop::sample::Index>(),
            unknown in any::<bool>(),
        ) {
            let field = &grids()[grid];
            let n = tets(field).tets.len();
            let hint = if unknown { NO_TET } else { start.index(n) as u32 };
            let p = DVec3::new(x, y, z);
            let at = field.at(0.0);
            let (tree, walked) = (at.velocity(p), at.hinted(hint).velocity(p));
            prop_assert!((tree - walked).length() <= 1e-12 * tree.length().max(1.0), "{p}: {tree} vs {walked}");
            prop_assert_eq!(field.tet_of(hint, p) == NO_TET, !field.contains(p));
        }
    }
}
