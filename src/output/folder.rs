//! The files a run writes into its output folder, made in one place for the CLI and the Python
//! module: which format gives which sinks and files, the folder created, and an earlier run's
//! stale outputs removed (issue 26, item 3: the two had drifted — Python could not write VTK
//! and never removed stale files).

use super::{EventCsv, McapOptions, McapSink, OutputError, Sink, SinkMark, TrajectoryCsv, VtkSink, stale};
use std::path::{Path, PathBuf};

/// An output file format of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// DIR/<scene>.mcap: Foxglove's schemas, opens in Foxglove and rerun.
    Mcap,
    /// DIR/trajectories.csv and DIR/events.csv.
    Csv,
    /// DIR/<scene>.rrd: rerun's native recording (needs the `rerun` cargo feature).
    Rrd,
    /// DIR/<scene>.pvd (its frames in DIR/<scene>_vtk/), DIR/<scene>_walls.vtp and
    /// DIR/events.csv: for ParaView.
    Vtk,
}

impl Format {
    /// Every format, in the order of the names below.
    pub const ALL: [Format; 4] = [Format::Mcap, Format::Csv, Format::Rrd, Format::Vtk];

    /// The name a user writes (`--formats mcap,csv`, `formats=["vtk"]`).
    pub fn name(self) -> &'static str {
        match self {
            Format::Mcap => "mcap",
            Format::Csv => "csv",
            Format::Rrd => "rrd",
            Format::Vtk => "vtk",
        }
    }

    /// The format named `name`; an unknown name, or `rrd` in a build without the `rerun`
    /// feature, is an error that says why and lists the names.
    pub fn parse(name: &str) -> Result<Format, String> {
        let names: Vec<String> = Format::ALL.iter().map(|f| format!("\"{}\"", f.name())).collect();
        let format = Format::ALL
            .into_iter()
            .find(|f| f.name() == name)
            .ok_or_else(|| format!("{name:?} is not one of {}", names.join(", ")))?;
        format.available().map(|()| format).map_err(|e| format!("{name:?}: {e}"))
    }

    /// Whether this build can write the format: `rrd` needs the `rerun` feature (the error says
    /// how to get it; the caller names the format).
    pub fn available(self) -> Result<(), String> {
        if self == Format::Rrd && !cfg!(feature = "rerun") {
            return Err("this wetbounce was built without the `rerun` feature; rebuild with \
                        `cargo build --release --features rerun`, or open the .mcap in rerun"
                .into());
        }
        Ok(())
    }

    /// What a run writes when no format is named: the MCAP, and the rerun recording in a build
    /// that can write it.
    pub fn defaults() -> Vec<Format> {
        if cfg!(feature = "rerun") { vec![Format::Mcap, Format::Rrd] } else { vec![Format::Mcap] }
    }
}

/// What names and fills the files of one run.
#[derive(Debug, Clone)]
pub struct Folder<'a> {
    /// The output folder (created if needed).
    pub out: &'a Path,
    /// The files' stem: `<stem>.mcap`, `<stem>.pvd`, … (the scene file's stem by default).
    pub stem: &'a str,
    /// The scene file, as the MCAP's metadata names it.
    pub scene_path: &'a Path,
    /// The scene's text, embedded in the MCAP (and the rerun recording).
    pub scene_source: &'a str,
    /// Particles drawn as spheres on the MCAP's `/scene` up to this count.
    pub max_spheres: usize,
    /// The scene has rotation: the CSV files and the MCAP get the spin columns.
    pub rotation: bool,
}

/// The sinks of a run and the files they write, and what an earlier run left that was removed.
pub struct Outputs {
    /// One sink per file (the events' CSV serves both `csv` and `vtk`); `Send`, so that a caller
    /// may step on another thread (Python releases the GIL that way).
    pub sinks: Vec<Box<dyn Sink + Send>>,
    /// The files the sinks write, in the order they were created.
    pub written: Vec<PathBuf>,
    /// An earlier run's outputs removed from the folder (the caller says so), and the
    /// removals that failed (warnings: the run goes on).
    pub stale: stale::Removed,
}

impl Folder<'_> {
    /// Creates the folder and every sink `formats` asks for, before the run starts, so that a
    /// bad folder fails fast; when one cannot be created, those created before it are closed
    /// (their errors returned too) rather than dropped. Then removes the earlier run's outputs
    /// that this run does not write (`output::stale`): after the sinks exist, so that a run that
    /// cannot start removes nothing.
    pub fn create(&self, formats: &[Format]) -> Result<Outputs, Vec<OutputError>> {
        let mut outputs = self.open(formats, &[])?;
        outputs.stale = stale::remove(self.out, self.stem, &outputs.written);
        Ok(outputs)
    }
}

impl Folder<'_> {
    /// The sinks of a resumed run, from the marks its checkpoint kept ([`SinkMark`]): each CSV
    /// file cut at its mark and appended to, the ParaView collection likewise, an MCAP (and a
    /// rerun recording) started as the run's next part, `<stem>.part<N>.mcap`. The formats are
    /// the checkpointed run's; a mark of a format not asked for is left alone, a format asked
    /// for without a mark (added at resume) starts a new file as `create` does. No stale file
    /// is removed: every file of the folder is the run's.
    pub fn resume(&self, formats: &[Format], marks: &[SinkMark]) -> Result<Outputs, Vec<OutputError>> {
        self.open(formats, marks)
    }

    /// The sinks of `formats`, each going on from its mark in `marks` or, without one, a new
    /// file; on an error those opened are closed (their errors returned too) rather than
    /// dropped.
    fn open(&self, formats: &[Format], marks: &[SinkMark]) -> Result<Outputs, Vec<OutputError>> {
        let out = self.out;
        std::fs::create_dir_all(out)
            .map_err(|e| vec![OutputError::new(out, format!("cannot create the output folder: {e}"))])?;
        let mut sinks: Vec<Box<dyn Sink + Send>> = Vec::new();
        let mut written: Vec<PathBuf> = Vec::new();
        let (stem, rotation) = (self.stem, self.rotation);
        let file_mark = |name: &str| {
            marks.iter().find_map(|m| match m {
                SinkMark::File { name: n, bytes } if n == name => Some(*bytes),
                _ => None,
            })
        };
        let parts = |format: &str| {
            marks
                .iter()
                .find_map(|m| match m {
                    SinkMark::Parts { format: f, parts, .. } if f == format => Some(*parts),
                    _ => None,
                })
                .unwrap_or(0)
        };
        let part_name = |part: u32, ext: &str| super::part_file(stem, part, ext);
        let created = (|| -> Result<(), OutputError> {
            if formats.contains(&Format::Mcap) {
                let part = parts("mcap") + 1;
                let file = out.join(part_name(part, "mcap"));
                let options = McapOptions {
                    max_spheres: self.max_spheres,
                    scene_path: self.scene_path.display().to_string(),
                    scene_source: self.scene_source.to_owned(),
                };
                let mut sink = McapSink::create_for(&file, options, rotation)?.as_part(part);
                written.push(file);
                // The layout fitted to the scene comes with the first part; a resumed run's
                // scene is the same.
                if part == 1 {
                    let layout = out.join(super::mcap::layout::file_name(stem));
                    sink = sink.with_layout(&layout);
                    written.push(layout);
                }
                sinks.push(Box::new(sink));
            }
            if formats.contains(&Format::Csv) {
                let t = out.join("trajectories.csv");
                match file_mark("trajectories.csv") {
                    Some(bytes) => sinks.push(Box::new(TrajectoryCsv::resume(&t, bytes, rotation)?)),
                    None => sinks.push(Box::new(TrajectoryCsv::create_for(&t, rotation)?)),
                }
                written.push(t);
            }
            if formats.contains(&Format::Vtk) {
                let mark = marks.iter().find_map(|m| match m {
                    SinkMark::Vtk { tail_at, frames, walls_written } => {
                        Some((*tail_at, *frames, *walls_written))
                    }
                    _ => None,
                });
                let vtk = match mark {
                    Some(mark) => VtkSink::resume(out, stem, mark)?,
                    None => VtkSink::create(out, stem)?,
                };
                written.push(vtk.pvd_path().to_path_buf());
                written.push(vtk.walls_path().to_path_buf());
                sinks.push(Box::new(vtk));
            }
            if formats.contains(&Format::Csv) || formats.contains(&Format::Vtk) {
                let e = out.join("events.csv");
                match file_mark("events.csv") {
                    Some(bytes) => sinks.push(Box::new(EventCsv::resume(&e, bytes, rotation)?)),
                    None => sinks.push(Box::new(EventCsv::create_for(&e, rotation)?)),
                }
                written.push(e);
            }
            #[cfg(feature = "rerun")]
            if formats.contains(&Format::Rrd) {
                let rrd = marks.iter().find_map(|m| match m {
                    SinkMark::Parts { format, parts, recording } if format == "rrd" => {
                        Some((*parts, recording))
                    }
                    _ => None,
                });
                let (file, sink) = match rrd {
                    Some((parts, recording)) => {
                        let file = out.join(part_name(parts + 1, "rrd"));
                        let part = (parts + 1, recording.as_str());
                        let sink = super::RerunSink::create_part(&file, stem, self.scene_source, part)?;
                        (file, sink)
                    }
                    None => {
                        let file = out.join(part_name(1, "rrd"));
                        (file.clone(), super::RerunSink::create(&file, stem, self.scene_source)?)
                    }
                };
                sinks.push(Box::new(sink));
                written.push(file);
            }
            Ok(())
        })();
        match created {
            Ok(()) => Ok(Outputs { sinks, written, stale: stale::Removed::default() }),
            Err(e) => {
                let mut errors = vec![e];
                errors.extend(sinks.iter_mut().filter_map(|s| s.finish().err()));
                Err(errors)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_format_parses_from_its_name_and_an_unknown_one_lists_them() {
        for f in Format::ALL {
            if f.available().is_ok() {
                assert_eq!(Format::parse(f.name()), Ok(f));
            }
        }
        let e = Format::parse("hdf5").unwrap_err();
        assert!(e.contains("\"hdf5\"") && e.contains("\"vtk\"") && e.contains("\"mcap\""), "{e}");
    }

    #[test]
    fn a_folder_that_cannot_be_created_is_an_error_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a_file");
        std::fs::write(&file, "x").unwrap();
        let out = file.join("out");
        let folder = Folder {
            out: &out,
            stem: "s",
            scene_path: Path::new("s.toml"),
            scene_source: "",
            max_spheres: 10,
            rotation: false,
        };
        let Err(errors) = folder.create(&[Format::Csv]) else { panic!("created inside a file") };
        assert_eq!(errors[0].path, out);
        assert!(errors[0].to_string().contains("cannot create the output folder"), "{}", errors[0]);
    }
}
