//! `TriangleMesh`: Penumbra's triangle BVH for tracing rays from Python,
//! the batch call that the benchmark harness times against Embree's.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use penumbra::accel::TriangleBvh;
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
/// all cores). Rays are traced on the calling thread with the GIL released:
/// runs of consecutive rays from one point as packets, the others eight at
/// a time with their traversals interleaved. The hits are those of the
/// watertight test the renderer uses (of equally near triangles the lowest
/// index), and do not depend on batch size or order.
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

/// Rays converted and traced at a time: a batch of millions goes through
/// buffers that stay in the cache, and nothing of its size is allocated
/// but the result arrays. Converting a whole batch first would take 52 bytes per
/// ray of temporary memory (rays, limits, hits): 52 MB for the harness's
/// million rays, and 2% more instructions for camera rays.
const CHUNK: usize = 4096;

/// A checked query: origins and directions of shape (N, 3), and `tmax` as
/// one float32 per ray if given.
struct Query<'py> {
    origins: Bound<'py, PyArray2<f32>>,
    directions: Bound<'py, PyArray2<f32>>,
    tmax: Option<Bound<'py, PyArray1<f32>>>,
}

impl<'py> Query<'py> {
    fn new(
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        tmin: f32,
        tmax: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Self> {
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
        let tmax = match tmax {
            None => None,
            Some(t) => Some(limits(t, o.shape()[0])?),
        };
        Ok(Query {
            origins: o,
            directions: d,
            tmax,
        })
    }

    fn len(&self) -> usize {
        self.origins.shape()[0]
    }

    /// Calls `trace(first, rays, tmax)` for the rays in chunks of at most
    /// [`CHUNK`], `first` the index of a chunk's first ray, with the GIL
    /// released.
    fn trace(
        &self,
        py: Python<'_>,
        mut trace: impl FnMut(usize, &[Ray], &[f32]) + Send,
    ) -> PyResult<()> {
        let (o, d) = (self.origins.readonly(), self.directions.readonly());
        let t = self.tmax.as_ref().map(|t| t.readonly());
        let slice = |e: numpy::AsSliceError| value_error(e.to_string());
        let (o, d) = (o.as_slice().map_err(slice)?, d.as_slice().map_err(slice)?);
        let t = match &t {
            Some(t) => Some(t.as_slice().map_err(slice)?),
            None => None,
        };
        py.detach(|| {
            let (mut rays, infinite) = (Vec::with_capacity(CHUNK), [f32::INFINITY; CHUNK]);
            for (k, (o, d)) in o.chunks(3 * CHUNK).zip(d.chunks(3 * CHUNK)).enumerate() {
                rays.clear();
                rays.extend(
                    o.chunks_exact(3)
                        .zip(d.chunks_exact(3))
                        .map(|(o, d)| Ray::new(Vec3::from_slice(o), Vec3::from_slice(d), 0.0)),
                );
                let first = k * CHUNK;
                let limits = match t {
                    Some(t) => &t[first..first + rays.len()],
                    None => &infinite[..rays.len()],
                };
                trace(first, &rays, limits);
            }
        });
        Ok(())
    }
}

/// `tmax`, a number or one per ray, as a float32 array of `n`, checked.
fn limits<'py>(t: &Bound<'py, PyAny>, n: usize) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let np = t.py().import("numpy")?;
    let b = np
        .call_method1("broadcast_to", (t, (n,)))
        .map_err(|e| value_error(format!("tmax must be a number or have shape (N,): {e}")))?;
    let arr = np.call_method1("ascontiguousarray", (b, "float32"))?;
    let arr = arr
        .cast_into::<PyArray1<f32>>()
        .map_err(|_| value_error("tmax must be a number or have shape (N,)"))?;
    let nan = {
        let view = arr.readonly();
        let v = view.as_slice().map_err(|e| value_error(e.to_string()))?;
        v.iter().any(|t| t.is_nan())
    };
    if nan {
        return Err(value_error("tmax must not be NaN"));
    }
    Ok(arr)
}

/// A writable view of a fresh numpy array's elements.
fn writable<'a, 'py, T: numpy::Element>(
    a: &'a mut numpy::PyReadwriteArray1<'py, T>,
) -> PyResult<&'a mut [T]> {
    a.as_slice_mut().map_err(|e| value_error(e.to_string()))
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
        let q = Query::new(origins, directions, tmin, tmax)?;
        let n = q.len();
        let (t, prim) = (
            PyArray1::<f32>::zeros(py, n, false),
            PyArray1::<i64>::zeros(py, n, false),
        );
        let (u, v) = (
            PyArray1::<f32>::zeros(py, n, false),
            PyArray1::<f32>::zeros(py, n, false),
        );
        {
            let (mut tw, mut pw) = (t.readwrite(), prim.readwrite());
            let (mut uw, mut vw) = (u.readwrite(), v.readwrite());
            let (ts, ps) = (writable(&mut tw)?, writable(&mut pw)?);
            let (us, vs) = (writable(&mut uw)?, writable(&mut vw)?);
            let mut hits = Vec::with_capacity(CHUNK);
            q.trace(py, |first, rays, limits| {
                self.bvh.closest_hit_each(rays, tmin, limits, &mut hits);
                for (i, h) in (first..).zip(&hits) {
                    (ts[i], ps[i]) = h.map_or((f32::INFINITY, -1), |h| (h.t, i64::from(h.id)));
                    (us[i], vs[i]) = h.map_or((0.0, 0.0), |h| (h.b1, h.b2));
                }
            })?;
        }
        let d = PyDict::new(py);
        d.set_item("t", t)?;
        d.set_item("prim", prim)?;
        d.set_item("u", u)?;
        d.set_item("v", v)?;
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
        let q = Query::new(origins, directions, tmin, tmax)?;
        let blocked = PyArray1::<bool>::zeros(py, q.len(), false);
        {
            let mut bw = blocked.readwrite();
            let bs = writable(&mut bw)?;
            let mut out = Vec::with_capacity(CHUNK);
            q.trace(py, |first, rays, limits| {
                self.bvh.occluded_each(rays, tmin, limits, &mut out);
                bs[first..first + out.len()].copy_from_slice(&out);
            })?;
        }
        Ok(blocked)
    }

    fn __repr__(&self) -> String {
        format!("TriangleMesh({} triangles)", self.bvh.len())
    }
}
