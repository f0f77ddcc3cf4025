//! `penumbra._penumbra`: the Rust half of the `penumbra` Python package.
//!
//! The binding is thin on purpose: a scene is the library's own
//! [`SceneDesc`](penumbra::scene::SceneDesc) (one description type, two front
//! ends: TOML and a Python dict), render options become the library's
//! [`Overrides`](penumbra::scene::Overrides), and statistics are the CLI's
//! [`stats_document`](penumbra::render::stats_document). So a Python render
//! and a `penumbra render` with the same options give the same pixels and the
//! same numbers, and every validation message is the CLI's.

mod convert;
mod error;
mod images;
mod mesh;
mod options;
mod points;
mod run;
mod scene;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use numpy::{PyArray3, PyArrayMethods};
use penumbra::render::{stats_document, Checkpointing, Region, RenderOptions};
use pyo3::exceptions::{PyFileNotFoundError, PyTypeError};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use penumbra::sampling::{Distribution, PointTable, Rng};
use penumbra::scene::{read_points, Points};

use crate::convert::{channel_names, image_to_numpy, json_to_py, warn};
use crate::error::SceneError;
use crate::options::{parse_distribution, parse_options, positive_f32, ranged_int, Options};
use crate::scene::Scene;

/// Largest point count `samples` draws, as `penumbra samples --count`.
const MAX_SAMPLES: i64 = 100_000;

/// Renders the whole frame. Returns `(image, stats)`.
///
/// The image is a float32 numpy array of shape (height, width, 3), linear RGB,
/// top row first; the stats are the document `penumbra render --stats`
/// writes. An integrator that writes channels beside the image (`aov`,
/// `moment`) makes it (height, width, 3 + C): RGB, then the channels in
/// Mitsuba's order, their names in `stats["channels"]` (`R`, `G`, `B`
/// first). Options override the scene's values exactly as the command line's
/// do. The GIL is released while rendering; Ctrl-C stops the render and
/// raises KeyboardInterrupt.
///
/// A render may be progressive, as `penumbra render`'s flags of the same
/// names: no tile starts after `time_limit` seconds (the image holds the
/// samples so far and `stats["ended"]` is `"time-limit"`); `checkpoint`
/// names a file the render's state is saved to (atomically) every
/// `checkpoint_interval` seconds, at the end and on Ctrl-C (which then
/// raises KeyboardInterrupt once it is saved); `resume` continues the
/// render saved in a checkpoint to the very pixels an uninterrupted render
/// makes. A checkpoint of another scene, file content, option that changes
/// the pixels or version is refused with a ValueError naming the file and
/// left as it is; one that cannot be read or saved raises OSError.
/// `on_pass(image, info)` is called on this thread after each pass but the
/// last (a render of several passes: `passes`, or an integrator's own),
/// with the image so far (an array as the one returned) and a dict of
/// `pass`, `passes`, `elapsed` (seconds) and `rays` (traced so far).
#[pyfunction]
#[pyo3(
    signature = (scene, *, time_limit = None, checkpoint = None, checkpoint_interval = None, resume = None, on_pass = None, **options),
    text_signature = "(scene, *, integrator=None, width=None, height=None, spp=None, passes=None, shadow_rays=None, \
reflection_rays=None, refraction_rays=None, distribution=None, pixel_distribution=None, \
lens_distribution=None, time_distribution=None, shadow_distribution=None, \
reflection_distribution=None, refraction_distribution=None, points=None, filter=None, filter_radius=None, filter_stddev=None, filter_b=None, filter_c=None, filter_lobes=None, splat=None, filter_steps=None, sample_border=None, alpha=None, aperture=None, \
focal_distance=None, max_depth=None, rr_depth=None, hide_emitters=None, sets_depth=None, path_sampler=None, light_sampler=None, emitter_samples=None, bsdf_samples=None, seed=None, metric=None, reflection_metric=None, \
shadow_metric=None, metric_threshold=None, \
metric_min_rays=None, shadow_metric_rays=None, pixel_metric=None, noise_threshold=None, stop_rule=None, confidence=None, replicas=None, noise_floor=None, min_spp=None, threads=None, progress=None, time_limit=None, checkpoint=None, checkpoint_interval=60.0, resume=None, on_pass=None)"
)]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    time_limit: Option<&Bound<'py, PyAny>>,
    checkpoint: Option<PathBuf>,
    checkpoint_interval: Option<&Bound<'py, PyAny>>,
    resume: Option<PathBuf>,
    on_pass: Option<&Bound<'py, PyAny>>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArray3<f32>>, Bound<'py, PyDict>)> {
    let opts = parse_options("render", options)?;
    let run = RunArgs::parse(time_limit, checkpoint, checkpoint_interval, resume, on_pass)?;
    render_impl(py, scene.get(), &opts, &run, None)
}

/// Renders the pixels `[x0, x1) × [y0, y1)` of the frame. Returns `(image, stats)`.
///
/// Every pixel keeps the value it has in the full frame (pixels are seeded by
/// their frame coordinates), so tiles rendered separately, on any machine,
/// stitch into exactly the full-frame image. The stats count this region's
/// rays only and carry a `region` entry `[x0, y0, x1, y1]`. The progressive
/// arguments are `render`'s; a checkpoint is of the region.
#[pyfunction]
#[pyo3(
    signature = (scene, x0, y0, x1, y1, *, time_limit = None, checkpoint = None, checkpoint_interval = None, resume = None, on_pass = None, **options),
    text_signature = "(scene, x0, y0, x1, y1, *, integrator=None, width=None, height=None, spp=None, passes=None, \
shadow_rays=None, reflection_rays=None, refraction_rays=None, distribution=None, \
pixel_distribution=None, lens_distribution=None, time_distribution=None, \
shadow_distribution=None, reflection_distribution=None, refraction_distribution=None, \
points=None, filter=None, filter_radius=None, filter_stddev=None, filter_b=None, filter_c=None, filter_lobes=None, splat=None, filter_steps=None, sample_border=None, alpha=None, aperture=None, focal_distance=None, max_depth=None, rr_depth=None, hide_emitters=None, sets_depth=None, path_sampler=None, light_sampler=None, emitter_samples=None, bsdf_samples=None, seed=None, metric=None, reflection_metric=None, \
shadow_metric=None, metric_threshold=None, \
metric_min_rays=None, shadow_metric_rays=None, pixel_metric=None, noise_threshold=None, stop_rule=None, confidence=None, replicas=None, noise_floor=None, min_spp=None, threads=None, progress=None, time_limit=None, checkpoint=None, checkpoint_interval=60.0, resume=None, on_pass=None)"
)]
#[allow(clippy::too_many_arguments)]
fn render_region<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    x0: &Bound<'py, PyAny>,
    y0: &Bound<'py, PyAny>,
    x1: &Bound<'py, PyAny>,
    y1: &Bound<'py, PyAny>,
    time_limit: Option<&Bound<'py, PyAny>>,
    checkpoint: Option<PathBuf>,
    checkpoint_interval: Option<&Bound<'py, PyAny>>,
    resume: Option<PathBuf>,
    on_pass: Option<&Bound<'py, PyAny>>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArray3<f32>>, Bound<'py, PyDict>)> {
    let opts = parse_options("render_region", options)?;
    let run = RunArgs::parse(time_limit, checkpoint, checkpoint_interval, resume, on_pass)?;
    let coord = |name: &str, v: &Bound<'py, PyAny>| -> PyResult<u32> {
        let v = ranged_int(name, v, 0, i64::from(u32::MAX))?;
        u32::try_from(v).map_err(|_| options::value_error(format!("{name} is out of range")))
    };
    let region = Region {
        x0: coord("x0", x0)?,
        y0: coord("y0", y0)?,
        x1: coord("x1", x1)?,
        y1: coord("y1", y1)?,
    };
    render_impl(py, scene.get(), &opts, &run, Some(region))
}

/// The arguments of a progressive render: when it ends, what it shows
/// after each pass, where it keeps its state.
struct RunArgs {
    time_limit: Option<Duration>,
    checkpoint: Option<PathBuf>,
    interval: Duration,
    resume: Option<PathBuf>,
    on_pass: Option<Py<PyAny>>,
}

impl RunArgs {
    fn parse(
        time_limit: Option<&Bound<'_, PyAny>>,
        checkpoint: Option<PathBuf>,
        interval: Option<&Bound<'_, PyAny>>,
        resume: Option<PathBuf>,
        on_pass: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<RunArgs> {
        let on_pass = match on_pass.filter(|f| !f.is_none()) {
            Some(f) if !f.is_callable() => {
                return Err(PyTypeError::new_err(
                    "on_pass must be a callable on_pass(image, info) or None",
                ))
            }
            f => f.map(|f| f.clone().unbind()),
        };
        if let Some(path) = resume.as_ref().filter(|p| !p.exists()) {
            return Err(PyFileNotFoundError::new_err(format!(
                "{}: no such checkpoint to resume",
                path.display()
            )));
        }
        if let Some(path) = &checkpoint {
            // Fail now, not after the first interval of rendering.
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                if !dir.is_dir() {
                    return Err(PyFileNotFoundError::new_err(format!(
                        "{}: directory {} does not exist",
                        path.display(),
                        dir.display()
                    )));
                }
            }
        }
        Ok(RunArgs {
            time_limit: time_limit
                .filter(|t| !t.is_none())
                .map(|t| seconds("time_limit", t))
                .transpose()?,
            checkpoint,
            interval: interval
                .filter(|t| !t.is_none())
                .map_or(Ok(Duration::from_secs(60)), |t| {
                    seconds("checkpoint_interval", t)
                })?,
            resume,
            on_pass,
        })
    }
}

/// A positive, finite number of seconds (an int or a float).
fn seconds(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Duration> {
    if v.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a number of seconds, got bool"
        )));
    }
    let s: f64 = v
        .extract()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be a number of seconds")))?;
    if !(s.is_finite() && s > 0.0 && s < 1e12) {
        return Err(options::value_error(format!(
            "{name} must be a positive number of seconds, got {s}"
        )));
    }
    Ok(Duration::from_secs_f64(s))
}

fn render_impl<'py>(
    py: Python<'py>,
    scene: &Scene,
    opts: &Options,
    args: &RunArgs,
    region: Option<Region>,
) -> PyResult<(Bound<'py, PyArray3<f32>>, Bound<'py, PyDict>)> {
    let checkpointing = args.checkpoint.is_some() || args.resume.is_some();
    let (built, digest) = match checkpointing {
        true => {
            let (built, digest) = scene.build_with_digest(py, opts, region)?;
            (built, Some(digest))
        }
        false => (scene.build(py, opts)?, None),
    };
    let s = &built.settings;
    if let Some(r) = region {
        if r.x0 >= r.x1 || r.y0 >= r.y1 || r.x1 > s.width || r.y1 > s.height {
            return Err(options::value_error(format!(
                "region x0={}, y0={}, x1={}, y1={} is empty or outside the {}x{} image \
                 (it needs 0 <= x0 < x1 <= width and 0 <= y0 < y1 <= height)",
                r.x0, r.y0, r.x1, r.y1, s.width, s.height
            )));
        }
    }
    for w in &built.warnings {
        warn(py, w)?;
    }
    let render_opts = RenderOptions {
        threads: opts.threads,
        region,
    };
    let run = run::Run {
        progress: opts.progress.as_ref(),
        on_pass: args.on_pass.as_ref(),
        time_limit: args.time_limit,
        checkpoint: digest.map(|digest| Checkpointing {
            save: args.checkpoint.clone(),
            interval: args.interval,
            resume: args.resume.clone(),
            digest,
        }),
    };
    let (image, stats) = run::render(py, &built, &render_opts, run)?;
    if stats.bad_samples > 0 {
        let first: Vec<String> = stats
            .first_bad_samples
            .iter()
            .map(|b| format!("({}, {}) sample {}", b.x, b.y, b.sample))
            .collect();
        warn(
            py,
            &format!(
                "{} non-finite samples were discarded (pixel, sample): {}",
                stats.bad_samples,
                first.join(", ")
            ),
        )?;
    }
    let mut doc = stats_document(scene.name(), &built, &stats);
    if let (Some(r), Some(map)) = (region, doc.as_object_mut()) {
        map.insert("region".into(), serde_json::json!([r.x0, r.y0, r.x1, r.y1]));
    }
    if let (Some(names), Some(map)) = (channel_names(&image), doc.as_object_mut()) {
        map.insert("channels".into(), serde_json::json!(names));
    }
    let stats = json_to_py(py, &doc)?.cast_into::<PyDict>()?;
    Ok((image_to_numpy(py, &image)?, stats))
}

/// The points of a ray distribution, in the order they are traced.
///
/// Returns a float32 array of shape (count, 2), or (count, 3) for
/// `fast-random` (a cube). The values are exactly those of
/// `penumbra samples --distribution D --count N --radius R --seed S`.
/// `custom` needs `points`: a path, an array or a function, as the render
/// functions' `points=` takes (a function is called with `count`).
#[pyfunction]
#[pyo3(
    signature = (distribution, count, radius = None, seed = None, points = None),
    text_signature = "(distribution, count, radius=1.0, seed=0, points=None)"
)]
fn samples<'py>(
    py: Python<'py>,
    distribution: &Bound<'py, PyAny>,
    count: &Bound<'py, PyAny>,
    radius: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    points: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
    let d: Distribution = parse_distribution("distribution", distribution)?;
    let count = ranged_int("count", count, 1, MAX_SAMPLES)? as usize;
    let radius = radius.map_or(Ok(1.0), |r| positive_f32("radius", r))?;
    let seed = seed.map_or(Ok(0), |s| options::u64_arg("seed", s))?;
    if let Some(w) = d.non_square_warning(count) {
        warn(py, &w)?;
    }
    let table = match points.filter(|p| !p.is_none()) {
        None if d.needs_table() => {
            return Err(options::value_error(
                "the custom distribution draws from your point sets: pass points= \
                 (a path, an array of shape (N, 2) or (S, N, 2), or a function of the set size)",
            ))
        }
        None => Arc::new(PointTable::NONE),
        Some(p) => match points::parse_points(p)? {
            points::PointsArg::Given(Points::Table(t)) => t,
            points::PointsArg::Given(Points::File(path)) => {
                let t = read_points(&path).map_err(|e| options::value_error(e.to_string()))?;
                Arc::new(t)
            }
            points::PointsArg::Function(f) => {
                Arc::new(points::function_table(f.bind(py), &[count as u32])?)
            }
        },
    };
    let mut points = Vec::new();
    d.generate_in(&table, count, radius, &mut Rng::new(seed), &mut points);
    let dims = if d.is_3d() { 3 } else { 2 };
    let flat: Vec<f32> = points
        .iter()
        .flat_map(|p| p.to_array().into_iter().take(dims))
        .collect();
    numpy::PyArray1::from_vec(py, flat).reshape([points.len(), dims])
}

/// Checks render options without rendering (raises TypeError or ValueError
/// as `render` would). Used by `penumbra.distributed` to fail on the client
/// rather than in every task.
#[pyfunction]
#[pyo3(signature = (**options))]
fn _check_options(options: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
    parse_options("render", options).map(|_| ())
}

/// The kernel set (instruction set of the tracing kernels) of scenes loaded
/// from now on, as `penumbra --simd` chooses it: with `name` (`avx512`,
/// `avx2`, `neon`, `portable`), chooses it, raising ValueError for a set
/// this processor lacks. Returns the set's name. Every set gives the same
/// pixels; `SIMD_SETS` lists those this processor supports, widest first.
#[pyfunction]
#[pyo3(signature = (name=None))]
fn kernels(name: Option<&str>) -> PyResult<&'static str> {
    if let Some(name) = name {
        penumbra::simd::set_active_name(name)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    }
    Ok(penumbra::simd::active().name())
}

/// The built-in scenes: `{name: description}`, as `penumbra scenes` lists them.
#[pyfunction]
fn scenes(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for b in penumbra::scene::builtin::SCENES {
        out.set_item(b.name, b.description)?;
    }
    Ok(out)
}

#[pymodule]
fn _penumbra(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add_class::<Scene>()?;
    m.add_class::<mesh::TriangleMesh>()?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_from_dict, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_dict, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(render_region, m)?)?;
    m.add_function(wrap_pyfunction!(samples, m)?)?;
    m.add_function(wrap_pyfunction!(scenes, m)?)?;
    m.add_function(wrap_pyfunction!(kernels, m)?)?;
    let sets: Vec<&str> = penumbra::simd::KernelSet::supported()
        .iter()
        .map(|k| k.name())
        .collect();
    m.add("SIMD_SETS", pyo3::types::PyTuple::new(py, sets)?)?;
    // A $PENUMBRA_SIMD the processor cannot run is said once, at import;
    // the widest set supported is used then.
    if let Err(e) = penumbra::simd::from_env() {
        warn(py, &format!("${}: {e}", penumbra::simd::SIMD_VAR))?;
    }
    m.add_function(wrap_pyfunction!(_check_options, m)?)?;
    m.add_function(wrap_pyfunction!(images::save_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::load_image, m)?)?;
    let names: Vec<&str> = Distribution::SELECTABLE.iter().map(|d| d.name()).collect();
    m.add("DISTRIBUTIONS", pyo3::types::PyTuple::new(py, names)?)?;
    m.add(
        "RENDER_OPTIONS",
        pyo3::types::PyTuple::new(py, options::names())?,
    )?;
    m.add("_OPTION_FLAGS", options::flag_table(py)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
