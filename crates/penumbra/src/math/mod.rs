//! Vectors, rays, bounds, orthonormal frames and colours.
//!
//! Penumbra computes in `f32` (as pbrt and Embree do): the precision is ample for
//! scenes of ordinary extent, and self-intersection is handled by offsetting ray
//! origins by an amount scaled to the hit point's magnitude ([`offset_origin`]),
//! not by a fixed epsilon.

mod bounds;
mod color;
mod frame;

pub use bounds::Aabb;
pub use color::Rgb;
pub use frame::Frame;
pub use glam::{Mat3, Mat4, Quat, Vec2, Vec3};

/// A ray with an origin, a direction (not necessarily normalised) and a time in
/// the shutter interval. Every secondary ray inherits the time of its primary
/// ray, so a whole light path sees the scene at one instant (motion blur).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub time: f32,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3, time: f32) -> Self {
        Ray { origin, dir, time }
    }

    /// The point at parameter `t`: `origin + t * dir`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// Relative size of the offset applied by [`offset_origin`]. `f32` has a 24-bit
/// mantissa (ε ≈ 6e-8); intersection routines lose a few ulps of the
/// magnitudes the hit point is computed from ([`reach`]), so an offset of
/// 2^-16 of that magnitude clears it safely while staying invisible at image
/// scale.
const OFFSET_SCALE: f32 = 1.0 / 65536.0;

/// The lane of `mask` (non-zero) with the smallest `t`, the first of equals:
/// what testing the lanes one after the other with a shrinking range keeps.
#[inline(always)]
pub fn nearest_lane(mask: u32, t: &[f32; 4]) -> usize {
    let mut lane = mask.trailing_zeros() as usize;
    let mut rest = mask & (mask - 1);
    while rest != 0 {
        let i = rest.trailing_zeros() as usize;
        if t[i] < t[lane] {
            lane = i;
        }
        rest &= rest - 1;
    }
    lane
}

/// Moves `p` off the surface with geometric normal `n`, to the side `toward`
/// points to, by an amount proportional to `reach`: the largest coordinate
/// magnitude of the computation that found `p` (see [`reach`]).
///
/// A fixed epsilon fails both ways: too small far from the origin (acne), too
/// large for small objects (light leaks). Scaling with the magnitude of the
/// coordinates follows the floating-point error of the hit computation.
#[inline]
pub fn offset_origin(p: Vec3, reach: f32, n: Vec3, toward: Vec3) -> Vec3 {
    let d = reach * OFFSET_SCALE;
    if n.dot(toward) >= 0.0 {
        p + d * n
    } else {
        p - d * n
    }
}

/// What [`offset_origin`] scales with for a point `p` found along a ray
/// from `from`: the largest coordinate magnitude of either (at least
/// 1e-3). A hit point is `from + t · dir`, which loses a few ulps of both
/// terms, not of `p`: a point near the world's origin seen from a camera
/// four units away is off by an ulp of 4 (1e-7 below a ground at y = 0,
/// say), far more than an ulp of its own coordinates, and an offset scaled
/// by `p` alone would leave such points under their surface, shadowed by it.
#[inline]
pub fn reach(p: Vec3, from: Vec3) -> f32 {
    p.abs().max(from.abs()).max_element().max(1e-3)
}

/// Mirror reflection of the incident direction `d` about the normal `n`.
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refraction of the unit incident direction `d` through the unit normal `n`
/// facing the incident side, with `eta = n_incident / n_transmitted`.
/// Returns `None` on total internal reflection (Snell's law has no solution).
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(eta * d + (eta * cos_i - cos_t) * n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_requested_side() {
        let p = Vec3::new(1000.0, 0.0, 0.0);
        let (n, r) = (Vec3::Y, reach(p, p));
        assert!(offset_origin(p, r, n, Vec3::Y).y > 0.0);
        assert!(offset_origin(p, r, n, -Vec3::Y).y < 0.0);
    }

    #[test]
    fn refraction_obeys_snell() {
        let n = Vec3::Y;
        let d = Vec3::new(0.6, -0.8, 0.0);
        let t = refract(d, n, 1.0 / 1.5).unwrap();
        let sin_i = 0.6;
        let sin_t = t.x / t.length();
        assert!((sin_i / sin_t - 1.5).abs() < 1e-5);
        assert!((t.length() - 1.0).abs() < 1e-5);
        // Total internal reflection from inside glass at a grazing angle.
        assert!(refract(Vec3::new(0.9, -0.436, 0.0).normalize(), n, 1.5).is_none());
    }

    #[test]
    fn reflection_preserves_angle() {
        let r = reflect(Vec3::new(1.0, -1.0, 0.0), Vec3::Y);
        assert_eq!(r, Vec3::new(1.0, 1.0, 0.0));
    }
}
