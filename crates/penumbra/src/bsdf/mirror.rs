//! A mirror weighted by the material's reflectivity: the perfect reflection
//! (a delta lobe). The thesis blurs it by tracing a set of rays distributed
//! around the perfect direction with radius `glossiness` (§3.3): that set is
//! the integrator's, drawn from `effect`; here is only the lobe it is drawn
//! around.

use super::sample::{BsdfFlags, BsdfSample};
use crate::math::{reflect, Rgb, Vec3};
use crate::scene::EffectSpec;

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
    pub fn flags(&self) -> BsdfFlags {
        let blur = if self.glossiness > 0.0 {
            BsdfFlags::GLOSSY
        } else {
            BsdfFlags::empty()
        };
        BsdfFlags::DELTA | BsdfFlags::REFLECTION | blur
    }

    /// The perfect reflection of the incident direction `d` (unit, toward
    /// the surface) about the unit normal `n` on its side.
    #[inline]
    pub fn direction(&self, d: Vec3, n: Vec3) -> Vec3 {
        reflect(d, n)
    }

    /// A delta lobe has no value for any pair of directions.
    pub fn eval(&self) -> Rgb {
        Rgb::ZERO
    }

    /// A delta lobe has no density.
    pub fn pdf(&self) -> f32 {
        0.0
    }

    /// The perfect reflection of `wo` (toward the viewer), weighted by the
    /// reflectivity.
    pub fn sample(&self, n: Vec3, wo: Vec3) -> Option<BsdfSample> {
        (wo.dot(n) > 0.0 && self.reflectivity > 0.0).then(|| BsdfSample {
            wi: self.direction(-wo, n),
            weight: Rgb::splat(self.reflectivity),
            pdf: 1.0,
            flags: BsdfFlags::DELTA | BsdfFlags::REFLECTION,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Distribution;

    #[test]
    fn reflects_about_the_normal() {
        let m = Mirror {
            reflectivity: 0.7,
            glossiness: 0.0,
            effect: EffectSpec {
                rays: 1,
                distribution: Distribution::Grid,
            },
        };
        let wo = Vec3::new(0.6, 0.8, 0.0);
        let s = m.sample(Vec3::Y, wo).unwrap();
        assert!((s.wi - Vec3::new(-0.6, 0.8, 0.0)).length() < 1e-6);
        assert_eq!(s.weight, Rgb::splat(0.7));
        assert!(m.flags().contains(BsdfFlags::DELTA) && !m.flags().contains(BsdfFlags::GLOSSY));
        assert!(m.sample(Vec3::Y, -wo).is_none(), "no reflection from below");
    }
}
