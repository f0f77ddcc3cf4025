//! The thesis material's mirror, weighted by its reflectivity: the perfect
//! reflection, blurred by the thesis's distribution of end points of radius
//! `glossiness` around it (§3.3) when the integrator traces a set of it.

use crate::math::{reflect, Vec3};
use crate::sampling::points::end_points;
use crate::sampling::{Distribution, EffectSpec, SetPoint};

#[derive(Clone, Copy, Debug)]
pub struct Mirror {
    pub reflectivity: f32,
    /// Radius of the distribution around the perfect direction; 0 is a
    /// perfect mirror.
    pub glossiness: f32,
    /// Rays per reflection and their distribution.
    pub effect: EffectSpec,
}

impl Mirror {
    /// The direction of the ray of set point `u` for light arriving along
    /// `d` (unit, toward the surface) at a surface of unit shading normal
    /// `n` and geometric normal `ng`, both on the side `d` comes from: the
    /// perfect reflection, moved to the end point `u` gives it when the
    /// mirror is glossy; a direction that ends up below the surface is
    /// mirrored back above it across the tangent plane (so a set keeps its
    /// size and symmetry and no energy is lost at grazing angles).
    #[inline]
    pub fn direction(&self, d: Vec3, n: Vec3, ng: Vec3, u: &SetPoint) -> Vec3 {
        blurred(reflect(d, n), self.glossiness, ng, u)
    }
}

/// The thesis's ray of a blurred set around the perfect direction `dir`:
/// the end point of `u` at `radius` (or `dir` itself for radius 0), folded
/// back across the plane of normal `side` when it ends up behind it, and
/// made unit.
#[inline]
pub fn blurred(dir: Vec3, radius: f32, side: Vec3, u: &SetPoint) -> Vec3 {
    let w = if radius > 0.0 {
        u.end_point(dir, dir, radius)
    } else {
        dir
    };
    folded(w, side)
}

/// [`blurred`] for every point of a set (of distribution `d`), appended
/// to `out`: the frame around `dir` is found once, the rays are the same.
pub fn blurred_set(
    dir: Vec3,
    radius: f32,
    side: Vec3,
    (points, d): (&[Vec3], Distribution),
    out: &mut Vec<Vec3>,
) {
    if radius > 0.0 {
        let end = end_points(dir, dir, radius, d);
        out.extend(points.iter().map(|&p| folded(end(p), side)));
    } else {
        out.extend(points.iter().map(|_| folded(dir, side)));
    }
}

/// `w` folded back across the plane of normal `side` when behind it, made
/// unit.
#[inline(always)]
fn folded(mut w: Vec3, side: Vec3) -> Vec3 {
    let below = w.dot(side);
    if below < 0.0 {
        w -= 2.0 * below * side;
    }
    w.normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Distribution;

    #[test]
    fn reflects_about_the_normal_and_stays_above() {
        let m = Mirror {
            reflectivity: 0.7,
            glossiness: 0.0,
            effect: EffectSpec {
                rays: 1,
                distribution: Distribution::Grid,
            },
        };
        let u = SetPoint::new(Vec3::ZERO, Distribution::Grid);
        let d = -Vec3::new(0.6, 0.8, 0.0);
        let w = m.direction(d, Vec3::Y, Vec3::Y, &u);
        assert!((w - Vec3::new(-0.6, 0.8, 0.0)).length() < 1e-6);
        // A wide blur at grazing incidence is folded back above the surface.
        let glossy = Mirror {
            glossiness: 2.0,
            ..m
        };
        let d = Vec3::new(0.99, -0.141, 0.0).normalize();
        for (x, y) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
            let u = SetPoint::new(Vec3::new(x, y, 0.0), Distribution::Jitter);
            let w = glossy.direction(d, Vec3::Y, Vec3::Y, &u);
            assert!(w.y >= 0.0 && (w.length() - 1.0).abs() < 1e-5, "{w:?}");
        }
    }
}
