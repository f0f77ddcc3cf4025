//! Brute-force intersection over all primitives: the oracle that the tests
//! of the trees (and of anything built on them) compare against. A test
//! calls the very same primitive routine through both and can demand
//! bit-identical distances.

use crate::math::Ray;

/// Closest hit among primitives `0..n`, testing each in index order with the
/// closest distance so far as `tmax`. The ray and `tmin` are taken for
/// symmetry with the trees' queries: the closure applies them itself.
pub fn brute_closest(
    n: usize,
    _ray: &Ray,
    _tmin: f32,
    mut tmax: f32,
    mut hit: impl FnMut(u32, f32) -> Option<f32>,
) -> Option<(u32, f32)> {
    let mut best = None;
    for prim in 0..n as u32 {
        if let Some(t) = hit(prim, tmax) {
            tmax = t;
            best = Some((prim, t));
        }
    }
    best
}

/// Whether any primitive of `0..n` is hit, stopping at the first.
pub fn brute_any(
    n: usize,
    _ray: &Ray,
    _tmin: f32,
    tmax: f32,
    mut hit: impl FnMut(u32, f32) -> bool,
) -> bool {
    (0..n as u32).any(|prim| hit(prim, tmax))
}
