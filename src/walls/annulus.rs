//! A ring (annulus) baffle, flat or conical, built as a triangle mesh; inner radius 0 gives a
//! disc (or a cone).

use super::MeshWall;
use glam::DVec3;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

/// A ring of zero thickness around the axis through `center` (m) along `normal`, between
/// `inner` and `outer` radius (m), as a sheet of triangles that particles may touch from either
/// side (a disc-and-doughnut baffle). The outer rim lies in the plane through `center`
/// perpendicular to `normal`; the inner rim (or, for a disc, the centre) is `cone_height` (m)
/// along `normal` from that plane: 0 gives a flat ring, otherwise a conical one (the sloped
/// baffles of extraction columns, under which drops do not collect). Both rims are regular
/// polygons of `segments` sides with their vertices on the circles, so a rim is at most
/// `r (1 − cos(π/segments))` inside its circle (0.03 % of the radius with 128 sides); each
/// sector is planar (two generators of a cone meet at its apex), so the normals are exact.
///
/// NOTE: a mesh rather than a closed form because the ring is not convex (the hole): the gap
/// along a straight move can fall, rise and fall again, which the closed-form shapes' Newton
/// sweep cannot handle, whereas parry's shape cast on the triangles is exact for any path.
pub fn annulus_mesh(
    center: DVec3,
    normal: DVec3,
    inner: f64,
    outer: f64,
    cone_height: f64,
    segments: u32,
) -> MeshWall {
    let n = normal.normalize();
    let e1 = n.any_orthonormal_vector();
    let e2 = n.cross(e1);
    let k = segments.max(3);
    let rim = |radius: f64, j: u32| {
        let theta = std::f64::consts::TAU * f64::from(j % k) / f64::from(k);
        center + radius * (theta.cos() * e1 + theta.sin() * e2)
    };
    let lift = cone_height * n;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    if inner > 0.0 {
        // Vertex 2j on the inner rim, 2j + 1 on the outer one; two triangles per sector.
        for j in 0..k {
            vertices.push(rim(inner, j) + lift);
            vertices.push(rim(outer, j));
        }
        for j in 0..k {
            let (a, b) = (2 * j, 2 * j + 1);
            let (c, d) = (2 * ((j + 1) % k), 2 * ((j + 1) % k) + 1);
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    } else {
        // A disc: a fan around the centre.
        vertices.push(center + lift);
        vertices.extend((0..k).map(|j| rim(outer, j)));
        triangles.extend((0..k).map(|j| [0, 1 + j, 1 + (j + 1) % k]));
    }
    // The triangles are non-degenerate by construction (the scene checks 0 ≤ inner < outer).
    let mesh = TriMesh::with_flags(vertices, triangles, TriMeshFlags::empty())
        .expect("a ring of non-degenerate triangles is a valid mesh");
    MeshWall { mesh, closed: false }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walls::Surface;

    #[test]
    fn sphere_passes_through_the_hole_and_stops_on_the_ring() {
        let ring = annulus_mesh(DVec3::ZERO, DVec3::Z, 0.01, 0.02, 0.0, 128);
        let r = 1e-3;
        // Up the axis: through the hole, no contact.
        assert!(ring.sweep(DVec3::new(0.0, 0.0, -0.01), DVec3::new(0.0, 0.0, 0.01), r).is_none());
        // Up at mid-ring: touches when its top reaches the plane.
        let hit = ring.sweep(DVec3::new(0.015, 0.0, -0.01), DVec3::new(0.015, 0.0, 0.01), r).unwrap();
        assert!((hit.enter - 0.45).abs() < 1e-9, "{hit:?}");
        let g = ring.gap(DVec3::new(0.0, 0.015, -0.002), r);
        assert!((g.gap - 1e-3).abs() < 1e-12 && (g.normal + DVec3::Z).length() < 1e-12);
        // A disc (inner radius 0) has no hole.
        let disc = annulus_mesh(DVec3::ZERO, DVec3::Z, 0.0, 0.02, 0.0, 64);
        assert!(disc.sweep(DVec3::new(0.0, 0.0, -0.01), DVec3::new(0.0, 0.0, 0.01), r).is_some());
    }

    #[test]
    fn conical_ring_slopes_from_outer_rim_up_to_inner_rim() {
        // Inner rim 5 mm above the outer one over 10 mm: a 26.6° slope.
        let cone = annulus_mesh(DVec3::ZERO, DVec3::Z, 0.01, 0.02, 0.005, 128);
        let below = DVec3::new(0.015, 0.0, 0.0025 - 0.002);
        let g = cone.gap(below, 1e-3);
        let expected = DVec3::new(-0.5, 0.0, -1.0).normalize();
        // Each sector is a flat facet, turned by up to π/128 about the axis from the exact cone.
        let facet = std::f64::consts::PI / 128.0;
        assert!((g.normal - expected).length() < facet, "{:?}", g.normal);
        assert!((g.gap - (0.002 * expected.z.abs() - 1e-3)).abs() < 1e-5, "{}", g.gap);
    }
}
