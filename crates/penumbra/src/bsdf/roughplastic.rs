//! `roughplastic`: a rough dielectric coating over a diffuse base, Mitsuba
//! 3's `roughplastic`: [`plastic`](super::plastic) with the coating's
//! mirror replaced by a microfacet reflection (Walter et al. 2007,
//! `F(wo·h) D(h) G(wo, wi, h) / (4 cos θo cos θi)`, Beckmann or GGX,
//! isotropic as Mitsuba's), and the coating's transmission `1 − F` by the
//! rough interface's: `T(θ)`, the share of light a rough dielectric
//! interface of index η transmits at the angle θ, integrated numerically
//! over the visible normals once per material (64 angles, read by linear
//! interpolation, as Mitsuba). The internal bounces divide the base by
//! `1 − R_int` (or `1 − ρ R_int` when `nonlinear`), `R_int` the rough
//! interface's reflectance from inside averaged under cosine-weighted
//! light (also integrated). So, without the cosine,
//!
//! `f(wo, wi) = specular · F D G / (4 cos θo cos θi) + ρ T(θo) T(θi) / (π η² (1 − R_int))`.
//!
//! One-sided, as Mitsuba's: black from behind the shading normal.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `distribution` | `beckmann`, `ggx` | `beckmann` | the microfacet distribution |
//! | `alpha` | number ≥ 0 | `0.1` | roughness of the coating |
//! | `sample_visible` | bool | `true` | sample the visible normals (else the whole distribution) |
//! | `diffuse_reflectance` | colour in [0, 1] or texture | `[0.5, 0.5, 0.5]` | the base's albedo |
//! | `specular_reflectance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the coating's reflection |
//! | `int_ior` | number > 0 or a name | `polypropylene` (1.49) | index of the coating |
//! | `ext_ior` | number > 0 or a name | `air` (1.000277) | index of the outside |
//! | `nonlinear` | bool | `false` | the base's colour in every internal bounce |
//!
//! Its lobes, by slot: 0, glossy reflection off the coating; 1, diffuse
//! reflection. With no lobe asked for, `sample` picks the glossy lobe with
//! probability `(1 − T) s / ((1 − T) s + T (1 − s))` (`s` the specular
//! sampling weight of [`plastic`](super::plastic), `T` at the view), draws
//! a microfacet normal and reflects, or draws a cosine-weighted direction;
//! either way the weight is `eval · cos / pdf` with `pdf` the mixture's.

use std::f32::consts::FRAC_1_PI;
use std::sync::Arc;

use super::dielectric::refract;
use super::fresnel;
use super::microfacet::{Microfacet, PARAMS as MICROFACET};
use super::{BsdfModel, Defaults};
use super::nested::choose;
use super::plastic::{internal_scattering, read_common, specular_sampling_weight, Common, PARAMS};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use crate::sampling::SetPoint;
use crate::texture::Texture;

/// Angles of the transmittance table (uniform in cos θ over [0, 1]).
pub const TABLE: usize = 64;

/// Points per side of the quadrature over the visible normals.
const QUADRATURE: usize = 48;

/// The rough plastic (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct RoughPlastic {
    pub distribution: Microfacet,
    pub diffuse_reflectance: Texture,
    pub specular_reflectance: Texture,
    /// `int_ior / ext_ior`.
    pub eta: f32,
    pub nonlinear: bool,
    /// The rough interface's transmittance from outside at cos θ = `i / (TABLE − 1)`.
    pub transmittance: Arc<[f32; TABLE]>,
    /// The rough interface's diffuse reflectance from inside.
    pub internal_reflectance: f32,
}

const GLOSSY: BsdfFlags = BsdfFlags::GLOSSY.union(BsdfFlags::REFLECTION);
const DIFFUSE: BsdfFlags = BsdfFlags::DIFFUSE.union(BsdfFlags::REFLECTION);

/// The direction of cosine `mu` in the xz plane.
fn at_cosine(mu: f32) -> Vec3 {
    let mu = mu.max(1e-6);
    Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu)
}

/// The mean over a midpoint grid of visible normals of `wi` of `f(m)`:
/// the expectation of `f` under the distribution of normals seen from `wi`.
fn over_visible_normals(d: &Microfacet, wi: Vec3, f: impl Fn(Vec3) -> f32) -> f32 {
    let mut sum = 0.0f64;
    for a in 0..QUADRATURE {
        for b in 0..QUADRATURE {
            let u = Vec2::new(
                (a as f32 + 0.5) / QUADRATURE as f32,
                (b as f32 + 0.5) / QUADRATURE as f32,
            );
            sum += f64::from(f(d.sample_visible_normal(wi, u)));
        }
    }
    (sum / (QUADRATURE * QUADRATURE) as f64) as f32
}

/// The share of light arriving from `wi` (above) that a rough interface of
/// relative index `eta` transmits once: `(1 − F) G1` of the refracted
/// direction, over the visible normals.
pub fn rough_transmittance(d: &Microfacet, wi: Vec3, eta: f32) -> f32 {
    over_visible_normals(d, wi, |m| {
        let f = fresnel::dielectric(wi.dot(m), eta);
        if f.r >= 1.0 {
            return 0.0;
        }
        let t = refract(wi, m, &f);
        if t.z * wi.z >= 0.0 {
            return 0.0;
        }
        (1.0 - f.r) * d.g1(t, m)
    })
}

/// The share of light arriving from `wi` (above) that a rough interface of
/// relative index `eta` reflects once: `F G1` of the reflected direction.
pub fn rough_reflectance(d: &Microfacet, wi: Vec3, eta: f32) -> f32 {
    over_visible_normals(d, wi, |m| {
        let c = wi.dot(m);
        let r = 2.0 * c * m - wi;
        if r.z <= 0.0 {
            return 0.0;
        }
        fresnel::dielectric(c, eta).r * d.g1(r, m)
    })
}

impl RoughPlastic {
    /// The rough plastic of these parameters; the coating's tables are
    /// integrated here.
    pub fn new(distribution: Microfacet, c: Common) -> RoughPlastic {
        let eta = c.eta;
        // The tables are of the distribution itself, whatever the sampler.
        let d = Microfacet {
            sample_visible: true,
            ..distribution
        };
        let mut transmittance = [0.0; TABLE];
        let mut internal = 0.0;
        for (i, t) in transmittance.iter_mut().enumerate() {
            let mu = i as f32 / (TABLE - 1) as f32;
            let wi = at_cosine(mu);
            *t = rough_transmittance(&d, wi, eta);
            internal += rough_reflectance(&d, wi, 1.0 / eta) * wi.z;
        }
        RoughPlastic {
            distribution,
            diffuse_reflectance: c.diffuse,
            specular_reflectance: c.specular,
            eta,
            nonlinear: c.nonlinear,
            transmittance: Arc::new(transmittance),
            internal_reflectance: 2.0 * internal / TABLE as f32,
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

    /// The coating's transmittance at the cosine `c` (interpolated).
    pub fn transmittance_at(&self, c: f32) -> f32 {
        let x = c.clamp(0.0, 1.0) * (TABLE - 1) as f32;
        let i = (x as usize).min(TABLE - 2);
        let t = x - i as f32;
        self.transmittance[i] * (1.0 - t) + self.transmittance[i + 1] * t
    }

    /// The probability of sampling the glossy lobe where the coating
    /// transmits `t_o` toward the view, at the point (the specular sampling
    /// weight of the colours there, as for [`plastic`](super::plastic)).
    fn prob_specular(&self, si: &SurfaceInteraction, t_o: f32) -> f32 {
        let w = specular_sampling_weight(self.diffuse(si), self.specular(si));
        let s = (1.0 - t_o) * w;
        let d = t_o * (1.0 - w);
        if s + d > 0.0 {
            s / (s + d)
        } else {
            0.0
        }
    }

    /// The glossy and the diffuse parts of `eval` for local `o`, `i`
    /// (both above).
    fn parts(&self, si: &SurfaceInteraction, o: Vec3, i: Vec3) -> (Rgb, Rgb) {
        let h = (o + i).normalize();
        let m = &self.distribution;
        let dg = m.d(h) * m.g(o, i, h);
        let glossy = if dg > 0.0 {
            self.specular(si) * (fresnel::dielectric(o.dot(h), self.eta).r * dg / (4.0 * o.z * i.z))
        } else {
            Rgb::ZERO
        };
        let t = self.transmittance_at(o.z) * self.transmittance_at(i.z);
        let diffuse = internal_scattering(self.diffuse(si), self.internal_reflectance, self.nonlinear)
            * (t * FRAC_1_PI / (self.eta * self.eta));
        (glossy, diffuse)
    }

    /// The densities of the two lobes for local `o`, `i` (both above).
    fn densities(&self, o: Vec3, i: Vec3) -> (f32, f32) {
        let h = (o + i).normalize();
        let ih = i.dot(h);
        let glossy = if o.dot(h) > 0.0 && ih > 0.0 {
            self.distribution.pdf(o, h) / (4.0 * ih)
        } else {
            0.0
        };
        (glossy, square_to_cosine_hemisphere_pdf(i))
    }
}

impl BsdfModel for RoughPlastic {
    const NAME: &'static str = "roughplastic";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "roughplastic",
        what: "rough plastic material",
        doc: "a rough dielectric coating over a diffuse base",
        mitsuba: &["roughplastic"],
        params: &[
            MICROFACET[0],
            // A number, as Mitsuba's: the coating's tables are integrated
            // once for it when the material is built.
            Param::new(
                "alpha",
                Type::Number,
                "0.1",
                "roughness ≥ 0 (RMS slope for Beckmann), along both tangents",
            ).range(Range::Between(0.0, 100.0)),
            MICROFACET[4],
            PARAMS[0],
            PARAMS[1],
            PARAMS[2],
            PARAMS[3],
            PARAMS[4],
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<RoughPlastic, Invalid> {
        let distribution = Microfacet::read(p)?;
        Ok(RoughPlastic::new(distribution, read_common(p, d.textures)?))
    }

    /// Mitsuba's `eval_diffuse_reflectance`: the diffuse reflectance under the coating.
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, _wo: Vec3) -> Rgb {
        self.diffuse_reflectance.eval(si)
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = GLOSSY;
        l.flags[1] = DIFFUSE;
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        let frame = si.shading_frame();
        let (o, i) = (frame.to_local(wo), frame.to_local(wi));
        if o.z <= 0.0 || i.z <= 0.0 {
            return Rgb::ZERO;
        }
        let (g, d) = self.parts(si, o, i);
        g + d
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let frame = si.shading_frame();
        let o = frame.to_local(wo);
        if o.z <= 0.0 {
            return None;
        }
        let p = self.prob_specular(si, self.transmittance_at(o.z));
        let (k, u) = match lobe {
            Some(k) => (k, u),
            None => match choose(u, p) {
                (true, u) => (0, u),
                (false, u) => (1, u),
            },
        };
        let i = match k {
            0 => {
                let (m, _) = self.distribution.sample(o, u.square());
                let om = o.dot(m);
                if om.is_nan() || om <= 0.0 {
                    return None;
                }
                2.0 * om * m - o
            }
            1 => square_to_cosine_hemisphere(u.square()),
            _ => return None,
        };
        if i.z <= 0.0 {
            return None;
        }
        let (g, d) = self.parts(si, o, i);
        let (pg, pd) = self.densities(o, i);
        let (value, pdf) = match lobe {
            Some(0) => (g, pg),
            Some(_) => (d, pd),
            None => (g + d, p * pg + (1.0 - p) * pd),
        };
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: frame.to_world(i),
            weight: value * (i.z / pdf),
            pdf,
            flags: if k == 0 { GLOSSY } else { DIFFUSE },
            lobe: k,
            eta: 1.0,
        })
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        let frame = si.shading_frame();
        let (o, i) = (frame.to_local(wo), frame.to_local(wi));
        if o.z <= 0.0 || i.z <= 0.0 {
            return 0.0;
        }
        let p = self.prob_specular(si, self.transmittance_at(o.z));
        let (pg, pd) = self.densities(o, i);
        p * pg + (1.0 - p) * pd
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{self, albedo, build, check_weights, interaction, model_p_value, sampled_albedo};
    use crate::bsdf::plastic::Plastic;

    fn views() -> [Vec3; 3] {
        [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.2, 0.77).normalize(),
            Vec3::new(-0.3, 0.9, 0.15).normalize(),
        ]
    }

    fn models() -> Vec<(String, RoughPlastic)> {
        let mut all = Vec::new();
        for dist in ["beckmann", "ggx"] {
            for visible in [true, false] {
                for rest in ["alpha = 0.1", "alpha = 0.5\ndiffuse_reflectance = [0.9, 0.3, 0.1]\nnonlinear = true"] {
                    let text = format!("distribution = \"{dist}\"\nsample_visible = {visible}\n{rest}");
                    all.push((text.clone(), build::<RoughPlastic>(&text).unwrap()));
                }
            }
        }
        all
    }

    /// The sampler's directions follow its pdf (χ² over distributions,
    /// samplers, roughnesses and views).
    #[test]
    fn sampling_passes_chi2() {
        let si = interaction(Vec3::Z);
        chi2::assert_samplers_pass(models(), &views(), &si, model_p_value);
    }

    /// Weights are eval·cos/pdf; eval is reciprocal; the albedo is at most
    /// 1 and the same by sampling and by integrating `eval`.
    #[test]
    fn weights_reciprocity_and_energy() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        for (text, m) in models() {
            for wo in views().map(|v| frame.to_world(v)) {
                check_weights(&m, &si, wo, 20_000);
                let (a, err) = sampled_albedo(&m, &si, wo, 200_000);
                let (b, err_b) = albedo(&m, &si, wo, 250_000);
                assert!(a.max_element() <= 1.0 + 4.0 * err + 2e-3, "{text}: albedo {a:?} ± {err}");
                assert!((a - b).abs().max_element() <= 4.0 * (err + err_b) + 2e-3, "{text}: {a:?} vs {b:?}");
                for wi in views().map(|v| frame.to_world(Vec3::new(-v.y, v.x, v.z))) {
                    let (x, y) = (m.eval(&si, wo, wi), m.eval(&si, wi, wo));
                    assert!((x - y).abs().max_element() <= 1e-5 * x.max_element().max(1.0), "{text}");
                }
            }
            assert_eq!(m.eval(&si, -n, n), Rgb::ZERO);
            assert!(m.sample(&si, -n, None, SetPoint::uniform(Vec2::splat(0.5))).is_none());
        }
    }

    /// A nearly smooth coating is the smooth plastic: its transmittance is
    /// `1 − F`, its internal reflectance the diffuse Fresnel reflectance,
    /// and its albedo the plastic's: to 1% with a black base, to 3% with a
    /// white one (the internal reflectance is a mean over 64 cosines, as
    /// Mitsuba's, about 1% off the plastic's fit, and a white base's light
    /// is divided by `1 − R ≈ 0.4`).
    #[test]
    fn a_smooth_coating_is_the_plastic() {
        let m = build::<RoughPlastic>("alpha = 0.005").unwrap();
        for mu in [0.05f32, 0.3, 0.7, 1.0] {
            let want = 1.0 - fresnel::dielectric(mu, m.eta).r;
            let got = m.transmittance_at(mu);
            assert!((got - want).abs() < 0.01, "cos {mu}: {got} vs {want}");
        }
        let fdr = fresnel::diffuse_reflectance(1.0 / m.eta);
        assert!((m.internal_reflectance - fdr).abs() < 0.01 * fdr + 0.005, "{} vs {fdr}", m.internal_reflectance);
        let si = interaction(Vec3::Z);
        for (base, tolerance) in [("[0, 0, 0]", 0.01), ("[1, 1, 1]", 0.03)] {
            let text = format!("alpha = 0.005\ndiffuse_reflectance = {base}");
            let rough = build::<RoughPlastic>(&text).unwrap();
            let smooth = build::<Plastic>(&format!("diffuse_reflectance = {base}")).unwrap();
            for wo in views() {
                let (a, ea) = sampled_albedo(&rough, &si, wo, 200_000);
                let (b, eb) = sampled_albedo(&smooth, &si, wo, 200_000);
                assert!((a - b).abs().max_element() <= 4.0 * (ea + eb) + tolerance, "{base} {wo:?}: {a:?} vs {b:?}");
            }
        }
    }

    /// Mitsuba's defaults; bad values refused.
    #[test]
    fn parameters() {
        let m = build::<RoughPlastic>("").unwrap();
        assert_eq!(
            m.distribution,
            Microfacet::new(super::super::microfacet::Kind::Beckmann, 0.1, 0.1, true)
        );
        assert!((m.eta - 1.49 / 1.000277).abs() < 1e-6);
        assert_eq!(m.diffuse_reflectance.constant(), Some(Rgb::splat(0.5)));
        for (text, want) in [
            ("alpha = -1", "must be between 0 and 100"),
            ("distribution = \"phong\"", "unknown microfacet distribution"),
            ("diffuse_reflectance = [0, 2, 0]", "must not exceed 1"),
        ] {
            let e = build::<RoughPlastic>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
