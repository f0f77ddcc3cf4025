use super::Vec3;

/// An orthonormal frame {u, v, n}: `n` is the given unit vector, `u` and `v`
/// span the plane normal to it.
///
/// This is the basis of thesis Listing 3.1, made robust: the listing builds `u`
/// by crossing with a fixed helper axis, which degenerates when the direction is
/// (anti)parallel to it. We use the branch-free construction of
/// "Building an Orthonormal Basis, Revisited" (JCGT 2017), which is continuous
/// except at one sign flip and exact for all axis-aligned directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub u: Vec3,
    pub v: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// Builds a frame around the unit vector `n`.
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let u = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let v = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { u, v, n }
    }

    /// World vector from local coordinates (x along u, y along v, z along n).
    #[inline]
    pub fn to_world(&self, l: Vec3) -> Vec3 {
        l.x * self.u + l.y * self.v + l.z * self.n
    }

    /// Local coordinates of a world vector.
    #[inline]
    pub fn to_local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.u), w.dot(self.v), w.dot(self.n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(n: Vec3) {
        let f = Frame::from_normal(n);
        for (a, b) in [(f.u, f.v), (f.v, f.n), (f.n, f.u)] {
            assert!(a.dot(b).abs() < 1e-5, "not orthogonal for {n:?}");
        }
        for w in [f.u, f.v] {
            assert!((w.length() - 1.0).abs() < 1e-5, "not unit for {n:?}");
        }
        assert!(f.u.cross(f.v).dot(n) > 0.999, "not right-handed for {n:?}");
    }

    #[test]
    fn orthonormal_for_axes_and_random_directions() {
        for n in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
            check(n);
        }
        let mut s = 1u32;
        for _ in 0..10_000 {
            let mut r = || {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                s as f32 / u32::MAX as f32 * 2.0 - 1.0
            };
            let n = Vec3::new(r(), r(), r());
            if n.length() > 1e-3 {
                check(n.normalize());
            }
        }
        check(Vec3::new(0.0, 1e-7, -1.0).normalize());
    }
}
