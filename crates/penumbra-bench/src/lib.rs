//! Shared pieces of Penumbra's benchmarks: clocks, medians, the ray and
//! triangle files exchanged with the harness in `bench/`, and procedural
//! meshes.
//!
//! # Files
//! Both are headerless little-endian `f32` arrays, written by the harness
//! with numpy so that Embree and Penumbra trace exactly the same numbers:
//!
//! * triangles: 9 floats per triangle (three vertices, x y z each);
//! * rays: 6 floats per ray (origin x y z, direction x y z); every ray is
//!   traced over `(0, inf)`.

use penumbra::math::{Aabb, Ray, Vec3};
use penumbra::sampling::Rng;
use std::path::Path;
use std::time::Instant;

/// On-CPU time of the calling thread in seconds, else wall-clock time
/// since the first call. Timing single-threaded work by the thread's CPU
/// time keeps other load on a shared machine out of the figures. It is
/// read with `clock_gettime`, which brings the count up to date first:
/// `/proc/thread-self/schedstat` advances only at scheduler ticks while a
/// thread computes (every 4 ms here), a tenth of a camera-ray batch.
pub fn thread_time() -> f64 {
    static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    cpu_time::ThreadTime::try_now().map_or_else(
        |_| START.get_or_init(Instant::now).elapsed().as_secs_f64(),
        |t| t.as_duration().as_secs_f64(),
    )
}

/// On-CPU time of the whole process in seconds, user and system, including
/// threads that have ended (`clock_gettime`; `None` where the clock is
/// missing). `/proc/self/stat` counts in 10 ms ticks: ±7% of a Whitted
/// frame's 0.15 CPU-seconds.
pub fn process_time() -> Option<f64> {
    cpu_time::ProcessTime::try_now()
        .ok()
        .map(|t| t.as_duration().as_secs_f64())
}

/// Median of a non-empty sample.
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn read_f32s(path: &Path, group: usize) -> Result<Vec<f32>, String> {
    // The library's bounded reader: a regular file within the size limit.
    let bytes = penumbra::input::read_file(path).map_err(|e| e.to_string())?;
    if bytes.len() % (4 * group) != 0 {
        return Err(format!(
            "{}: {} bytes is not a whole number of {}-float records",
            path.display(),
            bytes.len(),
            group
        ));
    }
    Ok(bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect())
}

/// Reads a triangle file (9 floats per triangle).
pub fn read_triangles(path: &Path) -> Result<Vec<[Vec3; 3]>, String> {
    let f = read_f32s(path, 9)?;
    Ok(f.chunks_exact(9)
        .map(|c| {
            [
                Vec3::new(c[0], c[1], c[2]),
                Vec3::new(c[3], c[4], c[5]),
                Vec3::new(c[6], c[7], c[8]),
            ]
        })
        .collect())
}

/// Reads a ray file (6 floats per ray).
pub fn read_rays(path: &Path) -> Result<Vec<Ray>, String> {
    let f = read_f32s(path, 6)?;
    Ok(f.chunks_exact(6)
        .map(|c| {
            Ray::new(
                Vec3::new(c[0], c[1], c[2]),
                Vec3::new(c[3], c[4], c[5]),
                0.0,
            )
        })
        .collect())
}

/// The radius of the benchmarks' bumpy sphere at polar angle `theta` and
/// azimuth `phi`: about 1, with a radial bump pattern. With
/// [`uv_sphere`](penumbra::geometry::tessellate::uv_sphere), `nu = 1000,
/// nv = 501` gives a million triangles. (Only the radius lives here: the
/// harness builds this crate against older revisions of the library too,
/// which lack the tessellator.)
pub fn bumpy_radius(theta: f32, phi: f32) -> f32 {
    1.0 + 0.08 * (7.0 * theta).sin() * (9.0 * phi).sin() + 0.02 * (31.0 * phi).cos()
}

/// `n` rays from uniformly random points of `b` in uniformly random
/// directions (seeded, so every run traces the same rays): the incoherent
/// rays of the criterion benches.
pub fn random_rays(n: usize, b: &Aabb, seed: u64) -> Vec<Ray> {
    let mut r = Rng::new(seed);
    (0..n)
        .map(|_| {
            let o = Vec3::new(
                r.range(b.min.x, b.max.x),
                r.range(b.min.y, b.max.y),
                r.range(b.min.z, b.max.z),
            );
            let z = r.range(-1.0, 1.0);
            let phi = r.range(0.0, std::f32::consts::TAU);
            let s = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(o, Vec3::new(s * phi.cos(), s * phi.sin(), z), 0.0)
        })
        .collect()
}
