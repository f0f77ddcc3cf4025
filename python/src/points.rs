//! The `points=` keyword: the `custom` distribution's point sets, as a
//! file, an array or a function.
//!
//! * a path (`str` or `os.PathLike`): a JSON or `.npy` file, read by the
//!   library as the command line's `--points` is;
//! * an array of shape `(N, 2)` (one set) or `(S, N, 2)`, or nested lists
//!   of `[x, y]` pairs whose sets may differ in size;
//! * a function `f(n)` returning such an array of sets of `n` points: it is
//!   called once for each set size the render draws from `custom` (with
//!   the GIL held, before the render starts), and its sets make the table.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use penumbra::sampling::PointTable;
use penumbra::scene::Points;

/// A `ValueError`, bounded as every message about input is.
fn value_error(message: String) -> PyErr {
    PyValueError::new_err(penumbra::input::quote::bounded(&message).into_owned())
}

/// What `points=` was given.
pub enum PointsArg {
    /// A file or a table, which the scene's build takes as it is.
    Given(Points),
    /// A function, called once the scene is built and its set sizes known.
    Function(Py<PyAny>),
}

/// Reads the `points=` keyword.
pub fn parse_points(v: &Bound<'_, PyAny>) -> PyResult<PointsArg> {
    if let Ok(path) = v.extract::<PathBuf>() {
        return Ok(PointsArg::Given(Points::File(path)));
    }
    if v.is_callable() {
        return Ok(PointsArg::Function(v.clone().unbind()));
    }
    let table = PointTable::new(sets(v)?).map_err(|e| value_error(format!("points: {e}")))?;
    Ok(PointsArg::Given(Points::Table(Arc::new(table))))
}

/// The table of a function's sets, for each of `sizes`.
pub fn function_table(f: &Bound<'_, PyAny>, sizes: &[u32]) -> PyResult<PointTable> {
    let mut all = Vec::new();
    for &n in sizes {
        let made = f.call1((n,))?;
        for (s, set) in sets(&made)?.into_iter().enumerate() {
            if set.len() != n as usize {
                return Err(value_error(format!(
                    "points: asked for sets of {n} points, the function's set {s} has {}",
                    set.len()
                )));
            }
            all.push(set);
        }
    }
    PointTable::new(all).map_err(|e| value_error(format!("points: {e}")))
}

/// The sets of an array or of nested lists.
fn sets(v: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<[f64; 2]>>> {
    let v = if v.hasattr("tolist")? {
        v.call_method0("tolist")?
    } else {
        v.clone()
    };
    if let Ok(one) = v.extract::<Vec<Vec<f64>>>() {
        return Ok(vec![pairs(0, one)?]);
    }
    if let Ok(many) = v.extract::<Vec<Vec<Vec<f64>>>>() {
        return many
            .into_iter()
            .enumerate()
            .map(|(s, set)| pairs(s, set))
            .collect();
    }
    let ty = v
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    Err(PyTypeError::new_err(format!(
        "points must be a path, an array of shape (N, 2) or (S, N, 2), nested lists of \
         [x, y] pairs, or a function of the set size returning one of those; got {ty}"
    )))
}

/// The `[x, y]` pairs of set `s`.
fn pairs(s: usize, set: Vec<Vec<f64>>) -> PyResult<Vec<[f64; 2]>> {
    set.into_iter()
        .enumerate()
        .map(|(i, p)| match p[..] {
            [x, y] => Ok([x, y]),
            _ => Err(value_error(format!(
                "points: set {s}, point {i}: expected [x, y], found {} numbers",
                p.len()
            ))),
        })
        .collect()
}
