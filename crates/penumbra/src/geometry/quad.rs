//! The quad: a parallelogram (the scene format's `quad`; Mitsuba's
//! `rectangle` is the square [−1, 1]² of the plane z = 0 under its
//! transform), one-sided, facing `edge_u × edge_v`. Its
//! surface coordinates are the hit's `(s, t)` along the edges, its
//! derivatives the edges. A leaf of static quads is tested four at a
//! time ([`Quad4`]).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `origin` | point | required | a corner |
//! | `edge_u`, `edge_v` | vectors, not parallel | required | the edges from it |

use super::interaction::LocalGeometry;
use super::mesh::Mesh;
use super::model::{plane_area_scale, MeshTable, ShapeHit, ShapeModel, ShapeSample};
use crate::math::{Aabb, Mat4, Ray, Vec2, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::{Discrete, Distribution};
use glam::{BVec4A, Vec4};

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

impl ShapeModel for Quad {
    const NAME: &'static str = "quad";

    fn bounds(&self, _meshes: &[Mesh]) -> Aabb {
        Aabb::from_points([
            self.origin,
            self.point(1.0, 0.0),
            self.point(0.0, 1.0),
            self.point(1.0, 1.0),
        ])
    }

    #[inline]
    fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<ShapeHit> {
        Quad::intersect(self, ray, tmin, tmax).map(|(t, b1, b2)| ShapeHit {
            t,
            b1,
            b2,
            inner: 0,
        })
    }

    #[inline]
    fn geometry(&self, _meshes: &[Mesh], hit: &ShapeHit, _p: Vec3) -> LocalGeometry {
        LocalGeometry {
            ng: self.normal,
            ns: self.normal,
            uv: Vec2::new(hit.b1, hit.b2),
            dpdu: self.edge_u,
            dpdv: self.edge_v,
        }
    }

    fn area(&self, _meshes: &[Mesh]) -> f32 {
        self.area
    }

    #[inline]
    fn is_flat(&self) -> bool {
        true
    }

    #[inline]
    fn plane(&self) -> Option<(Vec3, Vec3)> {
        Some((self.normal, self.origin))
    }

    fn center(&self, _meshes: &[Mesh]) -> Vec3 {
        Quad::center(self)
    }

    fn size(&self) -> Option<f32> {
        Some(0.5 * self.area.sqrt())
    }

    fn projected_area(&self, w: Vec3) -> Option<f32> {
        Some(self.area * self.normal.dot(w).max(0.0))
    }

    fn normal_cone(
        &self,
        _meshes: &[Mesh],
        _triangles: Option<&Discrete>,
        flip: bool,
    ) -> (Vec3, f32) {
        (if flip { -self.normal } else { self.normal }, 1.0)
    }

    fn area_scale(&self, m: &Mat4) -> f32 {
        plane_area_scale(self.edge_u, self.edge_v, m)
    }

    /// The corners carried by `m` (any affine map).
    fn transformed(&self, m: &Mat4, _scale: f32) -> Option<Quad> {
        let o = m.transform_point3(self.origin);
        Some(Quad::new(
            o,
            m.transform_point3(self.origin + self.edge_u) - o,
            m.transform_point3(self.origin + self.edge_v) - o,
        ))
    }

    #[inline(always)]
    fn sample(
        &self,
        _meshes: &[Mesh],
        _mesh: MeshTable,
        _from: Vec3,
        point: Vec3,
        d: Distribution,
    ) -> Option<ShapeSample> {
        let u = unit_square(point, d);
        let s = ShapeSample::on_area(self.point(u.x, u.y), self.normal, self.area);
        Some(s.with_hit(ShapeHit {
            b1: u.x,
            b2: u.y,
            ..ShapeHit::default()
        }))
    }
}

/// Up to four quads in structure-of-arrays form, tested against a ray at
/// once. A scene's few non-mesh objects are typically a ground and a light:
/// testing them one by one through the object list costs about 240
/// instructions per camera ray, a fifth of a 16-sample render's
/// intersection work; four lanes at once cost a quarter of that.
///
/// Each lane computes what [`Quad::intersect`] computes, with the same
/// operations in the same order, so the results agree bit for bit (a test
/// checks this). Unused lanes hold NaN normals and never hit.
#[derive(Clone, Copy, Debug)]
pub struct Quad4 {
    normal: [Vec4; 3],
    origin: [Vec4; 3],
    du: [Vec4; 3],
    dv: [Vec4; 3],
}

/// What [`Quad4::intersect`] finds: the mask of lanes hit and, per lane, the
/// hit distance and the (s, t) coordinates (meaningful in the mask's lanes).
#[derive(Clone, Copy, Debug)]
pub struct Quad4Hits {
    pub mask: u32,
    pub t: [f32; 4],
    pub s: [f32; 4],
    pub tt: [f32; 4],
}

impl Quad4 {
    /// The quads in lane order; `None` for more than four.
    pub fn new(quads: &[Quad]) -> Option<Quad4> {
        if quads.len() > 4 {
            return None;
        }
        let lanes = |f: &dyn Fn(&Quad) -> Vec3, nan: f32| {
            let mut v = [Vec4::splat(nan); 3];
            for (lane, q) in quads.iter().enumerate() {
                for (axis, a) in v.iter_mut().enumerate() {
                    a[lane] = f(q)[axis];
                }
            }
            v
        };
        Some(Quad4 {
            normal: lanes(&|q| q.normal, f32::NAN),
            origin: lanes(&|q| q.origin, 0.0),
            du: lanes(&|q| q.du, 0.0),
            dv: lanes(&|q| q.dv, 0.0),
        })
    }

    /// The lanes hit within `(tmin, tmax)`.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Quad4Hits {
        let o = ray.origin.to_array().map(Vec4::splat);
        let d = ray.dir.to_array().map(Vec4::splat);
        let dot = |a: &[Vec4; 3], b: &[Vec4; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let denom = dot(&self.normal, &d);
        let to_quad = [0, 1, 2].map(|i| self.origin[i] - o[i]);
        let t = dot(&self.normal, &to_quad) / denom;
        let rel = [0, 1, 2].map(|i| (o[i] + t * d[i]) - self.origin[i]);
        let s = dot(&rel, &self.du);
        let tt = dot(&rel, &self.dv);
        let (zero, one) = (Vec4::ZERO, Vec4::ONE);
        let within = |x: Vec4| x.cmpge(zero) & x.cmple(one);
        let ok: BVec4A = !denom.abs().cmplt(Vec4::splat(1e-12))
            & t.cmpgt(Vec4::splat(tmin))
            & t.cmplt(Vec4::splat(tmax))
            & within(s)
            & within(tt);
        Quad4Hits {
            mask: ok.bitmask(),
            t: t.to_array(),
            s: s.to_array(),
            tt: tt.to_array(),
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

    /// Every lane gives what `Quad::intersect` gives for its quad, bit for
    /// bit, for rays hitting, missing, grazing and parallel to the quads.
    #[test]
    fn four_at_once_match_one_at_a_time() {
        use crate::sampling::Rng;
        let mut r = Rng::new(11);
        let mut v = |s: f32| Vec3::new(r.range(-s, s), r.range(-s, s), r.range(-s, s));
        let quads: Vec<Quad> = (0..4).map(|_| Quad::new(v(2.0), v(3.0), v(3.0))).collect();
        let (mut hits, mut rays) = (0, Vec::new());
        for _ in 0..4000 {
            rays.push(Ray::new(v(5.0), v(1.0), 0.0));
        }
        // A ray in the plane of quad 0 and one along its normal through its centre.
        rays.push(Ray::new(quads[0].origin, quads[0].edge_u, 0.0));
        rays.push(Ray::new(
            quads[0].center() + quads[0].normal,
            -quads[0].normal,
            0.0,
        ));
        for n in 0..=4 {
            let pack = Quad4::new(&quads[..n]).unwrap();
            for ray in &rays {
                let h = pack.intersect(ray, 0.01, 8.0);
                for (lane, q) in quads[..n].iter().enumerate() {
                    let one = q.intersect(ray, 0.01, 8.0);
                    let four =
                        (h.mask >> lane & 1 != 0).then(|| (h.t[lane], h.s[lane], h.tt[lane]));
                    let bits =
                        |x: Option<(f32, f32, f32)>| x.map(|(a, b, c)| [a, b, c].map(f32::to_bits));
                    assert_eq!(bits(one), bits(four), "{ray:?} lane {lane}");
                    hits += usize::from(one.is_some());
                }
                assert_eq!(h.mask >> n, 0);
            }
        }
        assert!(hits > 1000, "{hits} hits");
        assert!(Quad4::new(&[quads[0]; 5]).is_none());
    }

    /// Carried by an affine map (a shear too), a quad's corners are the
    /// carried corners; it shows its area toward its normal, none from
    /// behind, and a light of it has half the side of its square as size.
    #[test]
    fn carried_quads_and_their_silhouette() {
        let q = Quad::new(Vec3::ZERO, 2.0 * Vec3::X, 3.0 * Vec3::Z);
        let mut m = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0));
        m.y_axis.x = 0.5;
        m.x_axis.x = 1.5;
        let t = q.transformed(&m, 1.0).unwrap();
        for (s, u) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let want = m.transform_point3(q.point(s, u));
            assert!((t.point(s, u) - want).length() < 1e-5);
        }
        assert_eq!(q.projected_area(q.normal), Some(6.0));
        assert_eq!(q.projected_area(-q.normal), Some(0.0));
        assert_eq!(q.size(), Some(0.5 * 6f32.sqrt()));
        assert_eq!(q.plane(), Some((q.normal, q.origin)));
    }
}
