//! What a light BVH knows of a bounded emitter, or of a group of them: a
//! box around the emitting surface, a cone around the directions of its
//! normals, the angle beyond the normals into which it still emits, and its
//! power; and from these an importance at a point that never says 0 where
//! the emitters can light it (pbrt-v4's `LightBounds`, Conty Estevez and
//! Kulla's *Importance sampling of many lights*, 2018).
//!
//! The cone of normals is `(axis, cos θo)`: every normal of the surface
//! lies within `θo` of `axis`. A surface emits into directions within
//! `θe` of its normal (`π/2` for an area light, which emits into the
//! hemisphere; the falloff angle for a spot light).

use std::f32::consts::PI;

use crate::math::{Aabb, Rgb, Vec3};

/// The slack, in radians, by which a cone made by [`LightBounds::union`]
/// is widened and by which [`LightBounds::importance`] compares angles: a
/// little more importance where rounding might otherwise say 0 for a point
/// just inside an emitter's reach.
const SLACK: f32 = 1e-4;

/// Bounds of an emitter (or of a group of emitters) and its power.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Around the emitting surface (a point for a point light).
    pub bounds: Aabb,
    /// The axis of the cone of normals (unit).
    pub axis: Vec3,
    /// The power (W, mean over the colour channels).
    pub phi: f32,
    /// The cosine of the cone of normals' half-angle θo.
    pub cos_theta_o: f32,
    /// The cosine of θe, the angle beyond a normal into which it emits.
    pub cos_theta_e: f32,
}

/// The mean of a colour's channels: what powers and importances weigh.
pub fn mean(c: Rgb) -> f32 {
    c.element_sum() / 3.0
}

/// The cosine of `a − b` for the angles of cosines `cos_a`, `cos_b` and
/// sines `sin_a`, `sin_b` in [0, π], clamped to 1 where `a < b`.
#[inline]
fn cos_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        1.0
    } else {
        cos_a * cos_b + sin_a * sin_b
    }
}

/// The sine of `a − b`, clamped to 0 where `a < b`.
#[inline]
fn sin_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        0.0
    } else {
        sin_a * cos_b - cos_a * sin_b
    }
}

#[inline]
fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

impl LightBounds {
    /// An emitter in `bounds` whose normals lie within the angle of cosine
    /// `cos_theta_o` of `axis`, each emitting into `θe` beyond.
    pub fn new(bounds: Aabb, axis: Vec3, phi: f32, cos_theta_o: f32, cos_theta_e: f32) -> Self {
        LightBounds {
            bounds,
            axis: axis.normalize_or(Vec3::Z),
            phi,
            cos_theta_o: cos_theta_o.clamp(-1.0, 1.0),
            cos_theta_e: cos_theta_e.clamp(-1.0, 1.0),
        }
    }

    /// The bounds of two groups together: the box around both, the
    /// smallest cone around both cones (pbrt-v4's `DirectionCone` union,
    /// widened by a ten-thousandth of a radian), the wider emission angle,
    /// the power summed.
    pub fn union(&self, o: &LightBounds) -> LightBounds {
        let (axis, cos_theta_o) =
            cone_union((self.axis, self.cos_theta_o), (o.axis, o.cos_theta_o));
        LightBounds {
            bounds: self.bounds.union(o.bounds),
            axis,
            phi: self.phi + o.phi,
            cos_theta_o,
            cos_theta_e: self.cos_theta_e.min(o.cos_theta_e),
        }
    }

    /// The centre of the box.
    pub fn centroid(&self) -> Vec3 {
        self.bounds.centroid()
    }

    /// How much the emitters of these bounds may light the point `p` whose
    /// surface has normal `n` (zero vector: no surface): power over the
    /// squared distance to the box's centre (at least half its diagonal),
    /// times the cosine of the smallest angle between the cone of normals
    /// widened by the directions the box subtends and the direction to
    /// `p`, times the cosine of the smallest angle between `n` (either
    /// side) and a direction to the box. Zero only where no point of the
    /// box with a normal of the cone can send light to `p` (outside every
    /// emission cone) or every such direction lies in `p`'s tangent plane.
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let pc = self.bounds.centroid();
        let diagonal = (self.bounds.max - self.bounds.min).length();
        let d2 = p
            .distance_squared(pc)
            .max(0.5 * diagonal)
            .max(f32::MIN_POSITIVE);
        let wi = (p - pc).normalize_or_zero();
        let cos_w = self.axis.dot(wi).clamp(-1.0, 1.0);
        let sin_w = safe_sqrt(1.0 - cos_w * cos_w);
        // The directions from the box toward `p`: within θb of `wi`.
        let cos_b = subtended(self.bounds, p);
        let sin_b = safe_sqrt(1.0 - cos_b * cos_b);
        let sin_o = safe_sqrt(1.0 - self.cos_theta_o * self.cos_theta_o);
        // θx = θw − θo, then θ' = θx − θb, each clamped at 0.
        let cos_x = cos_sub_clamped(sin_w, cos_w, sin_o, self.cos_theta_o);
        let sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, self.cos_theta_o);
        let cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
        // Compared with the emission angle widened by the slack.
        let sin_e = safe_sqrt(1.0 - self.cos_theta_e * self.cos_theta_e);
        let cos_e_wide = self.cos_theta_e * SLACK.cos() - sin_e * SLACK.sin();
        if cos_p <= cos_e_wide {
            return 0.0;
        }
        let mut importance = self.phi * cos_p.max(SLACK) / d2;
        if n != Vec3::ZERO {
            let cos_i = n.normalize_or_zero().dot(wi).abs().min(1.0);
            let sin_i = safe_sqrt(1.0 - cos_i * cos_i);
            importance *= cos_sub_clamped(sin_i, cos_i, sin_b, cos_b).max(0.0);
        }
        if importance.is_finite() {
            importance.max(0.0)
        } else {
            f32::MAX
        }
    }

    /// The cost of a group with these bounds in a BVH split along axis
    /// `dim` of the box `parent`: power times the measure of the directions
    /// it emits into times the box's area, the area stretched for thin
    /// boxes split across (pbrt-v4's `EvaluateCost`).
    pub fn cost(&self, parent: Aabb, dim: usize) -> f32 {
        let theta_o = self.cos_theta_o.clamp(-1.0, 1.0).acos();
        let theta_e = self.cos_theta_e.clamp(-1.0, 1.0).acos();
        let theta_w = (theta_o + theta_e).min(PI);
        let sin_o = safe_sqrt(1.0 - self.cos_theta_o * self.cos_theta_o);
        let m_omega = 2.0 * PI * (1.0 - self.cos_theta_o)
            + PI / 2.0
                * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o
                    + self.cos_theta_o);
        let d = parent.extent();
        let kr = if d[dim] > 0.0 {
            d.max_element() / d[dim]
        } else {
            1.0
        };
        self.phi * m_omega * kr * self.bounds.surface_area()
    }
}

/// The cosine of the half-angle of the cone of directions from `p` that
/// meet the bounding sphere of `b` (−1 when `p` is inside it).
fn subtended(b: Aabb, p: Vec3) -> f32 {
    let c = b.centroid();
    let r2 = (0.5 * (b.max - b.min)).length_squared();
    let d2 = p.distance_squared(c);
    if d2 <= r2 * (1.0 + 1e-4) || d2 <= 0.0 {
        return -1.0;
    }
    safe_sqrt(1.0 - r2 / d2)
}

/// The smallest cone holding the cones `a` and `b` (each an axis and the
/// cosine of its half-angle), widened by [`SLACK`].
fn cone_union((wa, cos_a): (Vec3, f32), (wb, cos_b): (Vec3, f32)) -> (Vec3, f32) {
    let (theta_a, theta_b) = (cos_a.clamp(-1.0, 1.0).acos(), cos_b.clamp(-1.0, 1.0).acos());
    let theta_d = wa.dot(wb).clamp(-1.0, 1.0).acos();
    if (theta_d + theta_b).min(PI) <= theta_a {
        return (wa, cos_a);
    }
    if (theta_d + theta_a).min(PI) <= theta_b {
        return (wb, cos_b);
    }
    let theta_o = 0.5 * (theta_a + theta_d + theta_b) + SLACK;
    if theta_o >= PI {
        return (wa, -1.0);
    }
    // Turn `wa` toward `wb` by θo − θa.
    let theta_r = theta_o - theta_a;
    let k = wa.cross(wb);
    if k.length_squared() == 0.0 {
        return (wa, -1.0);
    }
    let toward = k.normalize().cross(wa);
    let (s, c) = theta_r.sin_cos();
    let w = (wa * c + toward * s).normalize();
    (w, theta_o.cos())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// A direction uniform over the sphere (by rejection).
    pub(crate) fn random_unit(rng: &mut Rng) -> Vec3 {
        loop {
            let v = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            if (0.01..1.0).contains(&v.length_squared()) {
                return v.normalize();
            }
        }
    }

    /// The union of two cones holds every direction of both: directions
    /// drawn within each cone lie within the union's.
    #[test]
    fn cone_union_holds_both_cones() {
        let mut rng = Rng::new(3);
        for _ in 0..2000 {
            let (wa, wb) = (random_unit(&mut rng), random_unit(&mut rng));
            let (ca, cb) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let (w, c) = cone_union((wa, ca), (wb, cb));
            for (axis, cos) in [(wa, ca), (wb, cb)] {
                for _ in 0..20 {
                    let d = random_unit(&mut rng);
                    if d.dot(axis) >= cos {
                        assert!(d.dot(w) >= c - 1e-5, "{d:?} outside {w:?} {c}");
                    }
                }
                assert!(axis.dot(w) >= c - 1e-5);
            }
        }
    }

    /// A one-sided square facing up lights no point below its plane
    /// outside its bounding sphere and every point above it; from above,
    /// farther is less important.
    #[test]
    fn importance_sees_the_emitting_side() {
        let b = LightBounds::new(
            Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0)),
            Vec3::Y,
            1.0,
            1.0,
            0.0,
        );
        assert_eq!(b.importance(Vec3::new(0.3, -5.0, 0.2), Vec3::ZERO), 0.0);
        let near = b.importance(Vec3::new(5.0, 0.5, 0.0), Vec3::ZERO);
        let far = b.importance(Vec3::new(0.0, 9.0, 0.0), Vec3::ZERO);
        assert!(
            near > 0.0 && far > 0.0 && far < b.importance(Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO)
        );
        // A surface facing the square at a grazing angle still sees it.
        assert!(b.importance(Vec3::new(3.0, 0.01, 0.0), Vec3::Y) > 0.0);
    }
}
