//! `photon_render._photon`: the Python face of the Photon library. Every render goes through
//! `photon::render_job::RenderJob`, the call the command line makes, so `photon_render.render`
//! and `photon render` give the same image for the same settings, bit for bit.
//!
//! Rendering runs on a worker thread with the GIL released; the calling thread wakes every
//! 50 ms to let Python handle signals, and a KeyboardInterrupt sets the render's cancel flag
//! (checked between tiles and rows), waits for the worker to stop, and is raised.

use numpy::{IntoPyArray, PyArray1, PyArrayMethods};
use photon::description::Loaded;
use photon::film::Image;
use photon::io::checkpoint::RunInfo;
use photon::photon::{MapKind, PhotonConfig};
use photon::progressive::ProgressiveState;
use photon::render_job::RenderJob;
use photon::session::{Budget, CheckpointPlan, Ending, Session};
use photon::settings::RenderOptions;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

pyo3::create_exception!(
    photon_render,
    PhotonError,
    PyValueError,
    "A scene, setting or file Photon cannot use; the message names the file, line and column where it can."
);

/// A library error as a `PhotonError`; a setting's is told as the keyword argument.
fn to_py(e: photon::Error) -> PyErr {
    match e {
        photon::Error::Setting(s) => PhotonError::new_err(match &s.value {
            _ if s.name.is_empty() => s.problem,
            Some(v) => format!("{}={v}: {}", s.name, s.problem),
            None => format!("{}: {}", s.name, s.problem),
        }),
        e => PhotonError::new_err(e.to_string()),
    }
}

/// Run `work` on a worker thread with the GIL released, cancelling it on KeyboardInterrupt.
fn run_cancellable<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> photon::Result<T> + Send,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    let finished = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let handle = s.spawn(|| {
            let result = work(&cancel);
            *finished.0.lock().unwrap_or_else(|e| e.into_inner()) = true;
            finished.1.notify_all();
            result
        });
        // Wake for signals every 50 ms, or as soon as the work ends.
        let wait = || {
            let done = finished.0.lock().unwrap_or_else(|e| e.into_inner());
            let (done, _) = finished
                .1
                .wait_timeout_while(done, Duration::from_millis(50), |d| !*d)
                .unwrap_or_else(|e| e.into_inner());
            *done
        };
        while !py.detach(wait) {
            if let Err(interrupt) = py.check_signals() {
                cancel.store(true, Ordering::SeqCst);
                let _ = py.detach(|| handle.join());
                return Err(interrupt);
            }
        }
        handle
            .join()
            .map_err(|_| PyRuntimeError::new_err("the render thread panicked"))?
            .map_err(to_py)
    })
}

/// A whole number argument `name` in `0..=max`, or a `PhotonError` that names it (a
/// negative or huge Python int is not an `OverflowError`).
fn whole<T: TryFrom<i64>>(name: &str, v: &Bound<'_, PyAny>, max: i64) -> PyResult<T> {
    let bad = || {
        PhotonError::new_err(format!(
            "{name}={v}: expected a whole number from 0 to {max}"
        ))
    };
    if v.cast::<pyo3::types::PyBool>().is_ok() {
        return Err(bad());
    }
    let n = v.extract::<i64>().map_err(|_| bad())?;
    if !(0..=max).contains(&n) {
        return Err(bad());
    }
    T::try_from(n).map_err(|_| bad())
}

/// The `threads` argument: `None` or 0 is one per core.
fn threads_arg(threads: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    threads
        .filter(|t| !t.is_none())
        .map(|t| whole("threads", t, 256))
        .transpose()
}

fn pool(threads: Option<usize>) -> PyResult<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start worker threads: {e}")))
}

/// A Python value as JSON, for the options' serde names and types. NaN and infinities are
/// refused (JSON has none: they would read as "not given").
fn to_json(name: &str, v: &Bound<'_, PyAny>) -> PyResult<serde_json::Value> {
    use serde_json::Value;
    if v.is_none() {
        Ok(Value::Null)
    } else if let Ok(b) = v.cast::<pyo3::types::PyBool>() {
        Ok(Value::Bool(b.is_true()))
    } else if let Ok(i) = v.extract::<i64>() {
        Ok(Value::from(i))
    } else if let Ok(f) = v.extract::<f64>() {
        if !f.is_finite() {
            return Err(PhotonError::new_err(format!(
                "{name}={f}: must be a finite number"
            )));
        }
        Ok(Value::from(f))
    } else if let Ok(s) = v.extract::<String>() {
        Ok(Value::String(s))
    } else if let Ok(t) = v.cast::<PyTuple>() {
        t.iter()
            .map(|x| to_json(name, &x))
            .collect::<PyResult<_>>()
            .map(Value::Array)
    } else if let Ok(l) = v.cast::<PyList>() {
        l.iter()
            .map(|x| to_json(name, &x))
            .collect::<PyResult<_>>()
            .map(Value::Array)
    } else {
        Err(PhotonError::new_err(format!(
            "cannot use {} as a render option",
            v.get_type().name()?
        )))
    }
}

/// Keyword arguments as render options: each a setting of `photon::settings::SETTINGS`, by
/// the name a scene's `[render]` table gives it.
fn options(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<RenderOptions> {
    let mut options = RenderOptions::default();
    if let Some(kw) = kwargs {
        for (k, v) in kw.iter() {
            let k = k.extract::<String>()?;
            let value = to_json(&k, &v)?;
            options
                .set_json(&k, value)
                .map_err(|e| to_py(photon::Error::Setting(e)))?;
        }
    }
    Ok(options)
}

/// An image as a float32 array of shape (height, width, 3), linear RGB.
fn image_array<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = image.pixels.iter().flat_map(|p| p.to_array()).collect();
    let shape = [image.height as usize, image.width as usize, 3];
    Ok(flat.into_pyarray(py).reshape(shape)?.into_any())
}

/// A scene, loaded from a built-in name, a .toml, .gltf or .glb file.
#[pyclass(frozen, module = "photon_render")]
struct Scene {
    inner: Arc<photon::scene::Scene>,
    spec: RenderOptions,
    desc: photon::description::SceneDesc,
    warnings: Vec<String>,
}

#[pymethods]
impl Scene {
    /// The scene's name (a file's absolute path, or the built-in's name).
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// The resolution the scene asks for: (width, height).
    #[getter]
    fn resolution(&self) -> (u32, u32) {
        self.inner.default_resolution
    }

    /// What the importer could not map (glTF), one message per kind.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The scene as a TOML scene file; relative paths are written against `directory`.
    #[pyo3(signature = (directory = None))]
    fn to_toml(&self, directory: Option<PathBuf>) -> PyResult<String> {
        let dir = directory.unwrap_or_else(|| PathBuf::from("."));
        photon::description::toml_write::to_toml(&self.desc, &dir).map_err(to_py)
    }

    fn __repr__(&self) -> String {
        let (w, h) = self.inner.default_resolution;
        format!(
            "<photon.Scene '{}' {w}×{h}, {} primitives>",
            self.inner.name,
            self.inner.primitive_count()
        )
    }
}

/// Load a scene: a built-in name (see `photon scenes`), or a .toml, .gltf or .glb file.
#[pyfunction]
fn load_scene(py: Python<'_>, name_or_path: PathBuf) -> PyResult<Scene> {
    let name = name_or_path.to_string_lossy().into_owned();
    let (scene, loaded): (photon::scene::Scene, Loaded) =
        run_cancellable(py, |_| photon::description::load_scene(&name))?;
    Ok(Scene {
        inner: Arc::new(scene),
        spec: loaded.desc.render.clone(),
        desc: loaded.desc,
        warnings: loaded.warnings,
    })
}

/// Render `scene` as `photon render` would. Each keyword is a render setting of
/// `photon::settings::SETTINGS`, by its `[render]` name (`photon render`'s flag with `_`).
/// Returns (image, aovs): a float32 array (height, width, 3) and a dict of AOV arrays
/// (direct, caustic, indirect, albedo, normal; empty for the progressive integrators).
#[pyfunction]
#[pyo3(signature = (scene, *, threads = None, **kwargs))]
fn render<'py>(
    py: Python<'py>,
    scene: &Scene,
    threads: Option<&Bound<'py, PyAny>>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    let options = options(kwargs)?;
    let pool = pool(threads_arg(threads)?)?;
    let inner = scene.inner.clone();
    let spec = scene.spec.clone();
    let result = run_cancellable(py, move |cancel| {
        let job = RenderJob::new(&inner, &spec, options)?;
        pool.install(|| job.render(&|_| {}, cancel))
    })?;
    let aovs = PyDict::new(py);
    if let Some(out) = &result.output {
        for (name, image) in [
            ("direct", &out.aovs.direct),
            ("caustic", &out.aovs.caustic),
            ("indirect", &out.aovs.indirect),
            ("albedo", &out.aovs.albedo),
            ("normal", &out.aovs.normal),
        ] {
            aovs.set_item(name, image_array(py, image)?)?;
        }
    }
    Ok((image_array(py, &result.image)?, aovs))
}

/// A progressive render (sppm, ppm or the vcm family) as an iterator of images, one after each pass, driven
/// by the library's `Session`: the budget (passes, time), checkpoints and resume are the
/// command line's. A KeyboardInterrupt abandons the pass in flight and saves the checkpoint
/// (if the run has one); iterating again continues from the completed passes. When the budget
/// is spent the checkpoint is removed, unless it is kept.
#[pyclass(module = "photon_render")]
struct Progressive {
    scene: Arc<photon::scene::Scene>,
    /// `None` once the budget is spent.
    session: Option<Session>,
    /// The last state, kept after the session ends.
    finished: Option<ProgressiveState>,
    pool: Arc<rayon::ThreadPool>,
}

impl Progressive {
    fn state(&self) -> &ProgressiveState {
        match (&self.session, &self.finished) {
            (Some(s), _) => s.state(),
            (None, Some(state)) => state,
            (None, None) => unreachable!("a run holds a session or its final state"),
        }
    }
}

#[pymethods]
impl Progressive {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(session) = self.session.as_mut() else {
            return Ok(None);
        };
        if session.is_done() {
            let session = self.session.take().expect("checked above");
            self.finished = Some(session.finish(Ending::Finished).map_err(to_py)?);
            return Ok(None);
        }
        let (scene, pool) = (self.scene.clone(), self.pool.clone());
        let ran = run_cancellable(py, |cancel| {
            pool.install(|| session.next_pass(&scene, cancel))
        });
        if let Err(interrupt) = ran {
            session.save_checkpoint().map_err(to_py)?;
            return Err(interrupt);
        }
        image_array(py, &session.state().image()).map(Some)
    }

    /// Passes done so far (counting those of the checkpoint a resumed run started from).
    #[getter]
    fn passes(&self) -> u64 {
        self.state().next_pass()
    }

    /// The image of the passes done so far.
    fn image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        image_array(py, &self.state().image())
    }
}

/// The `checkpoint_every` keyword: seconds ≥ 0.
fn checkpoint_cadence(seconds: f64) -> PyResult<Duration> {
    Duration::try_from_secs_f64(seconds).map_err(|_| {
        PhotonError::new_err(format!(
            "checkpoint_every={seconds}: must be a number of seconds ≥ 0"
        ))
    })
}

/// `photon_render.progressive(scene, passes=64, integrator="sppm", ...)`: see the module.
#[pyfunction]
#[pyo3(signature = (scene, *, threads = None, checkpoint = None, checkpoint_every = 30.0, keep_checkpoint = false, **kwargs))]
fn progressive(
    py: Python<'_>,
    scene: &Scene,
    threads: Option<&Bound<'_, PyAny>>,
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    keep_checkpoint: bool,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Progressive> {
    let threads = threads_arg(threads)?;
    let mut options = options(kwargs)?;
    // An iterator of passes: sppm unless the keywords or the scene choose ppm.
    if options.integrator.is_none() && scene.spec.integrator.is_none_or(|k| !k.is_progressive()) {
        options.integrator = Some(photon::settings::IntegratorKind::Sppm);
    }
    if let Some(path) = &checkpoint {
        // Another run's checkpoint is its passes: never replaced by a new run.
        if path.exists() {
            return Err(PhotonError::new_err(format!(
                "'{}' exists: continue it with photon_render.resume(scene, '{0}'), or remove it",
                path.display()
            )));
        }
        photon::io::atomic::check_writable_path(path).map_err(to_py)?;
    }
    let (inner, spec) = (scene.inner.clone(), scene.spec.clone());
    let session = run_cancellable(py, move |_| {
        let job = RenderJob::new(&inner, &spec, options)?;
        if !job.integrator().is_progressive() {
            return Err(photon::Error::InvalidSetting(format!(
                "progressive renders are sppm, ppm, vcm, bdpt or lighttrace, not {}",
                job.integrator().name()
            )));
        }
        job.session()
    })?;
    let every = checkpoint_cadence(checkpoint_every)?;
    let plan = checkpoint.map(|path| CheckpointPlan {
        info: RunInfo {
            target_passes: session.budget().passes,
            ..RunInfo::default()
        },
        path: std::path::absolute(&path).unwrap_or(path),
        every,
        keep: keep_checkpoint,
    });
    Ok(Progressive {
        scene: scene.inner.clone(),
        session: Some(match plan {
            Some(plan) => session.with_checkpoints(plan),
            None => session,
        }),
        finished: None,
        pool: Arc::new(pool(threads)?),
    })
}

/// `photon_render.resume(scene, "run.checkpoint", passes=128)`: go on from a checkpoint of
/// `scene` (the same scene, checked by content), saving to it as before; it is kept.
#[pyfunction]
#[pyo3(signature = (scene, checkpoint, *, passes = None, time = None, threads = None, checkpoint_every = 30.0))]
fn resume(
    py: Python<'_>,
    scene: &Scene,
    checkpoint: PathBuf,
    passes: Option<&Bound<'_, PyAny>>,
    time: Option<f64>,
    threads: Option<&Bound<'_, PyAny>>,
    checkpoint_every: f64,
) -> PyResult<Progressive> {
    let threads = threads_arg(threads)?;
    let passes = passes
        .filter(|p| !p.is_none())
        .map(|p| whole("passes", p, i64::MAX))
        .transpose()?;
    let budget = Budget {
        passes,
        seconds: time,
    };
    let every = checkpoint_cadence(checkpoint_every)?;
    let (session, _) = py
        .detach(|| Session::resume(&checkpoint, budget))
        .map_err(to_py)?;
    if session.state().scene_hash != scene.inner.content_hash() {
        return Err(PhotonError::new_err(format!(
            "'{}' was written for another scene (or another version of '{}'); it cannot be continued with this one",
            checkpoint.display(),
            session.state().scene_name
        )));
    }
    Ok(Progressive {
        scene: scene.inner.clone(),
        session: Some(session.with_checkpoint_every(every)),
        finished: None,
        pool: Arc::new(pool(threads)?),
    })
}

/// `photon_render.job_create("job", "scene.toml", tasks=8, integrator="ppm", passes=64)`: a
/// job folder, as `photon job create` writes it (the scene with every file it reads, the
/// settings, the tasks' ranges). Returns the number of tasks.
#[pyfunction]
#[pyo3(signature = (folder, scene, *, tasks, **kwargs))]
fn job_create(
    py: Python<'_>,
    folder: PathBuf,
    scene: PathBuf,
    tasks: &Bound<'_, PyAny>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<usize> {
    let tasks: u64 = whole("tasks", tasks, i64::from(u32::MAX))?;
    let settings = options(kwargs)?;
    let scene = scene.to_string_lossy().into_owned();
    py.detach(|| {
        let plan = photon::job::plan(&scene, settings, Default::default())?;
        photon::job::create(&folder, &plan, tasks).map(|m| m.tasks.len())
    })
    .map_err(to_py)
}

/// `photon_render.job_run("job", 3)`: render task 3 of a job into its part, as
/// `photon job run` does. Returns "rendered", "already done", "done by another worker", or
/// "busy" (another live worker holds it).
#[pyfunction]
#[pyo3(signature = (folder, task, *, threads = None))]
fn job_run(
    py: Python<'_>,
    folder: PathBuf,
    task: &Bound<'_, PyAny>,
    threads: Option<&Bound<'_, PyAny>>,
) -> PyResult<&'static str> {
    let task: usize = whole("task", task, i64::from(u32::MAX))?;
    let pool = pool(threads_arg(threads)?)?;
    let outcome = run_cancellable(py, |cancel| {
        pool.install(|| photon::job::run_task(&folder, task, cancel))
    })?;
    Ok(match outcome {
        photon::job::TaskOutcome::Rendered { .. } => "rendered",
        photon::job::TaskOutcome::AlreadyDone => "already done",
        photon::job::TaskOutcome::DoneByAnother => "done by another worker",
        photon::job::TaskOutcome::Busy { .. } => "busy",
    })
}

/// `image, info = photon_render.job_merge("job")`: the parts present merged, bit for bit the
/// image of one uninterrupted render once every task is done; `info` has `done`, `tasks`,
/// `units` (passes or samples per pixel merged), `total` and `missing` (task numbers).
#[pyfunction]
fn job_merge<'py>(
    py: Python<'py>,
    folder: PathBuf,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    let (merged, manifest) = py
        .detach(|| {
            let manifest = photon::job::Manifest::load(&folder)?;
            photon::job::merge(&folder).map(|m| (m, manifest))
        })
        .map_err(to_py)?;
    let info = PyDict::new(py);
    info.set_item("done", merged.done)?;
    info.set_item("tasks", manifest.tasks.len())?;
    info.set_item("units", merged.units)?;
    info.set_item("total", manifest.total)?;
    info.set_item("missing", merged.missing)?;
    info.set_item("problems", merged.problems)?;
    Ok((image_array(py, &merged.image)?, info))
}

/// Traced photon maps: `caustic` and `global` maps of photons with NumPy views.
#[pyclass(frozen, module = "photon_render")]
struct PhotonMaps {
    inner: Arc<photon::photon::PhotonMaps>,
}

#[pymethods]
impl PhotonMaps {
    /// The photons of map `kind` ("global" or "caustic") as NumPy arrays: positions (N, 3)
    /// float32, directions (N, 3) float32 (toward where the photon came from), power (N, 3)
    /// float32 in watts, normals (N, 3) float32, depth (N,) uint8 (bounces before storing).
    #[pyo3(signature = (kind = "global"))]
    fn arrays<'py>(&self, py: Python<'py>, kind: &str) -> PyResult<Bound<'py, PyDict>> {
        let kind = match kind {
            "global" => MapKind::Global,
            "caustic" => MapKind::Caustic,
            other => {
                return Err(PhotonError::new_err(format!(
                    "map '{other}': expected 'global' or 'caustic'"
                )));
            }
        };
        let maps = self.inner.clone();
        let (positions, directions, power, normals, depth) = py.detach(move || {
            let map = maps.map(kind);
            let photons = map.photons();
            let n = photons.len();
            let (mut pos, mut dir, mut pow, mut nor) = (
                Vec::with_capacity(3 * n),
                Vec::with_capacity(3 * n),
                Vec::with_capacity(3 * n),
                Vec::with_capacity(3 * n),
            );
            let mut depth = Vec::with_capacity(n);
            for (i, p) in photons.iter().enumerate() {
                pos.extend_from_slice(&p.position);
                dir.extend_from_slice(&p.incoming().to_array());
                pow.extend_from_slice(&map.power(i).to_array());
                nor.extend_from_slice(&p.normal().to_array());
                depth.push(p.depth);
            }
            (pos, dir, pow, nor, depth)
        });
        let n = depth.len();
        let d = PyDict::new(py);
        for (name, v) in [
            ("positions", positions),
            ("directions", directions),
            ("power", power),
            ("normals", normals),
        ] {
            d.set_item(name, v.into_pyarray(py).reshape([n, 3])?)?;
        }
        d.set_item("depth", PyArray1::from_vec(py, depth))?;
        Ok(d)
    }

    /// Photons in each map: {"global": n, "caustic": n}.
    fn __len__(&self) -> usize {
        self.inner.global.len() + self.inner.caustic.len()
    }

    #[getter]
    fn counts(&self) -> (usize, usize) {
        (self.inner.global.len(), self.inner.caustic.len())
    }

    /// Save as a .phm file (what `photon render --photon-map` reads).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let maps = self.inner.clone();
        py.detach(move || photon::io::phm::save(&maps, &path))
            .map_err(to_py)
    }
}

/// Trace photon maps for `scene` as the photon integrator does: `photons` for the global map,
/// `caustic_photons` (at least as many) for the caustic map.
#[pyfunction]
#[pyo3(signature = (scene, *, photons = None, caustic_photons = None, seed = None, per_channel = false, threads = None))]
fn trace_photons(
    py: Python<'_>,
    scene: &Scene,
    photons: Option<&Bound<'_, PyAny>>,
    caustic_photons: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    per_channel: bool,
    threads: Option<&Bound<'_, PyAny>>,
) -> PyResult<PhotonMaps> {
    let given = |v: Option<&Bound<'_, PyAny>>, name: &str| -> PyResult<Option<u64>> {
        v.filter(|v| !v.is_none())
            .map(|v| whole(name, v, i64::MAX))
            .transpose()
    };
    let photons = given(photons, "photons")?.unwrap_or(250_000);
    let caustic_photons = given(caustic_photons, "caustic_photons")?;
    let seed = match seed.filter(|s| !s.is_none()) {
        Some(s) => s.extract::<u64>().map_err(|_| {
            PhotonError::new_err(format!(
                "seed={s}: expected a whole number from 0 to 2**64 - 1"
            ))
        })?,
        None => 0,
    };
    let threads = threads_arg(threads)?;
    let config = PhotonConfig {
        photons: caustic_photons.unwrap_or(photons).max(photons),
        global_photons: Some(photons),
        per_channel,
        seed,
        ..PhotonConfig::default()
    };
    let pool = pool(threads)?;
    let inner = scene.inner.clone();
    let maps = run_cancellable(py, move |_| {
        config.validate()?;
        pool.install(|| photon::photon::trace_photons(&inner, &config, &|_, _| {}))
    })?;
    Ok(PhotonMaps {
        inner: Arc::new(maps),
    })
}

/// Read a .phm file.
#[pyfunction]
fn load_photons(py: Python<'_>, path: PathBuf) -> PyResult<PhotonMaps> {
    let maps = py
        .detach(move || photon::io::phm::load(&path))
        .map_err(to_py)?;
    Ok(PhotonMaps {
        inner: Arc::new(maps),
    })
}

#[pymodule]
fn _photon(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("PhotonError", m.py().get_type::<PhotonError>())?;
    m.add_class::<Scene>()?;
    m.add_class::<PhotonMaps>()?;
    m.add_class::<Progressive>()?;
    m.add_function(wrap_pyfunction!(load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(progressive, m)?)?;
    m.add_function(wrap_pyfunction!(resume, m)?)?;
    m.add_function(wrap_pyfunction!(job_create, m)?)?;
    m.add_function(wrap_pyfunction!(job_run, m)?)?;
    m.add_function(wrap_pyfunction!(job_merge, m)?)?;
    m.add_function(wrap_pyfunction!(trace_photons, m)?)?;
    m.add_function(wrap_pyfunction!(load_photons, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
