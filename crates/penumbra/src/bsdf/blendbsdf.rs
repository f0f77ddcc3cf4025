//! `blendbsdf`: a linear blend of two materials, Mitsuba 3's `blendbsdf`:
//! `(1 − weight) · bsdf_0 + weight · bsdf_1` (weight 0 is `bsdf_0` alone,
//! 1 is `bsdf_1` alone).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `weight` | number in [0, 1] or texture | `0.5` | the share of `bsdf_1` (a texture read as one value, its luminance, at the point) |
//! | `bsdf_0` | material name | required | the first material |
//! | `bsdf_1` | material name | required | the second material |
//!
//! Its lobes are `bsdf_0`'s, in its slots, then `bsdf_1`'s (slot `k` of
//! `bsdf_1` is slot `n + k`, `n` the slots of `bsdf_0`); a lobe asked for
//! alone is its material's, its weight times that material's share.
//! `eval` and `pdf` are blended alike. With no lobe asked for, `sample`
//! picks `bsdf_1` with probability `weight` (the point's first coordinate),
//! samples it, and weighs a smooth direction by the blend,
//! `eval · cos / pdf` of both materials together; a delta direction keeps
//! the picked material's weight (its share and its probability cancel).

use std::sync::Arc;

use super::{BsdfModel, Defaults};
use super::nested::{self, choose};
use super::sample::{BsdfSample, Lobes};
use super::Bsdf;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;
use crate::texture::Texture;

/// The blend (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct BlendBsdf {
    pub weight: Texture,
    pub bsdf_0: Arc<Bsdf>,
    pub bsdf_1: Arc<Bsdf>,
}

impl BlendBsdf {
    /// The blend of `bsdf_0` and `bsdf_1`; `Err` if their lobes together do
    /// not fit the slots.
    pub fn new(weight: Texture, bsdf_0: Arc<Bsdf>, bsdf_1: Arc<Bsdf>) -> Result<BlendBsdf, String> {
        let b = BlendBsdf {
            weight,
            bsdf_0,
            bsdf_1,
        };
        if !b.bsdf_1.lobes().place(&mut Lobes::default(), b.offset()) {
            return Err(format!(
                "the two materials have more than {} lobes together",
                super::MAX_LOBES
            ));
        }
        Ok(b)
    }

    /// The share of `bsdf_1` at the point (the one place it is read).
    fn weight(&self, si: &SurfaceInteraction) -> f32 {
        self.weight.eval_1(si)
    }

    /// The slot `bsdf_1`'s lobes start at.
    fn offset(&self) -> usize {
        self.bsdf_0.lobes().slots()
    }
}

impl BsdfModel for BlendBsdf {
    const NAME: &'static str = "blendbsdf";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "blendbsdf",
        what: "blended material",
        doc: "a linear blend of two materials",
        mitsuba: &["blendbsdf"],
        params: &[
            Param::new(
                "weight",
                Type::NumberTexture,
                "0.5",
                "the share of `bsdf_1`, in [0, 1] (0: `bsdf_0` alone, 1: `bsdf_1` alone)",
            ).range(Range::Unit),
            nested::param("bsdf_0", "required", "the name of the first material"),
            nested::param("bsdf_1", "required", "the name of the second material"),
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<BlendBsdf, Invalid> {
        let weight = nested::share(p, d.textures, "weight", 0.5)?;
        let b0 = nested::read(p, "bsdf_0", d)?;
        let b1 = nested::read(p, "bsdf_1", d)?;
        BlendBsdf::new(weight, b0, b1).map_err(|e| p.node_error(e))
    }

    /// Mitsuba's `eval_diffuse_reflectance`: the held models' blended by the weight.
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, wo: Vec3) -> Rgb {
        let w = self.weight(si);
        self.bsdf_0.diffuse_reflectance(si, wo) * (1.0 - w)
            + self.bsdf_1.diffuse_reflectance(si, wo) * w
    }

    fn lobes(&self) -> Lobes {
        let mut l = self.bsdf_0.lobes();
        self.bsdf_1.lobes().place(&mut l, self.offset());
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        let w = self.weight(si);
        self.bsdf_0.eval(si, wo, wi) * (1.0 - w) + self.bsdf_1.eval(si, wo, wi) * w
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let w = self.weight(si);
        let at = self.offset();
        if let Some(k) = lobe {
            let (m, own, share) = if k < at {
                (&self.bsdf_0, k, 1.0 - w)
            } else {
                (&self.bsdf_1, k - at, w)
            };
            let mut s = m.sample(si, wo, Some(own), u)?;
            s.weight *= share;
            s.lobe += k - own;
            return Some(s);
        }
        let (second, u) = choose(u, w);
        let (m, at, p) = if second {
            (&self.bsdf_1, at, w)
        } else {
            (&self.bsdf_0, 0, 1.0 - w)
        };
        let mut s = m.sample(si, wo, None, u)?;
        s.lobe += at;
        if s.flags.is_delta() {
            s.pdf *= p;
            return Some(s);
        }
        let pdf = self.pdf(si, wo, s.wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        s.weight = self.eval(si, wo, s.wi) * (s.wi.dot(si.n).abs() / pdf);
        s.pdf = pdf;
        Some(s)
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        let w = self.weight(si);
        self.bsdf_0.pdf(si, wo, wi) * (1.0 - w) + self.bsdf_1.pdf(si, wo, wi) * w
    }

    fn shadow_transmittance(&self, si: &SurfaceInteraction) -> f32 {
        let w = self.weight(si);
        self.bsdf_0.shadow_transmittance(si) * (1.0 - w) + self.bsdf_1.shadow_transmittance(si) * w
    }

    fn uniform_shadow_transmittance(&self) -> Option<f32> {
        let (t0, t1) = (
            self.bsdf_0.uniform_shadow_transmittance()?,
            self.bsdf_1.uniform_shadow_transmittance()?,
        );
        if t0 == t1 {
            // The same either way, whatever the weight.
            return Some(t0);
        }
        let w = crate::texture::one(self.weight.constant()?);
        Some(t0 * (1.0 - w) + t1 * w)
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::bsdf::chi2::{self, build, build_in, check_weights, interaction, sampled_albedo, smooth_p_value};
    use crate::bsdf::conductor::Conductor;
    use crate::bsdf::diffuse::Diffuse;
    use crate::bsdf::plastic::Plastic;
    use crate::bsdf::roughconductor::RoughConductor;
    use crate::math::Vec2;
    use crate::sampling::Rng;

    fn grey(w: f32) -> Texture {
        Texture::Constant(Rgb::splat(w))
    }

    fn arc(b: impl Into<Bsdf>) -> Arc<Bsdf> {
        Arc::new(b.into())
    }

    fn pairs() -> Vec<(Arc<Bsdf>, Arc<Bsdf>)> {
        let gold = arc(build::<RoughConductor>("distribution = \"ggx\"\nalpha_u = 0.05\nalpha_v = 0.3\nmaterial = \"Au\"").unwrap());
        let paint = arc(build::<Diffuse>("reflectance = [0.1, 0.6, 0.3]").unwrap());
        let plastic = arc(build::<Plastic>("").unwrap());
        let mirror = arc(build::<Conductor>("material = \"Ag\"").unwrap());
        vec![(gold.clone(), paint), (plastic, gold), (mirror, arc(build::<Diffuse>("").unwrap()))]
    }

    fn views() -> [Vec3; 3] {
        [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.2, 0.77).normalize(),
            Vec3::new(-0.3, 0.9, 0.15).normalize(),
        ]
    }

    /// χ², weights eval·cos/pdf, reciprocity, and the albedo is the blend
    /// of the two albedos (each ≤ 1), over weights and pairs.
    #[test]
    fn sampling_weights_and_energy() {
        let si = interaction(Vec3::Z);
        let mut cases = Vec::new();
        for (a, b) in pairs() {
            for w in [0.0, 0.25, 0.9] {
                for wo in views() {
                    cases.push((BlendBsdf::new(grey(w), a.clone(), b.clone()).unwrap(), wo));
                }
            }
        }
        let level = chi2::sidak(cases.len());
        for (k, (m, wo)) in cases.iter().enumerate() {
            let wo = *wo;
            let weight = m.weight(&si);
            // A blend of a mirror alone has no smooth directions to count.
            let smooth = (weight < 1.0 && m.bsdf_0.lobes().any_smooth())
                || (weight > 0.0 && m.bsdf_1.lobes().any_smooth());
            if smooth {
                let p = smooth_p_value(m, &si, wo, k as u64).unwrap();
                assert!(p > level, "{} {weight} {wo:?}: p = {p:e}", m.bsdf_0.name());
            }
            check_weights(m, &si, wo, 10_000);
            let (a, err) = sampled_albedo(m, &si, wo, 100_000);
            let (a0, e0) = chi2::albedo_of(|u| m.bsdf_0.sample(&si, wo, None, u), 100_000);
            let (a1, e1) = chi2::albedo_of(|u| m.bsdf_1.sample(&si, wo, None, u), 100_000);
            let want = a0 * (1.0 - weight) + a1 * weight;
            assert!((a - want).abs().max_element() <= 4.0 * (err + e0 + e1) + 3e-3, "{a:?} vs {want:?}");
            assert!(a.max_element() <= 1.0 + 4.0 * err + 2e-3);
            for wi in views() {
                let wi = Vec3::new(-wi.y, wi.x, wi.z);
                let (x, y) = (m.eval(&si, wo, wi), m.eval(&si, wi, wo));
                assert!((x - y).abs().max_element() <= 1e-5 * x.max_element().max(1.0));
            }
        }
    }

    /// A blend of a model with itself is the model: the same values,
    /// densities and sample weights.
    #[test]
    fn a_blend_of_one_model_is_the_model() {
        let si = interaction(Vec3::new(0.2, 0.1, 0.97).normalize());
        for (m, _) in pairs() {
            let b = BlendBsdf::new(grey(0.3), m.clone(), m.clone()).unwrap();
            let mut rng = Rng::new(6);
            for wo in views() {
                for _ in 0..2000 {
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    let Some(s) = b.sample(&si, wo, None, u) else { continue };
                    let (e, f) = (b.eval(&si, wo, s.wi), m.eval(&si, wo, s.wi));
                    assert!((e - f).abs().max_element() <= 1e-5 * f.max_element().max(1.0));
                    let (p, q) = (b.pdf(&si, wo, s.wi), m.pdf(&si, wo, s.wi));
                    assert!((p - q).abs() <= 1e-5 * q.max(1.0));
                    if !s.flags.is_delta() {
                        let want = f * (s.wi.dot(si.n).abs() / q);
                        assert!((s.weight - want).abs().max_element() <= 1e-3 * want.max_element().max(1e-2));
                    }
                }
                let (x, ex) = sampled_albedo(&b, &si, wo, 100_000);
                let (y, ey) = chi2::albedo_of(|u| m.sample(&si, wo, None, u), 100_000);
                assert!((x - y).abs().max_element() <= 4.0 * (ex + ey) + 1e-3, "{x:?} vs {y:?}");
            }
        }
    }

    /// Lobes by slot: `bsdf_1`'s follow `bsdf_0`'s, each asked for alone
    /// weighs its share.
    #[test]
    fn lobes_follow_each_other() {
        let (gold, paint) = pairs().remove(0);
        let b = BlendBsdf::new(grey(0.25), gold.clone(), paint.clone()).unwrap();
        let l = b.lobes();
        assert_eq!(l.slots(), 2);
        assert_eq!((l.flags[0], l.flags[1]), (gold.lobes().flags[0], paint.lobes().flags[0]));
        let si = interaction(Vec3::Z);
        let u = SetPoint::uniform(Vec2::new(0.3, 0.6));
        let s = b.sample(&si, Vec3::Z, Some(1), u).unwrap();
        let d = paint.sample(&si, Vec3::Z, Some(0), u).unwrap();
        assert_eq!((s.lobe, s.wi, s.weight), (1, d.wi, d.weight * 0.25));
        assert!(b.sample(&si, Vec3::Z, Some(2), u).is_none());
    }

    /// Mitsuba's default weight, its range, and the held materials.
    #[test]
    fn parameters() {
        let mut named = HashMap::new();
        let (a, b) = pairs().remove(1);
        named.insert("a".to_string(), a);
        named.insert("b".to_string(), b);
        let m = build_in::<BlendBsdf>("bsdf_0 = \"a\"\nbsdf_1 = \"b\"", &named).unwrap();
        assert_eq!(m.weight.constant(), Some(Rgb::splat(0.5)));
        assert_eq!(m.lobes().slots(), 3);
        for (text, want) in [
            ("bsdf_0 = \"a\"\nbsdf_1 = \"b\"\nweight = 2", "must be between 0 and 1"),
            ("bsdf_0 = \"a\"", "missing field `bsdf_1`"),
            ("bsdf_0 = \"a\"\nbsdf_1 = \"c\"", "no material named `c`"),
        ] {
            let e = build_in::<BlendBsdf>(text, &named).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
