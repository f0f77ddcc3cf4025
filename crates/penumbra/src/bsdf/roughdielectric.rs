//! `roughdielectric`: a rough interface between two dielectrics (frosted
//! glass), Mitsuba 3's `roughdielectric`: the microfacet reflection and
//! transmission of Walter et al. (2007) with a Beckmann or GGX
//! distribution ([`microfacet`](super::microfacet)), the separable Smith G
//! and the dielectric Fresnel reflectance at each facet. Two-sided, the
//! normal pointing outside, as [`dielectric`](super::dielectric).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `int_ior` | number > 0 or a name | `bk7` (1.5046) | index of the inside |
//! | `ext_ior` | number > 0 or a name | `air` (1.000277) | index of the outside; must differ from `int_ior` |
//! | `distribution` | `beckmann`, `ggx` | `beckmann` | the microfacet distribution |
//! | `alpha` | number ≥ 0 or texture | `0.1` | roughness along both tangents |
//! | `alpha_u`, `alpha_v` | number ≥ 0 or texture | `alpha` | anisotropic roughness (both, not with `alpha`) |
//! | `sample_visible` | bool | `true` | sample the visible normals (else the whole distribution) |
//! | `specular_reflectance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the reflection |
//! | `specular_transmittance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the transmission |
//!
//! With `h` the half vector of the viewer's direction `wo` and the light's
//! `wi` (`wo + wi` for reflection, `wo + η wi` for transmission, η the
//! index of the light's side over the viewer's, turned to the outside),
//! the value is `F D G / (4 |cos θo| |cos θi|)` for reflection and
//! `(1 − F) D G |wo·h| |wi·h| / (|cos θo| |cos θi| (wo·h + η wi·h)²)` for
//! transmission: Walter's, times 1/η² for radiance (which cancels its η²),
//! as Mitsuba in radiance mode.
//!
//! Its lobes: slot 0 glossy reflection, slot 1 glossy transmission; the
//! Whitted integrator lights them directly through `eval` (light from the
//! viewer's side only: shadow rays do not cross the surface). `sample`
//! with a lobe asked for draws that lobe (reflection about, or refraction
//! through, a normal of the visible normals of `wo`); with none, it draws
//! the facet from the point and picks reflection with the probability of
//! the facet's Fresnel reflectance, by a third number, as Mitsuba does:
//! each lobe then weighs its `G1` alone. The third number is a path
//! sampler's own dimension in `path`, `direct` and `distributed`'s paths,
//! and a hash of the point where a set draws the points
//! ([`SetPoint::third`]).

use super::conductor::{factor, SPECULAR_REFLECTANCE};
use super::dielectric::{read_eta, IOR_PARAMS, SPECULAR_TRANSMITTANCE};
use super::fresnel;
use super::microfacet::{Microfacet, Roughness, PARAMS};
use super::{BsdfModel, Defaults};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use crate::description::{Invalid, Kind, Props, Schema};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::SetPoint;
use crate::texture::Texture;

/// The rough dielectric (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct RoughDielectric {
    pub distribution: Roughness,
    /// `int_ior / ext_ior`.
    pub eta: f32,
    pub specular_reflectance: Texture,
    pub specular_transmittance: Texture,
}

const REFLECTION: BsdfFlags = BsdfFlags::GLOSSY.union(BsdfFlags::REFLECTION);
const TRANSMISSION: BsdfFlags = BsdfFlags::GLOSSY.union(BsdfFlags::TRANSMISSION);

/// A pair of directions in the shading frame, turned so that the viewer is
/// outside (`o.z > 0`), with the relative index of the light's side over
/// the viewer's.
struct Local {
    o: Vec3,
    i: Vec3,
    eta: f32,
    reflect: bool,
    /// The half vector, on the outside.
    h: Vec3,
}

impl RoughDielectric {
    fn local(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Option<Local> {
        let frame = si.shading_frame();
        let (mut o, mut i) = (frame.to_local(wo), frame.to_local(wi));
        if o.z == 0.0 || i.z == 0.0 {
            return None;
        }
        let mut eta = self.eta;
        if o.z < 0.0 {
            (o, i, eta) = (-o, -i, 1.0 / eta);
        }
        let reflect = i.z > 0.0;
        let h = if reflect { o + i } else { o + i * eta };
        let len = h.length();
        if len.is_nan() || len <= 0.0 {
            return None;
        }
        let h = h / len;
        let h = if h.z < 0.0 { -h } else { h };
        // Both directions on the facet's proper sides.
        if o.dot(h) <= 0.0 || i.dot(h) * i.z <= 0.0 {
            return None;
        }
        Some(Local {
            o,
            i,
            eta,
            reflect,
            h,
        })
    }

    /// The Fresnel reflectance of the facet the point `u` draws (the
    /// probability of choosing reflection, as Mitsuba's); `None` where it
    /// draws none the viewer sees.
    fn facet_fresnel(&self, si: &SurfaceInteraction, wo: Vec3, u: Vec2) -> Option<f32> {
        let o0 = si.shading_frame().to_local(wo);
        if o0.z == 0.0 {
            return None;
        }
        let (o, eta) = if o0.z < 0.0 { (-o0, 1.0 / self.eta) } else { (o0, self.eta) };
        let (m, pdf_m) = self.distribution.at(si).sample(o, u);
        let om = o.dot(m);
        if pdf_m.is_nan() || pdf_m <= 0.0 || om <= 0.0 {
            return None;
        }
        Some(fresnel::dielectric(om, eta).r)
    }

    /// The lobe's density (not times a choice) of `l`.
    fn lobe_pdf(&self, d: &Microfacet, l: &Local) -> f32 {
        let pm = d.pdf(l.o, l.h);
        if l.reflect {
            pm / (4.0 * l.i.dot(l.h))
        } else {
            let (oh, ih) = (l.o.dot(l.h), l.i.dot(l.h));
            let denom = oh + l.eta * ih;
            pm * l.eta * l.eta * ih.abs() / (denom * denom)
        }
    }

    /// Lobe `k`'s direction for the point `u`, its weight and density (not
    /// divided by a choice).
    fn sample_lobe(&self, si: &SurfaceInteraction, wo: Vec3, k: usize, u: Vec2) -> Option<(Vec3, Rgb, f32)> {
        let frame = si.shading_frame();
        let o0 = frame.to_local(wo);
        if o0.z == 0.0 {
            return None;
        }
        let (o, eta) = if o0.z < 0.0 { (-o0, 1.0 / self.eta) } else { (o0, self.eta) };
        let d = &self.distribution.at(si);
        let (m, pdf_m) = d.sample(o, u);
        let om = o.dot(m);
        if pdf_m.is_nan() || pdf_m <= 0.0 || om <= 0.0 {
            return None;
        }
        let f = fresnel::dielectric(om, eta);
        let i = if k == 0 {
            2.0 * om * m - o
        } else {
            if f.r >= 1.0 {
                return None;
            }
            (m * (f.eta_ti * om + f.cos_t) - o * f.eta_ti).normalize()
        };
        if (k == 0) != (i.z > 0.0) {
            return None;
        }
        let wi = frame.to_world(if o0.z < 0.0 { -i } else { i });
        // The weight from the half vector of the pair as `eval` and `pdf`
        // find it (the drawn normal up to rounding, which near the
        // critical angle moves the Fresnel factor).
        let l = self.local(si, wo, wi)?;
        let (h, i) = (l.h, l.i);
        let oh = o.dot(h);
        let f = fresnel::dielectric(oh, eta);
        let value = if k == 0 {
            self.specular_reflectance.eval(si) * f.r
        } else {
            self.specular_transmittance.eval(si) * ((1.0 - f.r) * f.eta_ti * f.eta_ti)
        };
        let shadowing = if d.sample_visible {
            d.g1(i, h)
        } else {
            d.g(o, i, h) * oh / (o.z * h.z)
        };
        let pdf = self.lobe_pdf(d, &l);
        (shadowing > 0.0 && pdf > 0.0).then_some((wi, value * shadowing, pdf))
    }
}

impl BsdfModel for RoughDielectric {
    const NAME: &'static str = "roughdielectric";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "roughdielectric",
        what: "rough dielectric material",
        doc: "a rough dielectric interface: microfacet reflection and transmission",
        mitsuba: &["roughdielectric"],
        params: &[
            IOR_PARAMS[0],
            IOR_PARAMS[1],
            PARAMS[0],
            PARAMS[1],
            PARAMS[2],
            PARAMS[3],
            PARAMS[4],
            SPECULAR_REFLECTANCE,
            SPECULAR_TRANSMITTANCE,
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<RoughDielectric, Invalid> {
        let eta = read_eta(p)?;
        if eta == 1.0 {
            return Err(p.error(
                "int_ior",
                "must differ from `ext_ior` (an interface of one index is not there)",
            ));
        }
        Ok(RoughDielectric {
            distribution: Microfacet::read_textured(p, d.textures)?,
            eta,
            specular_reflectance: factor(p, d.textures, "specular_reflectance")?,
            specular_transmittance: factor(p, d.textures, "specular_transmittance")?,
        })
    }

    fn lobes(&self) -> Lobes {
        Lobes::reflection_and_transmission(BsdfFlags::GLOSSY)
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        let Some(l) = self.local(si, wo, wi) else {
            return Rgb::ZERO;
        };
        let d = &self.distribution.at(si);
        let dg = d.d(l.h) * d.g(l.o, l.i, l.h);
        if dg.is_nan() || dg <= 0.0 {
            return Rgb::ZERO;
        }
        let (oh, ih) = (l.o.dot(l.h), l.i.dot(l.h));
        let f = fresnel::dielectric(oh, l.eta).r;
        let cos = l.o.z * l.i.z.abs();
        if l.reflect {
            self.specular_reflectance.eval(si) * (f * dg / (4.0 * cos))
        } else {
            let denom = oh + l.eta * ih;
            let t = (1.0 - f) * dg * (oh * ih).abs() / (cos * denom * denom);
            self.specular_transmittance.eval(si) * t
        }
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let sq = u.square();
        let k = match lobe {
            Some(k @ (0 | 1)) => k,
            Some(_) => return None,
            // As Mitsuba: the facet drawn from the point, then reflection
            // with the probability of its Fresnel factor, by the third number.
            None => usize::from(u.third() >= self.facet_fresnel(si, wo, sq)?),
        };
        let (wi, weight, pdf) = self.sample_lobe(si, wo, k, sq)?;
        // The choice's probability as `pdf` finds it, from the pair's half
        // vector (the drawn facet up to rounding).
        let p = match lobe {
            Some(_) => 1.0,
            None => {
                let l = self.local(si, wo, wi)?;
                let f = fresnel::dielectric(l.o.dot(l.h), l.eta).r;
                if k == 0 {
                    f
                } else {
                    1.0 - f
                }
            }
        };
        if p <= 0.0 {
            return None;
        }
        let eta = match (k, wo.dot(si.n) < 0.0) {
            (0, _) => 1.0,
            (_, true) => 1.0 / self.eta,
            (_, false) => self.eta,
        };
        Some(BsdfSample {
            wi,
            weight: weight * (1.0 / p),
            pdf: pdf * p,
            flags: if k == 0 { REFLECTION } else { TRANSMISSION },
            lobe: k,
            eta,
        })
    }

    /// The density of `sample` with no lobe asked for.
    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        let Some(l) = self.local(si, wo, wi) else {
            return 0.0;
        };
        let f = fresnel::dielectric(l.o.dot(l.h), l.eta).r;
        self.lobe_pdf(&self.distribution.at(si), &l) * if l.reflect { f } else { 1.0 - f }
    }

    /// The lobe is chosen by the drawn facet's Fresnel factor.
    fn wants_third(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{
        self, albedo, build, check_weights, interaction, model_p_value, views,
    };

    fn models() -> Vec<(String, RoughDielectric)> {
        let mut all = Vec::new();
        for dist in ["beckmann", "ggx"] {
            for visible in [true, false] {
                for rough in ["alpha = 0.1", "alpha = 0.5", "alpha_u = 0.1\nalpha_v = 0.4"] {
                    let text = format!("distribution = \"{dist}\"\n{rough}\nsample_visible = {visible}");
                    all.push((text.clone(), build::<RoughDielectric>(&text).unwrap()));
                }
            }
        }
        all
    }

    /// The sampler's directions (reflected and transmitted, both sides)
    /// follow its pdf.
    #[test]
    fn sampling_passes_chi2() {
        let si = interaction(Vec3::Z);
        chi2::assert_samplers_pass(models(), &views(), &si, model_p_value);
    }

    /// Weights are eval·cos/pdf, with a lobe asked for or not; reflection
    /// is reciprocal; from outside the albedo is at most 1; with visible
    /// normals a lobe asked for weighs at most its Fresnel part (times the
    /// radiance scale).
    #[test]
    fn weights_reciprocity_and_energy() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        for (text, m) in models() {
            for wo in views().map(|v| frame.to_world(v)) {
                check_weights(&m, &si, wo, 20_000);
                if wo.dot(n) > 0.0 {
                    let (a, err) = albedo(&m, &si, wo, 250_000);
                    assert!(a.max_element() <= 1.0 + 4.0 * err + 1e-3, "{text}: albedo {a:?} ± {err}");
                }
                for wi in views().map(|v| frame.to_world(Vec3::new(-v.y, v.x, v.z))) {
                    if wi.dot(n) * wo.dot(n) > 0.0 {
                        let (a, b) = (m.eval(&si, wo, wi), m.eval(&si, wi, wo));
                        assert!((a - b).abs().max_element() <= 1e-4 * a.max_element().max(1.0), "{text}");
                    }
                }
                let mut rng = crate::sampling::Rng::new(5);
                for _ in 0..2000 {
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    for k in [0, 1] {
                        let Some(s) = m.sample(&si, wo, Some(k), u) else { continue };
                        let l = m.local(&si, wo, s.wi).expect("a sampled pair");
                        let f = fresnel::dielectric(l.o.dot(l.h), l.eta).r;
                        let p = if k == 0 { f } else { 1.0 - f };
                        let want = m.eval(&si, wo, s.wi) * (s.wi.dot(n).abs() / s.pdf);
                        assert!((s.weight - want).abs().max_element() <= 1e-3 * want.max_element().max(1e-2), "{text} lobe {k}");
                        assert!((s.pdf * p - m.pdf(&si, wo, s.wi)).abs() <= 1e-3 * s.pdf.max(1e-3));
                        if m.distribution.base.sample_visible {
                            assert!(s.weight.max_element() <= 2.3, "{text}: {:?}", s.weight);
                        }
                    }
                }
            }
        }
    }

    /// Parameters are Mitsuba's; equal indices and bad values are refused.
    #[test]
    fn parameters() {
        let m = build::<RoughDielectric>("").unwrap();
        assert!((m.eta - 1.5046 / 1.000277).abs() < 1e-6);
        assert_eq!(m.distribution.base.alpha_u, 0.1);
        for (text, want) in [
            ("int_ior = 1.2\next_ior = 1.2", "must differ from `ext_ior`"),
            ("alpha = -1", "must be between 0 and 100"),
            ("ext_ior = -1", "must be a positive number"),
            ("specular_transmittance = [0, 0, 1.1]", "must not exceed 1"),
        ] {
            let e = build::<RoughDielectric>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
