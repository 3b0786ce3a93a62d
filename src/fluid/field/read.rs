//! Reading a velocity field from a VTK file with `vtkio`: image data (`.vti`), rectilinear
//! grids (`.vtr`), structured grids (`.vts`), unstructured grids (`.vtu`, ASCII, binary or
//! zlib-compressed appended data) and legacy `.vtk` files (what OpenFOAM's `foamToVTK
//! -legacy` writes), into a grid and one velocity per node.

use super::structured::{Axis, Structured};
use super::unstructured::{CellProblem, Unstructured, hexahedron_corners};
use super::{DataAt, Grid};
use crate::numeric::num;
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

/// The largest field file read (bytes), a `.pvtu`'s pieces each: 1 GiB, some 40 million
/// points of a binary 32-bit velocity with their coordinates. Beyond it a path is far more
/// likely wrong than a field, and reading it whole would take the memory of a run
/// ([`crate::files`]).
pub const FIELD_FILE_CAP: u64 = 1 << 30;

pub use super::vet::INFLATE_CAP;

/// Reads the field of `file`.
pub fn load(file: &Path, request: Request) -> Result<Loaded, FieldError> {
    let fail = |message: String| FieldError { file: file.to_path_buf(), message };
    let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("");
    let format = match ext {
        "vti" => "VTK XML image data (.vti)",
        "vtr" => "VTK XML rectilinear grid (.vtr)",
        "vts" => "VTK XML structured grid (.vts)",
        "vtu" => "VTK XML unstructured grid (.vtu)",
        "pvtu" => "VTK XML parallel unstructured grid (.pvtu)",
        "vtk" => "legacy VTK (.vtk)",
        other => {
            if let Err(e) = std::fs::metadata(file) {
                return Err(fail(format!("cannot read the field file: {e}")));
            }
            return Err(fail(format!(
                "unknown field format \"{}\": expected .vti, .vtr, .vts, .vtu, .pvtu or legacy .vtk",
                if other.is_empty() { "(no extension)" } else { other }
            )));
        }
    };
    let bytes = read_file(file).map_err(fail)?;
    // The most values the file can hold: a value takes a byte at least, or (XML) comes out of
    // the capped inflation of compressed data.
    let budget = (bytes.len() as u64).saturating_add(if ext == "vtk" { 0 } else { INFLATE_CAP });
    if ext == "vtk" {
        legacy_header(&bytes).map_err(fail)?;
    }
    let mut vtk = import(ext, &bytes).map_err(|e| fail(format!("cannot read it as {format}: {e}")))?;
    drop(bytes);
    if ext == "pvtu" {
        load_sources(&mut vtk, file).map_err(fail)?;
    }
    let (grid, attributes) = match vtk.data {
        DataSet::ImageData { extent, origin, spacing, pieces, .. } => {
            let [piece] = one_piece(pieces, file).map_err(fail)?;
            let piece = load_piece(piece, file).map_err(fail)?;
            let dims = extent.clone().into_dims().map(u64::from);
            let start = extent.into_ranges().map(|r| *r.start());
            let points = dims.iter().try_fold(1u64, |p, &d| p.checked_mul(d)).filter(|&p| p <= budget);
            if points.is_none() {
                return Err(fail(format!(
                    "its extent of {} × {} × {} points is more than the file can hold",
                    dims[0], dims[1], dims[2]
                )));
            }
            if spacing.iter().enumerate().any(|(a, &h)| dims[a] > 1 && !(h > 0.0 && h.is_finite())) {
                return Err(fail(format!(
                    "degenerate grid: spacing [{}] must be > 0 along every axis",
                    spacing.map(|h| num(h as f64)).join(", ")
                )));
            }
            let image = Image {
                origin: origin.map(shortest),
                spacing: spacing.map(shortest),
                start: start.map(f64::from),
                dims: dims.map(|d| d as usize),
            };
            (Coords::Image(image), piece.data)
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
            // The points and their count in checked arithmetic (a product that wraps would
            // let 0 points pass and the cells loop over 2⁶⁴).
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

/// The bytes of a field file, under the rule of every file read ([`crate::files`]).
fn read_file(file: &Path) -> Result<Vec<u8>, String> {
    crate::files::read(file, FIELD_FILE_CAP, "a field file").map_err(|p| match p {
        crate::files::FileProblem::Io(e) => format!("cannot read the field file: {e}"),
        other => other.to_string(),
    })
}

/// Parses a field file's `bytes` with `vtkio`: legacy as it is; XML with raw appended data
/// re-encoded first ([`super::appended`]) and vetted ([`super::vet`]) so that `vtkio` is
/// handed no size it would trust beyond the file. A panic inside `vtkio` on a malformed file
/// that vetting did not foresee (it slices without checking in places) is the last resort:
/// caught, silently, and turned into an error rather than taken down with the run.
fn import(ext: &str, bytes: &[u8]) -> Result<vtkio::Vtk, String> {
    if ext == "vtk" {
        // vtkio's parser stops at a section it cannot read and keeps what came before (a file
        // cut inside its cell data would lose them without a word): the whole file must be read.
        let parsed =
            quietly(|| Ok(vtkio::parser::parse_be(bytes).ok().map(|(rest, vtk)| (rest.len(), vtk))))?;
        return match parsed {
            Some((0, vtk)) => legacy_counts(bytes, &vtk).map(|()| vtk),
            Some((rest, _)) => {
                let at = bytes.len() - rest;
                let line = bytes[at..].split(|&b| b == b'\n').next().unwrap_or(&[]);
                let line = String::from_utf8_lossy(&line[..line.len().min(40)]).into_owned();
                Err(format!(
                    "it cannot be read past byte {at} of {} (at {line:?}): the file is cut short or damaged there",
                    bytes.len()
                ))
            }
            // The parser's own message.
            None => quietly(|| vtkio::Vtk::parse_legacy_be(bytes).map_err(|e| one_line(&e))),
        };
    }
    let fixed = super::appended::raw_to_base64(bytes)?;
    let xml: &[u8] = fixed.as_deref().unwrap_or(bytes);
    let arrays = super::vet::vet(xml, ext, bytes.len() as u64)?;
    let vtk = quietly(|| vtkio::Vtk::parse_xml(xml).map_err(|e| one_line(&e)))?;
    // vtkio leaves out an array it cannot decode (a damaged zlib stream) without a word: name
    // it, rather than report it missing later.
    match &vtk.data {
        DataSet::ImageData { pieces, .. } => {
            first_inline(pieces).map_or(Ok(()), |p| dropped(&arrays, &p.data))?
        }
        DataSet::RectilinearGrid { pieces, .. } => {
            first_inline(pieces).map_or(Ok(()), |p| dropped(&arrays, &p.data))?
        }
        DataSet::StructuredGrid { pieces, .. } => {
            first_inline(pieces).map_or(Ok(()), |p| dropped(&arrays, &p.data))?
        }
        DataSet::UnstructuredGrid { pieces, .. } => {
            first_inline(pieces).map_or(Ok(()), |p| dropped(&arrays, &p.data))?
        }
        _ => {}
    }
    Ok(vtk)
}

fn first_inline<P>(pieces: &[Piece<P>]) -> Option<&P> {
    match pieces.first() {
        Some(Piece::Inline(p)) => Some(p),
        _ => None,
    }
}

/// The first of the point and cell arrays the file holds (`seen`) that vtkio left out of `data`.
fn dropped(seen: &[(DataAt, String)], data: &Attributes) -> Result<(), String> {
    for (at, name) in seen {
        let list = match at {
            DataAt::Point => &data.point,
            DataAt::Cell => &data.cell,
        };
        if find(list, name).is_none() {
            return Err(format!(
                "array \"{name}\" ({} data) cannot be decoded: its data are damaged",
                if *at == DataAt::Point { "point" } else { "cell" }
            ));
        }
    }
    Ok(())
}

/// `f`, with a panic inside it caught and its message kept off the terminal (the default hook
/// prints it and a backtrace): the caller reports the error, naming the file.
fn quietly<T>(f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    use std::cell::Cell;
    use std::sync::Once;
    thread_local!(static QUIET: Cell<bool> = const { Cell::new(false) });
    static HOOK: Once = Once::new();
    // One hook for the process, which stays silent only on a thread inside `quietly`: other
    // threads' panics are printed as before.
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let was = QUIET.with(|q| q.replace(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    QUIET.with(|q| q.set(was));
    result.unwrap_or_else(|_| Err("the VTK reader (vtkio) failed on it: the file is malformed".into()))
}

/// A `.pvtu`'s pieces, each read from its `.vtu` file under the same rules as a field file,
/// in place of `vtkio`'s own loading (which recurses without end into a `.pvtu` that lists
/// itself, and reads a device without bound).
fn load_sources(vtk: &mut vtkio::Vtk, file: &Path) -> Result<(), String> {
    let DataSet::UnstructuredGrid { pieces, .. } = &mut vtk.data else { return Ok(()) };
    let dir = file.parent().unwrap_or(Path::new(""));
    let mut loaded = Vec::with_capacity(pieces.len());
    for (i, piece) in std::mem::take(pieces).into_iter().enumerate() {
        let Piece::Source(source, _) = piece else {
            loaded.push(piece);
            continue;
        };
        let path = dir.join(&source);
        let at = |m: String| format!("piece {i}, {}: {m}", path.display());
        // A piece is a serial file: a .pvtu that names a .pvtu (itself, or one that names it
        // back) would be read without end.
        if path.extension().and_then(|e| e.to_str()) != Some("vtu") {
            return Err(at(format!(
                "the pieces of a .pvtu are .vtu files, not \"{source}\" (a .pvtu that lists a .pvtu, itself \
                 or another, is refused: it would be read without end)"
            )));
        }
        let bytes = read_file(&path).map_err(at)?;
        let piece_vtk = import("vtu", &bytes)
            .map_err(|e| at(format!("cannot read it as VTK XML unstructured grid (.vtu): {e}")))?;
        match piece_vtk.data {
            DataSet::UnstructuredGrid { pieces: inner, .. } => loaded.extend(inner),
            _ => return Err(at("is not an unstructured grid".into())),
        }
    }
    *pieces = loaded;
    Ok(())
}

/// A legacy file's `POINT_DATA n` and `CELL_DATA n` against its grid: vtkio reads a count and
/// then as many arrays as it can, and keeps none when they are not there (a file cut after
/// `POINT_DATA 2` would be read as a grid without point data).
fn legacy_counts(bytes: &[u8], vtk: &vtkio::Vtk) -> Result<(), String> {
    let grid_points = |dims: [u32; 3]| dims.iter().map(|&d| d as u64).product::<u64>();
    let grid_cells = |dims: [u32; 3]| dims.iter().filter(|&&d| d > 1).map(|&d| d as u64 - 1).product::<u64>();
    let (points, cells) = match &vtk.data {
        DataSet::ImageData { extent, .. }
        | DataSet::StructuredGrid { extent, .. }
        | DataSet::RectilinearGrid { extent, .. } => {
            let dims = extent.clone().into_dims();
            (grid_points(dims), grid_cells(dims))
        }
        DataSet::UnstructuredGrid { pieces, .. } => match first_inline(pieces) {
            Some(p) => ((p.points.len() / 3) as u64, p.cells.types.len() as u64),
            None => return Ok(()),
        },
        _ => return Ok(()),
    };
    for (key, grid, what) in [("POINT_DATA", points, "points"), ("CELL_DATA", cells, "cells")] {
        // A section starts a line; its count follows the keyword.
        let mut needle = b"\n".to_vec();
        needle.extend_from_slice(key.as_bytes());
        let Some(at) = bytes.windows(needle.len()).position(|w| w == needle.as_slice()) else { continue };
        let line = bytes[at + 1..].split(|&b| b == b'\n').next().unwrap_or(&[]);
        let line = String::from_utf8_lossy(line);
        let n = line.split_ascii_whitespace().nth(1).and_then(|w| w.parse::<u64>().ok());
        if n != Some(grid) {
            return Err(format!(
                "\"{}\" at byte {}: the grid has {grid} {what} (the file is cut short or the count is wrong)",
                line.trim(),
                at + 1
            ));
        }
    }
    Ok(())
}

/// A legacy file's structured-points header, checked as written: the DIMENSIONS against the
/// bytes of the file (2·10⁹ points per axis in a 300-byte file), the SPACING before `vtkio`
/// reads it in single precision (where 1e-300 becomes 0, and would be shown as 0).
fn legacy_header(bytes: &[u8]) -> Result<(), String> {
    let mut dims: Option<(String, [u64; 3])> = None;
    let mut spacing: Option<String> = None;
    // The header is text up to the first data section; a binary file's data come after.
    for line in bytes.split(|&b| b == b'\n').take(64) {
        let line = String::from_utf8_lossy(line);
        let mut words = line.split_ascii_whitespace();
        let key = words.next().unwrap_or("").to_ascii_uppercase();
        let rest: Vec<&str> = words.collect();
        match key.as_str() {
            "DIMENSIONS" => {
                let d: Vec<u64> = rest.iter().filter_map(|w| w.parse().ok()).collect();
                if let [x, y, z] = d[..] {
                    dims = Some((rest.join(" "), [x, y, z]));
                }
            }
            "SPACING" | "ASPECT_RATIO" => spacing = Some(rest.join(" ")),
            "POINT_DATA" | "CELL_DATA" | "POINTS" | "CELLS" | "X_COORDINATES" => break,
            _ => {}
        }
    }
    if let Some((text, d)) = &dims {
        // u128: three 32-bit counts cannot overflow it.
        let points = d.iter().fold(1u128, |p, &n| p.saturating_mul(n as u128));
        if points > bytes.len() as u128 {
            return Err(format!(
                "DIMENSIONS {text} declares {} points, more than the file's {} bytes hold (a value takes a \
                 byte at least)",
                num(points as f64),
                bytes.len()
            ));
        }
    }
    if let Some(text) = spacing {
        super::vet::vet_spacing("SPACING", &text, dims.map(|d| d.1))?;
    }
    Ok(())
}

/// Image data as declared: its nodes are made only once the velocity's length has confirmed
/// their number (a few bytes may declare 2·10⁹ nodes per axis).
struct Image {
    origin: [f64; 3],
    spacing: [f64; 3],
    /// The extent's first index per axis.
    start: [f64; 3],
    dims: [usize; 3],
}

impl Image {
    fn axes(&self) -> [Vec<f64>; 3] {
        [0, 1, 2].map(|a| {
            let (o, h, s) = (self.origin[a], self.spacing[a], self.start[a]);
            (0..self.dims[a]).map(|i| o + (s + i as f64) * h).collect()
        })
    }
}

/// Grid coordinates as read, before the velocity picks point or cell nodes.
enum Coords {
    /// Image data.
    Image(Image),
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
    let (array, data, comps, values) = velocity_array(attributes, request)?;
    // Image data: the velocity's length first (checked arithmetic), the nodes after.
    let coords = match coords {
        Coords::Image(image) => {
            let d = image.dims;
            let nodes = match data {
                DataAt::Point => d.iter().try_fold(1usize, |p, &n| p.checked_mul(n)),
                DataAt::Cell => d.iter().try_fold(1usize, |p, &n| p.checked_mul(n.saturating_sub(1).max(1))),
            };
            let what = if data == DataAt::Point { "points" } else { "cells" };
            if d.contains(&0) || nodes.is_none_or(|n| values.len() / comps.max(1) != n) {
                return Err(format!(
                    "array \"{array}\" has {} values of {comps} components, the grid of {} × {} × {} points has {} {what}",
                    values.len() / comps.max(1),
                    d[0],
                    d[1],
                    d[2],
                    nodes.map_or("more than 1.8e19".to_string(), |n| n.to_string())
                ));
            }
            Coords::Axes(image.axes())
        }
        other => other,
    };
    if let Coords::Axes(axes) = &coords {
        for (a, name) in axes.iter().zip(["x", "y", "z"]) {
            if a.is_empty() {
                return Err(format!("degenerate grid: no points along {name}"));
            }
            if let Some(v) = a.iter().find(|v| !v.is_finite()) {
                return Err(format!("its {name} coordinates hold {}", num(*v)));
            }
            if let Some(w) = a.windows(2).find(|w| w[1] <= w[0]) {
                return Err(format!(
                    "degenerate grid: the {name} coordinates do not increase ({} then {})",
                    num(w[0]),
                    num(w[1])
                ));
            }
        }
    }
    if let Some(problem) = too_large(&coords) {
        return Err(problem);
    }
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
        // Expanded into axes above.
        Coords::Image(_) => return Err("image data whose nodes were not made".into()),
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
            let declared = nx.checked_mul(ny).and_then(|n| n.checked_mul(nz));
            if nx < 2 || ny < 2 || nz < 2 || declared != Some(points.len()) {
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
        CellProblem::Count(cell, vtk_type, got, need) => {
            format!("cell {cell} of VTK type {vtk_type} lists {got} points; that type has {need}")
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

/// Refuses a grid whose span along an axis has no finite cube: a cell's volume (span³)
/// overflows there, and a cell 1e150 m tall would be called degenerate for a volume of ∞.
fn too_large(coords: &Coords) -> Option<String> {
    let spans: [(f64, f64); 3] = match coords {
        Coords::Image(_) => return None,
        Coords::Axes(axes) => {
            axes.each_ref().map(|a| (a.first().copied().unwrap_or(0.0), a.last().copied().unwrap_or(0.0)))
        }
        Coords::Hexes(points, _) | Coords::Cells(points, _) => [0, 1, 2].map(|k| {
            points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[k]), hi.max(p[k])))
        }),
    };
    for (k, (lo, hi)) in spans.into_iter().enumerate() {
        let span = hi - lo;
        if span.is_finite() && !(span * span * span).is_finite() {
            return Some(format!(
                "its {} coordinates span {} m ({} … {}): a cell's volume would overflow (the engine takes \
                 spans up to 5e102 m)",
                ["x", "y", "z"][k],
                num(span),
                num(lo),
                num(hi)
            ));
        }
        if !span.is_finite() && lo.is_finite() && hi.is_finite() {
            return Some(format!(
                "its {} coordinates span {} … {}: beyond what a double can measure",
                ["x", "y", "z"][k],
                num(lo),
                num(hi)
            ));
        }
    }
    None
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

#[cfg(test)]
mod tests {
    use super::quietly;

    #[test]
    fn a_panic_inside_quietly_is_an_error_and_the_thread_goes_on() {
        let r: Result<(), String> = quietly(|| panic!("slice index out of range"));
        assert!(r.unwrap_err().contains("vtkio"));
        // Quiet only inside: a later call that does not panic gives its own result.
        assert_eq!(quietly(|| Ok(3)), Ok(3));
    }
}
