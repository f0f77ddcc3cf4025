//! TEMPORARY stand-in; replaced by the full module.
use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;
pub fn square_to_disk_concentric(p: Vec2) -> Vec2 {
    let a = 2.0 * p.x - 1.0;
    let b = 2.0 * p.y - 1.0;
    if a == 0.0 && b == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, PI / 4.0 * (b / a))
    } else {
        (b, PI / 2.0 - PI / 4.0 * (a / b))
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
}
pub fn square_to_uniform_sphere(p: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * p.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * p.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
pub fn square_to_uniform_cone(p: Vec2, cos_max: f32) -> Vec3 {
    let z = 1.0 - p.x * (1.0 - cos_max);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * p.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
