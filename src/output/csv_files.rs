//! The CSV sinks.

use super::{OutputError, Sink};
use crate::contact::ContactEvent;
use crate::pipeline::{LostParticle, Simulation};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

type Writer = csv::Writer<BufWriter<File>>;

fn create(path: &Path, header: &[&str]) -> Result<Writer, OutputError> {
    let file = File::create(path).map_err(|e| OutputError::new(path, e))?;
    let mut w = csv::Writer::from_writer(BufWriter::with_capacity(1 << 20, file));
    w.write_record(header).map_err(|e| OutputError::new(path, e))?;
    Ok(w)
}

/// `trajectories.csv`: `t,id,x,y,z,vx,vy,vz,state`, SI units, one row per particle per frame.
pub struct TrajectoryCsv {
    path: PathBuf,
    w: Writer,
}

impl TrajectoryCsv {
    /// Creates the file and writes the header.
    pub fn create(path: impl Into<PathBuf>) -> Result<Self, OutputError> {
        let path = path.into();
        let w = create(&path, &["t", "id", "x", "y", "z", "vx", "vy", "vz", "state"])?;
        Ok(TrajectoryCsv { path, w })
    }
}

impl Sink for TrajectoryCsv {
    fn frame(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        let p = &sim.world.particles;
        for i in 0..p.len() {
            let (x, v) = (p.pos[i], p.vel[i]);
            self.w
                .serialize((sim.world.time, p.id[i], x.x, x.y, x.z, v.x, v.y, v.z, p.state[i].name()))
                .map_err(|e| OutputError::new(&self.path, e))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.w.flush().map_err(|e| OutputError::new(&self.path, e))
    }
}

/// `events.csv`: `t,id,other,kind,normal_speed,st,eps,contact_time,outcome`, one row per contact.
pub struct EventCsv {
    path: PathBuf,
    w: Writer,
}

impl EventCsv {
    /// Creates the file and writes the header.
    pub fn create(path: impl Into<PathBuf>) -> Result<Self, OutputError> {
        let path = path.into();
        let header = ["t", "id", "other", "kind", "normal_speed", "st", "eps", "contact_time", "outcome"];
        let w = create(&path, &header)?;
        Ok(EventCsv { path, w })
    }
}

impl Sink for EventCsv {
    fn events(&mut self, sim: &Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        for e in events {
            let (other, kind) = sim.setup.name_of(e.other);
            self.w
                .serialize((
                    e.time,
                    e.id,
                    other,
                    kind,
                    e.normal_speed,
                    e.st,
                    e.eps,
                    e.contact_time,
                    e.outcome.name(),
                ))
                .map_err(|err| OutputError::new(&self.path, err))?;
        }
        Ok(())
    }

    /// A removal is a row of kind `removed`, outcome `non_finite`, with the contact columns empty.
    fn lost(&mut self, _sim: &Simulation, lost: &[LostParticle]) -> Result<(), OutputError> {
        let none: Option<f64> = None;
        for l in lost {
            self.w
                .serialize((l.time, l.id, "", "removed", none, none, none, none, "non_finite"))
                .map_err(|err| OutputError::new(&self.path, err))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.w.flush().map_err(|e| OutputError::new(&self.path, e))
    }
}
