//! The CSV sinks. Each flushes at every output frame (and after its header), so a run that is
//! killed or whose disk fills keeps every whole frame and every event up to its last frame.

use super::file::OutputFile;
use super::{OutputError, Sink, SinkMark};
use crate::contact::ContactEvent;
use crate::pipeline::{LostParticle, Simulation};
use std::path::{Path, PathBuf};

type Writer = csv::Writer<OutputFile>;

fn create(path: &Path, header: &[&str]) -> Result<Writer, OutputError> {
    let file = OutputFile::create(path, 1 << 20)?;
    let mut w = csv::Writer::from_writer(file);
    w.write_record(header).map_err(|e| OutputError::write(path, e))?;
    // The header reaches the file at once: a run stopped before its first event still leaves
    // a readable events.csv, and a file that cannot be written fails before the run starts.
    w.flush().map_err(|e| OutputError::write(path, e))?;
    Ok(w)
}

/// Opens `path` to go on from a checkpoint: cut to `bytes` (what followed was written after the
/// checkpoint, and the resumed run writes it again), then appended to, with no header.
fn resume(path: &Path, bytes: u64) -> Result<Writer, OutputError> {
    let file = OutputFile::append_at(path, bytes, 1 << 20)?;
    Ok(csv::WriterBuilder::new().has_headers(false).from_writer(file))
}

/// The mark of a CSV file: flushed, and its length.
fn mark(w: &mut Writer, path: &Path) -> Result<Option<SinkMark>, OutputError> {
    w.flush().map_err(|e| OutputError::write(path, e))?;
    let bytes = w.get_ref().length().map_err(|e| OutputError::write(path, e))?;
    let name = path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    Ok(Some(SinkMark::File { name, bytes }))
}

/// Flushes what is left and syncs the file to the disk.
fn finish(w: &mut Writer, path: &Path) -> Result<(), OutputError> {
    w.flush().and_then(|()| w.get_ref().sync_data()).map_err(|e| OutputError::write(path, e))
}

/// `trajectories.csv`: `t,id,x,y,z,vx,vy,vz,state`, SI units, one row per particle per frame;
/// in a scene with rotation also `wx,wy,wz`, the angular velocity (rad/s), after `state`.
pub struct TrajectoryCsv {
    path: PathBuf,
    w: Writer,
    rotation: bool,
}

impl TrajectoryCsv {
    /// Creates the file and writes the header (without the spin columns).
    pub fn create(path: impl Into<PathBuf>) -> Result<Self, OutputError> {
        Self::create_for(path, false)
    }

    /// Creates the file and writes the header, with the spin columns when `rotation` (the
    /// scene's `setup.physics.rotation`): a scene without rotation keeps the file it had.
    pub fn create_for(path: impl Into<PathBuf>, rotation: bool) -> Result<Self, OutputError> {
        let path = path.into();
        let mut header = vec!["t", "id", "x", "y", "z", "vx", "vy", "vz", "state"];
        if rotation {
            header.extend(["wx", "wy", "wz"]);
        }
        let w = create(&path, &header)?;
        Ok(TrajectoryCsv { path, w, rotation })
    }

    /// Opens the file of a checkpointed run to go on at `bytes` ([`SinkMark::File`]).
    pub fn resume(path: impl Into<PathBuf>, bytes: u64, rotation: bool) -> Result<Self, OutputError> {
        let path = path.into();
        let w = resume(&path, bytes)?;
        Ok(TrajectoryCsv { path, w, rotation })
    }
}

impl Sink for TrajectoryCsv {
    fn frame(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        let p = &sim.world.particles;
        for i in 0..p.len() {
            let (x, v) = (p.pos[i], p.vel[i]);
            let row = (sim.world.time, p.id[i], x.x, x.y, x.z, v.x, v.y, v.z, p.state[i].name());
            let written = if self.rotation {
                let w = p.spin(i);
                self.w.serialize((row, w.x, w.y, w.z))
            } else {
                self.w.serialize(row)
            };
            written.map_err(|e| OutputError::write(&self.path, e))?;
        }
        self.w.flush().map_err(|e| OutputError::write(&self.path, e))
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        finish(&mut self.w, &self.path)
    }

    fn mark(&mut self) -> Result<Option<SinkMark>, OutputError> {
        mark(&mut self.w, &self.path)
    }
}

/// `events.csv`: `t,id,other,kind,normal_speed,st,eps,contact_time,outcome`, one row per contact;
/// in a scene with rotation also `tangential_speed` (m/s) and `incidence_angle` (rad), after
/// `outcome`.
pub struct EventCsv {
    path: PathBuf,
    w: Writer,
    rotation: bool,
}

impl EventCsv {
    /// Creates the file and writes the header (without the tangential columns).
    pub fn create(path: impl Into<PathBuf>) -> Result<Self, OutputError> {
        Self::create_for(path, false)
    }

    /// Creates the file and writes the header, with the tangential columns when `rotation`.
    pub fn create_for(path: impl Into<PathBuf>, rotation: bool) -> Result<Self, OutputError> {
        let path = path.into();
        let mut header =
            vec!["t", "id", "other", "kind", "normal_speed", "st", "eps", "contact_time", "outcome"];
        if rotation {
            header.extend(["tangential_speed", "incidence_angle"]);
        }
        let w = create(&path, &header)?;
        Ok(EventCsv { path, w, rotation })
    }

    /// Opens the file of a checkpointed run to go on at `bytes` ([`SinkMark::File`]).
    pub fn resume(path: impl Into<PathBuf>, bytes: u64, rotation: bool) -> Result<Self, OutputError> {
        let path = path.into();
        let w = resume(&path, bytes)?;
        Ok(EventCsv { path, w, rotation })
    }
}

impl Sink for EventCsv {
    /// The events since the last frame reach the file.
    fn frame(&mut self, _sim: &Simulation) -> Result<(), OutputError> {
        self.w.flush().map_err(|e| OutputError::write(&self.path, e))
    }

    fn events(&mut self, sim: &Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        for e in events {
            let (other, kind) = sim.setup.name_of(e.other);
            let row =
                (e.time, e.id, other, kind, e.normal_speed, e.st, e.eps, e.contact_time, e.outcome.name());
            let written = if self.rotation {
                self.w.serialize((row, e.tangential_speed, e.incidence_angle))
            } else {
                self.w.serialize(row)
            };
            written.map_err(|err| OutputError::write(&self.path, err))?;
        }
        Ok(())
    }

    /// A removal is a row of kind `removed`, outcome `non_finite`, with the contact columns empty.
    fn lost(&mut self, _sim: &Simulation, lost: &[LostParticle]) -> Result<(), OutputError> {
        let none: Option<f64> = None;
        for l in lost {
            let row = (l.time, l.id, "", "removed", none, none, none, none, "non_finite");
            let written =
                if self.rotation { self.w.serialize((row, none, none)) } else { self.w.serialize(row) };
            written.map_err(|err| OutputError::write(&self.path, err))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        finish(&mut self.w, &self.path)
    }

    fn mark(&mut self) -> Result<Option<SinkMark>, OutputError> {
        mark(&mut self.w, &self.path)
    }
}
