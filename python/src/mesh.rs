//! `TriangleMesh`: Penumbra's triangle BVH for tracing rays from Python,
//! the batch call that the benchmark harness times against Embree's.

use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use penumbra::accel::{TriHit, TriangleBvh};
use penumbra::math::{Ray, Vec3};

/// Most triangles a mesh may hold: the BVH numbers its packets of four in
/// 28 bits.
const MAX_TRIANGLES: usize = 1 << 29;

/// Triangles in Penumbra's BVH, to trace batches of rays against.
///
/// `TriangleMesh(vertices, faces)` takes float vertices of shape (V, 3) and
/// integer faces of shape (F, 3) indexing them; `TriangleMesh(triangles)`
/// takes one float array of shape (N, 3, 3). The BVH is built at once (on
/// all cores). Rays are traced on the calling thread with the GIL released,
/// eight at a time with their traversals interleaved; the hits are those of
/// the watertight test the renderer uses, and do not depend on batch size
/// or order.
#[pyclass(frozen, module = "penumbra")]
pub struct TriangleMesh {
    bvh: TriangleBvh,
}

fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// `a` as a contiguous array of `dtype` with `cols` columns (any leading
/// shape), flattened.
fn rows<T: numpy::Element + Copy>(
    a: &Bound<'_, PyAny>,
    dtype: &str,
    cols: usize,
    what: &str,
) -> PyResult<(Vec<T>, Vec<usize>)> {
    let np = a.py().import("numpy")?;
    let arr = np
        .call_method1("ascontiguousarray", (a, dtype))
        .map_err(|e| value_error(format!("{what}: {e}")))?;
    let arr = arr
        .cast_into::<numpy::PyArrayDyn<T>>()
        .map_err(|_| value_error(format!("{what}: not a numeric array")))?;
    let shape = arr.shape().to_vec();
    if shape.last() != Some(&cols) {
        return Err(value_error(format!(
            "{what} must have shape (..., {cols}), got {shape:?}"
        )));
    }
    let data = arr.readonly();
    let flat = data.as_slice().map_err(|e| value_error(e.to_string()))?;
    Ok((flat.to_vec(), shape))
}

fn vec3s(flat: &[f32]) -> Vec<Vec3> {
    flat.chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect()
}

/// The triangles of `TriangleMesh(vertices, faces)` or `TriangleMesh(triangles)`.
fn triangles(
    vertices: &Bound<'_, PyAny>,
    faces: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<[Vec3; 3]>> {
    let (flat, shape) = rows::<f32>(vertices, "float32", 3, "vertices")?;
    if flat.iter().any(|x| !x.is_finite()) {
        return Err(value_error("vertices must be finite"));
    }
    let points = vec3s(&flat);
    let tris: Vec<[Vec3; 3]> = match faces {
        None => {
            if shape.len() != 3 || shape[1] != 3 {
                return Err(value_error(format!(
                    "without faces, vertices must be triangles of shape (N, 3, 3), got {shape:?}"
                )));
            }
            points.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
        Some(f) => {
            if shape.len() != 2 {
                return Err(value_error(format!(
                    "with faces, vertices must have shape (V, 3), got {shape:?}"
                )));
            }
            let (idx, fshape) = rows::<i64>(f, "int64", 3, "faces")?;
            if fshape.len() != 2 {
                return Err(value_error(format!(
                    "faces must have shape (F, 3), got {fshape:?}"
                )));
            }
            if let Some((k, &i)) = idx
                .iter()
                .enumerate()
                .find(|(_, &i)| i < 0 || i as usize >= points.len())
            {
                return Err(value_error(format!(
                    "faces[{}, {}] = {i} is not a vertex index (0..{})",
                    k / 3,
                    k % 3,
                    points.len()
                )));
            }
            idx.chunks_exact(3)
                .map(|f| [0, 1, 2].map(|k| points[f[k] as usize]))
                .collect()
        }
    };
    if tris.len() > MAX_TRIANGLES {
        return Err(value_error(format!(
            "{} triangles; at most {MAX_TRIANGLES}",
            tris.len()
        )));
    }
    Ok(tris)
}

/// The rays and per-ray `tmax` of a query, checked.
fn query(
    origins: &Bound<'_, PyAny>,
    directions: &Bound<'_, PyAny>,
    tmin: f32,
    tmax: &Bound<'_, PyAny>,
) -> PyResult<(Vec<Ray>, Vec<f32>)> {
    let (o, oshape) = rows::<f32>(origins, "float32", 3, "origins")?;
    let (d, dshape) = rows::<f32>(directions, "float32", 3, "directions")?;
    if oshape.len() != 2 || oshape != dshape {
        return Err(value_error(format!(
            "origins and directions must both have shape (N, 3), got {oshape:?} and {dshape:?}"
        )));
    }
    let n = oshape[0];
    if !tmin.is_finite() || tmin < 0.0 {
        return Err(value_error(format!(
            "tmin must be finite and >= 0, got {tmin}"
        )));
    }
    let np = tmax.py().import("numpy")?;
    let limits = np
        .call_method1("broadcast_to", (tmax, (n,)))
        .map_err(|e| value_error(format!("tmax must be a number or have shape (N,): {e}")))?;
    let (limits, _) = rows::<f32>(
        &np.call_method1("reshape", (limits, (n, 1)))?,
        "float32",
        1,
        "tmax",
    )?;
    if limits.iter().any(|t| t.is_nan()) {
        return Err(value_error("tmax must not be NaN"));
    }
    let rays = vec3s(&o)
        .into_iter()
        .zip(vec3s(&d))
        .map(|(o, d)| Ray::new(o, d, 0.0))
        .collect();
    Ok((rays, limits))
}

#[pymethods]
impl TriangleMesh {
    #[new]
    #[pyo3(signature = (vertices, faces=None))]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let tris = triangles(vertices, faces)?;
        let bvh = py.detach(|| TriangleBvh::build(tris.len(), |i| tris[i]));
        Ok(TriangleMesh { bvh })
    }

    /// Number of triangles.
    fn __len__(&self) -> usize {
        self.bvh.len()
    }

    /// The closest hit of every ray `origins[i] + t * directions[i]` with
    /// `tmin < t < tmax` (a number, or one per ray). Returns a dict of arrays
    /// of length N: `t` (float32, inf for a miss), `prim` (int64, the
    /// triangle's index, -1 for a miss), `u` and `v` (float32 barycentric
    /// weights of the triangle's second and third vertices). Directions need
    /// not be unit length (`t` is in their units); a ray with a non-finite
    /// origin or direction hits nothing.
    #[pyo3(signature = (origins, directions, tmin=0.0, tmax=None))]
    fn intersect<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tmin: f32,
        tmax: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let inf = f32::INFINITY.into_pyobject(py)?.into_any();
        let (rays, limits) = query(origins, directions, tmin, tmax.unwrap_or(&inf))?;
        let hits = py.detach(|| {
            let mut out = Vec::new();
            self.bvh.closest_hit_each(&rays, tmin, &limits, &mut out);
            out
        });
        let col = |f: fn(&TriHit) -> f32, miss: f32| -> Vec<f32> {
            hits.iter().map(|h| h.as_ref().map_or(miss, f)).collect()
        };
        let prim: Vec<i64> = hits
            .iter()
            .map(|h| h.map_or(-1, |h| i64::from(h.id)))
            .collect();
        let d = PyDict::new(py);
        d.set_item("t", col(|h| h.t, f32::INFINITY).into_pyarray(py))?;
        d.set_item("prim", prim.into_pyarray(py))?;
        d.set_item("u", col(|h| h.b1, 0.0).into_pyarray(py))?;
        d.set_item("v", col(|h| h.b2, 0.0).into_pyarray(py))?;
        Ok(d)
    }

    /// Whether each ray crosses a triangle with `tmin < t < tmax`: a bool
    /// array of length N. Stops at the first triangle found, so it is
    /// cheaper than `intersect` for shadow and visibility rays.
    #[pyo3(signature = (origins, directions, tmin=0.0, tmax=None))]
    fn occluded<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tmin: f32,
        tmax: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let inf = f32::INFINITY.into_pyobject(py)?.into_any();
        let (rays, limits) = query(origins, directions, tmin, tmax.unwrap_or(&inf))?;
        let blocked = py.detach(|| {
            let mut out = Vec::new();
            self.bvh.occluded_each(&rays, tmin, &limits, &mut out);
            out
        });
        Ok(blocked.into_pyarray(py))
    }

    fn __repr__(&self) -> String {
        format!("TriangleMesh({} triangles)", self.bvh.len())
    }
}
