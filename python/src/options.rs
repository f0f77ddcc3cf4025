//! Render options from Python keyword arguments.
//!
//! One parser for `render`, `render_region` and `Scene.settings`, so the
//! three accept exactly the same names and reject bad values with the same
//! messages. The names, kinds and ranges are the library's options table
//! ([`penumbra::scene::OPTIONS`]), the one the command line builds its
//! flags from: a value the CLI refuses is refused here before any work is
//! done, and `None` always means "keep the scene's value".

use std::sync::Arc;

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString, PyTuple};

use penumbra::emitter::choice::LightChoice;
use penumbra::input::quote::{bounded, clip, MAX_QUOTED_CHARS};
use penumbra::sampling::{Distribution, Filter, PathSampler, PointTable};
use penumbra::scene::options::markdown::{default_text, View};
use penumbra::scene::options::{Kind, Value};
use penumbra::scene::{
    Choices, IntegratorChoice, Overrides, Points, RenderOption, StopRule, OPTIONS,
};

use crate::points::{parse_points, PointsArg};

/// The keyword argument that is not a render option: the progress callback.
const PROGRESS: &str = "progress";

/// Every keyword the render functions accept, in the documented order: the
/// table's Python options, then `progress`.
pub fn names() -> Vec<&'static str> {
    let mut names: Vec<&str> = penumbra::scene::options::python_names().collect();
    names.push(PROGRESS);
    names
}

/// Parsed render options.
#[derive(Default)]
pub struct Options {
    /// What replaces the scene's values (the CLI's overrides).
    pub overrides: Overrides,
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// `progress(done_tiles, total_tiles)`, called with the GIL held.
    pub progress: Option<Py<PyAny>>,
    /// `points=` as a function of the set size, called once the scene is
    /// built (see [`crate::points`]).
    pub points_fn: Option<Py<PyAny>>,
}

/// A `ValueError`, its message bounded as every error about input is (a
/// value it quotes is cut to a few dozen characters).
pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(bounded(&message.into()).into_owned())
}

fn type_error(name: &str, expected: &str, got: &Bound<'_, PyAny>) -> PyErr {
    let ty = got
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    PyTypeError::new_err(format!("{name} must be {expected}, got {ty}"))
}

fn python_option(name: &str) -> Option<&'static RenderOption> {
    OPTIONS.iter().find(|o| o.python && o.name == name)
}

/// Parses keyword arguments; `func` names the function in errors about unknown keywords.
pub fn parse_options(func: &str, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Options> {
    let mut choices = Choices::default();
    let mut progress = None;
    let mut points_fn = None;
    for (key, value) in kwargs.into_iter().flat_map(|k| k.iter()) {
        let key: String = key.extract()?;
        let option = python_option(&key);
        if option.is_none() && key != PROGRESS {
            return Err(unknown(func, &key));
        }
        if value.is_none() {
            continue;
        }
        match option {
            Some(o) if o.kind == Kind::File => match parse_points(&value)? {
                PointsArg::Given(points) => choices.overrides.points = Some(points),
                PointsArg::Function(f) => {
                    // An empty table until the function has made the real one.
                    let none = Arc::new(PointTable::NONE);
                    choices.overrides.points = Some(Points::Table(none));
                    points_fn = Some(f);
                }
            },
            Some(o) => o.store(&mut choices, parse_value(o, &value)?),
            None if value.is_callable() => progress = Some(value.unbind()),
            None => {
                return Err(type_error(
                    PROGRESS,
                    "a callable progress(done_tiles, total_tiles) or None",
                    &value,
                ))
            }
        }
    }
    Ok(Options {
        overrides: choices.overrides,
        threads: choices.threads.map(|t| t as usize),
        progress,
        points_fn,
    })
}

/// The `penumbra render` flags of the render options, for `python -m
/// penumbra` to build the same ones: a dict per flag with `name` (the
/// keyword), `flag`, `kind` (`int`, `float`, `bool`, `distribution` or `filter`),
/// `metavar`, `help`, and for a switch `off_flag` and `off_help` (or None).
pub fn flag_table(py: Python<'_>) -> PyResult<Bound<'_, PyTuple>> {
    let mut rows = Vec::new();
    for o in OPTIONS.iter().filter(|o| o.python) {
        let Some(flag) = o.flag else { continue };
        let kind = match o.kind {
            Kind::Int { .. } => "int",
            Kind::NonNegative | Kind::Positive | Kind::Between(..) => "float",
            Kind::StopRule => "stop_rule",
            Kind::Integrator => "integrator",
            Kind::PathSampler => "path_sampler",
            Kind::LightSampler => "light_sampler",
            Kind::Switch => "bool",
            Kind::Distribution => "distribution",
            Kind::Filter => "filter",
            Kind::Colour => continue,
            Kind::File => "path",
        };
        let d = PyDict::new(py);
        d.set_item("name", o.name)?;
        d.set_item("flag", format!("--{}", o.long()))?;
        d.set_item("kind", kind)?;
        d.set_item("metavar", o.metavar())?;
        let default = default_text(o, View::CommandLine);
        d.set_item("help", format!("{} (default: {default})", o.doc))?;
        d.set_item("off_flag", o.long_off().map(|l| format!("--{l}")))?;
        d.set_item("off_help", flag.off)?;
        rows.push(d);
    }
    PyTuple::new(py, rows)
}

/// A keyword's value, checked against its option's kind and range.
fn parse_value(o: &RenderOption, v: &Bound<'_, PyAny>) -> PyResult<Value> {
    let name = o.name;
    Ok(match o.kind {
        Kind::Int { min, max } => Value::Int(ranged_u32(name, v, min, max)?),
        Kind::NonNegative => Value::Number(nonneg_f32(name, v)?),
        Kind::Positive => Value::Number(positive_f32(name, v)?),
        Kind::Switch => Value::Switch(bool_arg(name, v)?),
        Kind::Distribution => Value::Distribution(parse_distribution(name, v)?),
        Kind::Filter => Value::Filter(parse_filter(name, v)?),
        Kind::StopRule => Value::StopRule(parse_stop_rule(name, v)?),
        Kind::Integrator => Value::Integrator(parse_integrator(name, v)?),
        Kind::PathSampler => Value::PathSampler(parse_path_sampler(name, v)?),
        Kind::LightSampler => Value::LightSampler(parse_light_sampler(name, v)?),
        Kind::Between(lo, hi) => Value::Number(between_f32(name, v, lo, hi)?),
        Kind::Colour => {
            return Err(PyTypeError::new_err(format!(
                "{name} is set in the scene, not as a render option"
            )))
        }
        Kind::File => {
            return Err(PyTypeError::new_err(format!(
                "{name} is read by parse_points"
            )))
        }
    })
}

fn unknown(func: &str, key: &str) -> PyErr {
    PyTypeError::new_err(format!(
        "{func}() got an unexpected keyword argument '{}' (render options are: {})",
        clip(key, MAX_QUOTED_CHARS),
        names().join(", ")
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
            v.repr().map_or_else(
                |_| "?".to_string(),
                |r| clip(&r.to_string(), MAX_QUOTED_CHARS).into_owned()
            )
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

fn between_f32(name: &str, v: &Bound<'_, PyAny>, lo: f32, hi: f32) -> PyResult<f32> {
    let f = finite_f32(name, v)?;
    if (lo..=hi).contains(&f) {
        Ok(f)
    } else {
        Err(value_error(format!(
            "{name} must be a number from {lo} to {hi}, got {f}"
        )))
    }
}

/// A distribution by name, with the CLI's message for an unknown one.
pub fn parse_distribution(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Distribution> {
    let from = Distribution::from_name;
    by_name(
        name,
        "distribution",
        v,
        from,
        &Distribution::SELECTABLE,
        Distribution::name,
    )
}

/// An adaptive sampling rule by name, with the CLI's message for an unknown one.
pub fn parse_stop_rule(name: &str, v: &Bound<'_, PyAny>) -> PyResult<StopRule> {
    let from = StopRule::from_name;
    by_name(name, "stop rule", v, from, &StopRule::ALL, StopRule::name)
}

/// An integrator by name, with the CLI's message for an unknown one.
pub fn parse_integrator(name: &str, v: &Bound<'_, PyAny>) -> PyResult<IntegratorChoice> {
    let from = IntegratorChoice::from_name;
    by_name(
        name,
        "integrator",
        v,
        from,
        &IntegratorChoice::ALL,
        IntegratorChoice::name,
    )
}

/// A path sampler by name, with the CLI's message for an unknown one.
pub fn parse_path_sampler(name: &str, v: &Bound<'_, PyAny>) -> PyResult<PathSampler> {
    let from = PathSampler::from_name;
    by_name(
        name,
        "path sampler",
        v,
        from,
        &PathSampler::ALL,
        PathSampler::name,
    )
}

/// A light sampler by name, with the CLI's message for an unknown one.
pub fn parse_light_sampler(name: &str, v: &Bound<'_, PyAny>) -> PyResult<LightChoice> {
    let from = LightChoice::from_name;
    by_name(
        name,
        "light sampler",
        v,
        from,
        &LightChoice::ALL,
        LightChoice::name,
    )
}

/// A pixel filter by name, with the CLI's message for an unknown one.
pub fn parse_filter(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Filter> {
    by_name(
        name,
        "filter",
        v,
        Filter::from_name,
        &Filter::ALL,
        Filter::name,
    )
}

/// The `what` (a distribution, a filter) that keyword `name` names.
fn by_name<T: Copy>(
    name: &str,
    what: &str,
    v: &Bound<'_, PyAny>,
    from: fn(&str) -> Option<T>,
    all: &[T],
    label: fn(T) -> &'static str,
) -> PyResult<T> {
    let s = v
        .cast::<PyString>()
        .map_err(|_| type_error(name, &format!("a {what} name (str)"), v))?
        .to_str()?
        .to_owned();
    from(&s).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&x| label(x)).collect();
        value_error(format!(
            "{name}: unknown {what} `{s}`; valid choices are: {}",
            names.join(", ")
        ))
    })
}
