//! The disk: a circle of radius `r` around `center`, facing `frame.n`.

use crate::math::{Ray, Vec3};

/// Ray–disk intersection: the plane hit in (tmin, tmax), then a distance
/// test to the centre.
#[inline]
pub fn intersect_disk(ray: &Ray, c: Vec3, n: Vec3, r: f32, tmin: f32, tmax: f32) -> Option<f32> {
    let denom = n.dot(ray.dir);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = n.dot(c - ray.origin) / denom;
    (t > tmin && t < tmax && (ray.at(t) - c).length_squared() <= r * r).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_the_rim_only() {
        let (c, n) = (Vec3::new(0.0, 2.0, 0.0), Vec3::Y);
        let down = |x: f32| Ray::new(Vec3::new(x, 5.0, 0.0), -Vec3::Y, 0.0);
        assert_eq!(intersect_disk(&down(0.5), c, n, 1.0, 0.0, 10.0), Some(3.0));
        assert_eq!(intersect_disk(&down(1.5), c, n, 1.0, 0.0, 10.0), None);
        // Outside the range, and parallel to the plane.
        assert_eq!(intersect_disk(&down(0.5), c, n, 1.0, 0.0, 2.5), None);
        let along = Ray::new(Vec3::new(-3.0, 2.0, 0.0), Vec3::X, 0.0);
        assert_eq!(intersect_disk(&along, c, n, 1.0, 0.0, 10.0), None);
    }
}
