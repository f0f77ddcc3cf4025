use crate::math::{Ray, Vec3};

/// A parallelogram `origin + s·edge_u + t·edge_v`, s, t ∈ [0, 1].
#[derive(Clone, Copy, Debug)]
pub struct Quad {
    pub origin: Vec3,
    pub edge_u: Vec3,
    pub edge_v: Vec3,
    /// Unit normal `edge_u × edge_v`, the emitting side of a rectangle light.
    pub normal: Vec3,
    /// Duals of the edges, `edge_v × w` and `w × edge_u` with
    /// `w = n / (n·n)` for the unnormalised normal `n`: the (s, t)
    /// coordinates of a point of the plane are its offset from `origin`
    /// dotted with them (one dot each instead of a cross and a dot).
    du: Vec3,
    dv: Vec3,
    /// `|edge_u × edge_v|`, asked for by every light sample of a rectangle light.
    area: f32,
}

impl Quad {
    pub fn new(origin: Vec3, edge_u: Vec3, edge_v: Vec3) -> Self {
        let n = edge_u.cross(edge_v);
        let w = n / n.length_squared().max(f32::MIN_POSITIVE);
        Quad {
            origin,
            edge_u,
            edge_v,
            normal: n.normalize_or_zero(),
            du: edge_v.cross(w),
            dv: w.cross(edge_u),
            area: n.length(),
        }
    }

    pub fn area(&self) -> f32 {
        self.area
    }

    pub fn point(&self, s: f32, t: f32) -> Vec3 {
        self.origin + s * self.edge_u + t * self.edge_v
    }

    pub fn center(&self) -> Vec3 {
        self.point(0.5, 0.5)
    }

    /// Hit distance in (tmin, tmax) and the (s, t) coordinates of the hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<(f32, f32, f32)> {
        let denom = self.normal.dot(ray.dir);
        if denom.abs() < 1e-12 {
            return None;
        }
        let t = self.normal.dot(self.origin - ray.origin) / denom;
        if !(t > tmin && t < tmax) {
            return None;
        }
        let rel = ray.at(t) - self.origin;
        let s = rel.dot(self.du);
        let tt = rel.dot(self.dv);
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&tt) {
            Some((t, s, tt))
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hit_coordinates() {
        let q = Quad::new(
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 4.0),
        );
        assert!((q.area() - 8.0).abs() < 1e-6);
        assert_eq!(q.normal, Vec3::new(0.0, -1.0, 0.0));
        let r = Ray::new(Vec3::new(0.5, 3.0, 1.0), -Vec3::Y, 0.0);
        let (t, s, tt) = q.intersect(&r, 0.0, 10.0).unwrap();
        assert!((t - 3.0).abs() < 1e-6 && (s - 0.25).abs() < 1e-6 && (tt - 0.25).abs() < 1e-6);
        let miss = Ray::new(Vec3::new(2.5, 3.0, 1.0), -Vec3::Y, 0.0);
        assert!(q.intersect(&miss, 0.0, 10.0).is_none());
        let parallel = Ray::new(Vec3::new(0.5, 0.0, -1.0), Vec3::Z, 0.0);
        assert!(q.intersect(&parallel, 0.0, 10.0).is_none());
    }
}
