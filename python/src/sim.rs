//! `wetbounce.Simulation`: stepping (`advance_to`), whole runs writing the CLI's files, the
//! particle columns as NumPy arrays, events and summary as pandas DataFrames.

use crate::errors::output_error;
use crate::scene::Scene;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};
use wetbounce::contact::ContactEvent;
use wetbounce::output::{Folder, Format, OutputError, Progress, RunSummary, Sink, Statistics};
use wetbounce::pipeline::LostParticle;
use wetbounce::run::{CheckpointPolicy, Checkpoints, Driver, Ended, RunFailed, RunReport};
use wetbounce::scene::LoadOptions;

/// How long the engine steps with the GIL released before Python's signal handlers get a
/// chance to run (Ctrl-C is noticed within about this time).
const CHUNK: Duration = Duration::from_millis(50);

/// One row of the events table, in the order `events.csv` has them.
#[derive(Debug, Clone, Copy)]
enum Row {
    Contact(ContactEvent),
    Lost(LostParticle),
}

/// A Python `UserWarning` (an earlier run's output that could not be removed: the run goes on).
fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    // A message with a NUL byte (a file name can hold none) would be cut there.
    let text = std::ffi::CString::new(message.replace('\0', " ")).unwrap_or_default();
    PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyUserWarning>(), &text, 1)
}

/// A sink that keeps every event and the statistics of `summary.json`.
#[derive(Default)]
struct Collector {
    rows: Vec<Row>,
    stats: Statistics,
}

impl Sink for Collector {
    fn events(&mut self, sim: &wetbounce::Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        self.rows.extend(events.iter().copied().map(Row::Contact));
        self.stats.events(sim, events)
    }

    fn lost(&mut self, _sim: &wetbounce::Simulation, lost: &[LostParticle]) -> Result<(), OutputError> {
        self.rows.extend(lost.iter().copied().map(Row::Lost));
        Ok(())
    }
}

/// A running simulation of a :class:`Scene`: step it with :meth:`advance_to`, or run it whole
/// with :meth:`run` (which can write the CLI's output files); read the particles' columns as
/// NumPy arrays (:attr:`positions`, :attr:`velocities`, :attr:`angular_velocities`,
/// :attr:`states`, …), the contact events and the summary as pandas DataFrames.
///
/// The engine steps with the GIL released: other Python threads run meanwhile, and Ctrl-C
/// (``KeyboardInterrupt``) stops :meth:`advance_to` or :meth:`run` within about 50 ms of
/// wall time, at the end of a step.
#[pyclass(module = "wetbounce")]
pub struct Simulation {
    sim: wetbounce::Simulation,
    scene_path: PathBuf,
    source: String,
    duration: f64,
    output_interval: f64,
    options: LoadOptions,
    collected: Collector,
    lost_seen: usize,
    wall_time: Duration,
    frames: u64,
    interrupted: bool,
    /// The files the last `run` wrote.
    files: Vec<PathBuf>,
    /// Loaded from a checkpoint (`load`): what `run` needs to go on with its files.
    resumed: Option<Box<wetbounce::run::checkpoint::Saved>>,
}

impl Simulation {
    pub fn new(scene: &Scene) -> Simulation {
        let s = &scene.scene;
        Simulation {
            sim: s.simulation(),
            scene_path: s.path.clone(),
            source: s.source.clone(),
            duration: s.duration,
            output_interval: s.output_interval,
            options: scene.options,
            collected: Collector::default(),
            lost_seen: 0,
            wall_time: Duration::ZERO,
            frames: 0,
            interrupted: false,
            files: Vec::new(),
            resumed: None,
        }
    }

    /// Steps towards `t_end` for at most [`CHUNK`] of wall time (at least one step), with the
    /// step rule of `wetbounce run` (so states at output times are the CLI's, bit for bit),
    /// handing each step's events to the collector.
    fn chunk(&mut self, t_end: f64) {
        let start = Instant::now();
        let Simulation { sim, collected, lost_seen, .. } = self;
        // Inside rayon's pool, as `wetbounce run`'s steps (`Simulation::advance_to`).
        rayon::scope(|_| {
            while sim.world.time < t_end {
                let (t, dt) = (sim.world.time, sim.setup.dt);
                let target = if t_end - t <= 1.000_000_001 * dt { t_end } else { t + dt };
                sim.advance_to(target);
                if !sim.record.events.is_empty() {
                    let events = std::mem::take(&mut sim.record.events);
                    // The collector never fails.
                    let _ = collected.events(sim, &events);
                    sim.record.events = events;
                    sim.record.events.clear();
                }
                if sim.record.lost.len() > *lost_seen {
                    let _ = collected.lost(sim, &sim.record.lost[*lost_seen..]);
                    *lost_seen = sim.record.lost.len();
                }
                if start.elapsed() >= CHUNK {
                    break;
                }
            }
        });
        self.wall_time += start.elapsed();
    }

    fn report(&self) -> RunReport {
        RunReport {
            time: self.sim.world.time,
            steps: self.sim.world.steps,
            wall_time: self.wall_time,
            frames: self.frames,
            interrupted: self.interrupted,
        }
    }

    fn summary_value(&self) -> serde_json::Value {
        let mut json = RunSummary::new(&self.sim, &self.report(), &self.collected.stats).to_json();
        json["scene"] = serde_json::Value::String(self.scene_path.display().to_string());
        json
    }

    /// Where `wetbounce run`'s loop would stand at the simulation's time: on its way to the
    /// next output frame.
    fn position(&self) -> wetbounce::run::RunPosition {
        let t = self.sim.world.time;
        wetbounce::run::RunPosition {
            k: wetbounce::run::RunPosition::next_index(t, self.output_interval),
            frames: self.frames,
            lost_reported: self.sim.record.lost.len() as u64,
            at_frame: false,
            wall_time: self.wall_time.as_secs_f64(),
        }
    }

    /// A column of `n` vectors as an `(n, 3)` array: one copy, moved into NumPy.
    fn vectors<'py>(py: Python<'py>, v: &[glam::DVec3]) -> Bound<'py, PyArray2<f64>> {
        let flat: Vec<f64> = v.iter().flat_map(|x| x.to_array()).collect();
        Array2::from_shape_vec((v.len(), 3), flat).expect("three numbers per vector").into_pyarray(py)
    }

    /// [`Simulation::run`]'s work: the run, its files and summary; returns the files written.
    fn run_whole(
        &mut self,
        py: Python<'_>,
        out: Option<PathBuf>,
        (formats, output_interval, max_spheres, name): (
            Option<Vec<String>>,
            Option<f64>,
            Option<usize>,
            Option<String>,
        ),
        quiet: bool,
        checkpoints: CheckpointPolicy,
    ) -> PyResult<Vec<PathBuf>> {
        if self.sim.world.steps > 0 && self.resumed.is_none() {
            return Err(PyRuntimeError::new_err(format!(
                "run: this simulation has already stepped to t = {} s; run() starts at t = 0, or \
                 where a loaded checkpoint left its run (make a new one with Scene.simulation(), \
                 or continue with advance_to)",
                self.sim.world.time
            )));
        }
        let interval = match output_interval {
            None => self.output_interval,
            Some(s) if !(s.is_finite() && s > 0.0) => {
                return Err(PyValueError::new_err(format!(
                    "output_interval: must be a finite time > 0 s, got {s}"
                )));
            }
            Some(s) => {
                if !self.options.allow_long_run {
                    wetbounce::scene::run_length(self.duration, s, self.sim.setup.dt)
                        .map_err(|e| PyValueError::new_err(format!("output_interval {s:e}: {e}")))?;
                }
                s
            }
        };
        let resumed = self.resumed.take();
        let interval = resumed.as_ref().map_or(interval, |r| r.scene.output_interval);
        let formats = formats.unwrap_or_else(|| match &resumed {
            Some(r) if !r.scene.formats.is_empty() => r.scene.formats.clone(),
            _ => vec!["mcap".to_owned()],
        });
        let name = name.or_else(|| resumed.as_ref().map(|r| r.scene.stem.clone()));
        let stem = name.unwrap_or_else(|| {
            if self.scene_path.file_name().is_some_and(|n| n == "<dict>") {
                "scene".to_owned()
            } else {
                self.scene_path.file_stem().map_or("scene".into(), |s| s.to_string_lossy().into_owned())
            }
        });
        let mut parsed = Vec::new();
        for f in &formats {
            parsed.push(Format::parse(f).map_err(|e| PyValueError::new_err(format!("formats: {e}")))?);
        }
        let folder = out.as_deref().map(|dir| Folder {
            out: dir,
            stem: &stem,
            scene_path: &self.scene_path,
            scene_source: &self.source,
            max_spheres: max_spheres.unwrap_or(usize::MAX),
            // The spin columns as `wetbounce run` decides them, so the files stay the CLI's.
            rotation: self.sim.setup.physics.rotation,
        });
        // The CLI's driver (`wetbounce::run::Driver`): the same files, stale outputs removed,
        // the same summary.json.
        let driver = match (&resumed, folder.as_ref()) {
            (Some(saved), Some(folder)) => Driver::resume(folder, &parsed, self.duration, saved),
            _ => Driver::new(folder.as_ref(), &parsed, self.duration, interval),
        };
        let mut driver = driver.map_err(|errors| output_error(&errors))?;
        if let Some(dir) = out.as_deref() {
            let scene = wetbounce::run::checkpoint::SavedScene {
                path: std::path::absolute(&self.scene_path).unwrap_or_else(|_| self.scene_path.clone()),
                given: self.scene_path.clone(),
                source: self.source.clone(),
                output_interval: interval,
                formats: parsed.iter().map(|f| f.name().to_string()).collect(),
                stem: stem.clone(),
                max_spheres: max_spheres.unwrap_or(usize::MAX),
            };
            let folder = dir.join("checkpoints");
            if resumed.is_none() {
                // An earlier run's checkpoints would resume it over this run's files.
                for old in wetbounce::run::checkpoint::list(&folder) {
                    let _ = std::fs::remove_file(old);
                }
            }
            driver = driver.checkpointing(Checkpoints::new(checkpoints, &folder, scene, self.sim.world.time));
        }
        for failed in &driver.stale().failed {
            warn(py, &failed.to_string())?;
        }

        let stop = AtomicBool::new(false);
        let done = AtomicBool::new(false);
        let mut interrupt: Option<PyErr> = None;
        let duration = self.duration;
        // The bar: tqdm's when it is installed (it draws in notebooks too), else the CLI's
        // (indicatif, on a terminal's standard error only).
        let bar = if quiet { None } else { tqdm_bar(py, duration) };
        let mut engine_bar = (!quiet && bar.is_none()).then(|| Progress::new(duration, false));
        let reached = AtomicU64::new(0f64.to_bits());
        let mut clock = Clock(&reached);
        let (sim, collected) = (&mut self.sim, &mut self.collected);
        let result: Result<RunReport, RunFailed> = std::thread::scope(|s| {
            let worker = s.spawn(|| {
                let mut extra: Vec<&mut dyn Sink> = vec![collected, &mut clock];
                if let Some(p) = engine_bar.as_mut() {
                    extra.push(p);
                }
                let r = driver.run(sim, extra, &stop);
                done.store(true, Ordering::Release);
                r
            });
            let mut shown = 0.0;
            while !done.load(Ordering::Acquire) {
                py.detach(|| {
                    let start = Instant::now();
                    while !done.load(Ordering::Acquire) && start.elapsed() < CHUNK {
                        std::thread::sleep(Duration::from_millis(2));
                    }
                });
                // The bar runs Python code, where a pending Ctrl-C is raised: it is the run's
                // interrupt then, as from check_signals (swallowed, it was lost).
                let drawn = match &bar {
                    Some(bar) => {
                        advance_bar(bar, &mut shown, f64::from_bits(reached.load(Ordering::Relaxed)))
                    }
                    None => Ok(()),
                };
                if interrupt.is_none()
                    && let Err(e) = drawn.and_then(|()| py.check_signals())
                {
                    interrupt = Some(e);
                    stop.store(true, Ordering::Relaxed);
                }
            }
            if let Some(bar) = &bar {
                let closed = advance_bar(bar, &mut shown, f64::from_bits(reached.load(Ordering::Relaxed)))
                    .and_then(|()| bar.call_method0("close").map(|_| ()));
                if let (None, Err(e)) = (&interrupt, closed) {
                    interrupt = Some(e);
                }
            }
            match worker.join() {
                Ok(r) => r,
                Err(panic) => std::panic::resume_unwind(panic),
            }
        });
        let signal = match &interrupt {
            Some(e) if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => {
                Some("SIGINT".to_owned())
            }
            Some(e) => Some(e.get_type(py).name()?.to_string()),
            None => None,
        };
        let Ended { report, errors, written, .. } = driver.finish(&self.sim, result, signal.as_deref());
        self.lost_seen = self.sim.record.lost.len();
        self.wall_time += report.wall_time;
        self.frames = report.frames;
        self.interrupted = report.interrupted;
        if let Some(e) = interrupt {
            return Err(e);
        }
        if !errors.is_empty() {
            return Err(output_error(&errors));
        }
        Ok(written)
    }
}

#[pymethods]
impl Simulation {
    /// Steps the simulation until its time is ``t`` (s), the last step shortened to land on
    /// it exactly. Steps are taken as ``wetbounce run`` takes them, so the particles at an
    /// output time are those of the CLI's ``trajectories.csv``. ``t`` may go past the scene's
    /// duration. The GIL is released while the engine steps; ``KeyboardInterrupt`` stops it
    /// at the end of a step (the simulation stays usable, at the time it reached).
    fn advance_to(&mut self, py: Python<'_>, t: f64) -> PyResult<()> {
        if !t.is_finite() {
            return Err(PyValueError::new_err(format!("advance_to: t must be a finite time (s), got {t}")));
        }
        if t < self.sim.world.time {
            return Err(PyValueError::new_err(format!(
                "advance_to: t = {t} s is before the simulation's time, {} s",
                self.sim.world.time
            )));
        }
        let steps = (t - self.sim.world.time) / self.sim.setup.dt;
        if steps > wetbounce::scene::MAX_STEPS && !self.options.allow_long_run {
            return Err(PyValueError::new_err(format!(
                "advance_to: t = {t} s is {steps:.3e} steps of dt = {} s away, more than {:e}; load the \
                 scene with allow_long_run=True to accept it",
                self.sim.setup.dt,
                wetbounce::scene::MAX_STEPS
            )));
        }
        while self.sim.world.time < t {
            py.detach(|| self.chunk(t));
            py.check_signals()?;
        }
        Ok(())
    }

    /// Saves the simulation as it stands to ``path``: a checkpoint of the same format as
    /// ``wetbounce run --checkpoint-every`` writes (docs/output.md, "Checkpoints"), holding the
    /// whole state — particles, contacts, injectors' generators, outlets — and the scene's text.
    /// :meth:`load` (or ``wetbounce resume``) goes on from it exactly: advancing a loaded
    /// simulation gives the bits the saved one would have. Written to a temporary file and
    /// renamed. A file that cannot be written raises :class:`OutputError`.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        let stem = self.scene_path.file_stem().map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        let scene = wetbounce::run::checkpoint::SavedScene {
            path: std::path::absolute(&self.scene_path).unwrap_or_else(|_| self.scene_path.clone()),
            given: self.scene_path.clone(),
            source: self.source.clone(),
            output_interval: self.output_interval,
            formats: Vec::new(),
            stem,
            max_spheres: usize::MAX,
        };
        let marks = [wetbounce::output::SinkMark::Statistics(self.collected.stats.clone())];
        wetbounce::run::save_to(&path, &self.sim, &scene, self.position(), &marks)
            .map_err(|e| output_error(&[OutputError::new(&path, e)]))
    }

    /// The simulation saved at ``path`` by :meth:`save`, or a checkpoint of ``wetbounce run``,
    /// at the time it was saved: its scene rebuilt from the copy of its text inside (mesh and
    /// field files are read again from the scene file's folder), its statistics kept; the
    /// events of :meth:`events` are those from the load on. A file that is not a checkpoint, of
    /// another format version, truncated or corrupted raises ``ValueError`` naming it and what
    /// is wrong.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Simulation> {
        let resumed =
            wetbounce::run::resume::resume(&path, None).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let wetbounce::run::resume::Resumed { saved, scene, sim, .. } = resumed;
        let stats = saved.statistics().cloned().unwrap_or_default();
        Ok(Simulation {
            sim,
            scene_path: saved.scene.given.clone(),
            source: scene.source.clone(),
            duration: scene.duration,
            output_interval: saved.scene.output_interval,
            options: LoadOptions { allow_long_run: true, allow_large_memory: true },
            collected: Collector { stats, ..Collector::default() },
            lost_seen: saved.position.lost_reported as usize,
            wall_time: Duration::from_secs_f64(saved.position.wall_time),
            frames: saved.position.frames,
            interrupted: false,
            files: Vec::new(),
            resumed: Some(Box::new(saved)),
        })
    }

    /// Runs the simulation from time 0 to the scene's duration, exactly as ``wetbounce run``
    /// does, and returns the files written. With ``out`` (a folder, created if needed), writes
    /// the CLI's files there: ``NAME.mcap`` (``"mcap"`` in ``formats``, the default),
    /// ``trajectories.csv`` and ``events.csv`` (``"csv"``), ``NAME.pvd`` with its frames in
    /// ``NAME_vtk/``, ``NAME_walls.vtp`` and ``events.csv`` for ParaView (``"vtk"``), and
    /// always ``summary.json``; ``NAME`` is ``name``, else the scene file's stem (``scene`` for
    /// a dict). An earlier run's outputs in the folder that this run does not write are removed,
    /// as the CLI removes them. A folder that cannot be created, like a file that cannot be
    /// written, raises :class:`OutputError` naming it.
    /// ``output_interval`` (s) overrides the scene's, as ``--output-interval``; ``max_spheres``
    /// is ``--max-spheres`` (``None``: spheres at every count). Without ``out`` nothing is written.
    ///
    /// The GIL is released while the engine runs. ``KeyboardInterrupt`` stops the run like
    /// Ctrl-C stops the CLI: the step finishes, every file gets a last frame and is closed,
    /// ``summary.json`` says ``"interrupted": true`` and ``"signal": "SIGINT"``, then the
    /// ``KeyboardInterrupt`` propagates. A file that cannot be written raises
    /// :class:`OutputError` (after the others are closed).
    ///
    /// ``checkpoint_every`` (simulated s) and ``checkpoint_wall`` (wall-clock minutes) write
    /// checkpoints into ``out/checkpoints/`` as ``wetbounce run --checkpoint-every`` does
    /// (the newest ``checkpoint_keep`` kept); an interrupted run always writes one. A
    /// simulation :meth:`load`-ed from a run's checkpoint goes on with that run: ``run(out)``
    /// continues its files where the checkpoint left them, as ``wetbounce resume`` does, with
    /// the checkpointed run's formats and interval unless given.
    ///
    /// Returns the simulation itself, finished, as :meth:`Scene.run` returns its new one; the
    /// files written are :attr:`files`. A progress bar shows the simulated time (tqdm's, which
    /// draws in terminals and notebooks, when tqdm is installed; else the CLI's on a
    /// terminal's standard error); ``quiet=True`` leaves it out.
    #[pyo3(signature = (out = None, *, formats = None, output_interval = None, max_spheres = None, name = None, quiet = false, checkpoint_every = None, checkpoint_wall = None, checkpoint_keep = 2))]
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        mut slf: PyRefMut<'_, Self>,
        py: Python<'_>,
        out: Option<PathBuf>,
        formats: Option<Vec<String>>,
        output_interval: Option<f64>,
        max_spheres: Option<usize>,
        name: Option<String>,
        quiet: bool,
        checkpoint_every: Option<f64>,
        checkpoint_wall: Option<f64>,
        checkpoint_keep: usize,
    ) -> PyResult<Py<Self>> {
        let given = (checkpoint_every, checkpoint_wall, Some(checkpoint_keep));
        let policy =
            CheckpointPolicy::checked(given, ["checkpoint_every", "checkpoint_wall", "checkpoint_keep"])
                .map_err(PyValueError::new_err)?;
        slf.files = slf.run_whole(py, out, (formats, output_interval, max_spheres, name), quiet, policy)?;
        Ok(slf.into())
    }

    /// The files the last :meth:`run` wrote (``summary.json`` last); empty before a run and
    /// for a run without ``out``.
    #[getter]
    fn files(&self) -> Vec<PathBuf> {
        self.files.clone()
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.sim.world.time
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.sim.world.steps
    }

    /// The time step Δt (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.sim.setup.dt
    }

    /// The scene's duration (s).
    #[getter]
    fn duration(&self) -> f64 {
        self.duration
    }

    /// Number of particles in the simulation now.
    fn __len__(&self) -> usize {
        self.sim.world.particles.len()
    }

    /// Centre positions (m), shape ``(n, 3)``, float64: a new array at each call (the engine's
    /// columns move at every step, so a view would not outlive it).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        Simulation::vectors(py, &self.sim.world.particles.pos)
    }

    /// Velocities (m/s), shape ``(n, 3)``, float64.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        Simulation::vectors(py, &self.sim.world.particles.vel)
    }

    /// Angular velocities ω (rad/s), shape ``(n, 3)``, float64: the ``wx, wy, wz`` columns
    /// of ``trajectories.csv``. In a scene without rotation (neither the ``rotation`` effect
    /// nor a friction key) the engine neither computes nor writes the spin: every row is
    /// exactly ``(0, 0, 0)``, and ``trajectories.csv`` has no such columns.
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        // Zeros in a scene without rotation, as the docstring says.
        let p = &self.sim.world.particles;
        let spins: Vec<glam::DVec3> = (0..p.len()).map(|i| p.spin(i)).collect();
        Simulation::vectors(py, &spins)
    }

    /// States, shape ``(n,)``, uint8: 0 free, 1 held (at a wall or in a pair), 2 resting —
    /// the codes of the MCAP's ``state`` field; ``STATE_NAMES[code]`` is the name written to
    /// ``trajectories.csv``.
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u8>> {
        let codes: Vec<u8> = self.sim.world.particles.state.iter().map(|s| s.code()).collect();
        PyArray1::from_vec(py, codes)
    }

    /// Particle ids (stable over the run), shape ``(n,)``, uint32.
    #[getter]
    fn ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        PyArray1::from_slice(py, &self.sim.world.particles.id)
    }

    /// Diameters (m), shape ``(n,)``, float64.
    #[getter]
    fn diameters<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.sim.world.particles.diameter)
    }

    /// Kind indices into :attr:`kind_names`, shape ``(n,)``, uint16.
    #[getter]
    fn kinds<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u16>> {
        PyArray1::from_slice(py, &self.sim.world.particles.kind)
    }

    /// The particles now, one row each, in the engine's order: ``id``, ``kind`` (its name),
    /// ``diameter`` (m), ``x``, ``y``, ``z`` (m), ``vx``, ``vy``, ``vz`` (m/s), ``state``
    /// (``free``, ``held``, ``resting``) and, in a scene with rotation, ``wx``, ``wy``, ``wz``
    /// (rad/s): a frame of ``trajectories.csv`` with the kind and the diameter. A pandas
    /// DataFrame, a copy.
    fn particles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let p = &self.sim.world.particles;
        let kinds = &self.sim.setup.kinds;
        let d = PyDict::new(py);
        let component =
            |v: &[glam::DVec3], axis: usize| PyArray1::from_vec(py, v.iter().map(|x| x[axis]).collect());
        d.set_item("id", PyArray1::from_slice(py, &p.id))?;
        d.set_item("kind", p.kind.iter().map(|&k| kinds[k as usize].name.as_str()).collect::<Vec<_>>())?;
        d.set_item("diameter", PyArray1::from_slice(py, &p.diameter))?;
        for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
            d.set_item(name, component(&p.pos, axis))?;
        }
        for (axis, name) in ["vx", "vy", "vz"].into_iter().enumerate() {
            d.set_item(name, component(&p.vel, axis))?;
        }
        d.set_item("state", p.state.iter().map(|s| s.name()).collect::<Vec<_>>())?;
        // The spin columns as trajectories.csv has them: only in a scene with rotation.
        if self.sim.setup.physics.rotation {
            for (axis, name) in ["wx", "wy", "wz"].into_iter().enumerate() {
                d.set_item(name, component(p.omega.values(), axis))?;
            }
        }
        py.import("pandas")?.getattr("DataFrame")?.call1((d,))
    }

    /// A trajectory recorder: steps through ``times`` (s: increasing, none before the
    /// simulation's time) as :meth:`advance_to` does and returns the particles at each — the
    /// columns of :meth:`particles` with ``t`` first, one row per particle per time: a long
    /// DataFrame (``df.groupby("t")``, ``df.pivot(index="t", columns="id", values="z")``).
    /// Given the scene's output times, its rows are those of ``trajectories.csv``.
    fn record<'py>(&mut self, py: Python<'py>, times: Vec<f64>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas")?;
        let mut frames = Vec::with_capacity(times.len());
        for (i, &t) in times.iter().enumerate() {
            let now = self.sim.world.time;
            if !(t.is_finite() && t >= now) {
                return Err(PyValueError::new_err(format!(
                    "record: times[{i}] = {t} s is before the simulation's time {now} s (or not finite): \
                     the times must increase from it"
                )));
            }
            self.advance_to(py, t)?;
            let frame = self.particles(py)?;
            frame.call_method1("insert", (0, "t", t))?;
            frames.push(frame);
        }
        if frames.is_empty() {
            // No time: the columns all the same, no row.
            let frame = self.particles(py)?.call_method1("head", (0,))?;
            frame.call_method1("insert", (0, "t", 0.0))?;
            return Ok(frame);
        }
        let kwargs = PyDict::new(py);
        kwargs.set_item("ignore_index", true)?;
        pandas.getattr("concat")?.call((frames,), Some(&kwargs))
    }

    /// A summary table for Jupyter: the scene, the time reached, the steps, the particles by
    /// state and the contacts so far.
    fn _repr_html_(&self) -> String {
        let p = &self.sim.world.particles;
        let count = |code: u8| p.state.iter().filter(|s| s.code() == code).count();
        let rows = [
            ("scene", html_escape(&self.scene_path.display().to_string())),
            (
                "time",
                format!(
                    "{} s of {} s ({:.0} %)",
                    self.sim.world.time,
                    self.duration,
                    100.0 * self.sim.world.time / self.duration
                ),
            ),
            ("steps", format!("{} (dt = {} s)", self.sim.world.steps, self.sim.setup.dt)),
            ("particles", format!("{}: {} free, {} held, {} resting", p.len(), count(0), count(1), count(2))),
            ("contacts so far", self.collected.rows.len().to_string()),
        ];
        html_table("wetbounce.Simulation", &rows)
    }

    /// The scene's particle kinds, by index.
    #[getter]
    fn kind_names(&self) -> Vec<String> {
        self.sim.setup.kinds.iter().map(|k| k.name.clone()).collect()
    }

    /// The scene's walls, by index.
    #[getter]
    fn wall_names(&self) -> Vec<String> {
        self.sim.setup.walls.iter().map(|w| w.name.clone()).collect()
    }

    /// The first particle found outside a flow field whose policy is ``outside = "error"``:
    /// ``None``, or a dict with ``id``, ``position`` (m, a tuple), ``t`` (s) and ``message``
    /// (the CLI's error). :meth:`run` stops there, as ``wetbounce run`` does; :meth:`advance_to`
    /// goes on stepping (the particle then sees the nearest point's velocity), so check this
    /// after it.
    #[getter]
    fn left_field<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(e) = &self.sim.record.left_field else { return Ok(None) };
        let d = PyDict::new(py);
        d.set_item("id", e.id)?;
        d.set_item("position", (e.position.x, e.position.y, e.position.z))?;
        d.set_item("t", e.time)?;
        d.set_item("message", e.to_string())?;
        Ok(Some(d))
    }

    /// Every contact so far, one row per contact, the columns of ``events.csv``: ``t``,
    /// ``id``, ``other`` (the wall's name or the other particle's id), ``kind`` (``wall``,
    /// ``particle``, or ``removed`` for a particle taken out as non-finite), ``normal_speed``,
    /// ``st``, ``eps``, ``contact_time`` (NaN for a removal), ``outcome`` (``held``,
    /// ``bounced``, ``deposited``, ``non_finite``). In a scene with rotation (when
    /// ``events.csv`` has them) also ``tangential_speed`` (m/s, the contact point's, relative
    /// to the wall or the other particle, just before the contact) and ``incidence_angle``
    /// (rad, of the centre's velocity from the normal: 0 head-on, π/2 grazing), NaN for a
    /// removal; without rotation the DataFrame has no such columns. A pandas DataFrame.
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        // `wetbounce run`'s rule for the spin columns of events.csv (src/main.rs).
        let rotation = self.sim.setup.physics.rotation;
        let rows = &self.collected.rows;
        let n = rows.len();
        let spin_columns = if rotation { n } else { 0 };
        let mut spin = [Vec::with_capacity(spin_columns), Vec::with_capacity(spin_columns)];
        let (mut t, mut id) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut other, mut kind, mut outcome) =
            (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        let mut num =
            [Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n)];
        for r in rows {
            match r {
                Row::Contact(e) => {
                    let (o, k) = self.sim.setup.name_of(e.other);
                    t.push(e.time);
                    id.push(e.id);
                    other.push(o);
                    kind.push(k);
                    for (c, v) in num.iter_mut().zip([e.normal_speed, e.st, e.eps, e.contact_time]) {
                        c.push(v);
                    }
                    outcome.push(e.outcome.name());
                    if rotation {
                        for (c, v) in spin.iter_mut().zip([e.tangential_speed, e.incidence_angle]) {
                            c.push(v);
                        }
                    }
                }
                Row::Lost(l) => {
                    t.push(l.time);
                    id.push(l.id);
                    other.push(String::new());
                    kind.push("removed");
                    for c in &mut num {
                        c.push(f64::NAN);
                    }
                    outcome.push("non_finite");
                    if rotation {
                        for c in &mut spin {
                            c.push(f64::NAN);
                        }
                    }
                }
            }
        }
        let d = PyDict::new(py);
        d.set_item("t", PyArray1::from_vec(py, t))?;
        d.set_item("id", PyArray1::from_vec(py, id))?;
        d.set_item("other", other)?;
        d.set_item("kind", kind)?;
        let [normal_speed, st, eps, contact_time] = num;
        d.set_item("normal_speed", PyArray1::from_vec(py, normal_speed))?;
        d.set_item("st", PyArray1::from_vec(py, st))?;
        d.set_item("eps", PyArray1::from_vec(py, eps))?;
        d.set_item("contact_time", PyArray1::from_vec(py, contact_time))?;
        d.set_item("outcome", outcome)?;
        if rotation {
            let [tangential_speed, incidence_angle] = spin;
            d.set_item("tangential_speed", PyArray1::from_vec(py, tangential_speed))?;
            d.set_item("incidence_angle", PyArray1::from_vec(py, incidence_angle))?;
        }
        py.import("pandas")?.getattr("DataFrame")?.call1((d,))
    }

    /// What each outlet took out so far: a pandas DataFrame with ``outlet``, ``id``, ``t``
    /// (removal time, s) and ``residence_time`` (s), in removal order.
    fn residence_times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (mut outlet, mut id, mut t, mut rt) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (o, removed) in self.sim.setup.outlets.iter().zip(&self.sim.record.removed) {
            for r in removed {
                outlet.push(o.name.clone());
                id.push(r.id);
                t.push(r.time);
                rt.push(r.residence_time);
            }
        }
        let d = PyDict::new(py);
        d.set_item("outlet", outlet)?;
        d.set_item("id", PyArray1::from_vec(py, id))?;
        d.set_item("t", PyArray1::from_vec(py, t))?;
        d.set_item("residence_time", PyArray1::from_vec(py, rt))?;
        py.import("pandas")?.getattr("DataFrame")?.call1((d,))
    }

    /// The summary so far, as the dict of ``summary.json`` (particles, impacts, per-wall
    /// impacts, per-outlet residence-time distributions, injectors; SI units; a mean of
    /// nothing is ``None``). After :meth:`run` with ``out``, the file's content without its
    /// ``signal`` and ``output_errors``.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = self.summary_value().to_string();
        py.import("json")?.getattr("loads")?.call1((text,))
    }

    /// The summary's tables as pandas DataFrames: ``"walls"`` (one row per wall: ``impacts``,
    /// ``held``, ``bounced``, ``deposited``, ``mean_st``, ``mean_eps``, ``held_time_s``),
    /// ``"outlets"`` (one row per outlet: the residence-time distribution's ``count``,
    /// ``mean``, ``min``, ``p10``, ``p50``, ``p90``, ``max`` in s, and ``histogram``, a dict) and ``"injectors"`` (``due``,
    /// ``injected``, ``skipped``), each indexed by name.
    fn summary_frames<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let json = self.summary_value();
        let pandas = py.import("pandas")?;
        let loads = py.import("json")?.getattr("loads")?;
        let frame = |rows: serde_json::Value, columns: &[&str]| -> PyResult<Bound<'py, PyAny>> {
            let rows = loads.call1((rows.to_string(),))?;
            let kwargs = PyDict::new(py);
            kwargs.set_item("columns", PyList::new(py, columns)?)?;
            let df = pandas
                .getattr("DataFrame")?
                .call((rows,), Some(&kwargs))?
                .call_method1("set_index", ("name",))?;
            // JSON's null (no impacts, no residence time yet) is NaN in a numeric column, as
            // pandas expects, not None in an object column.
            for column in columns.iter().filter(|c| !matches!(**c, "name" | "histogram")) {
                let numeric = pandas.call_method1("to_numeric", (df.get_item(*column)?,))?;
                df.set_item(*column, numeric)?;
            }
            Ok(df)
        };
        let outlets: Vec<serde_json::Value> = json["outlets"]
            .as_array()
            .map(|a| {
                a.iter()
                    .map(|o| {
                        let mut row = o["residence_time_s"].clone();
                        row["name"] = o["name"].clone();
                        row
                    })
                    .collect()
            })
            .unwrap_or_default();
        let d = PyDict::new(py);
        let walls = ["name", "impacts", "held", "bounced", "deposited", "mean_st", "mean_eps", "held_time_s"];
        d.set_item("walls", frame(json["walls"].clone(), &walls)?)?;
        let outlet_columns = ["name", "count", "mean", "min", "p10", "p50", "p90", "max", "histogram"];
        d.set_item("outlets", frame(serde_json::Value::Array(outlets), &outlet_columns)?)?;
        d.set_item("injectors", frame(json["injectors"].clone(), &["name", "due", "injected", "skipped"])?)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "Simulation({:?} at t = {} s of {} s: {} particles, {} steps)",
            self.scene_path.display().to_string(),
            self.sim.world.time,
            self.duration,
            self.sim.world.particles.len(),
            self.sim.world.steps
        )
    }
}

/// `s` with the five characters HTML gives a meaning escaped.
pub fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&#39;")
}

/// A two-column HTML table with a caption, for `_repr_html_`: the row names are ours, the
/// values already escaped.
pub fn html_table(caption: &str, rows: &[(&str, String)]) -> String {
    let mut html = format!("<table><caption style=\"text-align:left\"><b>{caption}</b></caption>");
    for (name, value) in rows {
        html.push_str(&format!(
            "<tr><th style=\"text-align:left\">{name}</th><td style=\"text-align:left\">{value}</td></tr>"
        ));
    }
    html.push_str("</table>");
    html
}

/// A sink that publishes the simulated time after every step, for the progress bar drawn
/// under the GIL while the engine steps on another thread.
struct Clock<'a>(&'a AtomicU64);

impl Sink for Clock<'_> {
    fn step(&mut self, sim: &wetbounce::Simulation) -> Result<(), OutputError> {
        self.0.store(sim.world.time.to_bits(), Ordering::Relaxed);
        Ok(())
    }
}

/// `tqdm.auto.tqdm(total=duration, unit="s")`, or `None` when tqdm is not installed.
fn tqdm_bar<'py>(py: Python<'py>, duration: f64) -> Option<Bound<'py, PyAny>> {
    let tqdm = py.import("tqdm.auto").ok()?.getattr("tqdm").ok()?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("total", duration).ok()?;
    kwargs.set_item("unit", "s").ok()?;
    kwargs.set_item("desc", "simulated").ok()?;
    kwargs
        .set_item(
            "bar_format",
            "{desc}: {percentage:3.0f}%|{bar}| {n:.4g}/{total:.4g} s [{elapsed}<{remaining}]",
        )
        .ok()?;
    tqdm.call((), Some(&kwargs)).ok()
}

/// Moves the bar from `shown` to `time` (s).
fn advance_bar(bar: &Bound<'_, PyAny>, shown: &mut f64, time: f64) -> PyResult<()> {
    if time > *shown {
        bar.call_method1("update", (time - *shown,))?;
        *shown = time;
    }
    Ok(())
}
