//! The thesis material's dielectric interface (glass, water), weighted by
//! its transparency: Fresnel-weighted perfect reflection and refraction,
//! each blurred by the thesis's distribution of radius `translucency` when
//! the integrator traces a set of it.

use super::mirror::blurred;
use crate::math::{reflect, refract, Vec3};
use crate::sampling::{EffectSpec, SetPoint};

#[derive(Clone, Copy, Debug)]
pub struct Dielectric {
    pub transparency: f32,
    /// Index of refraction of the inside (the side the normal points away from).
    pub ior: f32,
    /// Radius of the distributions around the perfect directions; 0 is clear.
    pub translucency: f32,
    /// Rays per refraction (and Fresnel reflection) and their distribution.
    pub effect: EffectSpec,
}

/// The perfect directions at an interface and the Fresnel reflectance.
#[derive(Clone, Copy, Debug)]
pub struct Split {
    /// Fraction reflected (1 under total internal reflection).
    pub fresnel: f32,
    pub reflected: Vec3,
    /// `None` under total internal reflection.
    pub refracted: Option<Vec3>,
}

impl Dielectric {
    /// The interface seen along the unit direction `d` (toward the surface),
    /// with the unit normal `n` on the viewer's side; `front` if the viewer
    /// is outside.
    #[inline]
    pub fn split(&self, d: Vec3, n: Vec3, front: bool) -> Split {
        let eta = if front { 1.0 / self.ior } else { self.ior };
        let cos_i = n.dot(-d).max(0.0);
        Split {
            fresnel: fresnel_dielectric(cos_i, eta),
            reflected: reflect(d, n),
            refracted: refract(d, n, eta),
        }
    }

    /// The refracted ray of set point `u` (blurred by `translucency`, kept on
    /// the far side of the geometric normal `ng` of the viewer's side) and
    /// its weight `transparency · (1 − F)`; `None` under total internal
    /// reflection. Radiance scaling by η² is left out, as in the thesis's
    /// Whitted model.
    #[inline]
    pub fn refraction(&self, s: &Split, ng: Vec3, u: &SetPoint) -> Option<(Vec3, f32)> {
        let t = s.refracted.filter(|_| s.fresnel < 1.0)?;
        let w = blurred(t, self.translucency, -ng, u);
        Some((w, self.transparency * (1.0 - s.fresnel)))
    }

    /// The Fresnel-reflected ray of set point `u` (blurred by
    /// `translucency`) and its weight `transparency · F`; `None` if nothing
    /// is reflected.
    #[inline]
    pub fn reflection(&self, s: &Split, ng: Vec3, u: &SetPoint) -> Option<(Vec3, f32)> {
        (s.fresnel > 0.0).then(|| {
            let w = blurred(s.reflected, self.translucency, ng, u);
            (w, self.transparency * s.fresnel)
        })
    }
}

/// Unpolarised Fresnel reflectance of a dielectric interface, for the cosine
/// of the incident angle and the ratio `eta = n_incident / n_transmitted`.
/// Returns 1 under total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_par = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_known_values() {
        // Normal incidence on glass: ((1 - 1.5) / (1 + 1.5))^2 = 0.04.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fresnel_dielectric(0.1, 1.5), 1.0);
        assert!((fresnel_dielectric(0.0, 1.0 / 1.5) - 1.0).abs() < 1e-6);
    }

    /// The refracted and reflected rays leave on their sides with weights
    /// that add up to the transparency; total internal reflection leaves
    /// only the reflection.
    #[test]
    fn the_two_rays_share_the_transparency() {
        use crate::sampling::Distribution;
        let g = Dielectric {
            transparency: 0.8,
            ior: 1.5,
            translucency: 0.1,
            effect: EffectSpec {
                rays: 4,
                distribution: Distribution::Jitter,
            },
        };
        let u = SetPoint::new(Vec3::new(0.5, -0.5, 0.0), Distribution::Jitter);
        let d = Vec3::new(0.6, -0.8, 0.0);
        let s = g.split(d, Vec3::Y, true);
        let (t, wt) = g.refraction(&s, Vec3::Y, &u).unwrap();
        let (r, wr) = g.reflection(&s, Vec3::Y, &u).unwrap();
        assert!(t.y < 0.0 && r.y > 0.0);
        assert!((wt + wr - 0.8).abs() < 1e-6);
        let inside = g.split(Vec3::new(0.9, -0.436, 0.0).normalize(), Vec3::Y, false);
        assert!(g.refraction(&inside, Vec3::Y, &u).is_none());
        assert!((g.reflection(&inside, Vec3::Y, &u).unwrap().1 - 0.8).abs() < 1e-6);
    }
}
