//! A triangle mesh as a shape: the index of one of the scene's
//! [`Mesh`]es, which hold the triangles (a file's, or a cube's).
//!
//! Its triangles are searched by the acceleration structure, four at a
//! time, so a ray asks the mesh nothing ([`ShapeModel::intersect`]
//! answers `None`); a hit's geometry is its triangle's, with the
//! interpolated normal as the shading normal where the mesh has vertex
//! normals, and the texture coordinates' derivatives where it has those.
//! A light of this shape draws a triangle by area, then a point uniformly
//! within it.

use super::interaction::LocalGeometry;
use super::mesh::Mesh;
use super::model::{MeshTable, ShapeHit, ShapeModel, ShapeSample};
use super::triangle::{intersect_triangle, RayShear};
use crate::math::{Aabb, Ray, Vec2, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::warp::square_to_triangle;
use crate::sampling::{Discrete, Distribution};

/// A triangle mesh: the index of one of the scene's meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshShape {
    pub mesh: u32,
}

impl MeshShape {
    pub fn new(mesh: u32) -> MeshShape {
        MeshShape { mesh }
    }

    /// Triangle `tri` of the mesh along `ray` within (tmin, tmax).
    #[inline]
    pub fn intersect_triangle(
        &self,
        meshes: &[Mesh],
        tri: u32,
        ray: &Ray,
        shear: &RayShear,
        tmin: f32,
        tmax: f32,
    ) -> Option<ShapeHit> {
        let [p0, p1, p2] = meshes[self.mesh as usize].vertices(tri as usize);
        let (t, b1, b2) = intersect_triangle(ray, shear, p0, p1, p2, tmin, tmax)?;
        Some(ShapeHit {
            t,
            b1,
            b2,
            inner: tri,
        })
    }
}

impl ShapeModel for MeshShape {
    const NAME: &'static str = "mesh";

    fn bounds(&self, meshes: &[Mesh]) -> Aabb {
        meshes[self.mesh as usize].bounds()
    }

    #[inline(always)]
    fn geometry(&self, meshes: &[Mesh], hit: &ShapeHit, _p: Vec3) -> LocalGeometry {
        let m = &meshes[self.mesh as usize];
        let tri = hit.inner as usize;
        let corners = m.vertices(tri);
        let [p0, p1, p2] = corners;
        let ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let ns = m.shading_normal(tri, hit.b1, hit.b2).unwrap_or(ng);
        let (uv, (dpdu, dpdv)) = match m.triangle_uvs(tri) {
            Some(uvs) => {
                let b0 = 1.0 - hit.b1 - hit.b2;
                let uv = b0 * uvs[0] + hit.b1 * uvs[1] + hit.b2 * uvs[2];
                (uv, triangle_derivatives(corners, uvs))
            }
            None => (Vec2::new(hit.b1, hit.b2), (p1 - p0, p2 - p0)),
        };
        LocalGeometry {
            ng,
            ns,
            uv,
            dpdu,
            dpdv,
        }
    }

    fn area(&self, meshes: &[Mesh]) -> f32 {
        let m = &meshes[self.mesh as usize];
        (0..m.triangles.len())
            .map(|i| {
                let [a, b, c] = m.vertices(i);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    #[inline]
    fn is_flat(&self) -> bool {
        true
    }

    /// A cone around its triangles' normals: the area-weighted mean
    /// normal, widened to the farthest; every direction without a table
    /// or when the normals cancel.
    fn normal_cone(
        &self,
        meshes: &[Mesh],
        triangles: Option<&Discrete>,
        flip: bool,
    ) -> (Vec3, f32) {
        let face = |n: Vec3| if flip { -n } else { n };
        let m = &meshes[self.mesh as usize];
        let Some(table) = triangles else {
            return (Vec3::Z, -1.0);
        };
        let normal = |i| {
            let [a, b, c] = m.vertices(i);
            face((b - a).cross(c - a).normalize_or_zero())
        };
        let sum: Vec3 = (0..m.triangles.len())
            .map(|i| table.pmf(i) * normal(i))
            .sum();
        if sum.length() < 1e-3 {
            return (Vec3::Z, -1.0);
        }
        let axis = sum.normalize();
        let cos = (0..m.triangles.len())
            .map(normal)
            .filter(|n| *n != Vec3::ZERO)
            .map(|n| n.dot(axis))
            .fold(1.0f32, f32::min);
        // A little wider than the smallest cosine, against rounding.
        (axis, if cos > -0.999 { cos - 1e-4 } else { -1.0 })
    }

    #[inline(always)]
    fn sample(
        &self,
        meshes: &[Mesh],
        (triangles, area): MeshTable,
        _from: Vec3,
        point: Vec3,
        d: Distribution,
    ) -> Option<ShapeSample> {
        sample_mesh(
            &meshes[self.mesh as usize],
            triangles?,
            area,
            unit_square(point, d),
        )
    }
}

/// A point of the mesh `m` of area `area` for the point `u` of the unit
/// square: a triangle chosen by `triangles` (by area), uniform within it.
#[inline(never)]
fn sample_mesh(m: &Mesh, triangles: &Discrete, area: f32, u: Vec2) -> Option<ShapeSample> {
    let (i, _, rest) = triangles.sample(u.x);
    let (b0, b1) = square_to_triangle(Vec2::new(rest, u.y));
    let [a, b, c] = m.vertices(i);
    let p = b0 * a + b1 * b + (1.0 - b0 - b1) * c;
    let s = ShapeSample::on_area(p, (b - a).cross(c - a).normalize_or_zero(), area);
    // `b1`, `b2`: the weights of the second and third corners, as a hit's.
    Some(s.with_hit(ShapeHit {
        t: 0.0,
        b1,
        b2: 1.0 - b0 - b1,
        inner: i as u32,
    }))
}

/// `dp/du` and `dp/dv` of the triangle `p` with texture coordinates `uv`
/// (pbrt's solution of the 2×2 system); the edges when the coordinates are
/// degenerate.
fn triangle_derivatives(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    if det.abs() < 1e-12 || !det.is_finite() {
        return (e1, e2);
    }
    let inv = 1.0 / det;
    ((d2.y * e1 - d1.y * e2) * inv, (d1.x * e2 - d2.x * e1) * inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle's derivatives map texture-coordinate steps onto the
    /// triangle: `p(uv) = p0 + dpdu (u − u0) + dpdv (v − v0)` at every corner.
    #[test]
    fn triangle_derivatives_map_texture_coordinates() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 1.0),
            Vec3::new(0.5, 3.0, 0.0),
        ];
        let uv = [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.9, 0.3),
            Vec2::new(0.2, 0.8),
        ];
        let (dpdu, dpdv) = triangle_derivatives(p, uv);
        for k in 0..3 {
            let d = uv[k] - uv[0];
            let q = p[0] + dpdu * d.x + dpdv * d.y;
            assert!((q - p[k]).length() < 1e-5, "corner {k}: {q:?}");
        }
        // Degenerate coordinates fall back to the edges.
        let (a, b) = triangle_derivatives(p, [Vec2::ZERO; 3]);
        assert_eq!((a, b), (p[1] - p[0], p[2] - p[0]));
    }
}
