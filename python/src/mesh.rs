//! `TriangleMesh`: Penumbra's triangle BVH for tracing rays from Python,
//! the batch call that the benchmark harness times against Embree's.

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use penumbra::accel::{TriHit, TriangleBvh};
use penumbra::math::{Ray, Vec3};

use crate::options::value_error;

/// Most triangles a mesh may hold: the BVH numbers its packets of (up to)
/// four triangles in 28 bits, and a packet may hold a single triangle.
const MAX_TRIANGLES: usize = (1 << 28) - 1;

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
    flat.chunks_exact(3).map(Vec3::from_slice).collect()
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

/// A float32 array of shape (N, 3) (converted if need be), read.
fn points<'py>(a: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let np = a.py().import("numpy")?;
    let arr = np
        .call_method1("ascontiguousarray", (a, "float32"))
        .map_err(|e| value_error(format!("{what}: {e}")))?;
    let arr = arr
        .cast_into::<PyArray2<f32>>()
        .map_err(|_| value_error(format!("{what} must have shape (N, 3)")))?;
    if arr.shape()[1] != 3 {
        return Err(value_error(format!(
            "{what} must have shape (N, 3), got {:?}",
            arr.shape()
        )));
    }
    Ok(arr)
}

/// The rays and per-ray `tmax` of a query, checked: one pass over the
/// arrays, since a batch may hold millions of rays.
fn query(
    origins: &Bound<'_, PyAny>,
    directions: &Bound<'_, PyAny>,
    tmin: f32,
    tmax: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Vec<Ray>, Vec<f32>)> {
    let (o, d) = (
        points(origins, "origins")?,
        points(directions, "directions")?,
    );
    if o.shape() != d.shape() {
        return Err(value_error(format!(
            "origins and directions must both have shape (N, 3), got {:?} and {:?}",
            o.shape(),
            d.shape()
        )));
    }
    if !tmin.is_finite() || tmin < 0.0 {
        return Err(value_error(format!(
            "tmin must be finite and >= 0, got {tmin}"
        )));
    }
    let n = o.shape()[0];
    let limits = match tmax {
        None => vec![f32::INFINITY; n],
        Some(t) => {
            let np = t.py().import("numpy")?;
            let b = np.call_method1("broadcast_to", (t, (n,))).map_err(|e| {
                value_error(format!("tmax must be a number or have shape (N,): {e}"))
            })?;
            let arr = np.call_method1("ascontiguousarray", (b, "float32"))?;
            let arr = arr
                .cast_into::<PyArray1<f32>>()
                .map_err(|_| value_error("tmax must be a number or have shape (N,)"))?;
            let v = arr.to_vec().map_err(|e| value_error(e.to_string()))?;
            if v.iter().any(|t| t.is_nan()) {
                return Err(value_error("tmax must not be NaN"));
            }
            v
        }
    };
    let (o, d) = (o.readonly(), d.readonly());
    let (o, d) = (
        o.as_slice().map_err(|e| value_error(e.to_string()))?,
        d.as_slice().map_err(|e| value_error(e.to_string()))?,
    );
    let rays = o
        .chunks_exact(3)
        .zip(d.chunks_exact(3))
        .map(|(o, d)| Ray::new(Vec3::from_slice(o), Vec3::from_slice(d), 0.0))
        .collect();
    Ok((rays, limits))
}

/// The columns of `intersect`'s result, in one pass over the hits.
fn columns(hits: &[Option<TriHit>]) -> (Vec<f32>, Vec<i64>, Vec<f32>, Vec<f32>) {
    let n = hits.len();
    let (mut t, mut prim) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut u, mut v) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for h in hits {
        let h = h.unwrap_or(TriHit {
            id: u32::MAX,
            t: f32::INFINITY,
            b1: 0.0,
            b2: 0.0,
        });
        t.push(h.t);
        prim.push(if h.id == u32::MAX {
            -1
        } else {
            i64::from(h.id)
        });
        u.push(h.b1);
        v.push(h.b2);
    }
    (t, prim, u, v)
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
        let (rays, limits) = query(origins, directions, tmin, tmax)?;
        let (t, prim, u, v) = py.detach(|| {
            let mut hits = Vec::new();
            self.bvh.closest_hit_each(&rays, tmin, &limits, &mut hits);
            columns(&hits)
        });
        let d = PyDict::new(py);
        d.set_item("t", t.into_pyarray(py))?;
        d.set_item("prim", prim.into_pyarray(py))?;
        d.set_item("u", u.into_pyarray(py))?;
        d.set_item("v", v.into_pyarray(py))?;
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
        let (rays, limits) = query(origins, directions, tmin, tmax)?;
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
