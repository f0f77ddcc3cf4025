//! Conversions between Python objects, JSON values and images.

use std::ffi::CString;

use numpy::{PyArray1, PyArray3, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Number, Value};

use penumbra::description::mitsuba::dict::DictValue;
use penumbra::input::quote::{bounded, clip, MAX_QUOTED_CHARS};
use penumbra::render::Image;

/// How deep a scene dict may nest; real scenes are four levels deep. The
/// limit turns a self-referencing dict into an error instead of a stack overflow.
const MAX_DEPTH: usize = 32;

/// Options for [`json_to_py`].
#[derive(Clone, Copy, Default)]
pub struct ToPy {
    /// Leave out `null` entries of objects (absent and `None` mean the same in a scene).
    pub drop_nulls: bool,
    /// Numbers are single-precision values widened to f64: show each as the
    /// shortest decimal that converts back to the same f32 (`0.7`, not
    /// `0.699999988079071`).
    pub f32_values: bool,
}

/// A JSON value as plain Python objects (dict, list, str, int, float, bool, None).
pub fn json_to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    json_to_py_with(py, v, ToPy::default())
}

pub fn json_to_py_with<'py>(py: Python<'py>, v: &Value, how: ToPy) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                let f = n.as_f64().unwrap_or(f64::NAN);
                let f = if how.f32_values { shortest_f32(f) } else { f };
                PyFloat::new(py, f).into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| json_to_py_with(py, x, how))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                if how.drop_nulls && x.is_null() {
                    continue;
                }
                d.set_item(k, json_to_py_with(py, x, how)?)?;
            }
            d.into_any()
        }
    })
}

/// The f64 nearest to the shortest decimal of `f as f32`, if that converts
/// back to the same f32 (it always should); else `f` itself, which certainly does.
fn shortest_f32(f: f64) -> f64 {
    let single = f as f32;
    match format!("{single}").parse::<f64>() {
        Ok(p) if (p as f32).to_bits() == single.to_bits() => p,
        _ => f,
    }
}

/// A Python object made of dicts, lists/tuples, str, int, float, bool and
/// None as a JSON value. Anything with a `tolist()` method (numpy arrays and
/// scalars) is converted through it, so vectors may be numpy arrays. `path`
/// names the value in errors, in the scene-error style `objects[1].center`.
pub fn py_to_json(v: &Bound<'_, PyAny>, path: &str, depth: usize) -> PyResult<Value> {
    if depth > MAX_DEPTH {
        return Err(PyValueError::new_err(
            bounded(&format!(
                "{}: nested more than {MAX_DEPTH} levels deep",
                show(path)
            ))
            .into_owned(),
        ));
    }
    if v.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = v.cast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if v.is_instance_of::<PyInt>() {
        if let Ok(i) = v.extract::<i64>() {
            return Ok(Value::from(i));
        }
        if let Ok(u) = v.extract::<u64>() {
            return Ok(Value::from(u));
        }
        return Err(PyValueError::new_err(
            bounded(&format!(
                "{}: integer {} is out of range",
                show(path),
                clip(&v.repr()?.to_string(), MAX_QUOTED_CHARS)
            ))
            .into_owned(),
        ));
    }
    if v.is_instance_of::<PyFloat>() {
        let f: f64 = v.extract()?;
        return Number::from_f64(f).map(Value::Number).ok_or_else(|| {
            PyValueError::new_err(
                bounded(&format!("{}: must be a finite number, got {f}", show(path))).into_owned(),
            )
        });
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(Value::String(s.to_str()?.to_owned()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut m = Map::new();
        for (k, x) in d.iter() {
            let k: String = k.extract().map_err(|_| {
                PyTypeError::new_err(
                    bounded(&format!(
                        "{}: keys must be strings, got {}",
                        show(path),
                        k.repr().map_or_else(
                            |_| "?".into(),
                            |r| clip(&r.to_string(), MAX_QUOTED_CHARS).into_owned()
                        )
                    ))
                    .into_owned(),
                )
            })?;
            let sub = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            m.insert(k, py_to_json(&x, &sub, depth + 1)?);
        }
        return Ok(Value::Object(m));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, x) in v.try_iter()?.enumerate() {
            out.push(py_to_json(&x?, &format!("{path}[{i}]"), depth + 1)?);
        }
        return Ok(Value::Array(out));
    }
    if v.hasattr("tolist")? {
        return py_to_json(&v.call_method0("tolist")?, path, depth + 1);
    }
    let ty = v
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    Err(PyTypeError::new_err(
        bounded(&format!(
            "{}: cannot use a {ty} in a scene (use dict, list, str, int, float, bool or None)",
            show(path)
        ))
        .into_owned(),
    ))
}

/// A dict in Mitsuba's form (`load_dict`'s) as a [`DictValue`], entries in
/// order. Lists, tuples and anything numpy converts (`__array__`: numpy
/// arrays, Mitsuba's points and vectors) are lists; a Mitsuba transform
/// (`ScalarTransform4f`) is its 4×4 `matrix`, a Mitsuba colour
/// (`ScalarColor3f`) an `rgb` dict. A value that cannot be in a scene is a
/// ValueError naming its key path.
pub fn py_to_dict_value(v: &Bound<'_, PyAny>, path: &str, depth: usize) -> PyResult<DictValue> {
    let fail = |message: String| {
        PyValueError::new_err(bounded(&format!("{}: {message}", show(path))).into_owned())
    };
    if depth > MAX_DEPTH {
        return Err(fail(format!("nested more than {MAX_DEPTH} levels deep")));
    }
    if let Ok(b) = v.cast::<PyBool>() {
        return Ok(DictValue::Bool(b.is_true()));
    }
    if v.is_instance_of::<PyInt>() {
        let repr = v.repr()?.to_string();
        return v.extract::<i64>().map(DictValue::Int).map_err(|_| {
            fail(format!(
                "integer {} is out of range",
                clip(&repr, MAX_QUOTED_CHARS)
            ))
        });
    }
    if v.is_instance_of::<PyFloat>() {
        let f: f64 = v.extract()?;
        if !f.is_finite() {
            return Err(fail(format!("must be a finite number, got {f}")));
        }
        return Ok(DictValue::Float(f));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(DictValue::String(s.to_str()?.to_owned()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut entries = Vec::with_capacity(d.len());
        for (k, x) in d.iter() {
            let Ok(k) = k.extract::<String>() else {
                return Err(fail(format!(
                    "keys must be strings, got {}",
                    k.repr().map_or_else(
                        |_| "?".into(),
                        |r| clip(&r.to_string(), MAX_QUOTED_CHARS).into_owned()
                    )
                )));
            };
            let sub = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            let value = py_to_dict_value(&x, &sub, depth + 1)?;
            entries.push((k, value));
        }
        return Ok(DictValue::Dict(entries));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, x) in v.try_iter()?.enumerate() {
            out.push(py_to_dict_value(&x?, &format!("{path}[{i}]"), depth + 1)?);
        }
        return Ok(DictValue::List(out));
    }
    let ty = v
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    let numpy = || v.py().import("numpy");
    if !v.hasattr("__array__")? && v.hasattr("matrix")? {
        return py_to_dict_value(&v.getattr("matrix")?, path, depth + 1);
    }
    if v.hasattr("__array__")? || v.hasattr("tolist")? {
        let plain = match v.hasattr("tolist")? {
            true => v.call_method0("tolist")?,
            false => numpy()?
                .call_method1("asarray", (v,))?
                .call_method0("tolist")?,
        };
        let value = py_to_dict_value(&plain, path, depth + 1)?;
        if ty.contains("Color3f") {
            return Ok(DictValue::Dict(vec![
                ("type".into(), DictValue::String("rgb".into())),
                ("value".into(), value),
            ]));
        }
        return Ok(value);
    }
    if v.is_none() {
        return Err(fail("None is not a value of a scene".into()));
    }
    Err(fail(format!(
        "cannot use a {ty} in a scene (use dict, list, str, int, float, bool, a numpy array \
         or a Mitsuba transform)"
    )))
}

fn show(path: &str) -> &str {
    if path.is_empty() {
        "scene"
    } else {
        path
    }
}

/// An image as a float32 numpy array of shape (height, width, 3).
pub fn image_to_numpy<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (h, w) = (image.height as usize, image.width as usize);
    let Some(extra) = &image.extra else {
        let flat: Vec<f32> = image.pixels.iter().flat_map(|p| p.to_array()).collect();
        return PyArray1::from_vec(py, flat).reshape([h, w, 3]);
    };
    // RGB, then the channels beside it, pixel by pixel.
    let c = extra.names.len();
    let mut flat = Vec::with_capacity(h * w * (3 + c));
    for (p, v) in image.pixels.iter().zip(extra.values.chunks_exact(c.max(1))) {
        flat.extend(p.to_array());
        flat.extend_from_slice(&v[..c]);
    }
    PyArray1::from_vec(py, flat).reshape([h, w, 3 + c])
}

/// The names of an image's channels as [`image_to_numpy`] orders them:
/// `R`, `G`, `B`, then those beside the image (Mitsuba's names); `None`
/// without any beside it.
pub fn channel_names(image: &Image) -> Option<Vec<String>> {
    image.extra.as_ref().map(|e| {
        ["R", "G", "B"]
            .iter()
            .map(|s| s.to_string())
            .chain(e.names.iter().cloned())
            .collect()
    })
}

/// Issues a Python `UserWarning` (the CLI prints `warning: ...` instead).
pub fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    let text = CString::new(message.replace('\0', " "))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 1)
}
