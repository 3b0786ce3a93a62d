//! Triangle-mesh walls from STL (ASCII or binary) and OBJ files, through parry's `TriMesh`.

use super::{Crossing, Drawable, Gap, Part, Solid, Surface, boxes_overlap};

/// The part number of the gap out of a closed mesh for a centre inside it.
const INSIDE: Part = Part::MAX;
use glam::DVec3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose;
use parry3d_f64::query::{PointQuery, ShapeCastOptions, cast_shapes};
use parry3d_f64::shape::{Ball, FeatureId, TriMesh, TriMeshFlags};
use std::path::Path;

/// A triangle mesh wall. An open mesh (a sheet) can be touched from either side; a closed
/// mesh is a solid body, whose inside is behind the wall (negative gap).
#[derive(Debug, Clone)]
pub struct MeshWall {
    /// The mesh, in scene coordinates (m), outward-oriented when closed.
    pub mesh: TriMesh,
    /// Whether every edge is shared by exactly two triangles with opposite directions.
    pub closed: bool,
}

/// Why a mesh file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be opened or read.
    #[error("cannot read mesh file '{path}': {source}")]
    Read {
        /// The path as given.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not a valid STL or OBJ file.
    #[error("mesh file '{path}' is not valid {format}: {message}")]
    Format {
        /// The path as given.
        path: String,
        /// `STL` or `OBJ`.
        format: &'static str,
        /// What the parser said.
        message: String,
    },
    /// The file extension is neither `.stl` nor `.obj`.
    #[error("mesh file '{path}' has unknown extension; expected .stl or .obj")]
    Extension {
        /// The path as given.
        path: String,
    },
    /// The path is not a file to read as a mesh: a device, a fifo, a folder, or too large.
    #[error("mesh file '{path}' {message}")]
    NotAMesh {
        /// The path as given.
        path: String,
        /// Why.
        message: String,
    },
    /// The geometry is unusable.
    #[error("mesh file '{path}': {message}")]
    Geometry {
        /// The path as given.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// The largest mesh file read (bytes). A binary STL of 10 million triangles is 500 MB; a larger
/// file is far more likely a wrong path (a disk image, a log) than a wall, and reading it whole
/// would take the memory of a run.
pub const MESH_FILE_CAP: u64 = 512 << 20;

/// Loads an STL (ASCII or binary) or OBJ file, scales it by `scale` and moves it by `translate`
/// (m). Rejects files with no triangles, non-finite coordinates, out-of-range indices or
/// degenerate (zero-area) triangles, naming the first bad one.
pub fn load_mesh(path: &Path, scale: f64, translate: DVec3) -> Result<MeshWall, MeshError> {
    let shown = path.display().to_string();
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    check_file(path, &shown)?;
    let (vertices, triangles) = match ext.as_deref() {
        Some("stl") => read_stl(path, &shown)?,
        Some("obj") => read_obj(path, &shown)?,
        _ => return Err(MeshError::Extension { path: shown }),
    };
    let geometry = |message: String| MeshError::Geometry { path: shown.clone(), message };
    if triangles.is_empty() {
        return Err(geometry("contains no triangles".into()));
    }
    if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
        return Err(geometry(format!("vertex {i} has a non-finite coordinate {:?}", vertices[i])));
    }
    let n = vertices.len() as u32;
    let vertices: Vec<DVec3> = vertices.into_iter().map(|v| v * scale + translate).collect();
    // Finite in the file but not once placed (a scale of 1e300): the geometry would be NaN.
    if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
        return Err(geometry(format!(
            "vertex {i} is not finite once scaled by {scale:e} and moved by {translate}: {:?}",
            vertices[i]
        )));
    }
    let extent = vertices.iter().fold(0.0f64, |m, v| m.max((*v - vertices[0]).length()));
    // Areas are squared lengths: beyond 1e150 m they overflow and every test below is void.
    if !(extent * extent).is_finite() {
        return Err(geometry(format!(
            "spans {extent:e} m once scaled by {scale:e} and moved by {translate}: too large to compute with"
        )));
    }
    for (i, t) in triangles.iter().enumerate() {
        if t.iter().any(|&k| k >= n) {
            return Err(geometry(format!("triangle {i} refers to a vertex beyond the {n} given")));
        }
        let [a, b, c] = t.map(|k| vertices[k as usize]);
        let area2 = (b - a).cross(c - a).length();
        // Coordinates are finite here, so the area is a number.
        if area2 <= 1e-12 * extent * extent {
            return Err(geometry(format!("triangle {i} is degenerate (zero area): vertices {a}, {b}, {c}")));
        }
    }
    let (vertices, mut triangles) = merge_duplicate_vertices(vertices, triangles);
    let closed = is_closed(&triangles);
    let mut flags = TriMeshFlags::empty();
    if closed {
        // Outward orientation, so that parry's pseudo-normals tell inside from outside.
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| vertices[k as usize]);
                a.dot(b.cross(c))
            })
            .sum();
        if volume < 0.0 {
            triangles.iter_mut().for_each(|t| t.swap(1, 2));
        }
        flags = TriMeshFlags::ORIENTED;
    }
    let mesh = TriMesh::with_flags(vertices, triangles, flags)
        .map_err(|e| geometry(format!("cannot build the mesh: {e}")))?;
    Ok(MeshWall { mesh, closed })
}

/// Refuses what is not a regular file and a file beyond [`MESH_FILE_CAP`], from its metadata,
/// before reading it: the rule of every file the engine reads ([`crate::files`]).
fn check_file(path: &Path, shown: &str) -> Result<(), MeshError> {
    match crate::files::check(path, MESH_FILE_CAP, "a mesh file") {
        Ok(_) => Ok(()),
        Err(crate::files::FileProblem::Io(source)) => Err(MeshError::Read { path: shown.into(), source }),
        Err(other) => Err(MeshError::NotAMesh { path: shown.into(), message: other.to_string() }),
    }
}

/// Vertices with identical coordinates become one (STL and OBJ repeat them per face).
fn merge_duplicate_vertices(vertices: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> RawMesh {
    let mut index = std::collections::HashMap::new();
    let mut merged = Vec::new();
    let remap: Vec<u32> = vertices
        .iter()
        .map(|v| {
            *index.entry(v.to_array().map(f64::to_bits)).or_insert_with(|| {
                merged.push(*v);
                merged.len() as u32 - 1
            })
        })
        .collect();
    (merged, triangles.into_iter().map(|t| t.map(|k| remap[k as usize])).collect())
}

/// Closed and consistently oriented: each directed edge once, and its reverse once.
fn is_closed(triangles: &[[u32; 3]]) -> bool {
    let mut edges = std::collections::HashMap::new();
    for t in triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *edges.entry((a, b)).or_insert(0u32) += 1;
        }
    }
    edges.iter().all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
}

type RawMesh = (Vec<DVec3>, Vec<[u32; 3]>);

fn read_stl(path: &Path, shown: &str) -> Result<RawMesh, MeshError> {
    let mut file =
        std::fs::File::open(path).map_err(|source| MeshError::Read { path: shown.into(), source })?;
    let stl = stl_io::read_stl(&mut file).map_err(|e| MeshError::Format {
        path: shown.into(),
        format: "STL",
        message: e.to_string(),
    })?;
    let vertices = stl.vertices.iter().map(|v| DVec3::from(v.0.map(f64::from))).collect();
    let triangles = stl.faces.iter().map(|f| f.vertices.map(|k| k as u32)).collect();
    Ok((vertices, triangles))
}

fn read_obj(path: &Path, shown: &str) -> Result<RawMesh, MeshError> {
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _) = tobj::load_obj(path, &options).map_err(|e| match e {
        tobj::LoadError::OpenFileFailed => MeshError::Read {
            path: shown.into(),
            source: std::fs::File::open(path).err().unwrap_or_else(|| std::io::Error::other(e)),
        },
        other => MeshError::Format { path: shown.into(), format: "OBJ", message: other.to_string() },
    })?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for model in models {
        let offset = vertices.len() as u32;
        let m = model.mesh;
        vertices
            .extend(m.positions.chunks_exact(3).map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)));
        triangles.extend(m.indices.chunks_exact(3).map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]));
    }
    Ok((vertices, triangles))
}

impl Surface for MeshWall {
    fn gap(&self, c: DVec3, r: f64) -> Gap {
        let (proj, feature) = self.mesh.project_local_point_and_get_feature(c);
        let d = c - proj.point;
        let dist = d.length();
        if self.closed && proj.is_inside && dist > 0.0 {
            // Inside a solid body: the gap is negative, the normal points out of it.
            return Gap { gap: -dist - r, normal: -d / dist };
        }
        let normal = if dist > 1e-15 {
            d / dist
        } else {
            // Centre on the surface: use the face normal.
            match feature {
                FeatureId::Face(i) => {
                    let n = self.mesh.num_triangles() as u32;
                    self.mesh.triangle(i % n).normal().unwrap_or(DVec3::Z)
                }
                _ => DVec3::Z,
            }
        };
        Gap { gap: dist - r, normal }
    }

    fn sweep(&self, c0: DVec3, c1: DVec3, r: f64) -> Option<Crossing> {
        let ball = Ball::new(r);
        let options = ShapeCastOptions { max_time_of_impact: 1.0, ..Default::default() };
        let cast = |from: DVec3, to: DVec3| {
            cast_shapes(
                &Pose::IDENTITY,
                DVec3::ZERO,
                &self.mesh,
                &Pose::from_translation(from),
                to - from,
                &ball,
                options,
            )
            .ok()
            .flatten()
            .map(|hit| hit.time_of_impact)
        };
        let Some(enter) = cast(c0, c1) else {
            // parry's cast misses a crossing shallower than its own tolerance: a sphere sliding
            // on another wall into a facet at a grazing angle ended 2.3e-6 r inside it, with no
            // contact (a crease of a plane and a mesh, docs/stability.md R2-1). The end's gap
            // says so; the entry is interpolated between the two gaps.
            let g1 = self.gap(c1, r).gap;
            return (g1 < 0.0).then(|| {
                let g0 = self.gap(c0, r).gap;
                Crossing { enter: (g0 / (g0 - g1)).clamp(0.0, 1.0), exit: 1.0 }
            });
        };
        let exit = cast(c1, c0).map_or(1.0, |back| 1.0 - back);
        Some(Crossing { enter, exit: exit.max(enter) })
    }

    fn may_touch(&self, c0: DVec3, c1: DVec3, r: f64) -> bool {
        let aabb = self.mesh.local_aabb();
        boxes_overlap(c0, c1, r, aabb.mins, aabb.maxs)
    }

    /// Every triangle within `within` of the sphere, each with its own gap and normal (found
    /// through the mesh's bounding-volume hierarchy): at a crease a sphere touches two facets
    /// at once, and the one it approaches is not always the nearest. A sphere whose centre is
    /// inside a closed mesh gets the one gap out of the body.
    fn touching(&self, c: DVec3, r: f64, within: f64, mut each: impl FnMut(Part, Gap)) {
        let nearest = self.gap(c, r);
        if self.closed && nearest.gap < -r {
            if nearest.gap < within {
                each(INSIDE, nearest);
            }
            return;
        }
        let reach = r + within.max(0.0);
        let region = Aabb::from_half_extents(c, DVec3::splat(reach));
        for i in self.mesh.bvh().intersect_aabb(&region) {
            let triangle = self.mesh.triangle(i);
            let d = c - triangle.project_local_point(c, true).point;
            let dist = d.length();
            if dist - r < within {
                let normal =
                    if dist > 1e-15 { d / dist } else { triangle.normal().unwrap_or(nearest.normal) };
                each(i, Gap { gap: dist - r, normal });
            }
        }
    }

    fn part_gap(&self, part: Part, c: DVec3, r: f64) -> Gap {
        let nearest = self.gap(c, r);
        if part == INSIDE || part >= self.mesh.num_triangles() as Part {
            return nearest;
        }
        let triangle = self.mesh.triangle(part);
        let d = c - triangle.project_local_point(c, true).point;
        let dist = d.length();
        let normal = if dist > 1e-15 { d / dist } else { triangle.normal().unwrap_or(nearest.normal) };
        Gap { gap: dist - r, normal }
    }

    /// The nearest triangle not in `skip` (through the mesh's hierarchy); a centre inside a
    /// closed mesh keeps the gap out of the body.
    fn gap_without(&self, c: DVec3, r: f64, skip: &[Part]) -> Gap {
        let nearest = self.gap(c, r);
        if skip.is_empty() || (self.closed && nearest.gap < -r) {
            return nearest;
        }
        let best = self.mesh.bvh().project_point(c, f64::MAX, |i, _| {
            (!skip.contains(&i)).then(|| self.mesh.triangle(i).project_local_point(c, true))
        });
        let Some((i, (_, projection))) = best else {
            return Gap { gap: f64::INFINITY, normal: nearest.normal };
        };
        let d = c - projection.point;
        let dist = d.length();
        let normal =
            if dist > 1e-15 { d / dist } else { self.mesh.triangle(i).normal().unwrap_or(nearest.normal) };
        Gap { gap: dist - r, normal }
    }
}

impl Drawable for MeshWall {
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let v = self.mesh.vertices();
        let lo = v.iter().fold(DVec3::splat(f64::INFINITY), |lo, v| lo.min(*v));
        let hi = v.iter().fold(DVec3::splat(f64::NEG_INFINITY), |hi, v| hi.max(*v));
        Some((lo, hi))
    }

    fn solid(&self, _center: DVec3, _half: f64) -> Solid {
        Solid::Triangles { vertices: self.mesh.vertices().to_vec(), indices: self.mesh.indices().to_vec() }
    }
}
