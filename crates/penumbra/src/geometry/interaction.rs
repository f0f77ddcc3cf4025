//! The surface-interaction record: everything shading needs to know about
//! the point where a ray met a surface.
//!
//! Every shape answers a hit with one ([`Shape::geometry`] for the shape's
//! own part, completed by the acceleration structure with the object's
//! material and emitter): the point, the geometric normal as the shape
//! defines it, the shading normal (the interpolated normal of a smooth
//! mesh) and the frame around it with tangents along `dp/du`, the surface coordinates `(u, v)` and their
//! derivatives, and which primitive was hit. It is the role of pbrt-v4's
//! `SurfaceInteraction` and Mitsuba 3's `SurfaceInteraction3f`: BSDFs,
//! emitters and textures read it, and nothing else reaches into shapes.
//!
//! Surface coordinates follow Mitsuba 3, so that its textured scenes carry
//! over:
//!
//! | shape | `(u, v)` | `dp/du`, `dp/dv` |
//! |---|---|---|
//! | sphere | `u = φ / 2π` (φ the angle about the z axis from +x, in [0, 2π)), `v = θ / π` (θ from +z) | the derivatives of the point in `u` and `v` |
//! | quad | the `(s, t)` of `origin + s·edge_u + t·edge_v` | `edge_u`, `edge_v` |
//! | disk | `u = r / radius`, `v = φ / 2π` about its normal from its frame's `u` axis | the derivatives in `u` and `v` (0 at the centre for `dp/dv`) |
//! | cylinder | `u = φ / 2π` about its axis from its frame's `u` axis, `v = z / length` from `p0` | `2π (−y u + x v)`, `length · axis` |
//! | triangle | the interpolated texture coordinates of the mesh, else the barycentrics `(b1, b2)` | solved from the texture coordinates, else the edges `p1 − p0`, `p2 − p0` |
//! | cube | a mesh: each face's corners carry the unit square's coordinates, as Mitsuba's | as for triangles |
//!
//! A shape of an instance answers in its group's space; the record carries
//! the point, normals (by the inverse transpose) and tangents carried to
//! world space. With `flip_normals` both normals are negated, the
//! coordinates and tangents kept (as Mitsuba does).
//!
//! [`Shape::geometry`]: super::Shape::geometry

use crate::math::{Frame, Vec2, Vec3};

/// Where a ray met a surface, in world space.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    /// The ray's parameter at the hit.
    pub t: f32,
    /// The point.
    pub p: Vec3,
    /// The ray's time (every secondary ray inherits it).
    pub time: f32,
    /// Unit geometric normal, as the shape defines it (not turned toward the ray).
    pub ng: Vec3,
    /// The unit shading normal (the interpolated normal of a smooth mesh),
    /// in the hemisphere of `ng`. The shading frame around it is
    /// [`shading_frame`](Self::shading_frame).
    pub n: Vec3,
    /// Surface coordinates.
    pub uv: Vec2,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// The primitive of the shape: a mesh's triangle; 0 for analytic shapes.
    pub prim: u32,
    /// On a mesh's triangle, the barycentric weights `(b1, b2)` of its
    /// second and third corners at the point (what a vertex attribute is
    /// interpolated with); 0 on analytic shapes.
    pub bary: Vec2,
    /// The object of the world that was hit.
    pub object: u32,
    /// The object's BSDF, an index into the scene's models.
    pub material: u32,
    /// The object's emitter, if it emits.
    pub emitter: Option<u32>,
}

impl SurfaceInteraction {
    /// The shading frame: `n` the shading normal, `u` along `dp/du`
    /// (orthogonalised), `v = n × u`. Made when asked for: most shading
    /// reads the normal alone.
    #[inline]
    pub fn shading_frame(&self) -> Frame {
        shading_frame(self.n, self.dpdu)
    }
}

/// The shape's part of a [`SurfaceInteraction`]: what the shape computes at
/// a point of its own space.
#[derive(Clone, Copy, Debug)]
pub struct LocalGeometry {
    pub ng: Vec3,
    /// The shading normal (unit, any hemisphere: it is turned to `ng`'s
    /// when the record is made).
    pub ns: Vec3,
    pub uv: Vec2,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
}

impl LocalGeometry {
    /// The geometry taken to another space: its normals by `normal`, its
    /// derivatives by `vector`; the texture coordinates kept.
    #[inline(always)]
    pub fn transformed(
        self,
        normal: impl Fn(Vec3) -> Vec3,
        vector: impl Fn(Vec3) -> Vec3,
    ) -> LocalGeometry {
        LocalGeometry {
            ng: normal(self.ng),
            ns: normal(self.ns),
            uv: self.uv,
            dpdu: vector(self.dpdu),
            dpdv: vector(self.dpdv),
        }
    }
}

/// The shading frame of normal `n` (unit) with its first tangent along
/// `dpdu`, made orthogonal to `n`; any frame around `n` if `dpdu` is zero or
/// along `n`.
#[inline]
pub fn shading_frame(n: Vec3, dpdu: Vec3) -> Frame {
    let t = dpdu - n * n.dot(dpdu);
    let len2 = t.length_squared();
    // A tangent part of less than 1e-4 of `dpdu` is rounding, not a direction.
    let enough = len2 > 1e-8 * dpdu.length_squared().max(f32::MIN_POSITIVE);
    if !enough || !len2.is_finite() {
        return Frame::from_normal(n);
    }
    let u = t / len2.sqrt();
    Frame {
        u,
        v: n.cross(u),
        n,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_follow_the_tangent() {
        let n = Vec3::new(0.2, 0.9, -0.1).normalize();
        let f = shading_frame(n, Vec3::new(1.0, 0.3, 0.2));
        assert!((f.u.length() - 1.0).abs() < 1e-6 && (f.v.length() - 1.0).abs() < 1e-6);
        assert!(f.u.dot(n).abs() < 1e-6 && f.v.dot(n).abs() < 1e-6 && f.u.dot(f.v).abs() < 1e-6);
        assert!(f.u.dot(Vec3::new(1.0, 0.3, 0.2)) > 0.0);
        assert!(f.u.cross(f.v).dot(n) > 0.999, "right-handed");
        // A tangent along the normal, or none, still gives a frame.
        for t in [n * 3.0, Vec3::ZERO, Vec3::splat(f32::NAN)] {
            let f = shading_frame(n, t);
            assert!(f.u.is_finite() && f.u.dot(n).abs() < 1e-5, "{t:?}");
        }
    }
}
