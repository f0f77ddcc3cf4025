//! What [`normalmap`](super::normalmap) and [`bumpmap`](super::bumpmap)
//! share: a held model seen through a perturbed shading normal, as
//! Mitsuba 3's adapters do.
//!
//! The held model is asked with the interaction's shading normal replaced
//! by the perturbed one `n'` (its frame's first tangent `dp/du` made
//! orthogonal to `n'`; the geometric normal kept). A direction `wi` is
//! answered only where it lies on the same side of both normals; `eval`
//! is the held model's times `|wi·n'| / |wi·n|`, so that a renderer
//! multiplying it by the cosine to the interaction's own shading normal
//! `n` gets the held model's cosine to `n'`, as Mitsuba (whose `eval`
//! holds the cosine) does. A sample's weight, `eval · |cos| / pdf` of the
//! held model at `n'`, is then the same number either way, and `pdf` is
//! the held model's.

use super::sample::BsdfSample;
use super::Bsdf;
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;

/// The interaction as the held model sees it: shading normal `n` (unit).
#[inline]
pub fn with_normal(si: &SurfaceInteraction, n: Vec3) -> SurfaceInteraction {
    SurfaceInteraction { n, ..*si }
}

/// True if `w` lies strictly on the same side of both normals.
#[inline]
fn same_side(si: &SurfaceInteraction, n: Vec3, w: Vec3) -> bool {
    w.dot(si.n) * w.dot(n) > 0.0
}

/// The held model's value through the normal `n`.
pub fn eval(bsdf: &Bsdf, si: &SurfaceInteraction, n: Vec3, wo: Vec3, wi: Vec3) -> Rgb {
    if !same_side(si, n, wi) {
        return Rgb::ZERO;
    }
    let f = bsdf.eval(&with_normal(si, n), wo, wi);
    f * (wi.dot(n) / wi.dot(si.n)).abs()
}

/// The held model's density through the normal `n`.
pub fn pdf(bsdf: &Bsdf, si: &SurfaceInteraction, n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
    if !same_side(si, n, wi) {
        return 0.0;
    }
    bsdf.pdf(&with_normal(si, n), wo, wi)
}

/// A sample of the held model through the normal `n`; `None` where the
/// direction drawn lies on opposite sides of the two normals.
pub fn sample(
    bsdf: &Bsdf,
    si: &SurfaceInteraction,
    n: Vec3,
    wo: Vec3,
    lobe: Option<usize>,
    u: SetPoint,
) -> Option<BsdfSample> {
    let s = bsdf.sample(&with_normal(si, n), wo, lobe, u)?;
    same_side(si, n, s.wi).then_some(s)
}

/// The normal `n`, or the interaction's own where `n` is not a finite
/// unit vector (a degenerate perturbation).
#[inline]
pub fn or_unperturbed(si: &SurfaceInteraction, n: Vec3) -> Vec3 {
    if n.is_finite() && (n.length_squared() - 1.0).abs() < 1e-3 {
        n
    } else {
        si.n
    }
}
