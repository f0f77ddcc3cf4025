use crate::math::{Ray, Vec3};

/// Ray–sphere intersection, nearest root in (tmin, tmax).
///
/// Uses the numerically stable form: the discriminant is computed from the
/// distance of the centre to the ray line (`|oc - (oc·d)d|²`) rather than
/// `b² - 4ac`, which cancels catastrophically for small spheres far away.
#[inline]
pub fn intersect_sphere(ray: &Ray, center: Vec3, radius: f32, tmin: f32, tmax: f32) -> Option<f32> {
    let len2 = ray.dir.length_squared();
    let d = ray.dir / len2.sqrt();
    let oc = ray.origin - center;
    let b = oc.dot(d);
    let perp = oc - b * d;
    let disc = radius * radius - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let c = oc.length_squared() - radius * radius;
    let q = -b - disc.sqrt().copysign(b);
    let scale = len2.sqrt();
    let (mut t0, mut t1) = (q, if q != 0.0 { c / q } else { -q });
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let (t0, t1) = (t0 / scale, t1 / scale);
    if t0 > tmin && t0 < tmax {
        Some(t0)
    } else if t1 > tmin && t1 < tmax {
        Some(t1)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_front_and_back() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0);
        assert!((intersect_sphere(&r, Vec3::ZERO, 1.0, 0.0, 100.0).unwrap() - 4.0).abs() < 1e-5);
        let inside = Ray::new(Vec3::ZERO, Vec3::Z * 2.0, 0.0);
        assert!(
            (intersect_sphere(&inside, Vec3::ZERO, 1.0, 0.0, 100.0).unwrap() - 0.5).abs() < 1e-5
        );
        assert!(intersect_sphere(&r, Vec3::new(0.0, 2.0, 0.0), 1.0, 0.0, 100.0).is_none());
        assert!(intersect_sphere(&r, Vec3::ZERO, 1.0, 0.0, 3.0).is_none());
    }

    #[test]
    fn small_far_sphere_is_accurate() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -1.0e4), Vec3::Z, 0.0);
        let t = intersect_sphere(&r, Vec3::ZERO, 0.01, 0.0, f32::INFINITY).unwrap();
        assert!((t - (1.0e4 - 0.01)).abs() < 2e-3, "t = {t}");
    }
}
