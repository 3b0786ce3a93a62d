//! The ParaView sink (`--formats vtk`): a time series of VTK XML PolyData files and the
//! ParaView collection (`.pvd`) that lists them with their times.
//!
//! - `DIR/<scene>.pvd` — the collection: one `DataSet` per output frame, `timestep` the
//!   simulated time (s), `file` the frame's `.vtp`. Opening it in ParaView gives the particles
//!   as a time series.
//! - `DIR/<scene>_vtk/particles_NNNNNN.vtp` — one frame: a point per particle (a vertex cell
//!   each, so that ParaView draws them as they are) with the point arrays of [`POINT_ARRAYS`].
//! - `DIR/<scene>_walls.vtp` — the walls as triangulated surfaces (the solids the MCAP and rerun
//!   writers draw, [`geometry::triangulate`]), with the cell array `wall`: the index of the
//!   wall in the scene's `[[walls]]` (the `.pvd` names them in a comment).
//!
//! Why `.vtp` frames and a `.pvd` rather than one VTKHDF file: `vtkio` writes XML PolyData, not
//! HDF5 (an HDF5 writer would bring the C HDF5 library into the build), and a file per frame
//! keeps the guarantee of the other formats — each frame reaches the disk whole before the
//! collection names it, so a run stopped in any way leaves a valid collection of whole frames.
//!
//! The arrays are binary: base64 of zlib-compressed blocks (`vtkZLibDataCompressor`, what
//! ParaView's own writers use), through `vtkio`. Positions and every real array are Float64: the
//! numbers are the CSV's and the MCAP's bit for bit.
//!
//! Flushing: a frame's `.vtp` is written and flushed whole, then the `.pvd` is extended — room
//! for the entry taken first, then its new entry and the closing tags in one write, over the
//! closing tags of the frame before — and flushed. So after every frame the `.pvd` is a complete document naming only whole files, and
//! a run killed outright (SIGKILL) leaves one that ParaView opens, up to its last frame.

use super::file::OutputFile;
use super::geometry::{self, Solid};
use super::{OutputError, Sink, SinkMark};
use crate::pipeline::Simulation;
use std::fmt::Write as _;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use vtkio::model::{Attribute, Attributes, ByteOrder, DataSet, PolyDataPiece, Version, VertexNumbers, Vtk};
use vtkio::xml::Compressor;

/// The point arrays of a particle frame, in the order they are written: name, type,
/// components, meaning.
pub const POINT_ARRAYS: &[(&str, &str, u32, &str)] = &[
    ("id", "UInt32", 1, "the particle's id (the CSV's `id`)"),
    ("kind", "UInt16", 1, "index of its kind in the scene's [[kinds]]"),
    ("diameter", "Float64", 1, "m"),
    ("radius", "Float64", 1, "m: the glyph scale array that draws spheres at true size"),
    ("velocity", "Float64", 3, "m/s"),
    ("speed", "Float64", 1, "m/s"),
    ("state", "UInt8", 1, "0 free, 1 held, 2 resting"),
];

/// The point arrays written after [`POINT_ARRAYS`] in a scene with rotation only.
pub const ROTATION_POINT_ARRAYS: &[(&str, &str, u32, &str)] =
    &[("angular_velocity", "Float64", 3, "rad/s (scenes with rotation only)")];

/// zlib level of the arrays: 6 is zlib's default, and ParaView's.
const COMPRESSION_LEVEL: u32 = 6;

/// What closes the `.pvd`; each frame's entry is written over it, followed by it again.
pub const PVD_TAIL: &str = "  </Collection>\n</VTKFile>\n";

/// Writes the `.pvd` collection, the particle frames and the walls.
pub struct VtkSink {
    pvd_path: PathBuf,
    pvd: OutputFile,
    /// Where the closing tags start in the `.pvd`: the next entry goes there.
    tail_at: u64,
    frames_dir: PathBuf,
    /// The frames' folder as the `.pvd` names it (relative to the `.pvd`, XML-escaped).
    frames_rel: String,
    walls_path: PathBuf,
    walls_written: bool,
    frames: u64,
}

/// `s` with the five XML special characters escaped, for an attribute value.
fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// `s` fit for the inside of an XML comment (which may not hold `--`).
fn comment_safe(s: &str) -> String {
    s.replace("--", "- -")
}

impl VtkSink {
    /// Creates `dir/<stem>.pvd` (an empty collection, valid at once) and the frames' folder
    /// `dir/<stem>_vtk/`; the walls' file `dir/<stem>_walls.vtp` is written with the first frame.
    pub fn create(dir: &Path, stem: &str) -> Result<Self, OutputError> {
        let frames_name = format!("{stem}_vtk");
        let frames_dir = dir.join(&frames_name);
        std::fs::create_dir_all(&frames_dir).map_err(|e| OutputError::create(&frames_dir, e))?;
        // An earlier run's frames past this run's last would stay beside a `.pvd` that does not
        // list them (issue 25, finding 13): clear them before the first frame.
        let mut stale = super::stale::Removed::default();
        super::stale::remove_frames(&frames_dir, &mut stale);
        if let Some(first) = stale.failed.first() {
            return Err(OutputError::new(&frames_dir, first));
        }
        let pvd_path = dir.join(format!("{stem}.pvd"));
        let mut pvd = OutputFile::create(&pvd_path, 1 << 16)?;
        let head = "<?xml version=\"1.0\"?>\n\
                    <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
        pvd.write_all(head.as_bytes())
            .and_then(|()| pvd.write_all(PVD_TAIL.as_bytes()))
            .and_then(|()| pvd.flush())
            .map_err(|e| OutputError::write(&pvd_path, e))?;
        Ok(VtkSink {
            pvd_path,
            pvd,
            tail_at: head.len() as u64,
            frames_dir,
            frames_rel: xml_escape(&frames_name),
            walls_path: dir.join(format!("{stem}_walls.vtp")),
            walls_written: false,
            frames: 0,
        })
    }

    /// Opens the collection of a checkpointed run to go on from its mark ([`SinkMark::Vtk`]):
    /// the `.pvd` cut after its closing tags there, the next frame numbered after the last
    /// one the checkpoint knew (a frame written after it is written again).
    pub fn resume(
        dir: &Path,
        stem: &str,
        (tail_at, frames, walls_written): (u64, u64, bool),
    ) -> Result<Self, OutputError> {
        let frames_name = format!("{stem}_vtk");
        let frames_dir = dir.join(&frames_name);
        std::fs::create_dir_all(&frames_dir).map_err(|e| OutputError::create(&frames_dir, e))?;
        let pvd_path = dir.join(format!("{stem}.pvd"));
        let pvd = OutputFile::append_at(&pvd_path, tail_at + PVD_TAIL.len() as u64, 1 << 16)?;
        Ok(VtkSink {
            pvd_path,
            pvd,
            tail_at,
            frames_dir,
            frames_rel: xml_escape(&frames_name),
            walls_path: dir.join(format!("{stem}_walls.vtp")),
            walls_written,
            frames,
        })
    }

    /// The collection file.
    pub fn pvd_path(&self) -> &Path {
        &self.pvd_path
    }

    /// The walls' file.
    pub fn walls_path(&self) -> &Path {
        &self.walls_path
    }

    /// Extends the `.pvd` by `entry` (whole lines), keeping it closed. The file first grows by
    /// the entry's length in newlines after the closing tags — whitespace after the document,
    /// which leaves it valid if the disk fills in the middle of that write — and only then are
    /// the closing tags overwritten by the entry and themselves, in the room already taken.
    fn append_to_pvd(&mut self, entry: &str) -> Result<(), OutputError> {
        let end = self.tail_at + PVD_TAIL.len() as u64;
        let room = vec![b'\n'; entry.len()];
        let text = format!("{entry}{PVD_TAIL}");
        let pvd = &mut self.pvd;
        pvd.seek(SeekFrom::Start(end))
            .and_then(|_| pvd.write_all(&room))
            .and_then(|()| pvd.flush())
            .and_then(|()| pvd.seek(SeekFrom::Start(self.tail_at)))
            .and_then(|_| pvd.write_all(text.as_bytes()))
            .and_then(|()| pvd.flush())
            .map_err(|e| OutputError::write(&self.pvd_path, e))?;
        self.tail_at += entry.len() as u64;
        Ok(())
    }

    fn write_walls(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        let mut points: Vec<f64> = Vec::new();
        let mut connectivity: Vec<u64> = Vec::new();
        let mut wall_of_cell: Vec<u32> = Vec::new();
        let mut names = String::new();
        for (index, w) in geometry::wall_solids(sim).into_iter().enumerate() {
            let shape = match w.solid {
                Solid::Cuboid { .. } => "box",
                Solid::Cylinder { .. } => "cylinder",
                Solid::Triangles { .. } => "triangles",
            };
            let _ = write!(names, "\n       {index} = {} ({shape})", comment_safe(&w.name));
            let (vertices, triangles) = geometry::triangulate(&w.solid);
            let first = (points.len() / 3) as u64;
            points.extend(vertices.iter().flat_map(|v| v.to_array()));
            connectivity.extend(triangles.iter().flatten().map(|&i| first + u64::from(i)));
            wall_of_cell.extend(std::iter::repeat_n(index as u32, triangles.len()));
        }
        let cells = wall_of_cell.len() as u64;
        let piece = PolyDataPiece {
            points: points.into(),
            polys: Some(VertexNumbers::XML { connectivity, offsets: (1..=cells).map(|k| 3 * k).collect() }),
            data: Attributes {
                point: vec![],
                cell: vec![Attribute::generic("wall", 1).with_data(wall_of_cell)],
            },
            ..Default::default()
        };
        write_vtp(&self.walls_path, piece)?;
        let comment = format!(
            "  <!-- The walls are in the file {} (open it beside this collection); its cell array \
             `wall` is the wall's index:{names} -->\n",
            xml_escape(&comment_safe(&self.walls_path.file_name().unwrap_or_default().to_string_lossy()))
        );
        self.append_to_pvd(&comment)
    }
}

/// A particle frame: the points, a vertex cell per point, and the point arrays of
/// [`POINT_ARRAYS`].
fn particles_piece(sim: &Simulation) -> PolyDataPiece {
    let p = &sim.world.particles;
    let n = p.len() as u64;
    let points: Vec<f64> = p.pos.iter().flat_map(|x| x.to_array()).collect();
    let velocity: Vec<f64> = p.vel.iter().flat_map(|v| v.to_array()).collect();
    let point = vec![
        Attribute::generic("id", 1).with_data(p.id.clone()),
        Attribute::generic("kind", 1).with_data(p.kind.clone()),
        Attribute::generic("diameter", 1).with_data(p.diameter.clone()),
        Attribute::generic("radius", 1).with_data(p.diameter.iter().map(|d| 0.5 * d).collect::<Vec<f64>>()),
        Attribute::generic("velocity", 3).with_data(velocity),
        Attribute::generic("speed", 1).with_data(p.vel.iter().map(|v| v.length()).collect::<Vec<f64>>()),
        Attribute::generic("state", 1).with_data(p.state.iter().map(|s| s.code()).collect::<Vec<u8>>()),
    ];
    let mut point = point;
    if sim.setup.physics.rotation {
        let omega: Vec<f64> = p.omega.values().iter().flat_map(|w| w.to_array()).collect();
        point.push(Attribute::generic("angular_velocity", 3).with_data(omega));
    }
    PolyDataPiece {
        points: points.into(),
        verts: Some(VertexNumbers::XML { connectivity: (0..n).collect(), offsets: (1..=n).collect() }),
        data: Attributes { point, cell: vec![] },
        ..Default::default()
    }
}

/// Writes `piece` as a VTK XML PolyData file at `path`, flushed to the OS before it returns.
/// The document is built in memory and written with [`OutputFile`], so that a write error is the
/// OS's, naming the file (vtkio's own writer turns it into a formatting error).
fn write_vtp(path: &Path, piece: PolyDataPiece) -> Result<(), OutputError> {
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        byte_order: ByteOrder::LittleEndian,
        title: String::new(),
        file_path: None,
        data: DataSet::inline(piece),
    };
    let xml = vtk
        .try_into_xml_format(Compressor::ZLib, COMPRESSION_LEVEL)
        .map_err(|e| OutputError::new(path, format!("cannot encode: {e}")))?;
    let text = xml.to_string();
    let mut file = OutputFile::create(path, text.len() + 1)?;
    file.write_all(text.as_bytes())
        .and_then(|()| file.write_all(b"\n"))
        .and_then(|()| file.flush())
        .map_err(|e| OutputError::write(path, e))
}

impl Sink for VtkSink {
    fn frame(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        if !self.walls_written {
            self.write_walls(sim)?;
            self.walls_written = true;
        }
        let name = format!("particles_{:06}.vtp", self.frames);
        write_vtp(&self.frames_dir.join(&name), particles_piece(sim))?;
        self.frames += 1;
        let entry = format!(
            "    <DataSet timestep=\"{}\" part=\"0\" file=\"{}/{}\"/>\n",
            sim.world.time, self.frames_rel, name
        );
        self.append_to_pvd(&entry)
    }

    fn mark(&mut self) -> Result<Option<SinkMark>, OutputError> {
        self.pvd.flush().map_err(|e| OutputError::write(&self.pvd_path, e))?;
        let (tail_at, frames, walls_written) = (self.tail_at, self.frames, self.walls_written);
        Ok(Some(SinkMark::Vtk { tail_at, frames, walls_written }))
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.pvd.sync().map_err(|e| OutputError::write(&self.pvd_path, e))
    }
}
