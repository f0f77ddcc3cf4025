//! Applying distribution points to the effects (thesis §3.1–3.3).
//!
//! Distributions produce points in their native shape for radius 1: the square
//! [−1, 1]² (grid, jitter, semi-jitter, poisson and the low-discrepancy sets
//! sobol, zsobol, pmj02, pmj02bn, halton, r2), the unit disk (random) or the
//! cube [−1, 1]³ (fast-random). The functions here place those points where an
//! effect needs them: around a ray's end point on the plane normal to it (the
//! thesis's own construction), or on a unit square or disk for effects that
//! sample a real surface or a round lens.

use super::warp::square_to_disk_concentric;
use super::{Distribution, Domain};
use crate::math::{Frame, Vec2, Vec3};

/// Largest ray budget per effect (the exponential growth of sets of sets
/// makes more pointless).
pub const MAX_RAYS: u32 = 1 << 16;

/// How many rays a set of an effect traces and how they are distributed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EffectSpec {
    pub rays: u32,
    pub distribution: Distribution,
}

/// One point of a distribution set, as a model samples from it: the
/// distribution's point in its native shape (see the module docs) and the
/// distribution it came from, which says what that shape is. Models take
/// their random numbers as a `SetPoint`: a model that wants uniform numbers
/// asks for [`square`](Self::square) (stratification kept), the thesis's
/// models use the [`native`](Self::native) point itself, as its listings do.
///
/// A model that chooses among its lobes by what the point draws (a rough
/// dielectric by the drawn facet's Fresnel factor, as Mitsuba's) needs one
/// more number: [`third`](Self::third), the source's own where it has one
/// (a path sampler's dimension), else one hashed from the point's bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetPoint {
    pub point: Vec3,
    pub distribution: Distribution,
    /// A third uniform number in [0, 1), where the point's source gives one.
    pub extra: Option<f32>,
}

impl SetPoint {
    pub fn new(point: Vec3, distribution: Distribution) -> SetPoint {
        SetPoint {
            point,
            distribution,
            extra: None,
        }
    }

    /// The point with a third uniform number `w` in [0, 1).
    pub fn with_third(self, w: f32) -> SetPoint {
        SetPoint {
            extra: Some(w),
            ..self
        }
    }

    /// A third number in [0, 1), independent of the point's own two: the
    /// source's, else a hash of the point's bits (a pure function of the
    /// point, uniform and unrelated to its coordinates' values, so a lobe
    /// it chooses is chosen with the right probability).
    #[inline]
    pub fn third(&self) -> f32 {
        if let Some(w) = self.extra {
            return w;
        }
        let [x, y, z] = self.point.to_array().map(f32::to_bits);
        let mut h = u64::from(x) | u64::from(y) << 32;
        h ^= u64::from(z).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        // The finaliser of SplitMix64.
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^= h >> 31;
        (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// The point of two uniform numbers `u` in [0, 1)², for callers that
    /// draw plain numbers (a square distribution's point `2u − 1`).
    pub fn uniform(u: Vec2) -> SetPoint {
        let p = 2.0 * u - Vec2::ONE;
        SetPoint::new(Vec3::new(p.x, p.y, 0.0), Distribution::Jitter)
    }

    /// The point as the distribution gave it: in [−1, 1]², the unit disk or
    /// the cube [−1, 1]³.
    #[inline]
    pub fn native(&self) -> Vec3 {
        self.point
    }

    /// A point of the unit square [0, 1)² ([`unit_square`]).
    #[inline]
    pub fn square(&self) -> Vec2 {
        unit_square(self.point, self.distribution)
    }

    /// A point of the unit disk ([`unit_disk`]).
    #[inline]
    pub fn disk(&self) -> Vec2 {
        unit_disk(self.point, self.distribution)
    }

    /// The thesis's end point around `center` ([`end_point`]).
    #[inline]
    pub fn end_point(&self, center: Vec3, axis: Vec3, radius: f32) -> Vec3 {
        end_point(center, axis, self.point, radius, self.distribution)
    }
}

/// The thesis's distributed end point: `center` moved by `radius · point` on
/// the plane normal to `axis` (Listing 3.1–3.2), or by the 3D offset itself
/// for fast-random, which deliberately skips the basis (Listing 3.6).
#[inline]
pub fn end_point(center: Vec3, axis: Vec3, point: Vec3, radius: f32, d: Distribution) -> Vec3 {
    end_points(center, axis, radius, d)(point)
}

/// [`end_point`] for every point of a set around one `center` and `axis`:
/// the plane's basis is found once.
#[inline]
pub fn end_points(center: Vec3, axis: Vec3, radius: f32, d: Distribution) -> impl Fn(Vec3) -> Vec3 {
    let f = (!d.is_3d()).then(|| Frame::from_normal(axis));
    move |point| match &f {
        None => center + radius * point,
        Some(f) => center + radius * (point.x * f.u + point.y * f.v),
    }
}

/// A point of the unit square [0, 1)² for sampling a surface uniformly.
/// Square distributions keep their stratification; `random`'s disk points are
/// mapped back to the square by the inverse of the area-preserving concentric
/// map, so they stay uniform.
#[inline]
pub fn unit_square(point: Vec3, d: Distribution) -> Vec2 {
    let p = if d.domain() == Domain::Disk {
        disk_to_square(Vec2::new(point.x, point.y))
    } else {
        Vec2::new(point.x, point.y)
    };
    (0.5 * (p + Vec2::ONE)).clamp(Vec2::ZERO, Vec2::splat(1.0 - f32::EPSILON))
}

/// A point of the unit disk (a round lens, a disk light): `random` is already
/// uniform on the disk; square distributions go through the concentric map,
/// which preserves area and therefore their stratification.
#[inline]
pub fn unit_disk(point: Vec3, d: Distribution) -> Vec2 {
    if d.domain() == Domain::Disk {
        Vec2::new(point.x, point.y)
    } else {
        square_to_disk_concentric(unit_square(point, d))
    }
}

/// Inverse of the concentric map, from the unit disk to [−1, 1]².
pub fn disk_to_square(p: Vec2) -> Vec2 {
    use std::f32::consts::{FRAC_PI_4, PI};
    let r = p.length();
    if r == 0.0 {
        return Vec2::ZERO;
    }
    let phi = p.y.atan2(p.x);
    // The concentric map sends the four triangles |a| ≥ |b| (left/right) and
    // |b| > |a| (top/bottom) to the four quarter sectors around ±x and ±y.
    let (a, b) = if (-FRAC_PI_4..=FRAC_PI_4).contains(&phi) {
        (r, r * phi / FRAC_PI_4)
    } else if phi > FRAC_PI_4 && phi <= 3.0 * FRAC_PI_4 {
        (r * (PI / 2.0 - phi) / FRAC_PI_4, r)
    } else if (-3.0 * FRAC_PI_4..-FRAC_PI_4).contains(&phi) {
        (-r * (-PI / 2.0 - phi) / FRAC_PI_4, -r)
    } else {
        let phi = if phi > 0.0 { phi - PI } else { phi + PI };
        (-r, -r * phi / FRAC_PI_4)
    };
    Vec2::new(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concentric_inverse_round_trips() {
        let n = 64;
        for i in 0..n {
            for j in 0..n {
                let s = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let d = square_to_disk_concentric(s);
                let back = 0.5 * (disk_to_square(d) + Vec2::ONE);
                assert!((back - s).length() < 1e-4, "{s:?} -> {d:?} -> {back:?}");
            }
        }
    }

    #[test]
    fn end_point_stays_on_normal_plane() {
        let axis = Vec3::new(0.3, -0.5, 0.8).normalize();
        let e = end_point(
            Vec3::ONE,
            axis,
            Vec3::new(0.5, -0.25, 0.0),
            2.0,
            Distribution::Grid,
        );
        assert!((e - Vec3::ONE).dot(axis).abs() < 1e-5);
        assert!(((e - Vec3::ONE).length() - 2.0 * (0.3125f32).sqrt()).abs() < 1e-5);
    }
}
