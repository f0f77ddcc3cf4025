//! `diffuse`: an ideal Lambertian reflector, `reflectance / π` (Mitsuba 3's
//! `diffuse`). One-sided, as Mitsuba's: it reflects on the side its
//! shading normal points to and is black from behind, unless `two_sided`
//! (Mitsuba's `twosided` around it) makes both sides reflect alike.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `reflectance` | colour in [0, 1] or texture | `[0.5, 0.5, 0.5]` | the albedo |
//! | `two_sided` | bool | `false` | reflect on both sides |

use std::f32::consts::FRAC_1_PI;

use super::{BsdfModel, Defaults};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::conductor::reflectance_texture;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use crate::sampling::SetPoint;
use crate::texture::Texture;

#[derive(Clone, Debug)]
pub struct Diffuse {
    pub reflectance: Texture,
    pub two_sided: bool,
}

impl Diffuse {
    /// The side `wo` leaves from: 1 in front, −1 behind a two-sided
    /// material, `None` where nothing is reflected.
    fn side(&self, si: &SurfaceInteraction, wo: Vec3) -> Option<f32> {
        let c = si.n.dot(wo);
        if c > 0.0 {
            Some(1.0)
        } else if self.two_sided && c < 0.0 {
            Some(-1.0)
        } else {
            None
        }
    }
}

impl BsdfModel for Diffuse {
    const NAME: &'static str = "diffuse";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "diffuse",
        what: "diffuse material",
        doc: "an ideal Lambertian reflector",
        mitsuba: &["diffuse"],
        params: &[
            Param::new(
                "reflectance",
                Type::ColourTexture,
                "[0.5, 0.5, 0.5]",
                "the albedo, each channel in [0, 1]",
            ).range(Range::Unit),
            Param::new(
                "two_sided",
                Type::Bool,
                "false",
                "reflect on both sides alike (otherwise only on the side the normal points to)",
            ).penumbra_only(),
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<Diffuse, Invalid> {
        let reflectance = reflectance_texture(p, d.textures, "reflectance", Rgb::splat(0.5))?;
        let two_sided = p.bool("two_sided")?.unwrap_or(false);
        Ok(Diffuse {
            reflectance,
            two_sided,
        })
    }

    /// Mitsuba's `eval_diffuse_reflectance`: the reflectance.
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, _wo: Vec3) -> Rgb {
        self.reflectance.eval(si)
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION;
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        match self.side(si, wo) {
            Some(s) if si.n.dot(wi) * s > 0.0 => self.reflectance.eval(si) * FRAC_1_PI,
            _ => Rgb::ZERO,
        }
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        if lobe.is_some_and(|k| k != 0) {
            return None;
        }
        let s = self.side(si, wo)?;
        let frame = si.shading_frame();
        // Behind, the hemisphere mirrored through the surface.
        let front = frame.to_world(square_to_cosine_hemisphere(u.square()));
        let wi = front * s;
        // eval · cos / pdf = (ρ/π) cos / (cos/π) = ρ.
        (wi.dot(si.n) * s > 0.0).then(|| BsdfSample {
            wi,
            weight: self.reflectance.eval(si),
            pdf: square_to_cosine_hemisphere_pdf(frame.to_local(front)),
            flags: BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION,
            lobe: 0,
            eta: 1.0,
        })
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        match self.side(si, wo) {
            Some(s) if si.n.dot(wi) * s > 0.0 => {
                square_to_cosine_hemisphere_pdf(si.shading_frame().to_local(wi * s))
            }
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::thesis::tests::interaction;
    use crate::math::Vec2;
    use crate::sampling::Rng;

    /// Every sample's weight is `eval · cos / pdf` (the reflectance), the
    /// pdf integrates to one over the hemisphere (a midpoint rule), and
    /// nothing is reflected from behind.
    #[test]
    fn samples_weigh_the_reflectance_and_the_pdf_is_normalised() {
        let d = Diffuse {
            reflectance: Texture::Constant(Rgb::new(0.2, 0.5, 0.8)),
            two_sided: false,
        };
        let n = Vec3::new(0.3, 0.2, 0.9).normalize();
        let si = interaction(n);
        let wo = Vec3::new(-0.2, 0.1, 0.95).normalize();
        let mut rng = Rng::new(2);
        for _ in 0..10_000 {
            let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
            let s = d.sample(&si, wo, None, u).unwrap();
            let want = d.eval(&si, wo, s.wi) * (s.wi.dot(n) / s.pdf);
            assert!((s.weight - want).abs().max_element() < 1e-4);
            assert!((s.pdf - d.pdf(&si, wo, s.wi)).abs() < 1e-4 * s.pdf);
        }
        let steps = 400;
        let mut total = 0.0;
        for i in 0..steps {
            let theta = (i as f32 + 0.5) / steps as f32 * std::f32::consts::FRAC_PI_2;
            for j in 0..steps {
                let phi = (j as f32 + 0.5) / steps as f32 * std::f32::consts::TAU;
                let l = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let wi = si.shading_frame().to_world(l);
                total += d.pdf(&si, wo, wi) * theta.sin();
            }
        }
        total *= std::f32::consts::FRAC_PI_2 / steps as f32 * std::f32::consts::TAU / steps as f32;
        assert!((total - 1.0).abs() < 1e-3, "{total}");
        assert_eq!(d.eval(&si, -wo, n), Rgb::ZERO);
        // The directions follow the pdf (χ²).
        let p = crate::bsdf::chi2::model_p_value(&d, &si, wo, 3).unwrap();
        assert!(p > crate::bsdf::chi2::sidak(1), "p = {p:e}");
        assert!(d
            .sample(&si, -wo, None, SetPoint::uniform(Vec2::splat(0.5)))
            .is_none());
    }

    /// Two-sided, the back reflects as the front: a sample from behind is
    /// the front's mirrored through the surface, with the same weight and pdf.
    #[test]
    fn a_two_sided_material_reflects_behind_as_in_front() {
        let d = Diffuse {
            reflectance: Texture::Constant(Rgb::new(0.2, 0.5, 0.8)),
            two_sided: true,
        };
        let n = Vec3::new(0.3, 0.2, 0.9).normalize();
        let si = interaction(n);
        let wo = Vec3::new(-0.2, 0.1, 0.95).normalize();
        let mut rng = Rng::new(3);
        for _ in 0..1000 {
            let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
            let front = d.sample(&si, wo, None, u).unwrap();
            let back = d.sample(&si, -wo, None, u).unwrap();
            assert!((back.wi + front.wi).length() < 1e-6);
            assert_eq!(back.weight, front.weight);
            assert!((back.pdf - front.pdf).abs() < 1e-6);
            assert!((d.pdf(&si, -wo, back.wi) - back.pdf).abs() < 1e-4 * back.pdf);
            assert_eq!(d.eval(&si, -wo, back.wi), d.eval(&si, wo, front.wi));
        }
        // Through the surface, nothing.
        assert_eq!(d.eval(&si, -wo, n), Rgb::ZERO);
        assert_eq!(d.pdf(&si, -wo, n), 0.0);
    }
}
