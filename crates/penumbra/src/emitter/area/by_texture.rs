//! An area light's points drawn by its texture (Mitsuba 3's `area` emitter
//! with a spatially varying radiance): surface coordinates `(u, v)` drawn
//! in proportion to the texture, then carried onto the shape by its
//! parameterisation. The density in area of a point is the density of its
//! `(u, v)` over `|∂p/∂u × ∂p/∂v|`, the area the map stretches a unit of
//! `(u, v)` to there.
//!
//! Taken where both sides allow it: a `bitmap` texture read at the surface
//! coordinates themselves (no `to_uv`), whose texels weigh a
//! [`Piecewise2D`]
//! ([`Bitmap::sampling_weights`](crate::texture::bitmap::Bitmap::sampling_weights));
//! on a rectangle in world space that keeps its normals, whose `(u, v)`
//! map is affine and one to one, so that
//! [`Area::pdf`](super::Area::pdf) inverts it at any point. Any other
//! textured light keeps the uniform draw: another texture; a mesh, disk or
//! cylinder (no inverse map from a point to its `(u, v)` here); a light
//! placed by an instance or moving; and a sphere, which a point outside
//! sees drawn in the cone it subtends: drawing the whole sphere by its
//! texture wastes the half facing away, and measured noisier than the cone
//! on an uneven texture (a variance 2.1 times the cone's), where
//! Mitsuba draws it by its texture.

use crate::geometry::{Quad, Shape, Surface};
use crate::math::{Vec2, Vec3};
use crate::sampling::piecewise2d::Piecewise2D;
use crate::texture::Texture;

/// A draw of points of a light by its texture (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct ByTexture {
    uv: Piecewise2D,
    /// The rectangle: `p = origin + u · edge_u + v · edge_v`, stretching
    /// `(u, v)` evenly by its area.
    quad: Quad,
}

/// A point drawn on the light: where, its normal, its surface coordinates
/// and its density in area.
#[derive(Clone, Copy, Debug)]
pub struct TexturePoint {
    pub p: Vec3,
    pub n: Vec3,
    pub uv: Vec2,
    pub pdf_area: f32,
}

impl ByTexture {
    /// The draw of `surface`'s points by `radiance`, where both allow it.
    pub fn new(surface: &Surface, radiance: &Texture) -> Option<ByTexture> {
        let Texture::Bitmap(bitmap) = radiance else {
            return None;
        };
        if !surface.is_plain() {
            return None;
        }
        let Shape::Quad(quad) = surface.shape() else {
            return None;
        };
        let (w, h, weights) = bitmap.sampling_weights()?;
        let uv = Piecewise2D::new(w, h, weights)?;
        Some(ByTexture { uv, quad: *quad })
    }

    /// The point for the uniform pair `u`.
    pub fn sample(&self, u: Vec2) -> Option<TexturePoint> {
        let (uv, pdf_uv) = self.uv.sample(u);
        let pdf_area = pdf_uv / self.quad.area();
        (pdf_area > 0.0 && pdf_area.is_finite()).then_some(TexturePoint {
            p: self.quad.point(uv.x, uv.y),
            n: self.quad.normal,
            uv,
            pdf_area,
        })
    }

    /// The density in area with which [`sample`](Self::sample) draws the
    /// point `p` of the rectangle.
    pub fn pdf_area(&self, p: Vec3) -> f32 {
        self.uv.pdf(self.uv_of(p)) / self.quad.area()
    }

    /// The surface coordinates of the point `p` of the rectangle (the
    /// inverse of its map), clamped to the unit square.
    fn uv_of(&self, p: Vec3) -> Vec2 {
        // Solve p − origin = s · edge_u + t · edge_v in the plane.
        let q = &self.quad;
        let d = p - q.origin;
        let (uu, uv, vv) = (
            q.edge_u.dot(q.edge_u),
            q.edge_u.dot(q.edge_v),
            q.edge_v.dot(q.edge_v),
        );
        let (du, dv) = (d.dot(q.edge_u), d.dot(q.edge_v));
        let det = uu * vv - uv * uv;
        let (s, t) = ((du * vv - dv * uv) / det, (dv * uu - du * uv) / det);
        Vec2::new(s.clamp(0.0, 1.0), t.clamp(0.0, 1.0))
    }
}
