//! The rerun sink (cargo feature `rerun`): `<scene>.rrd`, rerun's native recording.
//!
//! rerun reads the MCAP's point cloud but not its radii nor its `SceneUpdate`; this recording
//! has everything, on the timeline `sim_time` (simulated seconds):
//! - `particles`: points at their true radius, coloured by state (free / held / resting);
//! - `walls/<name>`: boxes, cylinders and meshes (static);
//! - `events`: one text-log line per contact with the columns of `events.csv`;
//! - `scene`: the scene file's text (static), so the recording carries its inputs.

use super::geometry::{self, Solid, WALL_COLOR};
use super::{OutputError, Sink, SinkMark};
use crate::contact::ContactEvent;
use crate::pipeline::{LostParticle, Simulation};
use glam::{DQuat, DVec3};
use std::path::PathBuf;

/// The timeline every entity is logged on.
pub const TIMELINE: &str = "sim_time";

/// Writes the rerun recording.
pub struct RerunSink {
    path: PathBuf,
    rec: Option<rerun::RecordingStream>,
    walls_written: bool,
    /// Which part of the run this file is (`<stem>.part<N>.rrd` from 2 on), and the recording
    /// id every part shares ([`SinkMark::Parts`]).
    part: u32,
    recording: String,
}

fn f3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

fn quat(q: DQuat) -> rerun::Quaternion {
    rerun::Quaternion::from_xyzw(q.as_quat().to_array())
}

fn rgba(c: [f32; 4]) -> rerun::Color {
    let b = c.map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8);
    rerun::Color::from_unmultiplied_rgba(b[0], b[1], b[2], b[3])
}

impl RerunSink {
    /// Creates the recording file at `path` for the scene `name`, with the scene's text: a new
    /// recording (its id made from the name and the clock).
    pub fn create(path: impl Into<PathBuf>, name: &str, scene_source: &str) -> Result<Self, OutputError> {
        let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
        let recording = format!("{name}-{}", now.as_nanos());
        Self::create_part(path, name, scene_source, (1, &recording))
    }

    /// The file of part `part` of the run whose recording id is `recording` (a resumed run goes
    /// on in `<stem>.part<N>.rrd`): the viewer merges the parts' files into one recording.
    pub fn create_part(
        path: impl Into<PathBuf>,
        name: &str,
        scene_source: &str,
        (part, recording): (u32, &str),
    ) -> Result<Self, OutputError> {
        let path = path.into();
        let rec = rerun::RecordingStreamBuilder::new("wetbounce")
            .recording_name(name)
            .recording_id(recording)
            .save(&path)
            .map_err(|e| OutputError::create(&path, e))?;
        let mut sink =
            RerunSink { path, rec: Some(rec), walls_written: false, part, recording: recording.to_string() };
        sink.log_static("scene", &rerun::TextDocument::new(scene_source))?;
        // Scenes put gravity along −z.
        sink.log_static("/", &rerun::ViewCoordinates::RIGHT_HAND_Z_UP())?;
        Ok(sink)
    }

    fn rec(&self) -> Result<&rerun::RecordingStream, OutputError> {
        self.rec.as_ref().ok_or_else(|| OutputError::new(&self.path, "written after the end of the run"))
    }

    fn log_static(&mut self, entity: &str, what: &impl rerun::AsComponents) -> Result<(), OutputError> {
        self.rec()?.log_static(entity, what).map_err(|e| OutputError::write(&self.path, e))
    }

    fn log(&self, entity: &str, what: &impl rerun::AsComponents) -> Result<(), OutputError> {
        self.rec()?.log(entity, what).map_err(|e| OutputError::write(&self.path, e))
    }

    fn write_walls(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        let color = rgba(WALL_COLOR);
        for w in geometry::wall_solids(sim) {
            let entity = format!("walls/{}", w.name);
            match w.solid {
                Solid::Cuboid { center, size, rotation } => self.log_static(
                    &entity,
                    &rerun::Boxes3D::from_centers_and_sizes([f3(center)], [f3(size)])
                        .with_quaternions([quat(rotation)])
                        .with_colors([color])
                        .with_fill_mode(rerun::FillMode::Solid),
                )?,
                Solid::Cylinder { center, radius, length, rotation } => self.log_static(
                    &entity,
                    &rerun::Cylinders3D::from_lengths_and_radii([length as f32], [radius as f32])
                        .with_centers([f3(center)])
                        .with_quaternions([quat(rotation)])
                        .with_colors([color])
                        .with_fill_mode(rerun::FillMode::Solid),
                )?,
                Solid::Triangles { vertices, indices } => self.log_static(
                    &entity,
                    &rerun::Mesh3D::new(vertices.iter().map(|v| f3(*v)))
                        .with_triangle_indices(indices.iter().map(|t| rerun::TriangleIndices::from(*t)))
                        .with_albedo_factor(color.0),
                )?,
            }
        }
        Ok(())
    }
}

impl Sink for RerunSink {
    fn frame(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        if !self.walls_written {
            self.write_walls(sim)?;
            self.walls_written = true;
        }
        let p = &sim.world.particles;
        self.rec()?.set_duration_secs(TIMELINE, sim.world.time);
        self.log(
            "particles",
            &rerun::Points3D::new(p.pos.iter().map(|x| f3(*x)))
                .with_radii(p.diameter.iter().map(|d| (0.5 * d) as f32))
                .with_colors(p.state.iter().map(|s| rgba(geometry::state_color(*s))))
                .with_labels(p.id.iter().map(|id| id.to_string()))
                .with_show_labels(false),
        )?;
        if sim.setup.physics.rotation {
            // The spin as an arrow from each centre along its axis, as long as the surface moves
            // in 10 ms (|ω| a × 0.01 s): a length in the scene's units, which a bare ω is not.
            self.log(
                "particles/angular_velocity",
                &rerun::Arrows3D::from_vectors(
                    p.omega.values().iter().zip(&p.diameter).map(|(w, d)| f3(*w * (0.5 * d) * 0.01)),
                )
                .with_origins(p.pos.iter().map(|x| f3(*x))),
            )?;
        }
        // The frame, and the events since the last one, reach the file before the run goes on
        // (the recording is written by a thread of rerun's; this waits for it).
        self.rec()?.flush_blocking().map_err(|e| OutputError::write(&self.path, e))
    }

    fn events(&mut self, sim: &Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        for e in events {
            let (other, kind) = sim.setup.name_of(e.other);
            self.rec()?.set_duration_secs(TIMELINE, e.time);
            let text = format!(
                "particle {} {} on {kind} {other}: V∞ = {:.6} m/s, St = {:.3}, ε = {:.3}, t_c = {:.6} s",
                e.id,
                e.outcome.name(),
                e.normal_speed,
                e.st,
                e.eps,
                e.contact_time
            );
            self.log("events", &rerun::TextLog::new(text).with_level(rerun::TextLogLevel::INFO))?;
        }
        // Frames come back to the frame time; events must not move it.
        self.rec()?.set_duration_secs(TIMELINE, sim.world.time);
        Ok(())
    }

    fn lost(&mut self, sim: &Simulation, lost: &[LostParticle]) -> Result<(), OutputError> {
        for l in lost {
            self.rec()?.set_duration_secs(TIMELINE, l.time);
            let text = format!("particle {} removed: its state became non-finite", l.id);
            self.log("events", &rerun::TextLog::new(text).with_level(rerun::TextLogLevel::INFO))?;
        }
        self.rec()?.set_duration_secs(TIMELINE, sim.world.time);
        Ok(())
    }

    fn mark(&mut self) -> Result<Option<SinkMark>, OutputError> {
        self.rec()?.flush_blocking().map_err(|e| OutputError::write(&self.path, e))?;
        Ok(Some(SinkMark::Parts {
            format: "rrd".into(),
            parts: self.part,
            recording: self.recording.clone(),
        }))
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        match self.rec.take() {
            Some(rec) => rec.flush_blocking().map_err(|e| OutputError::write(&self.path, e)),
            None => Ok(()),
        }
    }
}
