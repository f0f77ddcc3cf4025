//! The shapes a scene is made of, and what every shape answers: its bounds,
//! where a ray meets it, its normals there, its area, and points drawn on
//! it.
//!
//! Each shape is a type in a file of its own (its docs and tests beside
//! it) implementing [`ShapeModel`]; the closed enum [`Shape`] and its
//! dispatch are made by the `shapes!` list in this file, one line per
//! shape, one match per question. The acceleration structure and the
//! emitters ask a shape through these methods and never match on the
//! kind. A triangle mesh is a shape too; its triangles are searched by
//! the acceleration structure, which tests them four at a time, so the
//! per-ray methods answer for the analytic shapes.

pub use super::cylinder::Cylinder;
pub use super::disk::Disk;
use super::interaction::LocalGeometry;
use super::mesh::Mesh;
pub use super::mesh_shape::MeshShape;
pub use super::model::{MeshTable, ShapeHit, ShapeModel, ShapeSample};
pub use super::quad::Quad;
pub use super::sphere::Sphere;
use crate::math::{Aabb, Mat4, Ray, Vec3};
use crate::sampling::{Discrete, Distribution};

macro_rules! shapes {
    ($($variant:ident => $as:ident,)*) => {
        /// A shape in its own space (world space for static objects): one
        /// of the shapes of this layer.
        #[derive(Clone, Debug)]
        pub enum Shape {
            $($variant($variant),)*
        }

        $(impl From<$variant> for Shape {
            fn from(s: $variant) -> Shape {
                Shape::$variant(s)
            }
        })*

        impl Shape {
            /// The names of the shapes.
            pub const NAMES: &'static [&'static str] = &[$(<$variant as ShapeModel>::NAME,)*];

            /// What messages call the shape.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Shape::$variant(_) => <$variant as ShapeModel>::NAME,)*
                }
            }

            $(
                #[doc = concat!("The shape if it is a [`", stringify!($variant), "`].")]
                #[inline(always)]
                pub fn $as(&self) -> Option<&$variant> {
                    match self {
                        Shape::$variant(s) => Some(s),
                        #[allow(unreachable_patterns)]
                        _ => None,
                    }
                }
            )*

            /// The box holding the shape (`meshes` resolves a mesh's index).
            pub fn bounds(&self, meshes: &[Mesh]) -> Aabb {
                match self {
                    $(Shape::$variant(s) => ShapeModel::bounds(s, meshes),)*
                }
            }

            /// See [`ShapeModel::intersect`].
            #[inline]
            pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<ShapeHit> {
                match self {
                    $(Shape::$variant(s) => ShapeModel::intersect(s, ray, tmin, tmax),)*
                }
            }

            /// See [`ShapeModel::intersect_all`].
            #[inline]
            pub fn intersect_all(
                &self,
                rays: &[Ray],
                tmin: f32,
                tmax: f32,
                out: &mut [Option<ShapeHit>],
            ) {
                match self {
                    $(Shape::$variant(s) => ShapeModel::intersect_all(s, rays, tmin, tmax, out),)*
                }
            }

            /// See [`ShapeModel::geometry`]. Always inlined: the record,
            /// returned through memory by a call, would be read back with
            /// wider loads than it was stored with, and every such load
            /// waits for the stores to drain (a third of a hit's cost).
            #[inline(always)]
            pub fn geometry(&self, meshes: &[Mesh], hit: &ShapeHit, p: Vec3) -> LocalGeometry {
                match self {
                    $(Shape::$variant(s) => ShapeModel::geometry(s, meshes, hit, p),)*
                }
            }

            /// `then` of [`geometry`](Self::geometry), called in each
            /// shape's own branch: the record goes on in registers, never
            /// merged through memory with the other shapes' records (the
            /// loads of a merged record straddle its stores and wait for
            /// them to drain).
            #[inline(always)]
            pub fn with_geometry<R>(
                &self,
                meshes: &[Mesh],
                hit: &ShapeHit,
                p: Vec3,
                then: impl FnOnce(LocalGeometry) -> R,
            ) -> R {
                match self {
                    $(Shape::$variant(s) => then(ShapeModel::geometry(s, meshes, hit, p)),)*
                }
            }

            /// The surface area.
            pub fn area(&self, meshes: &[Mesh]) -> f32 {
                match self {
                    $(Shape::$variant(s) => ShapeModel::area(s, meshes),)*
                }
            }

            /// See [`ShapeModel::is_closed`].
            #[inline]
            pub fn is_closed(&self) -> bool {
                match self {
                    $(Shape::$variant(s) => s.is_closed(),)*
                }
            }

            /// See [`ShapeModel::is_flat`].
            #[inline]
            pub fn is_flat(&self) -> bool {
                match self {
                    $(Shape::$variant(s) => s.is_flat(),)*
                }
            }

            /// See [`ShapeModel::plane`].
            #[inline]
            pub fn plane(&self) -> Option<(Vec3, Vec3)> {
                match self {
                    $(Shape::$variant(s) => s.plane(),)*
                }
            }

            /// See [`ShapeModel::center`].
            pub fn center(&self, meshes: &[Mesh]) -> Vec3 {
                match self {
                    $(Shape::$variant(s) => ShapeModel::center(s, meshes),)*
                }
            }

            /// See [`ShapeModel::size`].
            pub fn size(&self) -> Option<f32> {
                match self {
                    $(Shape::$variant(s) => s.size(),)*
                }
            }

            /// See [`ShapeModel::projected_area`].
            #[inline]
            pub fn projected_area(&self, w: Vec3) -> Option<f32> {
                match self {
                    $(Shape::$variant(s) => s.projected_area(w),)*
                }
            }

            /// See [`ShapeModel::normal_cone`].
            pub fn normal_cone(
                &self,
                meshes: &[Mesh],
                triangles: Option<&Discrete>,
                flip: bool,
            ) -> (Vec3, f32) {
                match self {
                    $(Shape::$variant(s) => s.normal_cone(meshes, triangles, flip),)*
                }
            }

            /// See [`ShapeModel::area_scale`].
            pub fn area_scale(&self, m: &Mat4) -> f32 {
                match self {
                    $(Shape::$variant(s) => s.area_scale(m),)*
                }
            }

            /// See [`ShapeModel::transformed`].
            pub fn transformed(&self, m: &Mat4, scale: f32) -> Option<Shape> {
                match self {
                    $(Shape::$variant(s) => s.transformed(m, scale).map(Shape::$variant),)*
                }
            }

            /// See [`ShapeModel::uniform_in_area`].
            #[inline]
            pub fn uniform_in_area(&self) -> bool {
                match self {
                    $(Shape::$variant(s) => s.uniform_in_area(),)*
                }
            }

            /// A point of the shape, in its own space, for the distribution
            /// point `point` of `d`, seen from `from`; `meshes` resolves a
            /// mesh, whose triangle is chosen by `mesh` (its triangles by
            /// area, and its area). Uniform in area but for a sphere seen
            /// from outside, uniform in the cone it subtends (see
            /// [`ShapeModel::sample`]).
            #[inline(always)]
            pub fn sample(
                &self,
                meshes: &[Mesh],
                mesh: MeshTable,
                from: Vec3,
                point: Vec3,
                d: Distribution,
            ) -> Option<ShapeSample> {
                match self {
                    $(Shape::$variant(s) => ShapeModel::sample(s, meshes, mesh, from, point, d),)*
                }
            }

            /// See [`ShapeModel::sample_all`].
            #[inline]
            pub fn sample_all(
                &self,
                meshes: &[Mesh],
                mesh: MeshTable,
                from: &[Vec3],
                points: &[Vec3],
                d: Distribution,
                out: &mut [Option<ShapeSample>],
            ) {
                match self {
                    $(Shape::$variant(s) => s.sample_all(meshes, mesh, from, points, d, out),)*
                }
            }

            /// The solid-angle density with which [`sample`](Self::sample)
            /// draws `target` (a point of the shape with normal `n`, in the
            /// shape's space) from `from`; `area` is the shape's area.
            #[inline]
            pub fn density(&self, area: f32, from: Vec3, target: Vec3, n: Vec3) -> f32 {
                match self {
                    $(Shape::$variant(s) => ShapeModel::density(s, area, from, target, n),)*
                }
            }
        }
    };
}

// The shapes: one line each, the type (also the variant's name) and the
// name of the method that picks it out.
shapes! {
    Sphere => as_sphere,
    Quad => as_quad,
    Disk => as_disk,
    Cylinder => as_cylinder,
    MeshShape => as_mesh,
}

impl Shape {
    /// The geometric and shading normals at `p`, found by `hit` (unit; the
    /// geometric one as the shape defines it, not turned toward a ray).
    #[inline]
    pub fn normals(&self, meshes: &[Mesh], hit: &ShapeHit, p: Vec3) -> (Vec3, Vec3) {
        let g = self.geometry(meshes, hit, p);
        (g.ng, g.ns)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Frame, Vec2};

    /// Every hit of an analytic shape lies inside its bounds, on its
    /// surface, and its normal is unit length.
    #[test]
    fn hits_lie_on_the_shape_inside_its_bounds() {
        use crate::sampling::Rng;
        let shapes = [
            Shape::Sphere(Sphere::new(Vec3::new(0.2, 0.1, -0.3), 0.7)),
            Shape::Quad(Quad::new(Vec3::splat(-0.5), Vec3::X, Vec3::Z)),
            Shape::Disk(Disk::new(
                Vec3::ZERO,
                Frame::from_normal(Vec3::new(1.0, 2.0, 0.5).normalize()),
                0.8,
            )),
        ];
        let mut r = Rng::new(5);
        for shape in &shapes {
            let b = shape.bounds(&[]);
            let grown = Aabb::new(b.min - Vec3::splat(1e-5), b.max + Vec3::splat(1e-5));
            let mut hits = 0;
            for _ in 0..2000 {
                let o = Vec3::new(r.range(-3.0, 3.0), r.range(-3.0, 3.0), r.range(-3.0, 3.0));
                let to = Vec3::new(r.range(-0.5, 0.5), r.range(-0.5, 0.5), r.range(-0.5, 0.5));
                let ray = Ray::new(o, to - o, 0.0);
                let Some(h) = shape.intersect(&ray, 0.0, f32::INFINITY) else {
                    continue;
                };
                hits += 1;
                let p = ray.at(h.t);
                assert!(
                    p.cmpge(grown.min).all() && p.cmple(grown.max).all(),
                    "{p:?} outside {b:?}"
                );
                let (ng, ns) = shape.normals(&[], &h, p);
                assert!((ng.length() - 1.0).abs() < 1e-4 && ns == ng);
            }
            assert!(hits > 200, "{hits} hits of {shape:?}");
        }
    }

    /// The surface coordinates' derivatives are tangent and agree with the
    /// coordinates: a small step along `dp/du` (or `dp/dv`), put back on
    /// the surface, changes `(u, v)` by that step in `u` (or `v`) alone
    /// (a finite difference), on a sphere, a disk and a cylinder.
    #[test]
    fn derivatives_agree_with_the_coordinates() {
        use crate::sampling::Rng;
        let frame = Frame::from_normal(Vec3::new(0.3, 1.0, -0.4).normalize());
        let (c, r) = (Vec3::new(0.5, -0.2, 0.1), 0.8);
        let tube = Cylinder::new(c, c + 1.5 * frame.n, r).unwrap();
        let shapes = [
            Shape::Sphere(Sphere::new(c, r)),
            Shape::Disk(Disk::new(c, frame, r)),
            Shape::Cylinder(tube),
        ];
        // The point of the surface nearest to `p`, and its coordinates.
        let project = |s: &Shape, p: Vec3| {
            if let Some(t) = s.as_cylinder() {
                let along = t.frame.n * (p - t.base).dot(t.frame.n);
                t.base + along + r * (p - t.base - along).normalize()
            } else if s.is_closed() {
                c + r * (p - c).normalize()
            } else {
                p - frame.n * (p - c).dot(frame.n)
            }
        };
        let mut rng = Rng::new(3);
        let mut checked = 0;
        for s in &shapes {
            for _ in 0..500 {
                let dir = Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                );
                let p = if let Some(t) = s.as_cylinder() {
                    project(s, t.base + t.frame.n * (0.75 + 0.7 * dir.z) + dir)
                } else if s.is_closed() {
                    c + r * dir.normalize()
                } else {
                    project(s, c + 0.9 * r * dir.clamp_length_max(1.0))
                };
                let g = s.geometry(&[], &ShapeHit::default(), p);
                // Away from the sphere's poles and seam, the disk's centre and seam.
                if g.uv.x < 0.05 || g.uv.x > 0.95 || g.uv.y < 0.05 || g.uv.y > 0.95 {
                    continue;
                }
                let h = 1e-3;
                for (d, step) in [(g.dpdu, Vec2::new(h, 0.0)), (g.dpdv, Vec2::new(0.0, h))] {
                    assert!(d.dot(g.ng).abs() < 1e-4 * d.length(), "{s:?}: not tangent");
                    let q = project(s, p + h * d);
                    let moved = s.geometry(&[], &ShapeHit::default(), q).uv - g.uv;
                    assert!(
                        (moved - step).abs().max_element() < 2e-4,
                        "{s:?} at {:?}: {moved:?} for {step:?}",
                        g.uv
                    );
                }
                checked += 1;
            }
        }
        assert!(checked > 600, "{checked} points checked");
        // A quad's coordinates are the hit's (s, t), its derivatives its edges.
        let q = Quad::new(Vec3::ZERO, 2.0 * Vec3::X, 3.0 * Vec3::Z);
        let hit = ShapeHit {
            t: 1.0,
            b1: 0.25,
            b2: 0.5,
            inner: 0,
        };
        let g = Shape::Quad(q).geometry(&[], &hit, q.point(0.25, 0.5));
        assert_eq!(
            (g.uv, g.dpdu, g.dpdv),
            (Vec2::new(0.25, 0.5), q.edge_u, q.edge_v)
        );
    }

    /// The batch forms give, lane by lane, the scalar form's bits: rays
    /// against every analytic shape, and points drawn on every shape
    /// (a mesh of two triangles too) from shading points all around.
    #[test]
    fn batches_are_the_scalar_answers() {
        use crate::sampling::{Discrete, Rng};
        let mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::new(1.0, 0.5, 1.0)],
            triangles: vec![[0, 1, 2], [1, 3, 2]],
            ..Mesh::default()
        };
        let table = Discrete::new([0.5, 0.7]).unwrap();
        let meshes = [mesh];
        let frame = Frame::from_normal(Vec3::new(0.2, 1.0, -0.3).normalize());
        let shapes = [
            Shape::Sphere(Sphere::new(Vec3::new(0.2, 0.1, -0.3), 0.7)),
            Shape::Quad(Quad::new(Vec3::splat(-0.5), Vec3::X, Vec3::Z)),
            Shape::Disk(Disk::new(Vec3::ZERO, frame, 0.8)),
            Shape::Cylinder(Cylinder::new(Vec3::ZERO, Vec3::new(0.3, 1.0, 0.2), 0.5).unwrap()),
            Shape::MeshShape(MeshShape::new(0)),
        ];
        let mut r = Rng::new(21);
        let mut v = |s: f32| Vec3::new(r.range(-s, s), r.range(-s, s), r.range(-s, s));
        let rays: Vec<Ray> = (0..64).map(|_| Ray::new(v(3.0), v(0.5), 0.0)).collect();
        let from: Vec<Vec3> = (0..64).map(|_| v(3.0)).collect();
        let points: Vec<Vec3> = (0..64).map(|_| v(1.0)).collect();
        let bits = |h: Option<ShapeHit>| h.map(|h| (h.t.to_bits(), h.b1.to_bits(), h.b2.to_bits()));
        for shape in &shapes {
            let mut hits = vec![None; rays.len()];
            shape.intersect_all(&rays, 0.0, f32::INFINITY, &mut hits);
            for (ray, hit) in rays.iter().zip(&hits) {
                let one = shape.intersect(ray, 0.0, f32::INFINITY);
                assert_eq!(bits(*hit), bits(one), "{shape:?} {ray:?}");
            }
            let mesh = (Some(&table), 1.0);
            for d in [Distribution::Jitter, Distribution::Random] {
                let mut drawn = vec![None; points.len()];
                shape.sample_all(&meshes, mesh, &from, &points, d, &mut drawn);
                for k in 0..points.len() {
                    let one = shape.sample(&meshes, mesh, from[k], points[k], d);
                    // Debug prints every f32 so that it reads back to its bits.
                    assert_eq!(format!("{:?}", drawn[k]), format!("{one:?}"), "{shape:?}");
                    assert!(one.is_some());
                }
            }
        }
    }

    #[test]
    fn areas() {
        let q = Shape::Quad(Quad::new(Vec3::ZERO, 2.0 * Vec3::X, 3.0 * Vec3::Z));
        assert!((q.area(&[]) - 6.0).abs() < 1e-6);
        let s = Shape::Sphere(Sphere::new(Vec3::ZERO, 2.0));
        assert!((s.area(&[]) - 16.0 * std::f32::consts::PI).abs() < 1e-4);
    }
}
