//! `flank._native`: the Python extension module of flank, a thin binding
//! over [`flank::api`]. It converts arguments (the CLI's option names and
//! values) into the façade's option structs, runs the analysis with the GIL
//! released and Ctrl-C watched, and hands back the typed result as JSON
//! (the same serialization as `summary.json`) for the Python layer
//! (`python/flank/`) to wrap. No gear logic lives here.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use flank::api;
use flank::FlankError as LibError;
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::exceptions::{PyKeyError, PyKeyboardInterrupt, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};

pyo3::create_exception!(
    flank,
    FlankError,
    pyo3::exceptions::PyException,
    "An error of flank (the library's FlankError): `kind` names its variant, `message` its text."
);
pyo3::create_exception!(
    flank,
    SceneError,
    FlankError,
    "A malformed or refused input file (a scene, a profile, a deck): `file`, `line` (1-based) \
     and, where the error names one, `key` (the dotted scene key or override)."
);

/// The first backtick-quoted dotted name of a message (flank's errors open
/// with the key they are about: "`gear.hand` = \"right\": …").
fn quoted_key(message: &str) -> Option<String> {
    let start = message.find('`')? + 1;
    let len = message[start..].find('`')?;
    let key = &message[start..start + len];
    let plain = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.');
    plain.then(|| key.to_string())
}

/// A library error as a Python exception: Parse → [`SceneError`] with file,
/// line and key; Interrupted → KeyboardInterrupt; the rest → [`FlankError`].
fn to_py(py: Python<'_>, e: LibError, key: Option<&str>) -> PyErr {
    let text = e.to_string();
    let (err, kind) = match &e {
        LibError::Parse {
            file,
            line,
            message,
        } => {
            let err = SceneError::new_err(text.clone());
            let v = err.value(py);
            let key = key
                .map(String::from)
                .or_else(|| quoted_key(message.as_str()));
            let _ = v.setattr("file", file.display().to_string());
            let _ = v.setattr("line", *line);
            let _ = v.setattr("key", key);
            (err, "Parse")
        }
        LibError::Interrupted(m) => return PyKeyboardInterrupt::new_err(m.clone()),
        LibError::Io { path, source } => {
            let err = FlankError::new_err(format!("{}: {source}", path.display()));
            let _ = err.value(py).setattr("path", path.display().to_string());
            (err, "Io")
        }
        LibError::Material(_) => (FlankError::new_err(text.clone()), "Material"),
        LibError::Element { .. } => (FlankError::new_err(text.clone()), "Element"),
        LibError::Model(_) => (FlankError::new_err(text.clone()), "Model"),
        LibError::Singular(_) => (FlankError::new_err(text.clone()), "Singular"),
        LibError::Solver(_) => (FlankError::new_err(text.clone()), "Solver"),
        LibError::Campaign(_) => (FlankError::new_err(text.clone()), "Campaign"),
        LibError::Memory(_) => (FlankError::new_err(text.clone()), "Memory"),
    };
    let v = err.value(py);
    let _ = v.setattr("kind", kind);
    let _ = v.setattr("message", text);
    err
}

/// What the worker thread tells the calling thread.
enum Event {
    /// A progress step ([`flank::progress`]); the worker waits for the
    /// acknowledgement, so that a callback's exception stops the run
    /// before its next step.
    Step(String, usize, usize, mpsc::Sender<()>),
    /// The result is in its channel.
    Finished,
}

/// How long a worker waits for the calling thread to take a progress
/// event before it goes on (a callback that blocks must not stall the run
/// for ever).
const ACK_TIMEOUT: Duration = Duration::from_secs(10);

/// Runs `f` on a worker thread with the GIL released; the calling (main)
/// thread waits for the worker's events and polls Python's signal handlers
/// every 50 ms. On Ctrl-C the library's stop flag
/// ([`flank::interrupt::request`]) is raised, so a run that polls it stops
/// at its next safe point (atomic writes: no half-written file), and
/// KeyboardInterrupt is raised once the worker has returned. A panic in
/// the library becomes an exception, never an unwind across the FFI
/// boundary.
///
/// `progress`, a Python callable `(task, done, total)`, is called on the
/// calling thread (with the GIL) for every progress event of the library;
/// the step that reported it waits until the call has returned, so an
/// exception the callback raises stops the run at its next safe point (as
/// Ctrl-C) and is raised in its place.
fn run_released<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    f: impl FnOnce() -> Result<T, LibError> + Send,
) -> PyResult<Result<T, LibError>> {
    flank::interrupt::clear();
    let (tx, rx) = mpsc::channel();
    let (events_tx, events) = mpsc::channel::<Event>();
    let _observer = progress.map(|_| {
        let events_tx = events_tx.clone();
        flank::progress::observe(std::sync::Arc::new(
            move |p: flank::progress::Progress<'_>| {
                let (ack_tx, ack) = mpsc::channel();
                let step = Event::Step(p.task.to_string(), p.done, p.total, ack_tx);
                if events_tx.send(step).is_ok() {
                    let _ = ack.recv_timeout(ACK_TIMEOUT);
                }
            },
        ))
    });
    let (outcome, interrupt) = std::thread::scope(|s| {
        let finished = events_tx.clone();
        s.spawn(move || {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
            let _ = tx.send(r);
            let _ = finished.send(Event::Finished);
        });
        drop(events_tx);
        let mut interrupt: Option<PyErr> = None;
        let mut events = events;
        loop {
            // the receiver goes into the GIL-free wait and comes back (it is Send, not Sync)
            let (got, back) =
                py.detach(move || (events.recv_timeout(Duration::from_millis(50)), events));
            events = back;
            match got {
                Ok(Event::Step(task, done, total, ack)) => {
                    if let (Some(callback), None) = (progress, &interrupt) {
                        if let Err(e) = callback.call1((task, done, total)) {
                            flank::interrupt::request();
                            interrupt = Some(e);
                        }
                    }
                    let _ = ack.send(());
                }
                Ok(Event::Finished) => break (rx.try_recv().ok(), interrupt),
                Err(mpsc::RecvTimeoutError::Disconnected) => break (rx.try_recv().ok(), interrupt),
                Err(mpsc::RecvTimeoutError::Timeout) => {}
            }
            if interrupt.is_none() {
                if let Err(e) = py.check_signals() {
                    flank::interrupt::request();
                    interrupt = Some(e);
                }
            }
        }
    });
    flank::interrupt::clear();
    if let Some(e) = interrupt {
        return Err(e);
    }
    match outcome {
        Some(Ok(r)) => Ok(r),
        Some(Err(panic)) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(no message)".into());
            Err(FlankError::new_err(format!(
                "internal error (a panic in flank): {what}"
            )))
        }
        None => Err(FlankError::new_err(
            "internal error: the worker thread ended without a result",
        )),
    }
}

/// [`run_released`] with the library error converted.
fn released<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> Result<T, LibError> + Send,
) -> PyResult<T> {
    run_released(py, None, f)?.map_err(|e| to_py(py, e, None))
}

/// [`released`] with a progress callback (None: no events).
fn released_with<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    f: impl FnOnce() -> Result<T, LibError> + Send,
) -> PyResult<T> {
    run_released(py, progress, f)?.map_err(|e| to_py(py, e, None))
}

/// A serializable result as JSON text (what `summary.json` holds).
fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| FlankError::new_err(format!("result as JSON: {e}")))
}

/// A CLI option value (`hex20`, `active`, `clarabel`, …) parsed as clap
/// parses it for `--option`.
fn choice<T: clap::ValueEnum>(option: &str, value: Option<&str>) -> PyResult<Option<T>> {
    value
        .map(|v| {
            T::from_str(v, false).map_err(|_| {
                let known: Vec<String> = T::value_variants()
                    .iter()
                    .filter_map(|x| x.to_possible_value().map(|p| p.get_name().to_string()))
                    .collect();
                PyValueError::new_err(format!("{option}={v:?}: not one of {}", known.join(", ")))
            })
        })
        .transpose()
}

/// A value parsed by its `FromStr` (as the CLI parses `--solver`, `--compression`).
fn parsed<T: std::str::FromStr>(option: &str, value: Option<&str>) -> PyResult<Option<T>>
where
    T::Err: std::fmt::Display,
{
    value
        .map(|v| {
            v.parse::<T>()
                .map_err(|e| PyValueError::new_err(format!("{option}: {e}")))
        })
        .transpose()
}

/// The sector mesh options shared by the scene commands (`--flank-size`,
/// `--base-size`, `--element`).
fn mesh_options(
    flank_size: Option<f64>,
    base_size: Option<f64>,
    element: Option<&str>,
    with_load: bool,
) -> PyResult<api::BodyMeshOptions> {
    #[derive(Clone, Copy, clap::ValueEnum)]
    enum Element {
        Hex20,
        Wedge15,
    }
    let element = choice::<Element>("element", element)?.map(|e| match e {
        Element::Hex20 => flank::scene::ElementKind::Hex20,
        Element::Wedge15 => flank::scene::ElementKind::Wedge15,
    });
    Ok(api::BodyMeshOptions {
        flank_size,
        base_size,
        with_load,
        element,
    })
}

// ── scene values: Python ↔ TOML ──

fn to_toml(v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in d.iter() {
            t.insert(k.extract::<String>()?, to_toml(&x)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if let Ok(seq) = v.try_iter() {
        let mut a = Vec::new();
        for x in seq {
            a.push(to_toml(&x?)?);
        }
        return Ok(toml::Value::Array(a));
    }
    Err(PyTypeError::new_err(format!(
        "{}: not a TOML value (bool, int, float, str, list or dict)",
        v.repr()?
    )))
}

fn from_toml<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(from_toml(py, x)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, from_toml(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// A validated scene with where it came from: the file (or the name given
/// to a TOML string), its text, and the dotted keys set on it.
#[pyclass(module = "flank._native", name = "Scene")]
struct PyScene {
    path: PathBuf,
    text: String,
    overrides: Vec<(String, toml::Value)>,
    scene: api::Scene,
}

impl PyScene {
    fn parse(
        py: Python<'_>,
        path: PathBuf,
        text: String,
        overrides: Vec<(String, toml::Value)>,
        key: Option<&str>,
    ) -> PyResult<PyScene> {
        let pairs: Vec<(&str, toml::Value)> = overrides
            .iter()
            .map(|(k, v)| (k.as_str(), v.clone()))
            .collect();
        let scene = flank::scene::overrides::parse_scene_with(&text, &path, &pairs)
            .map_err(|e| to_py(py, e, key))?;
        Ok(PyScene {
            path,
            text,
            overrides,
            scene,
        })
    }

    /// The scene's TOML table with the overrides set.
    fn table(&self) -> PyResult<toml::Table> {
        let mut t: toml::Table = toml::from_str(&self.text)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", self.path.display())))?;
        for (k, v) in &self.overrides {
            flank::scene::overrides::set_key(&mut t, k, v.clone())
                .map_err(|e| PyValueError::new_err(format!("override `{k}`: {e}")))?;
        }
        Ok(t)
    }
}

fn overrides_of(d: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, toml::Value)>> {
    let mut out = Vec::new();
    if let Some(d) = d {
        for (k, v) in d.iter() {
            out.push((k.extract::<String>()?, to_toml(&v)?));
        }
    }
    Ok(out)
}

#[pymethods]
impl PyScene {
    /// Reads and validates the scene file `path` (any pair kind), with the
    /// dotted keys of `overrides` set as `flank campaign` sets a variant's.
    #[staticmethod]
    #[pyo3(signature = (path, overrides=None))]
    fn load(
        py: Python<'_>,
        path: PathBuf,
        overrides: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyScene> {
        let text = flank::text_file::read_utf8(&path).map_err(|e| to_py(py, e, None))?;
        let overrides = overrides_of(overrides)?;
        PyScene::parse(py, path, text, overrides, None)
    }

    /// Parses and validates scene TOML text; `path` names it in errors and
    /// anchors its relative paths (measured profiles).
    #[staticmethod]
    #[pyo3(signature = (text, path=PathBuf::from("<string>.toml"), overrides=None))]
    fn from_string(
        py: Python<'_>,
        text: String,
        path: PathBuf,
        overrides: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyScene> {
        let overrides = overrides_of(overrides)?;
        PyScene::parse(py, path, text, overrides, None)
    }

    /// Sets the dotted key (`pinion.micro.tip_relief_um`,
    /// `analyses.ltca.roll_angles_deg`) and validates the scene again; a
    /// refused value raises SceneError naming the key and leaves the scene
    /// as it was.
    fn set(&mut self, py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let value = to_toml(value)?;
        let mut overrides: Vec<(String, toml::Value)> = self
            .overrides
            .iter()
            .filter(|(k, _)| k != key)
            .cloned()
            .collect();
        overrides.push((key.to_string(), value));
        *self = PyScene::parse(
            py,
            self.path.clone(),
            self.text.clone(),
            overrides,
            Some(key),
        )?;
        Ok(())
    }

    /// The value at the dotted key, as the scene (with its overrides)
    /// writes it (file units: `load.torque_nm` in N·m); KeyError if absent.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let t = self.table()?;
        let mut cur = &toml::Value::Table(t);
        for part in key.split('.') {
            cur = match cur {
                toml::Value::Table(t) => t.get(part),
                toml::Value::Array(a) => part.parse::<usize>().ok().and_then(|i| a.get(i)),
                _ => None,
            }
            .ok_or_else(|| PyKeyError::new_err(key.to_string()))?;
        }
        from_toml(py, cur)
    }

    /// The scene as TOML with the overrides set (what the analyses read).
    fn to_toml(&self) -> PyResult<String> {
        if self.overrides.is_empty() {
            return Ok(self.text.clone());
        }
        toml::to_string(&self.table()?).map_err(|e| FlankError::new_err(e.to_string()))
    }

    /// A copy (the overrides of one do not reach the other).
    fn copy(&self, py: Python<'_>) -> PyResult<PyScene> {
        PyScene::parse(
            py,
            self.path.clone(),
            self.text.clone(),
            self.overrides.clone(),
            None,
        )
    }

    /// The scene file (or the name of a TOML string).
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// `spur`, `helical`, `spiral_bevel` or `hypoid`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.scene.kind.name()
    }

    /// The dotted keys set on the scene, in order.
    #[getter]
    fn overrides<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in &self.overrides {
            d.set_item(k, from_toml(py, v)?)?;
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let mut s = format!("Scene({:?}, kind={:?}", self.path, self.scene.kind.name());
        if !self.overrides.is_empty() {
            let keys: Vec<&str> = self.overrides.iter().map(|(k, _)| k.as_str()).collect();
            s.push_str(&format!(", overrides=[{}]", keys.join(", ")));
        }
        s + ")"
    }
}

/// `flank check`: the pair report as JSON.
#[pyfunction]
fn check(py: Python<'_>, scene: PyRef<'_, PyScene>) -> PyResult<String> {
    let s = &scene.scene;
    let report = released(py, || api::check(s))?;
    json(&report)
}

/// `flank tca`: (summary JSON, warnings).
#[pyfunction]
#[pyo3(signature = (scene, out, *, approach_mm=0.00635, positions_per_pitch=30,
    search_directions=18, offset_error_mm=0.0, pinion_axial_mm=0.0, gear_axial_mm=0.0,
    shaft_angle_error_deg=0.0, sweep_mm=None, quiet=false))]
#[allow(clippy::too_many_arguments)]
fn tca(
    py: Python<'_>,
    scene: PyRef<'_, PyScene>,
    out: PathBuf,
    approach_mm: f64,
    positions_per_pitch: usize,
    search_directions: usize,
    offset_error_mm: f64,
    pinion_axial_mm: f64,
    gear_axial_mm: f64,
    shaft_angle_error_deg: f64,
    sweep_mm: Option<f64>,
    quiet: bool,
) -> PyResult<(String, Vec<String>)> {
    let options = api::TcaOptions {
        out,
        approach_mm,
        positions_per_pitch,
        search_directions,
        misalignment: flank::geometry::gear_pair::Misalignment {
            offset_error_mm,
            pinion_axial_mm,
            gear_axial_mm,
            shaft_angle_error_rad: shaft_angle_error_deg.to_radians(),
            out_of_plane_tilt_rad: 0.0,
        },
        sweep_mm,
        quiet,
    };
    let s = &scene.scene;
    let run = released(py, || api::tca(s, &options))?;
    Ok((json(&run.summary)?, run.warnings.clone()))
}

/// `flank ltca`: the summary JSON.
#[pyfunction]
#[pyo3(signature = (scene, out, *, flank_size=None, base_size=None, element=None,
    roll_angles=None, points_per_line=None, solver=None, local=None, fe_cell_factor=None,
    cache=None, no_condition=false, threads=0, span_approach_mm=None, friction_mu=None,
    increments=None, cross_check=false, friction_model=None, edges=None, flank_region=None,
    compression=None, torques=None, quiet=false, progress=None))]
#[allow(clippy::too_many_arguments)]
fn ltca(
    py: Python<'_>,
    scene: PyRef<'_, PyScene>,
    out: PathBuf,
    flank_size: Option<f64>,
    base_size: Option<f64>,
    element: Option<&str>,
    roll_angles: Option<Vec<f64>>,
    points_per_line: Option<usize>,
    solver: Option<&str>,
    local: Option<&str>,
    fe_cell_factor: Option<f64>,
    cache: Option<PathBuf>,
    no_condition: bool,
    threads: usize,
    span_approach_mm: Option<f64>,
    friction_mu: Option<f64>,
    increments: Option<usize>,
    cross_check: bool,
    friction_model: Option<&str>,
    edges: Option<&str>,
    flank_region: Option<&str>,
    compression: Option<&str>,
    torques: Option<Vec<f64>>,
    quiet: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let options = api::LtcaOptions {
        out,
        mesh: mesh_options(flank_size, base_size, element, false)?,
        roll_angles_deg: roll_angles,
        points_per_line,
        solver: parsed("solver", solver)?,
        local: choice("local", local)?,
        fe_cell_factor,
        cache,
        condition: !no_condition,
        threads,
        quiet,
        friction_mu,
        increments,
        cross_check,
        friction_model: choice("friction_model", friction_model)?,
        flank_region: choice("flank_region", flank_region)?,
        compression: parsed("compression", compression)?,
        span_approach_mm,
        edges: choice("edges", edges)?,
        // a bevel pair's grid: the scene's `[analyses.ltca] positions`, as the CLI
        positions: None,
        // the map over torque (N·m), as `--torques`
        torques_nm: torques,
    };
    let s = &scene.scene;
    let result = released_with(py, progress.as_ref(), || api::ltca(s, &options))?;
    json(&result)
}

/// `flank run`: the summary JSON.
#[pyfunction]
#[pyo3(signature = (scene, out, *, flank_size=None, base_size=None, element=None,
    roll_angles=None, reference_angles=None, law=None, penalty_factor=None, slave=None,
    friction_mu=None, no_vtu=false, decks=false, no_refine=false, threads=0, resume=false,
    quiet=false, progress=None))]
#[allow(clippy::too_many_arguments)]
fn fe_run(
    py: Python<'_>,
    scene: PyRef<'_, PyScene>,
    out: PathBuf,
    flank_size: Option<f64>,
    base_size: Option<f64>,
    element: Option<&str>,
    roll_angles: Option<Vec<f64>>,
    reference_angles: Option<Vec<f64>>,
    law: Option<&str>,
    penalty_factor: Option<f64>,
    slave: Option<&str>,
    friction_mu: Option<f64>,
    no_vtu: bool,
    decks: bool,
    no_refine: bool,
    threads: usize,
    resume: bool,
    quiet: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let options = api::FeOptions {
        out,
        mesh: mesh_options(flank_size, base_size, element, false)?,
        threads,
        roll_angles_deg: roll_angles,
        reference_angles_deg: reference_angles,
        law: choice("law", law)?,
        penalty_factor,
        slave: choice("slave", slave)?,
        friction_mu,
        vtu: no_vtu.then_some(false),
        decks,
        refine_contact_limits: no_refine.then_some(false),
        quiet,
        resume,
    };
    let s = &scene.scene;
    let summary = released_with(py, progress.as_ref(), || api::fe_mesh_cycle(s, &options))?;
    json(&summary)
}

/// `flank compare`: the summary JSON (compare.json).
#[pyfunction]
#[pyo3(signature = (scene, out, *, points_per_line=vec![5, 10, 20, 40],
    fe_flank_sizes=vec![1.0, 0.5], fe_base_size=None, roll_angles=None, roll_step=1.0,
    flank_size=None, base_size=None, element=None, local=None, threads=0, friction_mu=None,
    increments=None, friction_model=None, compression=None, pmax_reference=vec![],
    quiet=false, progress=None))]
#[allow(clippy::too_many_arguments)]
fn compare(
    py: Python<'_>,
    scene: PyRef<'_, PyScene>,
    out: PathBuf,
    points_per_line: Vec<usize>,
    fe_flank_sizes: Vec<f64>,
    fe_base_size: Option<f64>,
    roll_angles: Option<Vec<f64>>,
    roll_step: f64,
    flank_size: Option<f64>,
    base_size: Option<f64>,
    element: Option<&str>,
    local: Option<&str>,
    threads: usize,
    friction_mu: Option<f64>,
    increments: Option<usize>,
    friction_model: Option<&str>,
    compression: Option<&str>,
    pmax_reference: Vec<PathBuf>,
    quiet: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let options = api::CompareOptions {
        out,
        points_per_line,
        fe_flank_sizes,
        fe_base_size,
        roll_angles_deg: roll_angles,
        roll_step_deg: roll_step,
        ltca: api::LtcaOptions {
            mesh: mesh_options(flank_size, base_size, element, false)?,
            local: choice("local", local)?,
            threads,
            quiet: true,
            increments,
            friction_model: choice("friction_model", friction_model)?,
            compression: parsed("compression", compression)?,
            ..Default::default()
        },
        threads,
        quiet,
        friction_mu,
        pmax_reference,
    };
    let s = &scene.scene;
    let summary = released_with(py, progress.as_ref(), || api::compare(s, &options))?;
    json(&summary)
}

/// `flank compliance`: the summary JSON.
#[pyfunction]
#[pyo3(signature = (scene, out, *, flank_size=None, base_size=None, element=None,
    bodies=vec!["pinion".to_string(), "gear".to_string()], method=None, flanks=None,
    flank_region=None, clamp_cuts=false, threads=0, memory_budget_mb=None, block_size=0,
    cache=None, format=None, no_condition=false, no_load=false))]
#[allow(clippy::too_many_arguments)]
fn compliance(
    py: Python<'_>,
    scene: PyRef<'_, PyScene>,
    out: PathBuf,
    flank_size: Option<f64>,
    base_size: Option<f64>,
    element: Option<&str>,
    bodies: Vec<String>,
    method: Option<&str>,
    flanks: Option<&str>,
    flank_region: Option<&str>,
    clamp_cuts: bool,
    threads: usize,
    memory_budget_mb: Option<f64>,
    block_size: usize,
    cache: Option<PathBuf>,
    format: Option<&str>,
    no_condition: bool,
    no_load: bool,
) -> PyResult<String> {
    let options = api::ComplianceOptions {
        out,
        mesh: mesh_options(flank_size, base_size, element, !no_load)?,
        bodies,
        method: choice("method", method)?,
        flanks: choice("flanks", flanks)?,
        clamp_cuts,
        threads,
        memory_budget_mb,
        block_size,
        cache,
        format: choice("format", format)?,
        condition: !no_condition,
        region: choice("flank_region", flank_region)?,
    };
    let s = &scene.scene;
    let summary = released(py, || api::compliance_of(s, &options))?;
    json(&summary)
}

/// A compliance tensor file: a dict of its metadata (JSON), the flank
/// nodes (labels, set index, u–v, positions, normals) and the matrix C
/// (3N × 3N, mm/N) as numpy arrays; the matrix is the file's buffer moved
/// into numpy, not a copy.
#[pyfunction]
fn read_compliance_tensor<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let p: &Path = &path;
    let t = released(py, || api::read_compliance_tensor(p))?;
    let api::ComplianceTensor {
        meta,
        flank,
        matrix,
    } = t;
    let n = flank.labels.len();
    let d = PyDict::new(py);
    d.set_item("meta", json(&meta)?)?;
    d.set_item("sets", flank.sets)?;
    d.set_item("labels", flank.labels.into_pyarray(py))?;
    d.set_item("set_of", flank.set_of.into_pyarray(py))?;
    let flat2: Vec<f64> = flank.uv.iter().flatten().copied().collect();
    d.set_item("uv", flat2.into_pyarray(py).reshape([n, 2])?)?;
    let flat3 = |v: &[[f64; 3]]| -> Vec<f64> { v.iter().flatten().copied().collect() };
    d.set_item(
        "positions",
        flat3(&flank.positions).into_pyarray(py).reshape([n, 3])?,
    )?;
    d.set_item(
        "normals",
        flat3(&flank.normals).into_pyarray(py).reshape([n, 3])?,
    )?;
    let dim = matrix.len().isqrt();
    if dim * dim != matrix.len() {
        return Err(FlankError::new_err(format!(
            "{}: {} matrix values, not a square",
            path.display(),
            matrix.len()
        )));
    }
    // a reshape of the contiguous 1-D array is a view of the same buffer
    d.set_item("matrix", matrix.into_pyarray(py).reshape([dim, dim])?)?;
    Ok(d)
}

/// `flank campaign run`: a dict of the run's report (`jobs`, `skipped`,
/// `finished`, `failed` as (job, log) pairs, `workers`, `wall_s`) and the
/// collected table (`input_keys`, `figure_keys`, `rows` as dicts; the rows
/// of `table.csv`), as JSON.
#[pyfunction]
#[pyo3(signature = (path, exe, *, out=None, workers=None, memory_mb=None, quiet=false,
    progress=None))]
#[allow(clippy::too_many_arguments)]
fn campaign(
    py: Python<'_>,
    path: PathBuf,
    exe: PathBuf,
    out: Option<PathBuf>,
    workers: Option<usize>,
    memory_mb: Option<f64>,
    quiet: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let options = api::CampaignOptions {
        out,
        exe,
        workers,
        memory_mb,
        quiet,
    };
    let p: &Path = &path;
    let run = released_with(py, progress.as_ref(), || api::campaign(p, &options))?;
    let r = &run.report;
    json(&serde_json::json!({
        "report": {
            "jobs": r.jobs,
            "skipped": r.skipped,
            "finished": r.finished,
            "failed": r.failed.iter().map(|(i, log)| (i, log.display().to_string())).collect::<Vec<_>>(),
            "workers": r.workers,
            "wall_s": r.wall_s,
        },
        "input_keys": run.table.input_keys,
        "figure_keys": run.table.figure_keys,
        "rows": table_rows(&run.table),
    }))
}

/// The collected table's rows as JSON objects (the rows of `table.csv`).
fn table_rows(table: &api::CampaignTable) -> Vec<serde_json::Value> {
    table
        .rows
        .iter()
        .map(|row| {
            serde_json::json!({
                "index": row.index,
                "id": row.id,
                "analysis": row.analysis,
                "status": row.status,
                "inputs": serde_json::Map::from_iter(row.inputs.iter().cloned()),
                "figures": serde_json::Map::from_iter(
                    row.figures.iter().map(|(k, x)| (k.clone(), serde_json::json!(x)))
                ),
                "seconds": row.seconds,
            })
        })
        .collect()
}

/// `flank campaign collect`: the table of a campaign's finished jobs
/// (written to its output folder, `out` or the campaign's own), nothing
/// run; JSON as [`campaign`]'s without the report.
#[pyfunction]
#[pyo3(signature = (path, *, out=None))]
fn campaign_collect(py: Python<'_>, path: PathBuf, out: Option<PathBuf>) -> PyResult<String> {
    let p: &Path = &path;
    let o = out.as_deref();
    let table = released(py, || api::campaign_collect(p, o))?;
    json(&serde_json::json!({
        "input_keys": table.input_keys,
        "figure_keys": table.figure_keys,
        "rows": table_rows(&table),
    }))
}

/// `flank blank`: the ISO 23509 blank design of an input set (JSON text,
/// the key names of Annex F) as its outputs (JSON: Annex F names, mm and
/// degrees).
#[pyfunction]
fn blank(py: Python<'_>, inputs: String) -> PyResult<String> {
    let text: &str = &inputs;
    let design = released(py, || api::blank(text))?;
    json(&design.outputs())
}

/// The grid convergence index from three grids ([`flank::grid_convergence::gci`],
/// Celik et al. 2008): sizes `h` fine → coarse, results `phi`, safety
/// factor `fs`; the estimate as JSON, or ValueError saying why none was made.
#[pyfunction]
#[pyo3(signature = (h, phi, fs=1.25))]
fn grid_convergence(h: [f64; 3], phi: [f64; 3], fs: f64) -> PyResult<String> {
    match flank::grid_convergence::gci(h, phi, fs) {
        Ok(g) => json(&g),
        Err(issue) => Err(PyValueError::new_err(format!("no GCI: {issue}"))),
    }
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SCHEMA_VERSION", api::SCHEMA_VERSION)?;
    m.add("FlankError", py.get_type::<FlankError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add_class::<PyScene>()?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(tca, m)?)?;
    m.add_function(wrap_pyfunction!(ltca, m)?)?;
    m.add_function(wrap_pyfunction!(fe_run, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(compliance, m)?)?;
    m.add_function(wrap_pyfunction!(read_compliance_tensor, m)?)?;
    m.add_function(wrap_pyfunction!(campaign, m)?)?;
    m.add_function(wrap_pyfunction!(campaign_collect, m)?)?;
    m.add_function(wrap_pyfunction!(blank, m)?)?;
    m.add_function(wrap_pyfunction!(grid_convergence, m)?)?;
    Ok(())
}
