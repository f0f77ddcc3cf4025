//! `plastic`: a smooth dielectric coating over a diffuse base, Mitsuba 3's
//! `plastic`. Light meets the coating's interface first: a share F(θ) (the
//! dielectric Fresnel reflectance) is reflected as by a mirror; the rest
//! enters, scatters off the Lambertian base, and leaves through the
//! interface again, `1 − F` of it at the other angle, the remainder
//! reflected back down to scatter again. The sum of those internal
//! scatterings is the factor `1 / (1 − F_dr)` with `F_dr` the diffuse
//! Fresnel reflectance of the inside ([`fresnel::diffuse_reflectance`] of
//! `1/η`, Mitsuba's fits); with `nonlinear` the base's colour enters each
//! bounce, `ρ / (1 − ρ F_dr)`, which darkens and saturates colours as wet
//! paint does. So, without the cosine,
//!
//! `f(wo, wi) = ρ (1 − F(θo)) (1 − F(θi)) / (π η² (1 − F_dr))` (diffuse part)
//!
//! plus the delta reflection weighted by `specular_reflectance · F(θo)`.
//! One-sided, as Mitsuba's: black from behind the shading normal.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `diffuse_reflectance` | colour in [0, 1] or texture | `[0.5, 0.5, 0.5]` | the base's albedo |
//! | `specular_reflectance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the coating's reflection (1 for realism) |
//! | `int_ior` | number > 0 or a name | `polypropylene` (1.49) | index of the coating |
//! | `ext_ior` | number > 0 or a name | `air` (1.000277) | index of the outside |
//! | `nonlinear` | bool | `false` | the base's colour in every internal bounce |
//!
//! Its lobes, by slot: 0, delta reflection off the coating (weight
//! `specular_reflectance · F`); 1, diffuse reflection (weight
//! `f · cos / pdf` of a cosine-weighted direction). With no lobe asked for,
//! `sample` takes the specular lobe with probability `F · s / (F · s +
//! (1 − F)(1 − s))`, where `s`, the specular sampling weight, is the mean
//! of `specular_reflectance` over the sum of the means of both colours, and
//! the diffuse lobe otherwise; `pdf` is the diffuse lobe's density times
//! its probability. The means are of the colours at the point: Mitsuba
//! takes the means of whole textures instead, which is the same for plain
//! colours and only moves noise between the lobes for textured ones.

use std::f32::consts::FRAC_1_PI;

use super::fresnel;
use super::ior;
use super::{BsdfModel, Defaults};
use super::nested::choose;
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::conductor::reflectance_texture;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use crate::sampling::SetPoint;
use crate::texture::{Texture, Textures};

/// The smooth plastic (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Plastic {
    pub diffuse_reflectance: Texture,
    pub specular_reflectance: Texture,
    /// `int_ior / ext_ior`.
    pub eta: f32,
    pub nonlinear: bool,
    /// The diffuse Fresnel reflectance of the inside of the coating.
    pub fdr_int: f32,
}

/// The schema entries the plastics share.
pub const PARAMS: [Param; 5] = [
    Param::new(
        "diffuse_reflectance",
        Type::ColourTexture,
        "[0.5, 0.5, 0.5]",
        "the albedo of the diffuse base, each channel in [0, 1]",
    ).range(Range::Unit),
    Param::new(
        "specular_reflectance",
        Type::ColourTexture,
        "[1, 1, 1]",
        "a factor on the coating's reflection, each channel in [0, 1] (1 for realism)",
    ).range(Range::Unit),
    Param::new(
        "int_ior",
        Type::NumberOrChoice("index of refraction", &ior::DIELECTRIC_NAMES),
        "polypropylene (1.49)",
        "index of refraction of the coating: a number > 0 or a name",
    ).range(Range::Positive),
    Param::new(
        "ext_ior",
        Type::NumberOrChoice("index of refraction", &ior::DIELECTRIC_NAMES),
        "air (1.000277)",
        "index of refraction of the outside: a number > 0 or a name",
    ).range(Range::Positive),
    Param::new(
        "nonlinear",
        Type::Bool,
        "false",
        "the base's colour enters every internal bounce (darker, more saturated colours)",
    ),
];

/// What the plastics read alike: the diffuse and specular colours (plain or
/// textures), the relative index and `nonlinear`.
pub fn read_common(p: &Props, textures: &Textures) -> Result<Common, Invalid> {
    let diffuse = reflectance_texture(p, textures, "diffuse_reflectance", Rgb::splat(0.5))?;
    let specular = reflectance_texture(p, textures, "specular_reflectance", Rgb::ONE)?;
    let int = ior::read_dielectric(p, "int_ior", "polypropylene")?;
    let ext = ior::read_dielectric(p, "ext_ior", "air")?;
    let nonlinear = p.bool("nonlinear")?.unwrap_or(false);
    Ok(Common {
        diffuse,
        specular,
        eta: int / ext,
        nonlinear,
    })
}

/// The parameters the plastics share, as read by [`read_common`].
#[derive(Clone, Debug)]
pub struct Common {
    pub diffuse: Texture,
    pub specular: Texture,
    /// `int_ior / ext_ior`.
    pub eta: f32,
    pub nonlinear: bool,
}

/// The share of samples steered to the specular lobe: the specular
/// colour's mean over the sum of both means (Mitsuba's weight).
pub fn specular_sampling_weight(diffuse: Rgb, specular: Rgb) -> f32 {
    let (d, s) = (mean(diffuse), mean(specular));
    if d + s > 0.0 {
        s / (d + s)
    } else {
        1.0
    }
}

fn mean(c: Rgb) -> f32 {
    (c.r + c.g + c.b) / 3.0
}

/// The diffuse base's albedo after the internal bounces: `ρ / (1 − F_dr)`,
/// or `ρ / (1 − ρ F_dr)` when `nonlinear`.
pub fn internal_scattering(diffuse: Rgb, fdr_int: f32, nonlinear: bool) -> Rgb {
    let f = |d: f32| {
        let denom = 1.0 - if nonlinear { d * fdr_int } else { fdr_int };
        if denom > 0.0 {
            d / denom
        } else {
            0.0
        }
    };
    Rgb::new(f(diffuse.r), f(diffuse.g), f(diffuse.b))
}

const SPECULAR: BsdfFlags = BsdfFlags::DELTA.union(BsdfFlags::REFLECTION);
const DIFFUSE: BsdfFlags = BsdfFlags::DIFFUSE.union(BsdfFlags::REFLECTION);

impl Plastic {
    /// The plastic of these parameters (`eta` = `int_ior / ext_ior`).
    pub fn new(c: Common) -> Plastic {
        Plastic {
            diffuse_reflectance: c.diffuse,
            specular_reflectance: c.specular,
            eta: c.eta,
            nonlinear: c.nonlinear,
            fdr_int: fresnel::diffuse_reflectance(1.0 / c.eta),
        }
    }

    /// The base's albedo at the point (the one place it is read).
    fn diffuse(&self, si: &SurfaceInteraction) -> Rgb {
        self.diffuse_reflectance.eval(si)
    }

    /// The factor on the coating's reflection at the point.
    fn specular(&self, si: &SurfaceInteraction) -> Rgb {
        self.specular_reflectance.eval(si)
    }

    /// The share of samples steered to the specular lobe at the point.
    pub fn specular_sampling_weight(&self, si: &SurfaceInteraction) -> f32 {
        specular_sampling_weight(self.diffuse(si), self.specular(si))
    }

    /// The probability of sampling the specular lobe where the coating
    /// reflects `f_i`, at the point.
    fn prob_specular(&self, si: &SurfaceInteraction, f_i: f32) -> f32 {
        let w = self.specular_sampling_weight(si);
        let s = f_i * w;
        let d = (1.0 - f_i) * (1.0 - w);
        if s + d > 0.0 {
            s / (s + d)
        } else {
            0.0
        }
    }

    /// The diffuse part of `eval` for the local cosines `co`, `ci` (both > 0).
    fn diffuse_value(&self, si: &SurfaceInteraction, co: f32, ci: f32) -> Rgb {
        let (f_o, f_i) = (
            fresnel::dielectric(co, self.eta).r,
            fresnel::dielectric(ci, self.eta).r,
        );
        internal_scattering(self.diffuse(si), self.fdr_int, self.nonlinear)
            * ((1.0 - f_o) * (1.0 - f_i) * FRAC_1_PI / (self.eta * self.eta))
    }
}

impl BsdfModel for Plastic {
    const NAME: &'static str = "plastic";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "plastic",
        what: "plastic material",
        doc: "a smooth dielectric coating over a diffuse base, with the internal scattering",
        mitsuba: &["plastic"],
        params: &PARAMS,
    };

    fn build(p: &Props, d: &Defaults) -> Result<Plastic, Invalid> {
        Ok(Plastic::new(read_common(p, d.textures)?))
    }

    /// Mitsuba's `eval_diffuse_reflectance`: the diffuse reflectance under the coating.
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, _wo: Vec3) -> Rgb {
        self.diffuse_reflectance.eval(si)
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = SPECULAR;
        l.flags[1] = DIFFUSE;
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        let (co, ci) = (si.n.dot(wo), si.n.dot(wi));
        if co <= 0.0 || ci <= 0.0 {
            return Rgb::ZERO;
        }
        self.diffuse_value(si, co, ci)
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let co = si.n.dot(wo);
        if co <= 0.0 {
            return None;
        }
        let f_o = fresnel::dielectric(co, self.eta).r;
        let (k, choice, u) = match lobe {
            Some(k) => (k, 1.0, u),
            None => {
                let p = self.prob_specular(si, f_o);
                match choose(u, p) {
                    (true, u) => (0, p, u),
                    (false, u) => (1, 1.0 - p, u),
                }
            }
        };
        match k {
            0 => Some(BsdfSample {
                wi: 2.0 * co * si.n - wo,
                weight: self.specular(si) * (f_o / choice),
                pdf: choice,
                flags: SPECULAR,
                lobe: 0,
                eta: 1.0,
            }),
            1 => {
                let local = square_to_cosine_hemisphere(u.square());
                if local.z <= 0.0 {
                    return None;
                }
                let wi = si.shading_frame().to_world(local);
                let ci = wi.dot(si.n);
                if ci <= 0.0 {
                    return None;
                }
                let pdf = choice * square_to_cosine_hemisphere_pdf(local);
                Some(BsdfSample {
                    wi,
                    weight: self.diffuse_value(si, co, ci) * (ci / pdf),
                    pdf,
                    flags: DIFFUSE,
                    lobe: 1,
                    eta: 1.0,
                })
            }
            _ => None,
        }
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        let (co, ci) = (si.n.dot(wo), si.n.dot(wi));
        if co <= 0.0 || ci <= 0.0 {
            return 0.0;
        }
        let p = 1.0 - self.prob_specular(si, fresnel::dielectric(co, self.eta).r);
        p * ci * FRAC_1_PI
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{self, build, check_weights, interaction, sampled_albedo, smooth_p_value};

    fn views() -> [Vec3; 4] {
        [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.2, 0.77).normalize(),
            Vec3::new(-0.3, 0.9, 0.15).normalize(),
            Vec3::new(0.1, -0.995, 0.02).normalize(),
        ]
    }

    fn models() -> Vec<(&'static str, Plastic)> {
        [
            "",
            "diffuse_reflectance = [0.9, 0.2, 0.05]\nnonlinear = true",
            "diffuse_reflectance = [1, 1, 1]\nint_ior = 1.9",
            "specular_reflectance = [0.3, 0.3, 0.3]\next_ior = \"water\"",
        ]
        .into_iter()
        .map(|t| (t, build::<Plastic>(t).unwrap()))
        .collect()
    }

    /// The diffuse lobe's directions follow `pdf` (χ², the specular
    /// samples counted as draws that give no direction, which `pdf`
    /// integrating to the diffuse lobe's probability requires).
    #[test]
    fn sampling_passes_chi2() {
        let si = interaction(Vec3::Z);
        chi2::assert_samplers_pass(models(), &views(), &si, smooth_p_value);
    }

    /// Weights are eval·cos/pdf; eval is reciprocal; the albedo (of all
    /// lobes, by sampling) is at most 1; nothing from behind.
    #[test]
    fn weights_reciprocity_and_energy() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        for (text, m) in models() {
            for wo in views().map(|v| frame.to_world(v)) {
                check_weights(&m, &si, wo, 20_000);
                let (a, err) = sampled_albedo(&m, &si, wo, 200_000);
                assert!(a.max_element() <= 1.0 + 4.0 * err + 2e-3, "{text}: albedo {a:?} ± {err}");
                for wi in views().map(|v| frame.to_world(Vec3::new(-v.y, v.x, v.z))) {
                    let (a, b) = (m.eval(&si, wo, wi), m.eval(&si, wi, wo));
                    assert!((a - b).abs().max_element() <= 1e-6, "{text}");
                }
            }
            assert_eq!(m.eval(&si, -n, n), Rgb::ZERO);
            assert!(m.sample(&si, -n, None, SetPoint::uniform(crate::math::Vec2::splat(0.5))).is_none());
        }
    }

    /// Energy against known answers: a black base reflects the Fresnel
    /// reflectance alone; a white base of the linear model at normal view
    /// reflects `F + (1 − F)(1 − F_dr,ext) / (η² (1 − F_dr,int))`, the
    /// outer diffuse reflectance integrated here, not fitted — nearly 1, as
    /// `(1 − F_dr,ext) / η² = 1 − F_dr,int` for a lossless interface.
    #[test]
    fn albedo_meets_its_limits() {
        let si = interaction(Vec3::Z);
        let black = build::<Plastic>("diffuse_reflectance = [0, 0, 0]").unwrap();
        for v in views() {
            let (a, err) = sampled_albedo(&black, &si, v, 40_000);
            let f = fresnel::dielectric(v.z, black.eta).r;
            assert!(err < 1e-3 * f && (a - Rgb::splat(f)).abs().max_element() < 1e-3 * f, "{a:?} vs {f}");
        }
        let white = build::<Plastic>("diffuse_reflectance = [1, 1, 1]").unwrap();
        let eta = white.eta;
        let n = 100_000;
        let fdr_ext: f64 = (0..n)
            .map(|i| {
                let mu = (i as f64 + 0.5) / n as f64;
                2.0 * f64::from(fresnel::dielectric(mu as f32, eta).r) * mu / n as f64
            })
            .sum();
        let f = f64::from(fresnel::dielectric(1.0, eta).r);
        let want = f + (1.0 - f) * (1.0 - fdr_ext) / (f64::from(eta).powi(2) * (1.0 - f64::from(white.fdr_int)));
        let (a, err) = sampled_albedo(&white, &si, Vec3::Z, 1_000_000);
        let got = f64::from(a.r);
        assert!((got - want).abs() < 4.0 * f64::from(err) + 2e-3, "{got} vs {want} ± {err}");
        assert!((want - 1.0).abs() < 0.01, "{want}");
    }

    /// Mitsuba's defaults and range checks.
    #[test]
    fn parameters() {
        let m = build::<Plastic>("").unwrap();
        assert!((m.eta - 1.49 / 1.000277).abs() < 1e-6);
        assert_eq!(
            (m.diffuse_reflectance.constant(), m.specular_reflectance.constant(), m.nonlinear),
            (Some(Rgb::splat(0.5)), Some(Rgb::ONE), false)
        );
        assert!((m.specular_sampling_weight(&interaction(Vec3::Z)) - 1.0 / 1.5).abs() < 1e-6);
        for (text, want) in [
            ("diffuse_reflectance = [1.2, 0, 0]", "must not exceed 1"),
            ("int_ior = -1", "must be a positive number"),
            ("int_ior = \"glass\"", "index of refraction"),
            ("nonlinear = 1", "expected a boolean"),
        ] {
            let e = build::<Plastic>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
