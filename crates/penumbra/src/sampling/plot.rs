//! TEMPORARY
use crate::math::Vec3;
pub fn draw_points(_p: &[Vec3], _r: f32, size: u32, _t: &str) -> image::RgbImage {
    image::RgbImage::new(size, size)
}
pub fn draw_all(_c: usize, _r: f32, _s: u64, size: u32) -> image::RgbImage {
    image::RgbImage::new(size, size)
}
