//! `thindielectric`: a thin dielectric sheet (a window pane, a soap film
//! without interference), Mitsuba 3's `thindielectric`: two parallel
//! interfaces so close that light leaves where it entered. Light is
//! reflected with the reflectance of the sheet, `R' = R + T²R/(1 − R²) =
//! 2R / (1 + R)` (R the Fresnel reflectance of one interface, summed over
//! the internal reflections), and passes straight through with `1 − R'`:
//! no bending and no radiance scale, since it leaves into the medium it
//! came from. Two-sided.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `int_ior` | number > 0 or a name | `bk7` (1.5046) | index of the sheet ([`ior`](super::ior) lists the names) |
//! | `ext_ior` | number > 0 or a name | `air` (1.000277) | index around it |
//! | `specular_reflectance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the reflection |
//! | `specular_transmittance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the transmission |
//!
//! Its lobes, by slot:
//!
//! | slot | lobe | weight of its ray |
//! |---|---|---|
//! | 0 | delta reflection about the shading normal | `specular_reflectance · R'` |
//! | 1 | delta transmission straight through (`wi = −wo`) | `specular_transmittance · (1 − R')` |
//!
//! With no lobe asked for, `sample` reflects with probability R'. The
//! transmission is a pass-through lobe ([`BsdfFlags::NULL`]), as Mitsuba
//! marks it: `volpath`'s shadow rays cross the sheet keeping what it
//! transmits, and its crossings are not scatterings there; the other
//! integrators' shadow rays stop at the sheet (the transmission is seen
//! along traced rays only), as in Mitsuba's `path`.

use super::conductor::SPECULAR_REFLECTANCE;
use super::dielectric::{read_interface, IOR_PARAMS, SPECULAR_TRANSMITTANCE};
use super::fresnel;
use super::{BsdfModel, Defaults};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use crate::description::{Invalid, Kind, Props, Schema};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;
use crate::texture::Texture;

/// The thin dielectric sheet (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct ThinDielectric {
    /// `int_ior / ext_ior`.
    pub eta: f32,
    pub specular_reflectance: Texture,
    pub specular_transmittance: Texture,
}

const REFLECTION: BsdfFlags = BsdfFlags::DELTA.union(BsdfFlags::REFLECTION);
/// A pass-through, as Mitsuba marks it: the volumetric path tracer does
/// not count it as a scattering.
const TRANSMISSION: BsdfFlags = BsdfFlags::DELTA
    .union(BsdfFlags::TRANSMISSION)
    .union(BsdfFlags::NULL);

impl ThinDielectric {
    /// The reflectance of the sheet at the cosine `cos` (either side).
    pub fn reflectance(&self, cos: f32) -> f32 {
        let r = fresnel::dielectric(cos.abs(), self.eta).r;
        2.0 * r / (1.0 + r)
    }
}

impl BsdfModel for ThinDielectric {
    const NAME: &'static str = "thindielectric";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "thindielectric",
        what: "thin dielectric material",
        doc: "a thin dielectric sheet: reflection and straight transmission",
        mitsuba: &["thindielectric"],
        params: &[IOR_PARAMS[0], IOR_PARAMS[1], SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE],
    };

    fn build(p: &Props, d: &Defaults) -> Result<ThinDielectric, Invalid> {
        let (eta, specular_reflectance, specular_transmittance) = read_interface(p, d.textures)?;
        Ok(ThinDielectric {
            eta,
            specular_reflectance,
            specular_transmittance,
        })
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = REFLECTION;
        l.flags[1] = TRANSMISSION;
        l
    }

    fn eval(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> Rgb {
        Rgb::ZERO
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let n = si.n;
        let cos = wo.dot(n);
        let r = self.reflectance(cos);
        let (k, p) = match lobe {
            Some(k) => (k, 1.0),
            None if u.square().x < r => (0, r),
            None => (1, 1.0 - r),
        };
        let (wi, weight, flags) = match k {
            0 if r > 0.0 => (2.0 * cos * n - wo, self.specular_reflectance.eval(si) * r, REFLECTION),
            1 if r < 1.0 => (-wo, self.specular_transmittance.eval(si) * (1.0 - r), TRANSMISSION),
            _ => return None,
        };
        Some(BsdfSample {
            wi,
            weight: weight * (1.0 / p),
            pdf: p,
            flags,
            lobe: k,
            eta: 1.0,
        })
    }

    fn pdf(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> f32 {
        0.0
    }

    /// What the sheet transmits straight through along `d`.
    fn null_transmission(&self, si: &SurfaceInteraction, d: Vec3) -> Rgb {
        let r = self.reflectance(d.dot(si.n).abs());
        self.specular_transmittance.eval(si) * (1.0 - r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{self, build, interaction};
    use crate::math::Vec2;

    /// The sheet reflects R' = 2R/(1 + R) and passes the rest straight on,
    /// the same from both sides: the two weights add up to 1.
    #[test]
    fn reflects_and_passes_what_the_sheet_does() {
        let t = build::<ThinDielectric>("int_ior = 1.5\next_ior = 1").unwrap();
        let si = interaction(Vec3::Z);
        let u = SetPoint::uniform(Vec2::splat(0.2));
        let r0 = 0.04f32;
        assert!((t.reflectance(1.0) - 2.0 * r0 / (1.0 + r0)).abs() < 1e-6);
        for wo in [Vec3::Z, Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.0, 0.99, -0.141).normalize()] {
            let r = t.sample(&si, wo, Some(0), u).unwrap();
            let p = t.sample(&si, wo, Some(1), u).unwrap();
            assert!((r.weight.r + p.weight.r - 1.0).abs() < 1e-6);
            assert_eq!(p.wi, -wo);
            assert!((r.wi.z - wo.z).abs() < 1e-6 && (r.wi.x + wo.x).abs() < 1e-6);
            let back = t.sample(&si, -wo, Some(1), u).unwrap();
            assert_eq!(back.weight, p.weight);
            let any = t.sample(&si, wo, None, u).unwrap();
            assert_eq!(any.lobe, usize::from(0.2 >= t.reflectance(wo.z)), "{wo:?}");
        }
        // With no lobe asked for, reflection is chosen with probability R'
        // (χ² of the two lobes' counts).
        let wo = Vec3::new(0.0, 0.95, 0.312).normalize();
        let r = f64::from(t.reflectance(wo.z));
        let mut rng = crate::sampling::Rng::new(12);
        let points = 200_000;
        let mut counts = [0.0; 2];
        for _ in 0..points {
            let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
            let s = t.sample(&si, wo, None, u).unwrap();
            counts[s.lobe] += 1.0;
            assert!((s.weight.r - 1.0).abs() < 1e-5, "{:?}", s.weight);
        }
        let expected = [points as f64 * r, points as f64 * (1.0 - r)];
        let p = chi2::p_value(&counts, &expected).unwrap();
        assert!(p > chi2::sidak(1), "p = {p:e}");
        let e = build::<ThinDielectric>("int_ior = 0").unwrap_err().to_string();
        assert!(e.contains("must be a positive number"), "{e}");
    }
}
