//! Render options from Python keyword arguments.
//!
//! One parser for `render`, `render_region` and `Scene.settings`, so the
//! three accept exactly the same names and reject bad values with the same
//! messages. Ranges are the command line's (`penumbra render --help`): a value
//! the CLI refuses is refused here before any work is done, and `None` always
//! means "keep the scene's value".

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};

use penumbra::sampling::Distribution;
use penumbra::scene::Overrides;

/// Every keyword the render functions accept, in the documented order.
pub const NAMES: [&str; 26] = [
    "width",
    "height",
    "spp",
    "shadow_rays",
    "reflection_rays",
    "refraction_rays",
    "distribution",
    "pixel_distribution",
    "lens_distribution",
    "time_distribution",
    "shadow_distribution",
    "reflection_distribution",
    "refraction_distribution",
    "aperture",
    "focal_distance",
    "max_depth",
    "seed",
    "metric",
    "reflection_metric",
    "shadow_metric",
    "metric_threshold",
    "metric_min_rays",
    "shadow_metric_rays",
    "pixel_metric",
    "threads",
    "progress",
];

/// Parsed render options.
#[derive(Default)]
pub struct Options {
    /// What replaces the scene's values (the CLI's overrides).
    pub overrides: Overrides,
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// `progress(done_tiles, total_tiles)`, called with the GIL held.
    pub progress: Option<Py<PyAny>>,
}

pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

fn type_error(name: &str, expected: &str, got: &Bound<'_, PyAny>) -> PyErr {
    let ty = got
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    PyTypeError::new_err(format!("{name} must be {expected}, got {ty}"))
}

/// Parses keyword arguments; `func` names the function in errors about unknown keywords.
pub fn parse_options(func: &str, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Options> {
    let mut o = Options::default();
    let Some(kwargs) = kwargs else {
        return Ok(o);
    };
    for (key, value) in kwargs.iter() {
        let key: String = key.extract()?;
        if value.is_none() {
            if !NAMES.contains(&key.as_str()) {
                return Err(unknown(func, &key));
            }
            continue;
        }
        let v = &value;
        let ov = &mut o.overrides;
        match key.as_str() {
            "width" => ov.width = Some(ranged_u32("width", v, 1, 32768)?),
            "height" => ov.height = Some(ranged_u32("height", v, 1, 32768)?),
            "spp" => ov.spp = Some(ranged_u32("spp", v, 1, 65536)?),
            "shadow_rays" => ov.shadow_rays = Some(ranged_u32("shadow_rays", v, 1, 65536)?),
            "reflection_rays" => {
                ov.reflection_rays = Some(ranged_u32("reflection_rays", v, 1, 65536)?)
            }
            "refraction_rays" => {
                ov.refraction_rays = Some(ranged_u32("refraction_rays", v, 1, 65536)?)
            }
            "distribution" => ov.distribution = Some(parse_distribution(&key, v)?),
            "pixel_distribution" => ov.pixel_distribution = Some(parse_distribution(&key, v)?),
            "lens_distribution" => ov.lens_distribution = Some(parse_distribution(&key, v)?),
            "time_distribution" => ov.time_distribution = Some(parse_distribution(&key, v)?),
            "shadow_distribution" => ov.shadow_distribution = Some(parse_distribution(&key, v)?),
            "reflection_distribution" => {
                ov.reflection_distribution = Some(parse_distribution(&key, v)?)
            }
            "refraction_distribution" => {
                ov.refraction_distribution = Some(parse_distribution(&key, v)?)
            }
            "aperture" => ov.aperture = Some(nonneg_f32("aperture", v)?),
            "focal_distance" => ov.focal_distance = Some(positive_f32("focal_distance", v)?),
            "max_depth" => ov.max_depth = Some(ranged_u32("max_depth", v, 0, 64)?),
            "seed" => ov.seed = Some(ranged_u32("seed", v, 0, u32::MAX)?),
            "metric" => ov.metric = Some(bool_arg("metric", v)?),
            "reflection_metric" => ov.reflection_metric = Some(bool_arg("reflection_metric", v)?),
            "shadow_metric" => ov.shadow_metric = Some(bool_arg("shadow_metric", v)?),
            "metric_threshold" => ov.metric_threshold = Some(nonneg_f32("metric_threshold", v)?),
            "metric_min_rays" => {
                ov.metric_min_rays = Some(ranged_u32("metric_min_rays", v, 1, 65536)?)
            }
            "shadow_metric_rays" => {
                ov.shadow_metric_rays = Some(ranged_u32("shadow_metric_rays", v, 1, 65536)?)
            }
            "pixel_metric" => ov.pixel_metric = Some(bool_arg("pixel_metric", v)?),
            "threads" => o.threads = Some(ranged_u32("threads", v, 1, 1024)? as usize),
            "progress" => {
                if !v.is_callable() {
                    return Err(type_error(
                        "progress",
                        "a callable progress(done_tiles, total_tiles) or None",
                        v,
                    ));
                }
                o.progress = Some(v.clone().unbind());
            }
            _ => return Err(unknown(func, &key)),
        }
    }
    Ok(o)
}

fn unknown(func: &str, key: &str) -> PyErr {
    PyTypeError::new_err(format!(
        "{func}() got an unexpected keyword argument '{key}' (render options are: {})",
        NAMES.join(", ")
    ))
}

/// An integer in `lo..=hi`. Booleans are refused: `spp=True` is a mistake, not 1.
pub fn ranged_int(name: &str, v: &Bound<'_, PyAny>, lo: i64, hi: i64) -> PyResult<i64> {
    if v.is_instance_of::<PyBool>() || !v.is_instance_of::<PyInt>() {
        return Err(type_error(name, "an int", v));
    }
    match v.extract::<i64>() {
        Ok(n) if (lo..=hi).contains(&n) => Ok(n),
        _ => Err(value_error(format!(
            "{name} must be an integer in {lo}..={hi}, got {}",
            v.repr().map_or_else(|_| "?".to_string(), |r| r.to_string())
        ))),
    }
}

fn ranged_u32(name: &str, v: &Bound<'_, PyAny>, lo: u32, hi: u32) -> PyResult<u32> {
    let n = ranged_int(name, v, i64::from(lo), i64::from(hi))?;
    u32::try_from(n).map_err(|_| value_error(format!("{name} is out of range")))
}

/// A switch: only `True` or `False` (not 0/1, which are more likely a mistake).
fn bool_arg(name: &str, v: &Bound<'_, PyAny>) -> PyResult<bool> {
    v.cast::<PyBool>()
        .map(|b| b.is_true())
        .map_err(|_| type_error(name, "a bool", v))
}

/// A seed for `samples`: any integer in `0..2**64`, as the CLI's `--seed`.
pub fn u64_arg(name: &str, v: &Bound<'_, PyAny>) -> PyResult<u64> {
    if v.is_instance_of::<PyBool>() || !v.is_instance_of::<PyInt>() {
        return Err(type_error(name, "an int", v));
    }
    v.extract::<u64>()
        .map_err(|_| value_error(format!("{name} must be an integer in 0..2**64")))
}

fn finite_f32(name: &str, v: &Bound<'_, PyAny>) -> PyResult<f32> {
    let is_number = !v.is_instance_of::<PyBool>()
        && (v.is_instance_of::<PyFloat>() || v.is_instance_of::<PyInt>());
    if !is_number {
        return Err(type_error(name, "a number", v));
    }
    let x: f64 = v.extract()?;
    let f = x as f32;
    if !f.is_finite() {
        return Err(value_error(format!(
            "{name} must be a finite number, got {x}"
        )));
    }
    Ok(f)
}

pub fn positive_f32(name: &str, v: &Bound<'_, PyAny>) -> PyResult<f32> {
    let f = finite_f32(name, v)?;
    if f > 0.0 {
        Ok(f)
    } else {
        Err(value_error(format!(
            "{name} must be a finite number > 0, got {f}"
        )))
    }
}

fn nonneg_f32(name: &str, v: &Bound<'_, PyAny>) -> PyResult<f32> {
    let f = finite_f32(name, v)?;
    if f >= 0.0 {
        Ok(f)
    } else {
        Err(value_error(format!(
            "{name} must be a finite number >= 0, got {f}"
        )))
    }
}

/// A distribution by name, with the CLI's message for an unknown one.
pub fn parse_distribution(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Distribution> {
    let s = v
        .cast::<PyString>()
        .map_err(|_| type_error(name, "a distribution name (str)", v))?
        .to_str()?
        .to_owned();
    Distribution::from_name(&s).ok_or_else(|| {
        let names: Vec<&str> = Distribution::ALL.iter().map(|d| d.name()).collect();
        value_error(format!(
            "{name}: unknown distribution `{s}`; valid choices are: {}",
            names.join(", ")
        ))
    })
}
