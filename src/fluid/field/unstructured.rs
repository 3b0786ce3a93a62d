//! Unstructured grids (VTK unstructured grids, and structured grids of hexahedra): every cell
//! cut into tetrahedra around its centre, located with a bounding-volume hierarchy, and
//! interpolated linearly (barycentric) inside the tetrahedron.
//!
//! The cut is OpenFOAM's `cellPoint` idea: each face (quadrilaterals split in two triangles)
//! and the cell's centre make one tetrahedron. A quadrilateral is split along the diagonal
//! from its lowest-numbered vertex, so the two cells sharing a face split it the same way and
//! the tetrahedra of neighbouring cells meet face to face: the interpolant is continuous. A
//! linear field is reproduced exactly, so the interpolation is second order in the cell size.
//!
//! Because they meet face to face, each tetrahedron knows its four face neighbours (found once
//! at load). A lookup that starts from a tetrahedron near the point (the one that held the same
//! particle at the end of the last step, [`crate::particles::Particles::tet`]) walks there: if
//! the point is outside the tetrahedron, it crosses the face opposite the most negative
//! barycentric coordinate, and again, up to [`WALK_STEPS`] times; the search tree is the
//! fallback when the walk has no start, leaves the grid (a concave boundary, a face two cells do
//! not share whole) or takes longer. Whichever tetrahedron the point is found in, the value is
//! the same up to rounding, since the interpolant is continuous across their shared faces.

use super::structured::Stencil;
use glam::DVec3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhNode};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::Tetrahedron;

/// The VTK linear 3-D cell types the reader accepts, with their faces in VTK's vertex order.
pub fn cell_faces(vtk_type: u8) -> Option<&'static [&'static [usize]]> {
    Some(match vtk_type {
        10 => &[&[0, 1, 2], &[0, 1, 3], &[1, 2, 3], &[0, 2, 3]],
        // A voxel is read as a hexahedron after reordering its vertices (`VOXEL_AS_HEX`).
        11 | 12 => {
            &[&[0, 3, 2, 1], &[4, 5, 6, 7], &[0, 1, 5, 4], &[1, 2, 6, 5], &[2, 3, 7, 6], &[3, 0, 4, 7]]
        }
        13 => &[&[0, 1, 2], &[3, 5, 4], &[0, 3, 4, 1], &[1, 4, 5, 2], &[2, 5, 3, 0]],
        14 => &[&[0, 3, 2, 1], &[0, 1, 4], &[1, 2, 4], &[2, 3, 4], &[3, 0, 4]],
        _ => return None,
    })
}

/// The eight corners of cell `(i, j, k)` of a block of points, as point indices `(i, j, k)`, in
/// VTK's hexahedron order (the bottom face counter-clockwise seen from above, then the top
/// face): how a structured grid's cell is written as an unstructured one.
pub fn hexahedron_corners(i: usize, j: usize, k: usize) -> [(usize, usize, usize); 8] {
    [
        (i, j, k),
        (i + 1, j, k),
        (i + 1, j + 1, k),
        (i, j + 1, k),
        (i, j, k + 1),
        (i + 1, j, k + 1),
        (i + 1, j + 1, k + 1),
        (i, j + 1, k + 1),
    ]
}

/// VTK's voxel vertex order as a hexahedron's.
pub const VOXEL_AS_HEX: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];

/// Number of vertices of each accepted cell type.
pub fn cell_size(vtk_type: u8) -> Option<usize> {
    Some(match vtk_type {
        10 => 4,
        11 | 12 => 8,
        13 => 6,
        14 => 5,
        _ => return None,
    })
}

/// Why a cell cannot be used.
#[derive(Debug, Clone, PartialEq)]
pub enum CellProblem {
    /// (cell, VTK type): a cell type other than the linear 3-D ones.
    Type(usize, u8),
    /// (cell, point): a cell names a point that does not exist.
    Point(usize, u64),
    /// (cell, VTK type, points listed, points the type has): a cell of the wrong length.
    Count(usize, u8, usize, usize),
    /// (cell, volume in m³): a cell has no volume (its vertices lie in a plane, a line or a point).
    Degenerate(usize, f64),
}

/// An unstructured grid cut into tetrahedra.
#[derive(Debug, Clone)]
pub struct Unstructured {
    /// The grid's points, then one centre per cell (the mean of its vertices).
    pub nodes: Vec<DVec3>,
    /// Number of the grid's own points (the centres follow them in `nodes`).
    pub points: usize,
    /// Tetrahedra as four indices into `nodes`.
    pub tets: Vec<[u32; 4]>,
    /// Cell `c`'s tetrahedra are `tets[cell_tets[c]..cell_tets[c + 1]]`.
    pub cell_tets: Vec<u32>,
    /// Each cell's vertices (indices into `nodes`) as `cell_points[cell_offsets[c]..cell_offsets[c + 1]]`.
    pub cell_points: Vec<u32>,
    /// See [`Unstructured::cell_points`].
    pub cell_offsets: Vec<u32>,
    /// Cells by their (slightly widened) bounding boxes.
    bvh: Bvh,
    /// Each cell's bounding box, the leaves of `bvh`.
    boxes: Vec<Aabb>,
    /// Bounds of the whole grid.
    pub bounds: Aabb,
    /// The smallest and largest cell size (m): the cube root of the cell's volume.
    pub cell_size_range: (f64, f64),
    /// `neighbours[t][i]`: the tetrahedron across the face of `t` opposite its vertex `i`, or
    /// [`NO_TET`] on the grid's boundary (or where no other tetrahedron has that face whole).
    neighbours: Vec<[u32; 4]>,
}

pub use crate::particles::NO_TET;

/// The most faces a walk crosses before the lookup falls back to the search tree: a particle
/// rarely crosses more than a cell (about six tetrahedra) in a step; a longer walk means a
/// remembered tetrahedron far from the point, where the tree is as quick.
pub const WALK_STEPS: usize = 24;

/// The face neighbours of `tets` ([`Unstructured::neighbours`]): the faces sorted by their
/// vertices, so that the two tetrahedra sharing one are side by side.
fn face_neighbours(tets: &[[u32; 4]]) -> Vec<[u32; 4]> {
    let mut faces: Vec<([u32; 3], u32, u8)> = Vec::with_capacity(4 * tets.len());
    for (t, v) in tets.iter().enumerate() {
        for i in 0..4 {
            let mut f = [v[(i + 1) % 4], v[(i + 2) % 4], v[(i + 3) % 4]];
            f.sort_unstable();
            faces.push((f, t as u32, i as u8));
        }
    }
    faces.sort_unstable();
    let mut neighbours = vec![[NO_TET; 4]; tets.len()];
    let mut k = 0;
    while k < faces.len() {
        let mut e = k + 1;
        while e < faces.len() && faces[e].0 == faces[k].0 {
            e += 1;
        }
        // Exactly two: a face of three or more tetrahedra (a broken mesh) links none of them,
        // and the lookup falls back to the tree there.
        if e - k == 2 {
            let ((_, a, i), (_, b, j)) = (faces[k], faces[k + 1]);
            neighbours[a as usize][i as usize] = b;
            neighbours[b as usize][j as usize] = a;
        }
        k = e;
    }
    neighbours
}

/// Barycentric coordinates of `p` in the tetrahedron `t`, and its six-fold signed volume.
#[inline]
fn barycentric(t: [DVec3; 4], p: DVec3) -> ([f64; 4], f64) {
    let (e1, e2, e3, q) = (t[1] - t[0], t[2] - t[0], t[3] - t[0], p - t[0]);
    let vol = e1.dot(e2.cross(e3));
    let l1 = q.dot(e2.cross(e3)) / vol;
    let l2 = e1.dot(q.cross(e3)) / vol;
    let l3 = e1.dot(e2.cross(q)) / vol;
    ([1.0 - l1 - l2 - l3, l1, l2, l3], vol)
}

/// The gradients of the four barycentric coordinates of tetrahedron `t` (1/m).
fn barycentric_gradients(t: [DVec3; 4]) -> [DVec3; 4] {
    let (e1, e2, e3) = (t[1] - t[0], t[2] - t[0], t[3] - t[0]);
    let vol = e1.dot(e2.cross(e3));
    let g1 = e2.cross(e3) / vol;
    let g2 = e3.cross(e1) / vol;
    let g3 = e1.cross(e2) / vol;
    [-(g1 + g2 + g3), g1, g2, g3]
}

/// A point counts as inside a tetrahedron when no barycentric coordinate is below this: the
/// round-off of a point on a shared face, far below any cell's size.
const INSIDE: f64 = -1e-10;

impl Unstructured {
    /// Cuts the cells (each a VTK type and its point indices) into tetrahedra and builds the
    /// search tree.
    pub fn new(points: Vec<DVec3>, cells: &[(u8, Vec<u64>)]) -> Result<Unstructured, CellProblem> {
        let n_points = points.len();
        let mut nodes = points;
        let mut tets = Vec::new();
        let mut cell_tets = vec![0u32];
        let mut cell_points = Vec::new();
        let mut cell_offsets = vec![0u32];
        let mut boxes = Vec::with_capacity(cells.len());
        let (mut small, mut large) = (f64::INFINITY, 0.0f64);
        for (c, (ty, verts)) in cells.iter().enumerate() {
            let faces = cell_faces(*ty).ok_or(CellProblem::Type(c, *ty))?;
            // The faces name the type's corners by position: a shorter list would be read past.
            let need = faces.iter().flat_map(|f| f.iter()).max().map_or(0, |&m| m + 1);
            if verts.len() != need {
                return Err(CellProblem::Count(c, *ty, verts.len(), need));
            }
            let mut v: Vec<u32> = Vec::with_capacity(verts.len());
            for &p in verts {
                if p as usize >= n_points {
                    return Err(CellProblem::Point(c, p));
                }
                v.push(p as u32);
            }
            if *ty == 11 {
                v = VOXEL_AS_HEX.iter().map(|&i| v[i]).collect();
            }
            let centre_index = nodes.len() as u32;
            let centre = v.iter().map(|&i| nodes[i as usize]).sum::<DVec3>() / v.len() as f64;
            let mut volume = 0.0;
            for face in faces {
                let f: Vec<u32> = face.iter().map(|&i| v[i]).collect();
                // Split a quadrilateral along the diagonal from its lowest-numbered vertex,
                // so that both cells sharing it cut it the same way.
                let tris: Vec<[u32; 3]> = if f.len() == 3 {
                    vec![[f[0], f[1], f[2]]]
                } else {
                    let k = (0..4).min_by_key(|&i| f[i]).unwrap_or(0);
                    let q = |i: usize| f[(k + i) % 4];
                    vec![[q(0), q(1), q(2)], [q(0), q(2), q(3)]]
                };
                for t in tris {
                    let tet = [t[0], t[1], t[2], centre_index];
                    let corners = tet.map(|i| if i == centre_index { centre } else { nodes[i as usize] });
                    let (e1, e2, e3) =
                        (corners[1] - corners[0], corners[2] - corners[0], corners[3] - corners[0]);
                    let vol = e1.dot(e2.cross(e3)).abs() / 6.0;
                    // Faces are oriented outwards or inwards depending on the writer; the
                    // volume is taken unsigned and a flat tetrahedron (a collapsed edge) is
                    // left out: it holds no point.
                    volume += vol;
                    if vol > 0.0 {
                        tets.push(tet);
                    }
                }
            }
            let bb = Aabb::from_points(v.iter().map(|&i| nodes[i as usize]));
            let diag = (bb.maxs - bb.mins).length();
            if volume.is_nan() || volume <= 1e-12 * diag * diag * diag {
                return Err(CellProblem::Degenerate(c, volume));
            }
            let size = volume.cbrt();
            small = small.min(size);
            large = large.max(size);
            let pad = DVec3::splat(1e-9 * diag);
            boxes.push(Aabb::new(bb.mins - pad, bb.maxs + pad));
            nodes.push(centre);
            cell_tets.push(tets.len() as u32);
            cell_points.extend_from_slice(&v);
            cell_offsets.push(cell_points.len() as u32);
        }
        let bounds = boxes.iter().fold(Aabb::new_invalid(), |a, b| a.merged(b));
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
        let neighbours = face_neighbours(&tets);
        Ok(Unstructured {
            neighbours,
            nodes,
            points: n_points,
            tets,
            cell_tets,
            cell_points,
            cell_offsets,
            bvh,
            boxes,
            bounds,
            cell_size_range: (small, large),
        })
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.cell_tets.len() - 1
    }

    fn corners(&self, t: usize) -> [DVec3; 4] {
        self.tets[t].map(|i| self.nodes[i as usize])
    }

    /// The tetrahedron holding `p`, among those of the cells whose boxes hold it, and `p`'s
    /// barycentric coordinates in it.
    fn locate(&self, p: DVec3) -> Result<(usize, [f64; 4]), ()> {
        for cell in self.bvh.leaves(|n: &BvhNode| n.aabb().contains_local_point(p)) {
            let c = cell as usize;
            if !self.boxes[c].contains_local_point(p) {
                continue;
            }
            for t in self.cell_tets[c] as usize..self.cell_tets[c + 1] as usize {
                let (l, _) = barycentric(self.corners(t), p);
                let worst = l[0].min(l[1]).min(l[2]).min(l[3]);
                if worst >= INSIDE {
                    return Ok((t, l));
                }
            }
        }
        Err(())
    }

    /// The tetrahedron holding `p`, walking from tetrahedron `start` (see the module's
    /// documentation); the search tree when `start` is [`NO_TET`] or the walk fails.
    fn locate_from(&self, start: u32, p: DVec3) -> Result<(usize, [f64; 4]), ()> {
        let mut t = start as usize;
        if t < self.tets.len() {
            for _ in 0..WALK_STEPS {
                let (l, _) = barycentric(self.corners(t), p);
                // The first most negative coordinate.
                let worst = (1..4).fold(0, |w, i| if l[i] < l[w] { i } else { w });
                if l[worst] >= INSIDE {
                    return Ok((t, l));
                }
                // Not a NaN coordinate either: a point that is not finite ends on the tree.
                let next = self.neighbours[t][worst];
                if next == NO_TET || l[worst].is_nan() {
                    break;
                }
                t = next as usize;
            }
        }
        self.locate(p)
    }

    /// The tetrahedron holding `p` ([`NO_TET`] when none does), walking from `start`: what a
    /// particle remembers for its next lookups.
    pub fn tet_of(&self, start: u32, p: DVec3) -> u32 {
        self.locate_from(start, p).map_or(NO_TET, |(t, _)| t as u32)
    }

    /// The face neighbours of every tetrahedron ([`Unstructured::neighbours`]), for tests.
    #[cfg(test)]
    pub(crate) fn neighbours(&self) -> &[[u32; 4]] {
        &self.neighbours
    }

    /// Whether `p` lies in a cell of the grid.
    pub fn contains(&self, p: DVec3) -> bool {
        self.locate(p).is_ok()
    }

    /// The stencil at `p`: the tetrahedron holding it, or when none does, the value at the
    /// grid's nearest point (`Err`, so that the caller applies its policy).
    #[allow(clippy::result_large_err)] // a stencil either way; Err says the point was outside
    pub fn stencil(&self, p: DVec3) -> Result<Stencil, Stencil> {
        self.stencil_from(NO_TET, p, true)
    }

    /// [`Unstructured::stencil`], the lookup walking from tetrahedron `start`
    /// ([`Unstructured::tet_of`]), the gradient only `with_gradient` (a velocity needs none).
    #[allow(clippy::result_large_err)] // as `stencil`
    #[inline]
    pub fn stencil_from(&self, start: u32, p: DVec3, with_gradient: bool) -> Result<Stencil, Stencil> {
        match self.locate_from(start, p) {
            Ok((t, l)) => Ok(self.tet_stencil(t, l, with_gradient)),
            Err(_) => {
                let (t, q) = self.nearest(p);
                // `q` is the nearest point of the grid, on this tetrahedron's surface up to
                // round-off. Outside the grid the value is constant along the outward
                // direction: no gradient is claimed there.
                let (l, _) = barycentric(self.corners(t), q);
                let l = l.map(|x| x.max(0.0));
                let sum: f64 = l.iter().sum();
                Err(self.tet_stencil(t, l.map(|x| x / sum), false))
            }
        }
    }

    /// How far `p` lies outside the grid (m), 0 inside.
    pub fn distance_outside(&self, p: DVec3) -> f64 {
        if self.contains(p) { 0.0 } else { (self.nearest(p).1 - p).length() }
    }

    /// The tetrahedron nearest `p` and the nearest point in it: the candidates of a box
    /// around `p` that doubles until it holds a tetrahedron nearer than its half-size.
    fn nearest(&self, p: DVec3) -> (usize, DVec3) {
        let q = p.clamp(self.bounds.mins, self.bounds.maxs);
        let mut half = self.cell_size_range.1.max((p - q).length());
        loop {
            let query = Aabb::new(p - DVec3::splat(half), p + DVec3::splat(half));
            let mut best: Option<(usize, DVec3, f64)> = None;
            for cell in self.bvh.intersect_aabb(&query) {
                let c = cell as usize;
                for t in self.cell_tets[c] as usize..self.cell_tets[c + 1] as usize {
                    let [a, b, cc, d] = self.corners(t);
                    let on = Tetrahedron::new(a, b, cc, d).project_local_point(p, true).point;
                    let dist = (on - p).length();
                    if best.is_none_or(|(_, _, b)| dist < b) {
                        best = Some((t, on, dist));
                    }
                }
            }
            match best {
                Some((t, on, dist)) if dist <= half => return (t, on),
                _ => half *= 2.0,
            }
        }
    }

    /// The stencil of tetrahedron `t` with weights `l` (the barycentric coordinates of the
    /// point), and the weights' gradients only `with_gradient`.
    #[inline]
    fn tet_stencil(&self, t: usize, l: [f64; 4], with_gradient: bool) -> Stencil {
        let mut s = Stencil::default();
        let gradient = if with_gradient { barycentric_gradients(self.corners(t)) } else { [DVec3::ZERO; 4] };
        for i in 0..4 {
            s.nodes[i] = self.tets[t][i];
            s.weights[i] = l[i];
            s.gradient[i] = gradient[i];
        }
        s
    }
}
