//! `twosided`: one-sided models made to reflect on both sides, Mitsuba 3's
//! `twosided`. Seen from the side the shading normal points to, the
//! surface is the material `bsdf`; seen from behind, it is `back` (by
//! default `bsdf` again) on the surface turned over (its normal negated),
//! so that a diffuse or a metal reflects alike on both sides. The held
//! models reflect only: a model with a transmission lobe is refused, as
//! Mitsuba refuses it.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `bsdf` | material name | required | the material of the front (and of the back without `back`) |
//! | `back` | material name | `bsdf` | the material of the back |
//!
//! Its lobes are the front material's, in its slots; with a `back`, the
//! back's follow them (slot `k` of the back is slot `n + k`, `n` the
//! front's slots). `diffuse`'s own `two_sided` flag is the same as
//! `twosided` around it.

use std::sync::Arc;

use super::{BsdfModel, Defaults};
use super::nested;
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::Bsdf;
use crate::description::mitsuba::objects::Object;
use crate::description::mitsuba::registry::Mapper;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Props, SceneError, Schema};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;

/// The two-sided material (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct TwoSided {
    pub front: Arc<Bsdf>,
    /// `None`: the front's material on the back too.
    pub back: Option<Arc<Bsdf>>,
}

impl TwoSided {
    /// The two-sided material of `front` and `back` (or `front` on both
    /// sides); `Err` with the reason if either transmits or their lobes do
    /// not fit the slots.
    pub fn new(front: Arc<Bsdf>, back: Option<Arc<Bsdf>>) -> Result<TwoSided, String> {
        for m in std::iter::once(&front).chain(&back) {
            if m.flags().contains(BsdfFlags::TRANSMISSION) {
                return Err(format!(
                    "a `{}` transmits light: `twosided` holds reflecting materials only",
                    m.name()
                ));
            }
        }
        let t = TwoSided { front, back };
        if let Some(b) = &t.back {
            if !b.lobes().place(&mut Lobes::default(), t.offset()) {
                return Err("the two materials have more lobes than a material may".into());
            }
        }
        Ok(t)
    }

    /// The slot the back's lobes start at.
    fn offset(&self) -> usize {
        self.front.lobes().slots()
    }

    /// The model seen from `wo`, the surface as it sees it, and the slot its
    /// lobes start at; `None` in the surface's plane.
    fn side(&self, si: &SurfaceInteraction, wo: Vec3) -> Option<(&Bsdf, SurfaceInteraction, usize)> {
        let c = si.n.dot(wo);
        if c > 0.0 {
            return Some((&self.front, *si, 0));
        }
        if c >= 0.0 || c.is_nan() {
            return None;
        }
        let mut turned = *si;
        turned.n = -si.n;
        turned.ng = -si.ng;
        Some(match &self.back {
            Some(b) => (b, turned, self.offset()),
            None => (&self.front, turned, 0),
        })
    }
}

/// Mitsuba's `twosided` around one `diffuse` (and nothing else) as the
/// diffuse material reflecting on both sides, named as the `twosided`.
fn around_diffuse(m: &mut dyn Mapper, obj: &Object) -> Option<Result<String, SceneError>> {
    if !obj.props.is_empty() {
        return None;
    }
    let held = match m.held(obj) {
        Ok(held) => held,
        Err(e) => return Some(Err(e)),
    };
    match held.as_slice() {
        [one] if one.tag == "bsdf" && one.plugin == "diffuse" => {
            Some(m.bsdf_as(one, obj, "two_sided"))
        }
        _ => None,
    }
}

impl BsdfModel for TwoSided {
    const NAME: &'static str = "twosided";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "twosided",
        what: "two-sided material",
        doc: "one or two reflecting materials, one on each side",
        mitsuba: &["twosided"],
        params: &[
            nested::param(
                "bsdf",
                "required",
                "the name of the material of the front (and of the back without `back`); a reflecting one",
            ),
            nested::param("back", "`bsdf`", "the name of the material of the back"),
        ],
    };

    const MITSUBA: Mitsuba = Mitsuba {
        differences: "around one `diffuse`, the `diffuse` with `two_sided = true`",
        reads: &[],
        adapt: Some(Adapt::Object(around_diffuse)),
    };

    fn build(p: &Props, d: &Defaults) -> Result<TwoSided, Invalid> {
        let front = nested::read(p, "bsdf", d)?;
        let back = nested::read_optional(p, "back", d)?;
        TwoSided::new(front, back).map_err(|e| p.node_error(e))
    }

    /// Mitsuba's `eval_diffuse_reflectance`: that of the side `wo` leaves from.
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, wo: Vec3) -> Rgb {
        match self.side(si, wo) {
            Some((m, s, _)) => m.diffuse_reflectance(&s, wo),
            None => Rgb::ZERO,
        }
    }

    fn lobes(&self) -> Lobes {
        let mut l = self.front.lobes();
        if let Some(b) = &self.back {
            b.lobes().place(&mut l, self.offset());
        }
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        match self.side(si, wo) {
            Some((m, s, _)) => m.eval(&s, wo, wi),
            None => Rgb::ZERO,
        }
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let (m, s, at) = self.side(si, wo)?;
        let own = match lobe {
            Some(k) if k < at => return None,
            Some(k) => Some(k - at),
            None => None,
        };
        let mut bs = m.sample(&s, wo, own, u)?;
        bs.lobe += at;
        Some(bs)
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        match self.side(si, wo) {
            Some((m, s, _)) => m.pdf(&s, wo, wi),
            None => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::bsdf::chi2::{self, build, build_in, check_weights, interaction, model_p_value, sampled_albedo};
    use crate::bsdf::diffuse::Diffuse;
    use crate::bsdf::plastic::Plastic;
    use crate::bsdf::roughconductor::RoughConductor;
    use crate::math::Vec2;

    fn rough() -> Arc<Bsdf> {
        Arc::new(build::<RoughConductor>("alpha_u = 0.1\nalpha_v = 0.4\nmaterial = \"Au\"").unwrap().into())
    }

    fn views() -> [Vec3; 3] {
        [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.2, 0.77).normalize(),
            Vec3::new(-0.3, 0.9, 0.15).normalize(),
        ]
    }

    /// From behind, the material is the front's on the surface turned over:
    /// every value and sample is the front's mirrored through the surface.
    #[test]
    fn the_back_mirrors_the_front() {
        let n = Vec3::Z;
        let si = interaction(n);
        let mirror = |v: Vec3| Vec3::new(v.x, v.y, -v.z);
        for inner in [rough(), Arc::new(build::<Plastic>("").unwrap().into())] {
            let t = TwoSided::new(Arc::clone(&inner), None).unwrap();
            assert_eq!(t.lobes(), inner.lobes());
            for wo in views() {
                for wi in views() {
                    let wi = Vec3::new(-wi.y, wi.x, wi.z);
                    let (a, b) = (t.eval(&si, mirror(wo), mirror(wi)), inner.eval(&si, wo, wi));
                    assert!((a - b).abs().max_element() <= 1e-5 * b.max_element().max(1.0));
                    let (a, b) = (t.pdf(&si, mirror(wo), mirror(wi)), inner.pdf(&si, wo, wi));
                    assert!((a - b).abs() <= 1e-4 * b.max(1.0), "{a} vs {b}");
                    assert_eq!(t.eval(&si, wo, mirror(wi)), Rgb::ZERO);
                }
                let mut rng = crate::sampling::Rng::new(5);
                for _ in 0..200 {
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    let a = t.sample(&si, mirror(wo), None, u);
                    // The sample is the front's for the mirrored pair.
                    if let Some(a) = a.filter(|a| !a.flags.is_delta()) {
                        assert!(a.wi.z < 0.0);
                        let (f, pdf) = (inner.eval(&si, wo, mirror(a.wi)), inner.pdf(&si, wo, mirror(a.wi)));
                        let want = f * (a.wi.z.abs() / pdf);
                        assert!((a.weight - want).abs().max_element() <= 1e-3 * want.max_element().max(1e-2));
                    }
                }
            }
        }
    }

    /// Around a diffuse it is the diffuse with `two_sided`.
    #[test]
    fn around_a_diffuse_it_is_the_two_sided_diffuse() {
        let d = build::<Diffuse>("reflectance = [0.2, 0.5, 0.8]").unwrap();
        let flag = build::<Diffuse>("reflectance = [0.2, 0.5, 0.8]\ntwo_sided = true").unwrap();
        let t = TwoSided::new(Arc::new(d.into()), None).unwrap();
        let n = Vec3::new(0.3, 0.2, 0.9).normalize();
        let si = interaction(n);
        let mut rng = crate::sampling::Rng::new(8);
        for wo in [Vec3::new(-0.2, 0.1, 0.95).normalize(), Vec3::new(0.2, 0.5, -0.7).normalize()] {
            for _ in 0..500 {
                let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                let (a, b) = (t.sample(&si, wo, None, u).unwrap(), flag.sample(&si, wo, None, u).unwrap());
                assert!(a.wi.dot(si.n) * b.wi.dot(si.n) > 0.0);
                assert_eq!(a.weight, b.weight);
                assert!((t.pdf(&si, wo, b.wi) - flag.pdf(&si, wo, b.wi)).abs() < 1e-4);
                assert_eq!(t.eval(&si, wo, b.wi), flag.eval(&si, wo, b.wi));
            }
        }
    }

    /// Two materials: each side samples its own (χ²), weights are
    /// eval·cos/pdf, albedo ≤ 1, reciprocity on each side, and the back's
    /// lobes follow the front's.
    #[test]
    fn front_and_back_each_answer_for_their_side() {
        let front = Arc::new(build::<Plastic>("diffuse_reflectance = [0.8, 0.1, 0.1]").unwrap().into());
        let t = TwoSided::new(front, Some(rough())).unwrap();
        let l = t.lobes();
        assert_eq!(l.slots(), 3);
        assert!(l.flags[2].contains(BsdfFlags::GLOSSY));
        let si = interaction(Vec3::Z);
        let wos: Vec<Vec3> = views().into_iter().flat_map(|v| [v, Vec3::new(v.x, v.y, -v.z)]).collect();
        let level = chi2::sidak(wos.len());
        for (k, &wo) in wos.iter().enumerate() {
            let p = if wo.z > 0.0 {
                chi2::smooth_p_value(&t, &si, wo, k as u64)
            } else {
                model_p_value(&t, &si, wo, k as u64)
            }
            .unwrap();
            assert!(p > level, "{wo:?}: p = {p:e}");
            check_weights(&t, &si, wo, 20_000);
            let (a, err) = sampled_albedo(&t, &si, wo, 100_000);
            assert!(a.max_element() <= 1.0 + 4.0 * err + 2e-3, "{a:?}");
            for wi in views() {
                let wi = Vec3::new(-wi.y, wi.x, wi.z * wo.z.signum());
                let (a, b) = (t.eval(&si, wo, wi), t.eval(&si, wi, wo));
                assert!((a - b).abs().max_element() <= 1e-5 * a.max_element().max(1.0));
            }
            let u = SetPoint::uniform(Vec2::splat(0.3));
            if wo.z < 0.0 {
                assert_eq!(t.sample(&si, wo, None, u).unwrap().lobe, 2);
                assert!(t.sample(&si, wo, Some(0), u).is_none());
            } else {
                assert!(t.sample(&si, wo, Some(2), u).is_none());
            }
        }
    }

    /// Read by material name; a transmitting material and a missing or
    /// unknown name are refused.
    #[test]
    fn parameters() {
        let mut named = HashMap::new();
        named.insert("paint".to_string(), Arc::new(Bsdf::from(build::<Diffuse>("").unwrap())));
        named.insert("glass".to_string(), Arc::new(Bsdf::from(build::<crate::bsdf::dielectric::Dielectric>("").unwrap())));
        let t = build_in::<TwoSided>("bsdf = \"paint\"", &named).unwrap();
        assert!(t.back.is_none() && t.front.name() == "diffuse");
        for (text, want) in [
            ("", "missing field `bsdf`"),
            ("bsdf = \"chalk\"", "no material named `chalk`"),
            ("bsdf = \"glass\"", "transmits light"),
            ("bsdf = \"paint\"\nback = \"glass\"", "transmits light"),
            ("bsdf = 3", "expected a string"),
        ] {
            let e = build_in::<TwoSided>(text, &named).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
