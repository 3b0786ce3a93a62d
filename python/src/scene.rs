//! `wetbounce.Scene`: a validated scene, from a file or a dict, its keys, and `check()`.

use crate::convert;
use crate::errors::scene_error;
use crate::sim::{Simulation, html_escape, html_table};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::{Path, PathBuf};
use toml::Table;
use wetbounce::scene::{LoadOptions, kind_reports};

/// What a scene made from a dict is called in messages: `<dict>`, or `DIR/<dict>` when its
/// mesh files are looked for in `DIR`.
const DICT_NAME: &str = "<dict>";

/// What a pickled scene is loaded again from ([`Scene::_from_text`]'s arguments): its text,
/// file and options.
type Reduced = (String, PathBuf, bool, bool);

/// A scene, loaded and validated exactly as ``wetbounce run`` and ``wetbounce check`` load
/// one: from a TOML file (:meth:`load`) or from a dict with the same structure
/// (:meth:`from_dict`). A bad scene raises :class:`SceneError` with the CLI's message, which
/// names the file (``<dict>`` for a dict), the key and the bad value.
///
/// A scene is immutable: :meth:`with_values` returns a new one with some keys changed,
/// validated again.
#[pyclass(module = "wetbounce", frozen)]
pub struct Scene {
    pub(crate) scene: wetbounce::Scene,
    /// The scene as a TOML document (what a dict or the file said, not the defaults).
    pub(crate) doc: Table,
    pub(crate) options: LoadOptions,
}

impl Scene {
    /// Loads `doc` as scene text named `label` (its folder is where mesh files are found).
    fn from_doc(doc: Table, label: &Path, options: LoadOptions) -> PyResult<Scene> {
        let text = toml::to_string(&doc).map_err(|e| {
            PyValueError::new_err(format!("{}: cannot be written as TOML: {e}", label.display()))
        })?;
        let scene = wetbounce::Scene::from_str_with(&text, label, options).map_err(|e| scene_error(&e))?;
        Ok(Scene { scene, doc, options })
    }
}

#[pymethods]
impl Scene {
    /// Reads and validates the scene file at ``path`` (mesh files are found relative to its
    /// folder). ``allow_long_run`` accepts more than 10⁷ output frames or 10¹⁰ steps, like
    /// ``wetbounce run --allow-long-run``; ``allow_large_memory`` a run whose estimated memory
    /// exceeds the machine's available memory, like ``--allow-large-memory``.
    #[staticmethod]
    #[pyo3(signature = (path, *, allow_long_run = false, allow_large_memory = false))]
    fn load(path: PathBuf, allow_long_run: bool, allow_large_memory: bool) -> PyResult<Scene> {
        let options = LoadOptions { allow_long_run, allow_large_memory };
        let scene = wetbounce::Scene::load_with(&path, options).map_err(|e| scene_error(&e))?;
        // The file parsed as a scene, so it parses as TOML.
        let doc: Table = toml::from_str(&scene.source).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Scene { scene, doc, options })
    }

    /// Validates a scene given as a dict with the structure of a scene file
    /// (``{"simulation": {...}, "fluid": {...}, "kinds": [{...}], ...}``): it is written as
    /// TOML and loaded through the same path as a file, so the checks and messages are the
    /// same; messages name the file ``<dict>``. Values are bool, int, float, str, dict, list
    /// or anything with ``tolist()`` (NumPy arrays); a value ``None`` is a key left out. Mesh
    /// files are found relative to ``base_dir`` (default: the working directory).
    #[staticmethod]
    #[pyo3(signature = (scene, *, base_dir = None, allow_long_run = false, allow_large_memory = false))]
    fn from_dict(
        scene: &Bound<'_, PyDict>,
        base_dir: Option<PathBuf>,
        allow_long_run: bool,
        allow_large_memory: bool,
    ) -> PyResult<Scene> {
        let doc = convert::dict_to_table(scene, "")?;
        let label = base_dir.map_or_else(|| PathBuf::from(DICT_NAME), |d| d.join(DICT_NAME));
        Scene::from_doc(doc, &label, LoadOptions { allow_long_run, allow_large_memory })
    }

    /// A new scene with the keys of ``changes`` set, validated again; the keys are the paths
    /// of the error messages: ``"simulation.duration"``, ``"kinds[0].restitution_max"``,
    /// ``"fluid.flow.mean_velocity"``. A missing table key is created (``"effects.drag"``);
    /// an array index must exist, or equal the array's length (appends); ``None`` removes
    /// the key. Messages still name the scene's file.
    fn with_values(&self, changes: &Bound<'_, PyDict>) -> PyResult<Scene> {
        let mut doc = self.doc.clone();
        for (k, v) in changes.iter() {
            let key: String = k.extract()?;
            let value = if v.is_none() { None } else { Some(convert::to_toml(&v, &key)?) };
            convert::set(&mut doc, &key, value)?;
        }
        Scene::from_doc(doc, &self.scene.path, self.options)
    }

    /// The value at a key path (``scene["kinds[0].density"]``), as the scene gives it: a key
    /// the scene leaves to its default raises ``KeyError``.
    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        convert::to_py(py, convert::get(&self.doc, key)?)
    }

    /// The scene as a dict (what the file or dict gave; defaults are not filled in).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        convert::table_to_py(py, &self.doc)
    }

    /// Pickling (Dask sends scenes to its workers, ``copy.deepcopy``): the scene's text, file
    /// and options, loaded again by :meth:`_from_text`.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Reduced)> {
        let load = py.get_type::<Scene>().getattr("_from_text")?;
        let o = self.options;
        Ok((
            load,
            (self.scene.source.clone(), self.scene.path.clone(), o.allow_long_run, o.allow_large_memory),
        ))
    }

    /// The scene of TOML ``text`` named ``path`` (its folder is where mesh and field files are
    /// found), as :meth:`load` would load that file: what unpickling calls.
    #[staticmethod]
    fn _from_text(
        text: &str,
        path: PathBuf,
        allow_long_run: bool,
        allow_large_memory: bool,
    ) -> PyResult<Scene> {
        let options = LoadOptions { allow_long_run, allow_large_memory };
        let scene = wetbounce::Scene::from_str_with(text, &path, options).map_err(|e| scene_error(&e))?;
        let doc: Table = toml::from_str(text).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Scene { scene, doc, options })
    }

    /// The scene as TOML text, as it was loaded (for a changed scene or a dict, the text
    /// written from it).
    #[getter]
    fn source(&self) -> &str {
        &self.scene.source
    }

    /// The scene's file (``<dict>`` for a dict).
    #[getter]
    fn path(&self) -> PathBuf {
        self.scene.path.clone()
    }

    /// Simulated duration (s).
    #[getter]
    fn duration(&self) -> f64 {
        self.scene.duration
    }

    /// Simulated time between output frames (s).
    #[getter]
    fn output_interval(&self) -> f64 {
        self.scene.output_interval
    }

    /// The time step Δt (s), the one chosen when the scene says ``dt = "auto"``.
    #[getter]
    fn dt(&self) -> f64 {
        self.scene.setup.dt
    }

    /// What ``wetbounce check`` prints, as data: a dict with ``file``, ``particles``,
    /// ``walls``, ``effects``, ``integrator``, ``dt``, ``duration``, ``impact_location``,
    /// ``bounce`` (``beta``, ``st_critical``, ``tangential_restitution``,
    /// ``hold_at_contact``), ``auto_step`` (with ``dt = "auto"``: ``accuracy``,
    /// ``integrator``, ``dt``, ``time_scale``, ``limited_by``; else ``None``), ``wall`` (the
    /// wall the impacts are computed against) and ``kinds``: one dict per kind and diameter
    /// (``kind``, ``diameter``, ``terminal_velocity``, ``rising``, ``reynolds``, ``stokes``,
    /// ``eps``, ``contact_time``, ``relaxation_time``, ``bounces``, ``wall``; SI units;
    /// ``pandas.DataFrame(report["kinds"])`` makes the CLI's table).
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.scene;
        let d = PyDict::new(py);
        d.set_item("file", s.path.display().to_string())?;
        d.set_item("particles", s.particles.len())?;
        d.set_item("walls", s.setup.walls.iter().map(|w| w.name.clone()).collect::<Vec<_>>())?;
        d.set_item("effects", s.setup.physics.effect_names.clone())?;
        d.set_item("integrator", s.setup.integrator.name())?;
        d.set_item("dt", s.setup.dt)?;
        d.set_item("duration", s.duration)?;
        d.set_item("output_interval", s.output_interval)?;
        d.set_item("impact_location", s.setup.impact_location.name())?;
        let bounce = PyDict::new(py);
        bounce.set_item("beta", s.setup.rule.beta)?;
        bounce.set_item("st_critical", s.setup.rule.st_critical)?;
        bounce.set_item("tangential_restitution", s.setup.rule.tangential_restitution)?;
        bounce.set_item("hold_at_contact", s.setup.rule.hold_at_contact)?;
        d.set_item("bounce", bounce)?;
        match &s.auto_step {
            Some(a) => {
                let auto = PyDict::new(py);
                auto.set_item("accuracy", a.accuracy.name())?;
                auto.set_item("integrator", a.integrator.name())?;
                auto.set_item("dt", a.dt)?;
                auto.set_item("time_scale", a.time_scale)?;
                auto.set_item("limited_by", a.limited_by.clone())?;
                d.set_item("auto_step", auto)?;
            }
            None => d.set_item("auto_step", py.None())?,
        }
        d.set_item("wall", s.setup.walls.first().map(|w| w.name.clone()))?;
        let kinds = PyList::empty(py);
        for r in kind_reports(s) {
            let k = PyDict::new(py);
            k.set_item("kind", r.kind)?;
            k.set_item("diameter", r.diameter)?;
            k.set_item("terminal_velocity", r.terminal_velocity)?;
            k.set_item("rising", r.rising)?;
            k.set_item("reynolds", r.reynolds)?;
            k.set_item("stokes", r.stokes)?;
            k.set_item("eps", r.eps)?;
            k.set_item("contact_time", r.contact_time)?;
            k.set_item("relaxation_time", r.relaxation_time)?;
            k.set_item("bounces", r.bounces)?;
            k.set_item("wall", r.wall)?;
            kinds.append(k)?;
        }
        d.set_item("kinds", kinds)?;
        Ok(d)
    }

    /// The simulation at time 0, to step with :meth:`Simulation.advance_to` or run whole with
    /// :meth:`Simulation.run`.
    fn simulation(&self) -> Simulation {
        Simulation::new(self)
    }

    /// Runs the scene whole (a new :class:`Simulation`, see :meth:`Simulation.run` for the
    /// arguments) and returns the finished simulation.
    #[pyo3(signature = (out = None, *, formats = None, output_interval = None, max_spheres = None, name = None, quiet = false))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        py: Python<'_>,
        out: Option<PathBuf>,
        formats: Option<Vec<String>>,
        output_interval: Option<f64>,
        max_spheres: Option<usize>,
        name: Option<String>,
        quiet: bool,
    ) -> PyResult<Py<Simulation>> {
        let sim = Py::new(py, Simulation::new(self))?;
        Simulation::run(
            sim.bind(py).borrow_mut(),
            py,
            out,
            formats,
            output_interval,
            max_spheres,
            name,
            quiet,
            None,
            None,
            2,
        )
    }

    /// A summary table for Jupyter: the file, the time and step, the fluid, kinds, walls,
    /// particles, injectors and outlets.
    fn _repr_html_(&self) -> String {
        let s = &self.scene;
        let names = |v: Vec<&str>| html_escape(&v.join(", "));
        let rows = [
            ("scene", html_escape(&s.path.display().to_string())),
            ("duration", format!("{} s, output every {} s", s.duration, s.output_interval)),
            ("step", format!("dt = {} s, {}", s.setup.dt, s.setup.integrator.name())),
            ("kinds", names(s.setup.kinds.iter().map(|k| k.name.as_str()).collect())),
            ("walls", names(s.setup.walls.iter().map(|w| w.name.as_str()).collect())),
            ("particles at t = 0", s.particles.len().to_string()),
            ("injectors, outlets", format!("{}, {}", s.setup.injectors.len(), s.setup.outlets.len())),
        ];
        html_table("wetbounce.Scene", &rows)
    }

    fn __repr__(&self) -> String {
        let s = &self.scene;
        format!(
            "Scene({:?}: {} particles, {} walls, {} injectors, duration {} s, dt {} s)",
            s.path.display().to_string(),
            s.particles.len(),
            s.setup.walls.len(),
            s.setup.injectors.len(),
            s.duration,
            s.setup.dt
        )
    }
}
