//! Placeholder until the watertight routine lands.
use crate::math::{Ray, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct RayShear;

impl RayShear {
    pub fn new(_ray: &Ray) -> Self {
        RayShear
    }
}

pub fn intersect_triangle(
    ray: &Ray,
    _shear: &RayShear,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32, f32)> {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = ray.dir.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-20 {
        return None;
    }
    let inv = 1.0 / det;
    let tv = ray.origin - p0;
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = ray.dir.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    (t > tmin && t < tmax).then_some((t, u, v))
}
