//! `mask`: a material made partly transparent, Mitsuba 3's `mask` (cut-out
//! leaves, fences). A share `opacity` of the light meets the held material
//! `bsdf`; the rest passes straight through, unbent and unweakened, as if
//! the surface were not there (a null, delta transmission lobe).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `opacity` | number in [0, 1] or texture | `0.5` | the share of light the held material sees |
//! | `bsdf` | material name | required | the material of the opaque share |
//!
//! Its lobes are the held material's, in its slots, then the pass-through
//! (delta transmission, `wi = −wo`, weight `1 − opacity`) in the next slot.
//! `eval` and `pdf` are the held material's times `opacity`. With no lobe
//! asked for, `sample` passes through with probability `1 − opacity` (the
//! point's first coordinate) and samples the held material otherwise. A
//! shadow ray crossing it keeps `1 − opacity` plus `opacity` times what the
//! held material lets through
//! ([`shadow_transmittance`](BsdfModel::shadow_transmittance)), which the
//! Whitted integrator reads (a textured opacity at the point the shadow ray
//! crosses); the path tracer's shadow rays stop at it and light behind it
//! arrives through the pass-through lobe (as in Mitsuba). A textured
//! opacity is read as one value (a colour's luminance), at the point's
//! `(u, v)`.

use std::sync::Arc;

use super::{BsdfModel, Defaults};
use super::nested::{self, choose};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::Bsdf;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;
use crate::texture::Texture;

/// The masked material (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Mask {
    pub opacity: Texture,
    pub bsdf: Arc<Bsdf>,
}

/// The pass-through lobe's kind.
pub const NULL: BsdfFlags = BsdfFlags::DELTA
    .union(BsdfFlags::TRANSMISSION)
    .union(BsdfFlags::NULL);

impl Mask {
    /// The mask of `opacity` around `bsdf`; `Err` if the held material's
    /// lobes leave no slot for the pass-through.
    pub fn new(opacity: Texture, bsdf: Arc<Bsdf>) -> Result<Mask, String> {
        if bsdf.lobes().slots() >= super::MAX_LOBES {
            return Err(format!(
                "the held material has {} lobes: no slot is left for the pass-through",
                super::MAX_LOBES
            ));
        }
        Ok(Mask { opacity, bsdf })
    }

    /// The opacity at the point (the one place it is read).
    fn opacity(&self, si: &SurfaceInteraction) -> f32 {
        self.opacity.eval_1(si)
    }

    /// The pass-through lobe's slot.
    fn null_slot(&self) -> usize {
        self.bsdf.lobes().slots()
    }
}

impl BsdfModel for Mask {
    const NAME: &'static str = "mask";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "mask",
        what: "mask material",
        doc: "a material seen by a share `opacity` of the light, the rest passing through",
        mitsuba: &["mask"],
        params: &[
            Param::new(
                "opacity",
                Type::NumberTexture,
                "0.5",
                "the share of light the held material sees, in [0, 1]; the rest passes straight through",
            ).range(Range::Unit),
            nested::param("bsdf", "required", "the name of the material of the opaque share"),
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<Mask, Invalid> {
        let opacity = nested::share(p, d.textures, "opacity", 0.5)?;
        let bsdf = nested::read(p, "bsdf", d)?;
        Mask::new(opacity, bsdf).map_err(|e| p.error("bsdf", e))
    }

    /// Mitsuba's `eval_diffuse_reflectance`: the held model's.
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, wo: Vec3) -> Rgb {
        self.bsdf.diffuse_reflectance(si, wo)
    }

    fn lobes(&self) -> Lobes {
        let mut l = self.bsdf.lobes();
        l.flags[self.null_slot()] = NULL;
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        self.bsdf.eval(si, wo, wi) * self.opacity(si)
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let a = self.opacity(si);
        let null = self.null_slot();
        let pass = |weight: f32, pdf: f32| {
            (weight > 0.0).then_some(BsdfSample {
                wi: -wo,
                weight: Rgb::splat(weight),
                pdf,
                flags: NULL,
                lobe: null,
                eta: 1.0,
            })
        };
        match lobe {
            Some(k) if k == null => pass(1.0 - a, 1.0),
            Some(k) => {
                let mut s = self.bsdf.sample(si, wo, Some(k), u)?;
                s.weight *= a;
                Some(s)
            }
            None => match choose(u, a) {
                (true, u) => {
                    let mut s = self.bsdf.sample(si, wo, None, u)?;
                    // Chosen with probability a, weighed by a: the weight stays.
                    s.pdf *= a;
                    Some(s)
                }
                (false, _) => pass(1.0, 1.0 - a),
            },
        }
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        self.bsdf.pdf(si, wo, wi) * self.opacity(si)
    }

    fn shadow_transmittance(&self, si: &SurfaceInteraction) -> f32 {
        let a = self.opacity(si);
        (1.0 - a) + a * self.bsdf.shadow_transmittance(si)
    }

    fn uniform_shadow_transmittance(&self) -> Option<f32> {
        let a = crate::texture::one(self.opacity.constant()?);
        Some((1.0 - a) + a * self.bsdf.uniform_shadow_transmittance()?)
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::bsdf::chi2::{self, build, build_in, check_weights, interaction, sampled_albedo, smooth_p_value};
    use crate::bsdf::plastic::Plastic;
    use crate::bsdf::roughconductor::RoughConductor;
    use crate::math::Vec2;
    use crate::sampling::Rng;

    fn grey(a: f32) -> Texture {
        Texture::Constant(Rgb::splat(a))
    }

    fn inners() -> Vec<Arc<Bsdf>> {
        vec![
            Arc::new(build::<RoughConductor>("alpha = 0.3\nmaterial = \"Cu\"").unwrap().into()),
            Arc::new(build::<Plastic>("diffuse_reflectance = [0.7, 0.4, 0.2]").unwrap().into()),
        ]
    }

    fn views() -> [Vec3; 3] {
        [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.2, 0.77).normalize(),
            Vec3::new(-0.3, 0.9, 0.15).normalize(),
        ]
    }

    /// χ² of the smooth samples, weights eval·cos/pdf, the pass-through's
    /// share, albedo ≤ 1 and reciprocity, for opacities and held models.
    #[test]
    fn sampling_weights_and_energy() {
        let si = interaction(Vec3::Z);
        let mut cases = Vec::new();
        for inner in inners() {
            for a in [0.0, 0.3, 0.8] {
                for wo in views() {
                    cases.push((Mask::new(grey(a), Arc::clone(&inner)).unwrap(), wo));
                }
            }
        }
        let level = chi2::sidak(cases.len());
        for (k, (m, wo)) in cases.iter().enumerate() {
            let wo = *wo;
            let opacity = m.opacity(&si);
            if opacity > 0.0 {
                let p = smooth_p_value(m, &si, wo, 100 + k as u64).unwrap();
                assert!(p > level, "{m:?} {wo:?}: p = {p:e}");
            }
            check_weights(m, &si, wo, 10_000);
            let (a, err) = sampled_albedo(m, &si, wo, 100_000);
            let (inner, _) = chi2::albedo_of(|u| m.bsdf.sample(&si, wo, None, u), 100_000);
            // What passes is 1 − opacity of the light, the rest is the held model's.
            let want = inner * opacity + Rgb::splat(1.0 - opacity);
            assert!((a - want).abs().max_element() <= 4.0 * err + 5e-3, "{a:?} vs {want:?}");
            for wi in views() {
                let wi = Vec3::new(-wi.y, wi.x, wi.z);
                let (x, y) = (m.eval(&si, wo, wi), m.eval(&si, wi, wo));
                assert!((x - y).abs().max_element() <= 1e-5 * x.max_element().max(1.0));
            }
            let null = m.lobes().slots() - 1;
            assert_eq!(m.lobes().flags[null], NULL);
            let u = SetPoint::uniform(Vec2::splat(0.5));
            match m.sample(&si, wo, Some(null), u) {
                Some(s) => {
                    assert_eq!((s.wi, s.weight, s.pdf), (-wo, Rgb::splat(1.0 - opacity), 1.0));
                }
                None => assert_eq!(opacity, 1.0),
            }
            assert!((m.shadow_transmittance(&si) - (1.0 - opacity)).abs() < 1e-7);
            assert_eq!(m.uniform_shadow_transmittance(), Some(m.shadow_transmittance(&si)));
        }
    }

    /// At opacity 1 the mask is the held model: the same values, densities
    /// and samples.
    #[test]
    fn opaque_it_is_the_held_model() {
        let si = interaction(Vec3::new(0.2, 0.1, 0.97).normalize());
        for inner in inners() {
            let m = Mask::new(grey(1.0), Arc::clone(&inner)).unwrap();
            let mut rng = Rng::new(4);
            for wo in views() {
                for _ in 0..2000 {
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    let (a, b) = (m.sample(&si, wo, None, u), inner.sample(&si, wo, None, u));
                    assert_eq!(a.is_some(), b.is_some());
                    if let (Some(a), Some(b)) = (a, b) {
                        assert!((a.wi - b.wi).length() < 1e-6 && a.weight == b.weight && a.pdf == b.pdf);
                        assert_eq!(m.eval(&si, wo, a.wi), inner.eval(&si, wo, a.wi));
                        assert_eq!(m.pdf(&si, wo, a.wi), inner.pdf(&si, wo, a.wi));
                    }
                }
            }
            assert_eq!(m.shadow_transmittance(&si), 0.0);
        }
    }

    /// Mitsuba's default opacity, its range, and the held material.
    #[test]
    fn parameters() {
        let mut named = HashMap::new();
        named.insert("leaf".to_string(), inners().remove(1));
        let m = build_in::<Mask>("bsdf = \"leaf\"", &named).unwrap();
        assert_eq!(m.opacity.constant(), Some(Rgb::splat(0.5)));
        assert_eq!(m.lobes().slots(), 3);
        for (text, want) in [
            ("bsdf = \"leaf\"\nopacity = 1.5", "must be between 0 and 1"),
            ("bsdf = \"leaf\"\nopacity = -0.1", "must be between 0 and 1"),
            ("opacity = 0.5", "missing field `bsdf`"),
            ("bsdf = \"stem\"", "no material named `stem`"),
        ] {
            let e = build_in::<Mask>(text, &named).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
