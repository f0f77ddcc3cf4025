//! What every shape answers: [`ShapeModel`], and the records its answers
//! come in ([`ShapeHit`], [`ShapeSample`]). The defaults are those of a
//! shape without the property (no closed form, not flat, not closed).
//!
//! Each shape is one type in a file of its own beside this one; the
//! `shapes!` list in [`shape`](super::shape) makes the closed enum
//! [`Shape`](super::Shape) and its dispatch from them.

use super::interaction::LocalGeometry;
use super::mesh::Mesh;
use crate::math::{Aabb, Frame, Mat4, Ray, Vec3};
use crate::sampling::{Discrete, Distribution};

/// Where a ray meets a shape: the distance and the surface coordinates that
/// the normals are computed from (the barycentrics and triangle of a mesh,
/// the (s, t) of a quad; unused by spheres and disks).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShapeHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
    /// The triangle of a mesh.
    pub inner: u32,
}

impl ShapeHit {
    /// A hit at distance `t` without surface coordinates.
    #[inline]
    pub fn at(t: f32) -> ShapeHit {
        ShapeHit {
            t,
            ..ShapeHit::default()
        }
    }
}

/// How a point was drawn on a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Density {
    /// Uniformly over a surface of this area; `two_sided` when the point
    /// is seen from inside a closed shape, whose inner side faces it.
    Area { area: f32, two_sided: bool },
    /// Uniformly over the directions of a cone of this solid angle, seen
    /// from the reference point.
    Cone(f32),
}

/// A point drawn on a surface: where, its unit normal (the side the
/// surface faces), and how it was drawn; and what finds its surface
/// coordinates as a ray's hit there would ([`ShapeModel::geometry`] of
/// `hit` at `local`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    pub p: Vec3,
    pub n: Vec3,
    pub density: Density,
    /// The surface coordinates a hit at the point would carry (a
    /// rectangle's `(s, t)`, a mesh's triangle and barycentrics; nothing
    /// for the shapes whose geometry follows from the point).
    pub hit: ShapeHit,
    /// The point in the shape's own space (where `p` is before a
    /// placement or motion carries it to the world).
    pub local: Vec3,
}

impl ShapeSample {
    /// A point drawn uniformly over an area, seen from its side.
    #[inline(always)]
    pub fn on_area(p: Vec3, n: Vec3, area: f32) -> ShapeSample {
        ShapeSample {
            p,
            n,
            density: Density::Area {
                area,
                two_sided: false,
            },
            hit: ShapeHit::default(),
            local: p,
        }
    }

    /// The same point with the surface coordinates `hit`.
    #[inline(always)]
    pub fn with_hit(self, hit: ShapeHit) -> ShapeSample {
        ShapeSample { hit, ..self }
    }
}

/// The solid-angle density of uniform area sampling: `r² / (cos θ · A)`
/// for a point seen at `cos_l` (to its normal) and squared distance `r2`;
/// 0 from behind.
#[inline]
pub fn area_pdf(cos_l: f32, r2: f32, area: f32) -> f32 {
    if cos_l > 0.0 && area > 0.0 {
        r2 / (cos_l * area)
    } else {
        0.0
    }
}

/// What a mesh's sampling needs besides the mesh: its triangles by area
/// and its area (`None` and anything for the other shapes).
pub type MeshTable<'a> = (Option<&'a Discrete>, f32);

/// What every shape answers, in its own space (world space for static
/// objects). `meshes` resolves a mesh's index; the analytic shapes ignore
/// it.
pub trait ShapeModel: Sized {
    /// What messages and scenes call the shape.
    const NAME: &'static str;

    /// The box holding the shape.
    fn bounds(&self, meshes: &[Mesh]) -> Aabb;

    /// The nearest point of the shape along `ray` within (tmin, tmax). A
    /// mesh answers `None`: its triangles are searched by the acceleration
    /// structure.
    #[inline]
    fn intersect(&self, _ray: &Ray, _tmin: f32, _tmax: f32) -> Option<ShapeHit> {
        None
    }

    /// [`intersect`](Self::intersect) for a batch of rays: `out[k]` for
    /// `rays[k]` (the slices of one length), one by one unless the shape
    /// has a kernel.
    #[inline]
    fn intersect_all(&self, rays: &[Ray], tmin: f32, tmax: f32, out: &mut [Option<ShapeHit>]) {
        debug_assert_eq!(rays.len(), out.len());
        for (ray, hit) in rays.iter().zip(out) {
            *hit = self.intersect(ray, tmin, tmax);
        }
    }

    /// The shape's part of the surface-interaction record at `p`, found by
    /// `hit` (see the [interaction module](super::interaction)).
    fn geometry(&self, meshes: &[Mesh], hit: &ShapeHit, p: Vec3) -> LocalGeometry;

    /// The surface area.
    fn area(&self, meshes: &[Mesh]) -> f32;

    /// True if a segment can cross the shape twice (in and out).
    #[inline]
    fn is_closed(&self) -> bool {
        false
    }

    /// True for a shape made of flat pieces, whose uniform samples any
    /// affine map keeps uniform.
    #[inline]
    fn is_flat(&self) -> bool {
        false
    }

    /// The plane of a flat analytic shape: its unit normal and a point of it.
    #[inline]
    fn plane(&self) -> Option<(Vec3, Vec3)> {
        None
    }

    /// The centre a light of this shape is collapsed to: the middle of its
    /// bounds unless the shape has a centre of its own.
    fn center(&self, meshes: &[Mesh]) -> Vec3 {
        self.bounds(meshes).centroid()
    }

    /// The size a light of this shape has collapsed to a point (the
    /// radius of a round shape, half the side of the square of equal area
    /// of a rectangle); `None` without one.
    fn size(&self) -> Option<f32> {
        None
    }

    /// The area the shape shows to a distant viewer in direction `w`
    /// (unit, from the shape): `A · max(cos θ, 0)` of a flat shape facing
    /// its normal, `π r²` of a sphere; `None` without a closed form.
    fn projected_area(&self, _w: Vec3) -> Option<f32> {
        None
    }

    /// A cone holding the normals of the shape (negated when `flip`,
    /// where that is meaningful): its axis and the cosine of its
    /// half-angle (−1: every direction). `triangles` is a mesh's table of
    /// triangles by area.
    fn normal_cone(
        &self,
        _meshes: &[Mesh],
        _triangles: Option<&Discrete>,
        _flip: bool,
    ) -> (Vec3, f32) {
        (Vec3::Z, -1.0)
    }

    /// The factor by which the affine map `m` multiplies the shape's
    /// areas: the square of its scale along x, as for a shape it scales
    /// uniformly (a flat shape answers for its plane).
    fn area_scale(&self, m: &Mat4) -> f32 {
        let (s, _, _) = m.to_scale_rotation_translation();
        s.x * s.x
    }

    /// The shape carried by the similarity `m` of scale `scale`; `None`
    /// for a shape that is not carried by value (a mesh's triangles are
    /// the scene's).
    fn transformed(&self, _m: &Mat4, _scale: f32) -> Option<Self> {
        None
    }

    /// True if [`sample`](Self::sample) draws uniformly in area from every
    /// point (a sphere seen from outside draws in its cone).
    #[inline]
    fn uniform_in_area(&self) -> bool {
        true
    }

    /// A point of the shape for the distribution point `point` of `d`,
    /// seen from `from`; a mesh chooses its triangle by `mesh`. Uniform in
    /// area unless [`uniform_in_area`](Self::uniform_in_area) says no.
    fn sample(
        &self,
        meshes: &[Mesh],
        mesh: MeshTable,
        from: Vec3,
        point: Vec3,
        d: Distribution,
    ) -> Option<ShapeSample>;

    /// [`sample`](Self::sample) for a batch: `out[k]` for `points[k]` seen
    /// from `from[k]` (the slices of one length), one by one unless the
    /// shape has a kernel.
    #[inline]
    fn sample_all(
        &self,
        meshes: &[Mesh],
        mesh: MeshTable,
        from: &[Vec3],
        points: &[Vec3],
        d: Distribution,
        out: &mut [Option<ShapeSample>],
    ) {
        debug_assert!(from.len() == points.len() && points.len() == out.len());
        for ((&from, &point), s) in from.iter().zip(points).zip(out) {
            *s = self.sample(meshes, mesh, from, point, d);
        }
    }

    /// The solid-angle density with which [`sample`](Self::sample) draws
    /// `target` (a point of the shape with normal `n`) from `from`; `area`
    /// is the shape's area.
    #[inline]
    fn density(&self, area: f32, from: Vec3, target: Vec3, n: Vec3) -> f32 {
        let to = target - from;
        let r2 = to.length_squared();
        let cos_l = n.dot(-to) / r2.sqrt();
        area_pdf(cos_l, r2, area)
    }
}

/// The factor by which the affine map `m` multiplies the areas of the
/// plane spanned by `u` and `v`.
pub(super) fn plane_area_scale(u: Vec3, v: Vec3, m: &Mat4) -> f32 {
    let w = m
        .transform_vector3(u)
        .cross(m.transform_vector3(v))
        .length();
    w / u.cross(v).length()
}

/// The frame `f` turned by the rotation of a similarity `m`: its axes
/// carried by `m` and made unit (right-handed, also under a mirror).
pub(super) fn placed_frame(m: &Mat4, f: &Frame) -> Frame {
    let n = m.transform_vector3(f.n).normalize();
    let u = m.transform_vector3(f.u).normalize();
    Frame {
        u,
        v: n.cross(u),
        n,
    }
}

/// The angle of `(x, y)` about the origin from +x, in [0, 2π).
#[inline]
pub(super) fn angle(x: f32, y: f32) -> f32 {
    let phi = y.atan2(x);
    if phi < 0.0 {
        phi + std::f32::consts::TAU
    } else {
        phi
    }
}
