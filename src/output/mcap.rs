//! The MCAP sink: one file that Foxglove opens as it is, and rerun reads the points of.
//!
//! Channels (log time = simulated time in nanoseconds from 0):
//! - `/particles`: `foxglove.PointCloud` per frame, fields `x y z` (float64, m), `id` (uint32),
//!   `diameter` (float64, m), `speed` (float64, m/s), `state` (uint8: 0 free, 1 held,
//!   2 resting), `kind` (uint16, index into the scene's kinds); in a scene with rotation also
//!   `wx wy wz` (float64, rad/s), the angular velocity;
//! - `/walls`: `foxglove.SceneUpdate` — entity `walls`, once at t = 0, on a topic of its own:
//!   a viewer that seeks shows the latest message of each topic before the seek time, so walls
//!   sharing a topic with the per-frame spheres were lost at the first seek; alone on their
//!   topic, the message at t = 0 is the latest one at every time, and costs nothing to repeat;
//! - `/scene`: `foxglove.SceneUpdate` — entity `particles` (spheres at true diameter coloured
//!   by state) per frame while the particle count is at most [`McapOptions::max_spheres`]
//!   (every count by default: Foxglove draws point clouds in pixels, so only these spheres
//!   show the particles at their size);
//! - `/events`: JSON (`jsonschema`), one message per contact with the columns of `events.csv`
//!   (in a scene with rotation, `tangential_speed` and `incidence_angle` too);
//! - `/event_log`: `foxglove.Log`, the same contacts as one line of text each, for Foxglove's
//!   Log panel (a list in time order that follows playback); a deposition is a warning, a
//!   particle removed for a non-finite state an error, a bounce or a hold information.
//!
//! Metadata records `scene` (`path`, `source`: the scene file's text) and `wetbounce`
//! (`version`), so every result carries its inputs.
//!
//! Each frame closes the current chunk: the chunk holds the events since the last frame and
//! the frame's messages, and reaches the file before the run goes on, so that a file cut short
//! (a killed run, a full disk) holds every frame but the last; [`recover`] reads them back.

use super::file::OutputFile;
use super::geometry::{self, Solid, WALL_COLOR};
use super::{OutputError, Sink, SinkMark};
use crate::contact::ContactEvent;
use crate::pipeline::{LostParticle, Simulation};
use foxglove::messages::packed_element_field::NumericType;
use foxglove::messages::{
    Color, CubePrimitive, CylinderPrimitive, Log, PackedElementField, Point3, PointCloud, Pose, Quaternion,
    SceneEntity, SceneUpdate, SpherePrimitive, Timestamp, TriangleListPrimitive, Vector3,
};
use foxglove::{
    Channel, ChannelBuilder, Context, McapCompression, McapWriteOptions, McapWriter, McapWriterHandle,
    PartialMetadata, RawChannel, Schema,
};
use glam::{DQuat, DVec3};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

mod events;
pub mod layout;
mod recover;
use events::{EventMessage, event_level, event_schema, number};
pub use recover::{Recovered, recover};

/// Topic of the point clouds.
pub const PARTICLES_TOPIC: &str = "/particles";
/// Topic of the walls (a scene update at t = 0).
pub const WALLS_TOPIC: &str = "/walls";
/// Topic of the particles' spheres (a scene update per frame).
pub const SCENE_TOPIC: &str = "/scene";
/// Topic of the contact events.
pub const EVENTS_TOPIC: &str = "/events";
/// Topic of the contact events as log lines.
pub const EVENT_LOG_TOPIC: &str = "/event_log";
/// The frame every message is expressed in.
pub const FRAME_ID: &str = "world";

/// Bytes per point of `/particles`: x, y, z, id, diameter, speed, state, kind.
const POINT_STRIDE: u32 = 8 * 3 + 4 + 8 + 8 + 1 + 2;
/// Bytes per point of `/particles` in a scene with rotation: the above, then wx, wy, wz.
const SPIN_POINT_STRIDE: u32 = POINT_STRIDE + 8 * 3;

/// Settings of the MCAP sink.
#[derive(Debug, Clone)]
pub struct McapOptions {
    /// Draw spheres on `/scene` only while there are at most this many particles: beyond
    /// that only the point cloud carries the particles, and the file is 1.2 to 1.4 times
    /// smaller (`usize::MAX`: always).
    pub max_spheres: usize,
    /// Path of the scene file, recorded as metadata.
    pub scene_path: String,
    /// The scene file's text, recorded as metadata.
    pub scene_source: String,
}

/// Writes `/particles`, `/walls`, `/scene`, `/events` and `/event_log` to an MCAP file (zstd
/// chunks).
pub struct McapSink {
    path: PathBuf,
    options: McapOptions,
    // Channels hold only a weak reference to their context: the sink keeps it alive.
    _ctx: Arc<Context>,
    // Dropping the handle would also close the file; `finish` closes it to see the error.
    writer: Option<McapWriterHandle<OutputFile>>,
    // The file's first OS error: the foxglove writer logs a failed write to `tracing` (nowhere
    // here) and answers every later call with "attempted another write after a write method
    // failed", which hides the cause.
    first_error: Arc<OnceLock<String>>,
    // An error was reported: the file cannot be finished, and is not named twice.
    failed: bool,
    particles: Channel<PointCloud>,
    walls: Channel<SceneUpdate>,
    scene: Channel<SceneUpdate>,
    events: Arc<RawChannel>,
    event_log: Channel<Log>,
    walls_written: bool,
    /// Which part of the run this file is: 1, and one more for each resumed part
    /// (`<stem>.part<N>.mcap`, [`SinkMark::Parts`]).
    part: u32,
    spheres_shown: bool,
    /// Where the layout fitted to the scene goes ([`layout`]), written with the walls.
    layout: Option<PathBuf>,
    json: Vec<u8>,
    order: Vec<usize>,
    rotation: bool,
}

/// The file's first OS error if there was one, else `e`.
fn first_error_or(first_error: &OnceLock<String>, e: &dyn std::fmt::Display) -> String {
    first_error.get().cloned().unwrap_or_else(|| e.to_string())
}

/// Simulated time as MCAP log time (ns from 0); the ns are rounded so that frames at exact
/// multiples of the output interval get exact stamps.
pub fn log_time_ns(t: f64) -> u64 {
    (t.max(0.0) * 1e9).round() as u64
}

fn stamp(t: f64) -> Timestamp {
    let ns = log_time_ns(t);
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}

fn vec3(v: DVec3) -> Vector3 {
    Vector3 { x: v.x, y: v.y, z: v.z }
}

fn pose(center: DVec3, rotation: DQuat) -> Pose {
    Pose {
        position: Some(vec3(center)),
        orientation: Some(Quaternion { x: rotation.x, y: rotation.y, z: rotation.z, w: rotation.w }),
    }
}

fn color([r, g, b, a]: [f32; 4]) -> Color {
    Color { r: r.into(), g: g.into(), b: b.into(), a: a.into() }
}

fn field(name: &str, offset: u32, ty: NumericType) -> PackedElementField {
    PackedElementField { name: name.into(), offset, r#type: ty as i32 }
}

impl McapSink {
    /// Creates the file at `path` and writes the metadata (no spin fields).
    pub fn create(path: impl Into<PathBuf>, options: McapOptions) -> Result<Self, OutputError> {
        Self::create_for(path, options, false)
    }

    /// The file of part `part` of a resumed run (`<stem>.part<N>.mcap`).
    pub fn as_part(mut self, part: u32) -> Self {
        self.part = part;
        self
    }

    /// Also writes, at the first frame, the Foxglove layout fitted to the scene at `path`
    /// ([`layout::fitted`]).
    pub fn with_layout(mut self, path: impl Into<PathBuf>) -> Self {
        self.layout = Some(path.into());
        self
    }

    /// Creates the file at `path` and writes the metadata; with `rotation` (the scene's
    /// `setup.physics.rotation`) the particles carry their spin and the events their tangential
    /// speed and incidence angle. A scene without rotation keeps the file it had.
    pub fn create_for(
        path: impl Into<PathBuf>,
        options: McapOptions,
        rotation: bool,
    ) -> Result<Self, OutputError> {
        let path = path.into();
        let file = OutputFile::create(&path, 1 << 16)?;
        let first_error = file.first_error();
        let err = |e: &dyn std::fmt::Display| OutputError::write(&path, first_error_or(&first_error, e));
        // A context of its own: the default one is global, and two runs in one process (the
        // tests) must not write into each other's files.
        let ctx = Context::new();
        let write_options = McapWriteOptions::new().compression(Some(McapCompression::Zstd));
        let writer =
            McapWriter::with_options(write_options).context(&ctx).create(file).map_err(|e| err(&e))?;
        let metadata = |pairs: &[(&str, &str)]| -> BTreeMap<String, String> {
            pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect()
        };
        writer
            .write_metadata(
                "scene",
                metadata(&[("path", &options.scene_path), ("source", &options.scene_source)]),
            )
            .map_err(|e| err(&e))?;
        writer
            .write_metadata("wetbounce", metadata(&[("version", env!("CARGO_PKG_VERSION"))]))
            .map_err(|e| err(&e))?;
        let particles = ChannelBuilder::new(PARTICLES_TOPIC).context(&ctx).build::<PointCloud>();
        let walls = ChannelBuilder::new(WALLS_TOPIC).context(&ctx).build::<SceneUpdate>();
        let scene = ChannelBuilder::new(SCENE_TOPIC).context(&ctx).build::<SceneUpdate>();
        let events = ChannelBuilder::new(EVENTS_TOPIC)
            .context(&ctx)
            .message_encoding("json")
            .schema(Schema::new("wetbounce.ContactEvent", "jsonschema", event_schema(rotation).into_bytes()))
            .build_raw()
            .map_err(|e| err(&e))?;
        let event_log = ChannelBuilder::new(EVENT_LOG_TOPIC).context(&ctx).build::<Log>();
        // The header and metadata reach the file now: a file that cannot be written fails before
        // the run starts, and the first chunk starts with an empty buffer.
        writer.flush().map_err(|e| err(&e))?;
        Ok(McapSink {
            path,
            options,
            _ctx: ctx,
            writer: Some(writer),
            first_error,
            failed: false,
            particles,
            walls,
            scene,
            events,
            event_log,
            walls_written: false,
            part: 1,
            spheres_shown: false,
            layout: None,
            json: Vec::new(),
            order: Vec::new(),
            rotation,
        })
    }

    /// The error that stops the run: the file's first OS error if there was one (else `e`),
    /// and how to read back what was written.
    fn fail(&mut self, e: &dyn std::fmt::Display) -> OutputError {
        self.failed = true;
        let cause = first_error_or(&self.first_error, e);
        OutputError::write(
            &self.path,
            format!(
                "{cause}; the frames written before are read back by `wetbounce recover {}`",
                self.path.display()
            ),
        )
    }

    /// Fails if a message written since the last check could not be written: the foxglove
    /// channels do not return their errors.
    fn check(&mut self) -> Result<(), OutputError> {
        match self.first_error.get() {
            Some(e) => Err(self.fail(&e.clone())),
            None => Ok(()),
        }
    }

    fn write_walls(&mut self, sim: &Simulation) {
        let mut entity = SceneEntity {
            timestamp: Some(stamp(sim.world.time)),
            frame_id: FRAME_ID.into(),
            id: "walls".into(),
            frame_locked: true,
            ..Default::default()
        };
        for w in geometry::wall_solids(sim) {
            match w.solid {
                Solid::Cuboid { center, size, rotation } => entity.cubes.push(CubePrimitive {
                    pose: Some(pose(center, rotation)),
                    size: Some(vec3(size)),
                    color: Some(color(WALL_COLOR)),
                }),
                Solid::Cylinder { center, radius, length, rotation } => {
                    entity.cylinders.push(CylinderPrimitive {
                        pose: Some(pose(center, rotation)),
                        size: Some(vec3(DVec3::new(2.0 * radius, 2.0 * radius, length))),
                        bottom_scale: 1.0,
                        top_scale: 1.0,
                        color: Some(color(WALL_COLOR)),
                    })
                }
                Solid::Triangles { vertices, indices } => entity.triangles.push(TriangleListPrimitive {
                    pose: Some(pose(DVec3::ZERO, DQuat::IDENTITY)),
                    points: vertices.iter().map(|v| Point3 { x: v.x, y: v.y, z: v.z }).collect(),
                    color: Some(color(WALL_COLOR)),
                    colors: Vec::new(),
                    indices: indices.iter().flatten().copied().collect(),
                }),
            }
        }
        self.walls.log_with_time(
            &SceneUpdate { deletions: Vec::new(), entities: vec![entity] },
            log_time_ns(sim.world.time),
        );
    }

    fn write_points(&self, sim: &Simulation) {
        let p = &sim.world.particles;
        let stride = if self.rotation { SPIN_POINT_STRIDE } else { POINT_STRIDE };
        let mut data = Vec::with_capacity(p.len() * stride as usize);
        for i in 0..p.len() {
            let x = p.pos[i];
            data.extend_from_slice(&x.x.to_le_bytes());
            data.extend_from_slice(&x.y.to_le_bytes());
            data.extend_from_slice(&x.z.to_le_bytes());
            data.extend_from_slice(&p.id[i].to_le_bytes());
            data.extend_from_slice(&p.diameter[i].to_le_bytes());
            data.extend_from_slice(&p.vel[i].length().to_le_bytes());
            data.push(p.state[i].code());
            data.extend_from_slice(&p.kind[i].to_le_bytes());
            if self.rotation {
                for w in p.spin(i).to_array() {
                    data.extend_from_slice(&w.to_le_bytes());
                }
            }
        }
        let mut fields = vec![
            field("x", 0, NumericType::Float64),
            field("y", 8, NumericType::Float64),
            field("z", 16, NumericType::Float64),
            field("id", 24, NumericType::Uint32),
            field("diameter", 28, NumericType::Float64),
            field("speed", 36, NumericType::Float64),
            field("state", 44, NumericType::Uint8),
            field("kind", 45, NumericType::Uint16),
        ];
        if self.rotation {
            fields.extend([
                field("wx", POINT_STRIDE, NumericType::Float64),
                field("wy", POINT_STRIDE + 8, NumericType::Float64),
                field("wz", POINT_STRIDE + 16, NumericType::Float64),
            ]);
        }
        let cloud = PointCloud {
            timestamp: Some(stamp(sim.world.time)),
            frame_id: FRAME_ID.into(),
            pose: Some(pose(DVec3::ZERO, DQuat::IDENTITY)),
            point_stride: stride,
            fields,
            data: data.into(),
        };
        self.particles.log_with_time(&cloud, log_time_ns(sim.world.time));
    }

    fn write_spheres(&mut self, sim: &Simulation) {
        let p = &sim.world.particles;
        let show = p.len() <= self.options.max_spheres;
        if !show && !self.spheres_shown {
            return;
        }
        let mut entity = SceneEntity {
            timestamp: Some(stamp(sim.world.time)),
            frame_id: FRAME_ID.into(),
            id: "particles".into(),
            frame_locked: true,
            ..Default::default()
        };
        // Past the limit the entity is replaced by an empty one, so no stale spheres linger.
        if show {
            entity.spheres = (0..p.len())
                .map(|i| SpherePrimitive {
                    pose: Some(pose(p.pos[i], DQuat::IDENTITY)),
                    size: Some(vec3(DVec3::splat(p.diameter[i]))),
                    color: Some(color(geometry::state_color(p.state[i]))),
                })
                .collect();
        }
        self.spheres_shown = show;
        self.scene.log_with_time(
            &SceneUpdate { deletions: Vec::new(), entities: vec![entity] },
            log_time_ns(sim.world.time),
        );
    }
    /// Writes one contact on `/events` (JSON) and on `/event_log` (a line of text), at `t`.
    fn write_event(&mut self, t: f64, message: &EventMessage) -> Result<(), OutputError> {
        self.json.clear();
        serde_json::to_writer(&mut self.json, message).map_err(|err| OutputError::write(&self.path, err))?;
        self.events.log_with_meta(&self.json, PartialMetadata::with_log_time(log_time_ns(t)));
        self.check()?;
        let line = Log {
            timestamp: Some(stamp(t)),
            level: event_level(message.outcome) as i32,
            message: message.line(),
            name: "wetbounce".into(),
            file: String::new(),
            line: 0,
        };
        self.event_log.log_with_time(&line, log_time_ns(t));
        self.check()
    }
}

impl Sink for McapSink {
    fn frame(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        // Checked before and after each message: the writer must get no call after a failed one.
        self.check()?;
        if !self.walls_written {
            self.write_walls(sim);
            self.walls_written = true;
            self.check()?;
            if let Some(path) = &self.layout {
                let (center, half) = geometry::scene_extent(sim);
                std::fs::write(path, layout::fitted(center, half))
                    .map_err(|e| OutputError::write(path, e))?;
            }
        }
        self.write_points(sim);
        self.check()?;
        self.write_spheres(sim);
        self.check()?;
        // The chunk ends with the frame, and reaches the file.
        let flushed = match &self.writer {
            Some(w) => w.flush(),
            None => Ok(()),
        };
        flushed.map_err(|e| self.fail(&e))?;
        self.check()
    }

    fn events(&mut self, sim: &Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        self.check()?;
        // Events arrive in time order per particle only; a viewer wants one time order.
        self.order.clear();
        self.order.extend(0..events.len());
        self.order.sort_by(|&a, &b| events[a].time.total_cmp(&events[b].time));
        for i in 0..self.order.len() {
            let e = &events[self.order[i]];
            let (other, kind) = sim.setup.name_of(e.other);
            let message = EventMessage {
                t: number(e.time),
                id: e.id,
                other,
                kind,
                normal_speed: number(e.normal_speed),
                st: number(e.st),
                eps: number(e.eps),
                contact_time: number(e.contact_time),
                outcome: e.outcome.name(),
                tangential_speed: self.rotation.then(|| number(e.tangential_speed)),
                incidence_angle: self.rotation.then(|| number(e.incidence_angle)),
            };
            self.write_event(e.time, &message)?;
        }
        Ok(())
    }

    fn lost(&mut self, _sim: &Simulation, lost: &[LostParticle]) -> Result<(), OutputError> {
        self.check()?;
        for l in lost {
            let message = EventMessage {
                t: number(l.time),
                id: l.id,
                other: String::new(),
                kind: "removed",
                normal_speed: None,
                st: None,
                eps: None,
                contact_time: None,
                outcome: "non_finite",
                tangential_speed: self.rotation.then_some(None),
                incidence_angle: self.rotation.then_some(None),
            };
            self.write_event(l.time, &message)?;
        }
        Ok(())
    }

    /// Writes the summary and footer, and syncs the file. A file that failed is left as it is:
    /// its error was reported, and the writer refuses to go on after a failed write.
    fn mark(&mut self) -> Result<Option<SinkMark>, OutputError> {
        Ok(Some(SinkMark::Parts { format: "mcap".into(), parts: self.part, recording: String::new() }))
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        let Some(w) = self.writer.take() else { return Ok(()) };
        if self.failed {
            return Ok(());
        }
        let mut file = w.close().map_err(|e| self.fail(&e))?;
        file.sync().map_err(|e| self.fail(&e))
    }
}
