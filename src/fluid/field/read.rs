//! Reading a velocity field from a VTK file with `vtkio`: image data (`.vti`), rectilinear
//! grids (`.vtr`), structured grids (`.vts`), unstructured grids (`.vtu`, ASCII, binary or
//! zlib-compressed appended data) and legacy `.vtk` files (what OpenFOAM's `foamToVTK
//! -legacy` writes), into a grid and one velocity per node.

use super::structured::{Axis, Structured};
use super::unstructured::{CellProblem, Unstructured, hexahedron_corners};
use super::{DataAt, Grid};
use glam::DVec3;
use std::path::{Path, PathBuf};
use vtkio::model::{Attribute, Attributes, DataSet, IOBuffer, Piece, PieceData, VertexNumbers};

/// A field file that cannot be used: the file and what is wrong with it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {message}", file.display())]
pub struct FieldError {
    /// The file.
    pub file: PathBuf,
    /// What is wrong.
    pub message: String,
}

/// The names taken as the velocity when the scene names no array, in this order.
pub const VELOCITY_NAMES: [&str; 5] = ["U", "U_rz", "velocity", "Velocity", "u"];

/// What the scene asks of the file.
#[derive(Debug, Clone, Copy)]
pub struct Request<'a> {
    /// The velocity array's name; `None`: the first of [`VELOCITY_NAMES`] present.
    pub array: Option<&'a str>,
    /// Point or cell data; `None`: point data if the array is there, else cell data.
    pub data: Option<DataAt>,
    /// Whether the file is a 2-D (r, z) table (2 components `(u_r, u_z)` or 3
    /// `(u_r, u_θ, u_z)`) rather than a 3-D field.
    pub axisymmetric: bool,
}

/// One file read: its grid, the velocity at each of the grid's nodes, and what it was.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The grid.
    pub grid: Grid,
    /// Velocity per node (m/s); `(u_r, u_θ, u_z)` for an axisymmetric table.
    pub values: Vec<DVec3>,
    /// The format's name (`VTK XML image data (.vti)`, ...).
    pub format: &'static str,
    /// The array read.
    pub array: String,
    /// Where its values sit.
    pub data: DataAt,
}

/// Reads the field of `file`.
pub fn load(file: &Path, request: Request) -> Result<Loaded, FieldError> {
    let fail = |message: String| FieldError { file: file.to_path_buf(), message };
    if let Err(e) = std::fs::metadata(file) {
        return Err(fail(format!("cannot read the field file: {e}")));
    }
    let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("");
    let format = match ext {
        "vti" => "VTK XML image data (.vti)",
        "vtr" => "VTK XML rectilinear grid (.vtr)",
        "vts" => "VTK XML structured grid (.vts)",
        "vtu" => "VTK XML unstructured grid (.vtu)",
        "pvtu" => "VTK XML parallel unstructured grid (.pvtu)",
        "vtk" => "legacy VTK (.vtk)",
        other => {
            return Err(fail(format!(
                "unknown field format \"{}\": expected .vti, .vtr, .vts, .vtu, .pvtu or legacy .vtk",
                if other.is_empty() { "(no extension)" } else { other }
            )));
        }
    };
    let mut vtk = import(file, ext).map_err(|e| fail(format!("cannot read it as {format}: {e}")))?;
    vtk.load_all_pieces().map_err(|e| fail(format!("cannot read its pieces: {}", one_line(&e))))?;
    let (grid, attributes) = match vtk.data {
        DataSet::ImageData { extent, origin, spacing, pieces, .. } => {
            let [piece] = one_piece(pieces, file).map_err(fail)?;
            let piece = load_piece(piece, file).map_err(fail)?;
            let dims = extent.clone().into_dims();
            let start = extent.into_ranges().map(|r| *r.start());
            let axes = [0, 1, 2].map(|a| {
                let (o, h) = (shortest(origin[a]), shortest(spacing[a]));
                (0..dims[a]).map(|i| o + (start[a] as f64 + i as f64) * h).collect::<Vec<f64>>()
            });
            if spacing.iter().enumerate().any(|(a, &h)| dims[a] > 1 && !(h > 0.0 && h.is_finite())) {
                return Err(fail(format!(
                    "degenerate grid: spacing {spacing:?} must be > 0 along every axis"
                )));
            }
            (Coords::Axes(axes), piece.data)
        }
        DataSet::RectilinearGrid { pieces, .. } => {
            let [piece] = one_piece(pieces, file).map_err(fail)?;
            let piece = load_piece(piece, file).map_err(fail)?;
            let c = &piece.coords;
            let axes = [&c.x, &c.y, &c.z].map(|b| floats(b).unwrap_or_default());
            (Coords::Axes(axes), piece.data)
        }
        DataSet::StructuredGrid { pieces, extent, .. } => {
            let [piece] = one_piece(pieces, file).map_err(fail)?;
            let piece = load_piece(piece, file).map_err(fail)?;
            let dims = extent.into_dims().map(|d| d as usize);
            let points = points_of(&piece.points).ok_or_else(|| fail("its points are not numbers".into()))?;
            (Coords::Hexes(points, dims), piece.data)
        }
        DataSet::UnstructuredGrid { pieces, .. } => {
            let mut points = Vec::new();
            let mut cells: Vec<(u8, Vec<u64>)> = Vec::new();
            let mut data: Option<Attributes> = None;
            let many = pieces.len() > 1;
            for piece in pieces {
                let piece = load_piece(piece, file).map_err(fail)?;
                if many {
                    return Err(fail(
                        "has several pieces: merge them into one (ParaView's Merge Blocks) first".into(),
                    ));
                }
                let offset = points.len() as u64;
                points.extend(
                    points_of(&piece.points).ok_or_else(|| fail("its points are not numbers".into()))?,
                );
                let types = &piece.cells.types;
                let lists = cell_lists(&piece.cells.cell_verts, types.len()).map_err(fail)?;
                for (ty, list) in types.iter().zip(lists) {
                    cells.push((*ty as u8, list.into_iter().map(|p| p + offset).collect()));
                }
                data = Some(piece.data);
            }
            (Coords::Cells(points, cells), data.unwrap_or_default())
        }
        DataSet::PolyData { .. } => {
            return Err(fail("holds polygon data (a surface), not a volume grid with a velocity".into()));
        }
        DataSet::Field { .. } => return Err(fail("holds only field data, no grid".into())),
    };
    build(grid, &attributes, request, format).map_err(fail)
}

/// `vtkio`'s import, with raw appended data re-encoded first ([`super::appended`]), and a
/// panic inside `vtkio` on a malformed file (it slices without checking in places) turned
/// into an error rather than taken down with the run.
fn import(file: &Path, ext: &str) -> Result<vtkio::Vtk, String> {
    let read = || -> Result<vtkio::Vtk, String> {
        if ext != "vtk" {
            let bytes = std::fs::read(file).map_err(|e| e.to_string())?;
            if let Some(fixed) = super::appended::raw_to_base64(&bytes)? {
                let mut vtk = vtkio::Vtk::parse_xml(std::io::Cursor::new(fixed)).map_err(|e| one_line(&e))?;
                vtk.file_path = Some(file.to_path_buf());
                return Ok(vtk);
            }
        }
        vtkio::Vtk::import(file).map_err(|e| one_line(&e))
    };
    std::panic::catch_unwind(read)
        .unwrap_or_else(|_| Err("the VTK reader (vtkio) failed on it: the file is malformed".into()))
}

/// Grid coordinates as read, before the velocity picks point or cell nodes.
enum Coords {
    /// A structured grid's node coordinates per axis.
    Axes([Vec<f64>; 3]),
    /// A curvilinear structured grid: points and dimensions.
    Hexes(Vec<DVec3>, [usize; 3]),
    /// An unstructured grid: points and cells (VTK type, point indices).
    Cells(Vec<DVec3>, Vec<(u8, Vec<u64>)>),
}

fn build(
    coords: Coords,
    attributes: &Attributes,
    request: Request,
    format: &'static str,
) -> Result<Loaded, String> {
    if let Coords::Axes(axes) = &coords {
        for (a, name) in axes.iter().zip(["x", "y", "z"]) {
            if a.is_empty() {
                return Err(format!("degenerate grid: no points along {name}"));
            }
            if let Some(v) = a.iter().find(|v| !v.is_finite()) {
                return Err(format!("its {name} coordinates hold {v}"));
            }
            if a.windows(2).any(|w| w[1] <= w[0]) {
                return Err(format!("degenerate grid: the {name} coordinates do not increase"));
            }
        }
    }
    let (array, data, comps, values) = velocity_array(attributes, request)?;
    let want: &[usize] = if request.axisymmetric { &[2, 3] } else { &[3] };
    if !want.contains(&comps) {
        return Err(if request.axisymmetric {
            format!(
                "array \"{array}\" has {comps} components; an axisymmetric table needs 2 (u_r, u_z) or 3 \
                 (u_r, u_θ, u_z)"
            )
        } else if comps == 2 {
            format!(
                "array \"{array}\" has 2 components: a 2-D (r, z) table needs axisymmetric = true, a 3-D \
                 field needs 3"
            )
        } else {
            format!("array \"{array}\" has {comps} components, a velocity needs 3")
        });
    }
    if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(format!(
            "array \"{array}\" holds {v} at value {i} (tuple {}): a velocity must be finite",
            i / comps
        ));
    }
    let tuples: Vec<DVec3> = values
        .chunks_exact(comps)
        .map(|c| if comps == 2 { DVec3::new(c[0], 0.0, c[1]) } else { DVec3::new(c[0], c[1], c[2]) })
        .collect();
    let (n_tuples, whole, name) = (tuples.len(), values.len() % comps == 0, array.clone());
    let count = move |what: &str, nodes: usize| -> Result<(), String> {
        if n_tuples != nodes || !whole {
            Err(format!(
                "array \"{name}\" has {n_tuples} values of {comps} components, the grid has {nodes} {what}"
            ))
        } else {
            Ok(())
        }
    };
    let grid = match coords {
        Coords::Axes(axes) => {
            let dims = axes.each_ref().map(Vec::len);
            if request.axisymmetric && (dims[1] != 1 || dims[0] < 2 || dims[2] < 2) {
                return Err(format!(
                    "an axisymmetric table must be one row in y (r along x, the axis along z), got {} × {} × {} points",
                    dims[0], dims[1], dims[2]
                ));
            }
            if !request.axisymmetric
                && let Some(a) = dims.iter().position(|&n| n < 2)
            {
                return Err(format!(
                    "degenerate grid: one point along {} ({} × {} × {} points); a 2-D (r, z) table needs \
                     axisymmetric = true",
                    ["x", "y", "z"][a],
                    dims[0],
                    dims[1],
                    dims[2]
                ));
            }
            let grid = match data {
                DataAt::Point => {
                    count("points", dims.iter().product())?;
                    axes.map(|n| {
                        let (lo, hi) = (n[0], n[n.len() - 1]);
                        Axis::new(n, lo, hi)
                    })
                }
                DataAt::Cell => {
                    count("cells", dims.iter().map(|&n| (n - 1).max(1)).product())?;
                    // Cell data sit at the cell centres: the grid of centres, reaching out to
                    // the outer faces (`Axis::cell` extends the outer cells' lines there).
                    axes.map(|n| {
                        let (lo, hi) = (n[0], n[n.len() - 1]);
                        let centres = if n.len() == 1 {
                            n
                        } else {
                            n.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
                        };
                        Axis::new(centres, lo, hi)
                    })
                }
            };
            Grid::Structured(Structured { axes: grid })
        }
        Coords::Hexes(points, dims) => {
            if request.axisymmetric {
                return Err("an axisymmetric table must be image data or a rectilinear grid".into());
            }
            let [nx, ny, nz] = dims;
            if nx < 2 || ny < 2 || nz < 2 || points.len() != nx * ny * nz {
                return Err(format!("degenerate grid: {nx} × {ny} × {nz} points, {} given", points.len()));
            }
            let id = |i: usize, j: usize, k: usize| (i + nx * (j + ny * k)) as u64;
            let mut cells = Vec::new();
            for k in 0..nz - 1 {
                for j in 0..ny - 1 {
                    for i in 0..nx - 1 {
                        let hex = hexahedron_corners(i, j, k).map(|(a, b, c)| id(a, b, c)).to_vec();
                        cells.push((12u8, hex));
                    }
                }
            }
            return unstructured(points, &cells, tuples, data, array, format, &count);
        }
        Coords::Cells(points, cells) => {
            if request.axisymmetric {
                return Err("an axisymmetric table must be image data or a rectilinear grid".into());
            }
            return unstructured(points, &cells, tuples, data, array, format, &count);
        }
    };
    Ok(Loaded { grid, values: tuples, format, array, data })
}

#[allow(clippy::too_many_arguments)]
fn unstructured(
    points: Vec<DVec3>,
    cells: &[(u8, Vec<u64>)],
    tuples: Vec<DVec3>,
    data: DataAt,
    array: String,
    format: &'static str,
    count: &dyn Fn(&str, usize) -> Result<(), String>,
) -> Result<Loaded, String> {
    if let Some(p) = points.iter().find(|p| !p.is_finite()) {
        return Err(format!("a point of the grid is not finite: {p}"));
    }
    if cells.is_empty() {
        return Err("degenerate grid: no cells".into());
    }
    match data {
        DataAt::Point => count("points", points.len())?,
        DataAt::Cell => count("cells", cells.len())?,
    }
    let n_points = points.len();
    let mesh = Unstructured::new(points, cells).map_err(|p| match p {
        CellProblem::Type(cell, vtk_type) => format!(
            "cell {cell} has VTK type {vtk_type}; the reader takes tetrahedra (10), voxels (11), hexahedra \
             (12), wedges (13) and pyramids (14)"
        ),
        CellProblem::Point(cell, point) => {
            format!("cell {cell} names point {point}, the grid has {n_points} points")
        }
        CellProblem::Degenerate(cell, volume) => {
            format!("degenerate cell {cell}: its volume is {volume:e} m³")
        }
    })?;
    // Every node gets a value: the grid's points, then the cells' centres.
    let values = match data {
        DataAt::Point => {
            let mut v = tuples;
            for c in 0..mesh.cells() {
                let verts =
                    &mesh.cell_points[mesh.cell_offsets[c] as usize..mesh.cell_offsets[c + 1] as usize];
                let mean = verts.iter().map(|&i| v[i as usize]).sum::<DVec3>() / verts.len() as f64;
                v.push(mean);
            }
            v
        }
        DataAt::Cell => {
            // A point's value is the inverse-distance-weighted mean of its cells' values
            // (OpenFOAM's volPointInterpolation); the centres keep the cells' own values.
            let mut sum = vec![DVec3::ZERO; n_points];
            let mut weight = vec![0.0; n_points];
            for (c, &value) in tuples.iter().enumerate().take(mesh.cells()) {
                let centre = mesh.nodes[n_points + c];
                for &i in &mesh.cell_points[mesh.cell_offsets[c] as usize..mesh.cell_offsets[c + 1] as usize]
                {
                    let w = 1.0 / (mesh.nodes[i as usize] - centre).length();
                    sum[i as usize] += w * value;
                    weight[i as usize] += w;
                }
            }
            let mut v: Vec<DVec3> =
                sum.iter().zip(&weight).map(|(s, &w)| if w > 0.0 { *s / w } else { DVec3::ZERO }).collect();
            v.extend_from_slice(&tuples);
            v
        }
    };
    Ok(Loaded { grid: Grid::Unstructured(mesh), values, format, array, data })
}

/// The velocity array: its name, where it sits, its components and its values.
fn velocity_array(
    attributes: &Attributes,
    request: Request,
) -> Result<(String, DataAt, usize, Vec<f64>), String> {
    let places: &[DataAt] = match request.data {
        Some(DataAt::Point) => &[DataAt::Point],
        Some(DataAt::Cell) => &[DataAt::Cell],
        None => &[DataAt::Point, DataAt::Cell],
    };
    let names: Vec<&str> = match request.array {
        Some(a) => vec![a],
        None => VELOCITY_NAMES.to_vec(),
    };
    for name in &names {
        for &place in places {
            let list = match place {
                DataAt::Point => &attributes.point,
                DataAt::Cell => &attributes.cell,
            };
            if let Some((comps, buf)) = find(list, name) {
                let values = floats(buf).ok_or_else(|| format!("array \"{name}\" is not numeric"))?;
                return Ok((name.to_string(), place, comps, values));
            }
        }
    }
    let listed = |list: &[Attribute]| {
        let mut n = Vec::new();
        for a in list {
            match a {
                Attribute::DataArray(d) => n.push(format!("\"{}\" ({})", d.name, d.elem.num_comp())),
                Attribute::Field { data_array, .. } => {
                    n.extend(data_array.iter().map(|d| format!("\"{}\" ({})", d.name, d.elem)))
                }
            }
        }
        if n.is_empty() { "none".to_string() } else { n.join(", ") }
    };
    let wanted = match request.array {
        Some(a) => format!("no array \"{a}\""),
        None => format!(
            "no velocity array (looked for {})",
            VELOCITY_NAMES.map(|n| format!("\"{n}\"")).join(", ")
        ),
    };
    let place = match request.data {
        Some(DataAt::Point) => " in its point data",
        Some(DataAt::Cell) => " in its cell data",
        None => "",
    };
    Err(format!(
        "{wanted}{place}; point data: {}; cell data: {} (name one with fluid.flow.array)",
        listed(&attributes.point),
        listed(&attributes.cell)
    ))
}

/// The array `name` of an attribute list (a data array, or a legacy field's member).
fn find<'a>(list: &'a [Attribute], name: &str) -> Option<(usize, &'a IOBuffer)> {
    for a in list {
        match a {
            Attribute::DataArray(d) if d.name == name => return Some((d.elem.num_comp() as usize, &d.data)),
            Attribute::Field { data_array, .. } => {
                if let Some(d) = data_array.iter().find(|d| d.name == name) {
                    return Some((d.elem as usize, &d.data));
                }
            }
            _ => {}
        }
    }
    None
}

fn floats(b: &IOBuffer) -> Option<Vec<f64>> {
    match b {
        // f32 values as their shortest decimal, which is what the writer meant (0.00025, not
        // 0.000250000011874).
        IOBuffer::F32(v) => Some(v.iter().map(|&x| shortest(x)).collect()),
        _ => b.cast_into::<f64>(),
    }
}

fn points_of(b: &IOBuffer) -> Option<Vec<DVec3>> {
    let v = floats(b)?;
    (v.len() % 3 == 0).then(|| v.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect())
}

/// `x` as the f64 of its shortest decimal form.
fn shortest(x: f32) -> f64 {
    format!("{x}").parse().unwrap_or(x as f64)
}

fn cell_lists(v: &VertexNumbers, n: usize) -> Result<Vec<Vec<u64>>, String> {
    let bad = || "its cell connectivity is inconsistent with its number of cells".to_string();
    match v {
        VertexNumbers::Legacy { vertices, .. } => {
            let mut out = Vec::with_capacity(n);
            let mut i = 0;
            while i < vertices.len() {
                let k = vertices[i] as usize;
                let list = vertices.get(i + 1..i + 1 + k).ok_or_else(bad)?;
                out.push(list.iter().map(|&p| p as u64).collect());
                i += 1 + k;
            }
            if out.len() != n { Err(bad()) } else { Ok(out) }
        }
        VertexNumbers::XML { connectivity, offsets } => {
            let offsets: &[u64] =
                if offsets.len() == n + 1 && offsets.first() == Some(&0) { &offsets[1..] } else { offsets };
            if offsets.len() != n {
                return Err(bad());
            }
            let mut start = 0usize;
            let mut out = Vec::with_capacity(n);
            for &end in offsets {
                let list = connectivity.get(start..end as usize).ok_or_else(bad)?;
                out.push(list.to_vec());
                start = end as usize;
            }
            Ok(out)
        }
    }
}

fn one_piece<P>(pieces: Vec<Piece<P>>, _file: &Path) -> Result<[Piece<P>; 1], String> {
    let n = pieces.len();
    <[Piece<P>; 1]>::try_from(pieces)
        .map_err(|_| format!("has {n} pieces; the reader takes structured grids of one piece"))
}

fn load_piece<P: PieceData>(piece: Piece<P>, file: &Path) -> Result<P, String> {
    piece.into_loaded_piece_data(Some(file)).map_err(|e| format!("cannot read a piece: {}", one_line(&e)))
}

fn one_line(e: &dyn std::fmt::Display) -> String {
    e.to_string().replace('\n', " ")
}
