//! Test inputs shared by the BVH tests: random points and directions, and the
//! flat scene whose zero-height boxes and in-plane rays are the hard cases of
//! the slab test.

use crate::math::{Aabb, Ray, Vec3};
use crate::sampling::Rng;

pub type Tri = [Vec3; 3];

pub fn rand_in(r: &mut Rng, b: &Aabb) -> Vec3 {
    Vec3::new(
        r.range(b.min.x, b.max.x),
        r.range(b.min.y, b.max.y),
        r.range(b.min.z, b.max.z),
    )
}

/// A uniform unit direction (rejection from the cube).
pub fn rand_dir(r: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0));
        let l = v.length_squared();
        if l > 1e-4 && l <= 1.0 {
            return v / l.sqrt();
        }
    }
}

/// `n` triangles in the plane y = 0 (flat boxes), every third one standing
/// on it with an edge in the plane.
pub fn flat_triangles(r: &mut Rng, n: usize) -> Vec<Tri> {
    (0..n)
        .map(|i| {
            let a = Vec3::new(r.range(-10.0, 10.0), 0.0, r.range(-10.0, 10.0));
            let b = a + Vec3::new(r.range(-1.0, 1.0), 0.0, r.range(-1.0, 1.0));
            let c = if i % 3 == 0 {
                a + Vec3::new(r.range(-1.0, 1.0), r.range(0.1, 1.0), r.range(-1.0, 1.0))
            } else {
                a + Vec3::new(r.range(-1.0, 1.0), 0.0, r.range(-1.0, 1.0))
            };
            [a, b, c]
        })
        .collect()
}

/// `n` rays along the axes and parallel to the plane y = 0, starting in it
/// (at +0 and -0), just above it and elsewhere, over (0, ∞).
pub fn axis_and_parallel_rays(r: &mut Rng, n: usize) -> Vec<(Ray, f32, f32)> {
    let dirs = [
        Vec3::X,
        -Vec3::X,
        Vec3::Y,
        -Vec3::Y,
        Vec3::Z,
        -Vec3::Z,
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(-1.0, -0.0, 0.5),
        Vec3::new(0.3, -0.0, -1.0),
    ];
    (0..n)
        .map(|i| {
            let d = dirs[i % dirs.len()];
            let y = match (i / dirs.len()) % 4 {
                0 => 0.0,
                1 => -0.0,
                2 => 1e-3,
                _ => r.range(-2.0, 2.0),
            };
            let o = Vec3::new(r.range(-12.0, 12.0), y, r.range(-12.0, 12.0));
            (Ray::new(o, d, 0.0), 0.0, f32::INFINITY)
        })
        .collect()
}
