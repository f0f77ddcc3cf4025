//! `roughconductor`: a rough metal, Mitsuba 3's `roughconductor`: the
//! Cook–Torrance microfacet reflection of Walter et al. (2007),
//! `F(wi·h) D(h) G(wo, wi, h) / (4 cos θo cos θi)` with `h` the half
//! vector, the conductor Fresnel reflectance of `eta + i·k`, a Beckmann or
//! GGX distribution ([`microfacet`](super::microfacet)) and the separable
//! Smith G. One-sided, as Mitsuba's: black from behind the shading normal.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `distribution` | `beckmann`, `ggx` | `beckmann` | the microfacet distribution |
//! | `alpha` | number ≥ 0 or texture | `0.1` | roughness along both tangents |
//! | `alpha_u`, `alpha_v` | number ≥ 0 or texture | `alpha` | anisotropic roughness (both, not with `alpha`); `u` along `dp/du` |
//! | `sample_visible` | bool | `true` | sample the visible normals (else the whole distribution) |
//! | `material` | `none` or a name of Mitsuba 3's table (`Au`, `Cu`, `W`, …) | `none` | a preset index ([`ior`](super::ior)); `none` reflects 1 at every facet |
//! | `eta`, `k` | colour ≥ 0 or texture | the material's | the complex index, not with a `material` other than `none` |
//! | `specular_reflectance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the reflection |
//!
//! Its lobe, slot 0, is glossy reflection: the Whitted integrator lights it
//! directly through `eval`. Sampling draws a microfacet normal (of the
//! visible normals of `wo` by default) and reflects `wo` about it; with
//! visible normals a sample weighs `F · G1(wi)` (at most 1 for a white
//! conductor).

use super::conductor::{factor, read_index, reflectance, Index, INDEX_PARAMS, SPECULAR_REFLECTANCE};
use super::microfacet::{Microfacet, Roughness, PARAMS};
use super::{BsdfModel, Defaults};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use crate::description::{Invalid, Kind, Props, Schema};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;
use crate::texture::Texture;

/// The rough conductor (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct RoughConductor {
    pub distribution: Roughness,
    /// `None`: reflectance 1 at every facet (`material = "none"`).
    pub index: Option<Index>,
    pub specular_reflectance: Texture,
}

const FLAGS: BsdfFlags = BsdfFlags::GLOSSY.union(BsdfFlags::REFLECTION);

impl BsdfModel for RoughConductor {
    const NAME: &'static str = "roughconductor";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "roughconductor",
        what: "rough conductor material",
        doc: "a rough metal: Beckmann or GGX microfacet reflection",
        mitsuba: &["roughconductor"],
        params: &[
            PARAMS[0],
            PARAMS[1],
            PARAMS[2],
            PARAMS[3],
            PARAMS[4],
            INDEX_PARAMS[0],
            INDEX_PARAMS[1],
            INDEX_PARAMS[2],
            SPECULAR_REFLECTANCE,
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<RoughConductor, Invalid> {
        Ok(RoughConductor {
            distribution: Microfacet::read_textured(p, d.textures)?,
            index: read_index(p, d.textures)?,
            specular_reflectance: factor(p, d.textures, "specular_reflectance")?,
        })
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = FLAGS;
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        let frame = si.shading_frame();
        let (o, i) = (frame.to_local(wo), frame.to_local(wi));
        if o.z <= 0.0 || i.z <= 0.0 {
            return Rgb::ZERO;
        }
        let h = (o + i).normalize();
        let m = &self.distribution.at(si);
        let dg = m.d(h) * m.g(o, i, h);
        if dg <= 0.0 {
            return Rgb::ZERO;
        }
        self.specular_reflectance.eval(si) * reflectance(&self.index, si, i.dot(h)) * (dg / (4.0 * o.z * i.z))
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
        let frame = si.shading_frame();
        let o = frame.to_local(wo);
        if o.z <= 0.0 {
            return None;
        }
        let d = &self.distribution.at(si);
        let (m, pdf_m) = d.sample(o, u.square());
        let om = o.dot(m);
        if pdf_m.is_nan() || pdf_m <= 0.0 || om <= 0.0 {
            return None;
        }
        let i = 2.0 * om * m - o;
        if i.z <= 0.0 {
            return None;
        }
        let shadowing = if d.sample_visible {
            d.g1(i, m)
        } else {
            d.g(o, i, m) * om / (o.z * m.z)
        };
        let weight = self.specular_reflectance.eval(si) * reflectance(&self.index, si, i.dot(m)) * shadowing;
        let wi = frame.to_world(i);
        Some(BsdfSample {
            wi,
            weight,
            // The density of the normal, times the Jacobian of reflection.
            pdf: self.pdf(si, wo, wi),
            flags: FLAGS,
            lobe: 0,
            eta: 1.0,
        })
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        let frame = si.shading_frame();
        let (o, i) = (frame.to_local(wo), frame.to_local(wi));
        if o.z <= 0.0 || i.z <= 0.0 {
            return 0.0;
        }
        let h = (o + i).normalize();
        let ih = i.dot(h);
        if o.dot(h) <= 0.0 || ih <= 0.0 {
            return 0.0;
        }
        self.distribution.at(si).pdf(o, h) / (4.0 * ih)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{self, albedo, build, check_weights, interaction, model_p_value};

    fn models() -> Vec<(String, RoughConductor)> {
        let mut all = Vec::new();
        for dist in ["beckmann", "ggx"] {
            for visible in [true, false] {
                for rough in ["alpha = 0.1", "alpha = 0.5", "alpha_u = 0.1\nalpha_v = 0.4"] {
                    let text = format!(
                        "distribution = \"{dist}\"\n{rough}\nsample_visible = {visible}\nmaterial = \"Cu\""
                    );
                    all.push((text.clone(), build::<RoughConductor>(&text).unwrap()));
                }
            }
        }
        all
    }

    fn views() -> [Vec3; 3] {
        [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.2, 0.77).normalize(),
            Vec3::new(-0.3, 0.9, 0.15).normalize(),
        ]
    }

    /// The sampler's directions follow its pdf (χ² over distributions,
    /// sampling techniques, roughnesses, anisotropy and views).
    #[test]
    fn sampling_passes_chi2() {
        let si = interaction(Vec3::Z);
        chi2::assert_samplers_pass(models(), &views(), &si, model_p_value);
    }

    /// Weights are eval·cos/pdf; eval is reciprocal; the albedo is at most
    /// 1; a white conductor sampling visible normals weighs at most 1.
    #[test]
    fn weights_reciprocity_and_energy() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        for (text, m) in models() {
            for wo in views().map(|v| frame.to_world(v)) {
                check_weights(&m, &si, wo, 20_000);
                let (a, err) = albedo(&m, &si, wo, 250_000);
                assert!(a.max_element() <= 1.0 + 4.0 * err + 1e-3, "{text}: albedo {a:?} ± {err}");
                for wi in views().map(|v| frame.to_world(Vec3::new(-v.y, v.x, v.z))) {
                    let (a, b) = (m.eval(&si, wo, wi), m.eval(&si, wi, wo));
                    assert!((a - b).abs().max_element() <= 1e-5 * a.max_element().max(1.0), "{text}");
                }
            }
        }
        for dist in ["beckmann", "ggx"] {
            for alpha in ["alpha = 0.05", "alpha = 0.7", "alpha_u = 1.0\nalpha_v = 0.1"] {
                let white = build::<RoughConductor>(&format!("distribution = \"{dist}\"\n{alpha}")).unwrap();
                for wo in views().map(|v| frame.to_world(v)) {
                    let most = check_weights(&white, &si, wo, 20_000);
                    assert!(most <= 1.0 + 1e-4, "{dist} {alpha}: weight {most}");
                }
            }
        }
        // From behind, nothing.
        let (_, m) = &models()[0];
        assert_eq!(m.eval(&si, -n, n), Rgb::ZERO);
        assert!(m.sample(&si, -n, None, SetPoint::uniform(crate::math::Vec2::splat(0.5))).is_none());
    }

    /// Parameters are Mitsuba's: roughness defaults to Beckmann 0.1 with
    /// visible normals; bad values are refused at their place.
    #[test]
    fn parameters() {
        let m = build::<RoughConductor>("").unwrap();
        assert_eq!(m.distribution, Roughness::fixed(Microfacet::new(super::super::microfacet::Kind::Beckmann, 0.1, 0.1, true)));
        assert!(m.index.is_none() && m.specular_reflectance == Texture::Constant(Rgb::ONE));
        for (text, want) in [
            ("alpha = -0.1", "must be between 0 and 100"),
            ("alpha_u = 0.1", "`alpha_v` is missing"),
            ("alpha = 0.1\nalpha_u = 0.1\nalpha_v = 0.2", "not both"),
            ("distribution = \"phong\"", "unknown microfacet distribution `phong`"),
            ("specular_reflectance = [1, 1.5, 1]", "must not exceed 1"),
        ] {
            let e = build::<RoughConductor>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
