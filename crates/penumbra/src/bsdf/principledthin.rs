//! `principledthin`: Mitsuba 3's `principledthin`, Burley's principled
//! material for a thin sheet (Burley 2015, "Extending the Disney BRDF to a
//! BSDF with Integrated Subsurface Scattering"), in Mitsuba's formulas:
//! both sides alike; a diffuse base with retro-reflection, a fake
//! subsurface term and sheen, of which a share `diff_trans / 2` crosses the
//! sheet as Lambertian transmission; and, for a share `spec_trans`, a GGX
//! reflection whose Fresnel factor blends the dielectric reflectance of
//! `eta` with Schlick's toward the hue of `base_color` (`spec_tint`), and a
//! GGX transmission straight through the sheet (the reflection mirrored to
//! the other side, its roughness scaled by `0.65 eta − 0.35`), tinted by
//! `base_color`. Light crossing a thin sheet does not bend: transmitted
//! directions keep their index.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `base_color` | colour in [0, 1] or texture | `[0.5, 0.5, 0.5]` | the colour of the base, the transmission and the tints |
//! | `roughness`, `anisotropic` | number in [0, 1] or texture | `0.5`, `0` | the GGX roughness (`α = roughness²`) and its anisotropy |
//! | `spec_trans` | number in [0, 1] or texture | `0` | the share of the specular lobes; 0 turns them off |
//! | `eta` | number > 0 or texture | `1.5` | the sheet's relative index |
//! | `spec_tint`, `sheen`, `sheen_tint`, `flatness` | number in [0, 1] or texture | `0` | as in [`principled`](super::principled) |
//! | `diff_trans` | number in [0, 2] or texture | `0` | twice the share of the base that crosses the sheet |
//! | `specular_reflectance_sampling_rate`, `specular_transmittance_sampling_rate`, `diffuse_reflectance_sampling_rate`, `diffuse_transmittance_sampling_rate` | number ≥ 0 | `1` | the weights of the lobes in the choice of a lobe to sample |
//! | `sample_visible` | bool | `true` | sample the visible normals (Penumbra's; Mitsuba always does) |
//!
//! Its lobes, by slot as Mitsuba's components: 0 diffuse reflection (the
//! base and the sheen), 1 diffuse transmission, 2 glossy transmission, 3
//! glossy reflection. With no lobe asked for, a lobe is chosen with
//! Mitsuba's weights, `rate · spec_trans / 2` for each specular lobe,
//! `rate (1 − spec_trans)(1 − diff_trans/2)` for the diffuse reflection and
//! `rate (1 − spec_trans) diff_trans/2` for the diffuse transmission (no
//! Fresnel factor enters them, so the choice is exactly Mitsuba's); the
//! weight is `eval · |cos| / pdf` with the density of the whole mixture.

use super::conductor::reflectance_texture;
use super::fresnel;
use super::microfacet::Microfacet;
use super::principled::{
    facet_agrees, ggx, hue, lerp, read_rate, read_weight, schlick, schlick_r0, schlick_weight, rate_param, weight_param,
    Weight, ANISOTROPIC, BASE_COLOR, FLATNESS, ROUGHNESS, SAMPLE_VISIBLE, SHEEN, SHEEN_TINT, SPEC_TINT,
};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::{BsdfModel, Defaults};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::sampling::SetPoint;
use crate::texture::{NumberOr, Texture};

use std::f32::consts::FRAC_1_PI;

/// The thin principled material (see the [module docs](self)): its
/// parameters, boxed to keep the enum of models small.
#[derive(Clone, Debug)]
pub struct PrincipledThin(Box<Params>);

impl std::ops::Deref for PrincipledThin {
    type Target = Params;
    fn deref(&self) -> &Params {
        &self.0
    }
}

/// The parameters of [`PrincipledThin`].
#[derive(Clone, Debug)]
pub struct Params {
    pub base_color: Texture,
    pub roughness: Weight,
    pub anisotropic: Weight,
    pub spec_trans: Weight,
    pub spec_tint: Weight,
    pub sheen: Weight,
    pub sheen_tint: Weight,
    pub flatness: Weight,
    /// In [0, 2], as given.
    pub diff_trans: Weight,
    pub eta: Texture,
    /// The sampling rates of the specular reflection and transmission and
    /// of the diffuse reflection and transmission.
    pub rates: [f32; 4],
    pub sample_visible: bool,
}

const DIFFUSE_REFLECTION: usize = 0;
const DIFFUSE_TRANSMISSION: usize = 1;
const GLOSSY_TRANSMISSION: usize = 2;
const GLOSSY_REFLECTION: usize = 3;

const FLAGS: [BsdfFlags; 4] = [
    BsdfFlags::DIFFUSE.union(BsdfFlags::REFLECTION),
    BsdfFlags::DIFFUSE.union(BsdfFlags::TRANSMISSION),
    BsdfFlags::GLOSSY.union(BsdfFlags::TRANSMISSION),
    BsdfFlags::GLOSSY.union(BsdfFlags::REFLECTION),
];

/// The parameters read at an interaction.
struct At {
    base: Rgb,
    roughness: f32,
    spec_trans: f32,
    /// Halved: in [0, 1].
    diff_trans: f32,
    eta: f32,
    reflection: Microfacet,
    transmission: Microfacet,
}

/// A pair of directions in the shading frame, both turned so that the
/// viewer is on the front (`o.z > 0`), with their half vector (of `o` and
/// `i` mirrored to the front).
struct Pair {
    o: Vec3,
    i: Vec3,
    h: Vec3,
}

impl PrincipledThin {
    fn at(&self, si: &SurfaceInteraction) -> At {
        let roughness = self.roughness.value.eval_1(si);
        let anisotropic = self.anisotropic.on.then(|| self.anisotropic.value.eval_1(si));
        let eta = self.eta.eval_1(si);
        let scaled = (0.65 * eta - 0.35) * roughness;
        At {
            base: self.base_color.eval(si),
            roughness,
            spec_trans: self.spec_trans.at(si),
            diff_trans: self.diff_trans.at(si) / 2.0,
            eta,
            reflection: ggx(roughness, anisotropic, self.sample_visible),
            transmission: ggx(scaled, anisotropic, self.sample_visible),
        }
    }

    fn pair(o: Vec3, i: Vec3) -> Option<Pair> {
        if o.z == 0.0 {
            return None;
        }
        let (o, i) = if o.z < 0.0 { (-o, -i) } else { (o, i) };
        let h = (o + Vec3::new(i.x, i.y, i.z.abs())).normalize();
        h.is_finite().then_some(Pair { o, i, h })
    }

    /// The probabilities of choosing each lobe (by slot).
    fn choice(&self, a: &At) -> Option<[f32; 4]> {
        let [rate_sr, rate_st, rate_dr, rate_dt] = self.rates;
        let mut p = [0.0; 4];
        if self.spec_trans.on {
            p[GLOSSY_REFLECTION] = a.spec_trans * rate_sr / 2.0;
            p[GLOSSY_TRANSMISSION] = a.spec_trans * rate_st / 2.0;
        }
        p[DIFFUSE_REFLECTION] = rate_dr * (1.0 - a.spec_trans) * (1.0 - a.diff_trans);
        if self.diff_trans.on {
            p[DIFFUSE_TRANSMISSION] = rate_dt * (1.0 - a.spec_trans) * a.diff_trans;
        }
        let total: f32 = p.iter().sum();
        (total > 0.0 && total.is_finite()).then(|| p.map(|x| x / total))
    }

    /// Each lobe's value for the pair (without the cosine of `i`).
    fn values(&self, si: &SurfaceInteraction, a: &At, q: &Pair) -> [Rgb; 4] {
        let mut v = [Rgb::ZERO; 4];
        let (o, i, h) = (q.o, q.i, q.h);
        let (reflect, refract) = (i.z > 0.0, i.z < 0.0);
        let (cos_o, cos_i) = (o.z, i.z.abs());
        if self.spec_trans.on && a.spec_trans > 0.0 {
            let oh = o.dot(h);
            let f = fresnel::dielectric(oh, a.eta).r;
            if reflect && facet_agrees(h, o, i, true) {
                let d = &a.reflection;
                let dg = d.d(h) * d.g(o, i, h);
                if dg > 0.0 {
                    let spec_tint = self.spec_tint.at(si);
                    let schlick = if self.spec_tint.on {
                        schlick(hue(a.base) * schlick_r0(a.eta), oh, a.eta)
                    } else {
                        Rgb::ZERO
                    };
                    let fresnel = (schlick - Rgb::splat(f)) * spec_tint + Rgb::splat(f);
                    v[GLOSSY_REFLECTION] = fresnel * (a.spec_trans * dg / (4.0 * cos_o * cos_i));
                }
            }
            if refract && facet_agrees(h, o, i, false) {
                let d = &a.transmission;
                let dg = d.d(h) * d.g(o, i, h);
                if dg > 0.0 {
                    v[GLOSSY_TRANSMISSION] = a.base * (a.spec_trans * (1.0 - f) * dg / (4.0 * cos_o * cos_i));
                }
            }
        }
        if reflect && a.spec_trans < 1.0 && a.diff_trans < 1.0 {
            let (fo, fi) = (schlick_weight(cos_i), schlick_weight(cos_o));
            let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
            let cos_d = h.dot(i);
            let rr = 2.0 * a.roughness * cos_d * cos_d;
            let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
            let shape = if self.flatness.on {
                let fss90 = rr / 2.0;
                let fss = lerp(1.0, fss90, fo) * lerp(1.0, fss90, fi);
                let f_ss = 1.25 * (fss * (1.0 / (cos_i + cos_o) - 0.5) + 0.5);
                lerp(f_diff + f_retro, f_ss, self.flatness.value.eval_1(si))
            } else {
                f_diff + f_retro
            };
            let share = (1.0 - a.spec_trans) * (1.0 - a.diff_trans);
            let mut base = a.base * (share * FRAC_1_PI * shape);
            let sheen = self.sheen.at(si);
            if self.sheen.on && sheen > 0.0 {
                let fd = schlick_weight(cos_d.abs());
                let tint = if self.sheen_tint.on {
                    let t = self.sheen_tint.value.eval_1(si);
                    (hue(a.base) - Rgb::ONE) * t + Rgb::ONE
                } else {
                    Rgb::ONE
                };
                base += tint * (sheen * share * fd);
            }
            v[DIFFUSE_REFLECTION] = base;
        }
        if self.diff_trans.on && refract && a.spec_trans < 1.0 && a.diff_trans > 0.0 {
            v[DIFFUSE_TRANSMISSION] = a.base * ((1.0 - a.spec_trans) * a.diff_trans * FRAC_1_PI);
        }
        v
    }

    /// Each lobe's density of drawing the pair (not times a choice).
    fn densities(&self, a: &At, q: &Pair) -> [f32; 4] {
        let mut d = [0.0; 4];
        let (o, i, h) = (q.o, q.i, q.h);
        if i.z > 0.0 {
            d[DIFFUSE_REFLECTION] = i.z * FRAC_1_PI;
        } else if i.z < 0.0 && self.diff_trans.on {
            d[DIFFUSE_TRANSMISSION] = -i.z * FRAC_1_PI;
        }
        if self.spec_trans.on {
            let jacobian = (1.0 / (4.0 * Vec3::new(i.x, i.y, i.z.abs()).dot(h))).abs();
            if i.z > 0.0 && facet_agrees(h, o, i, true) {
                d[GLOSSY_REFLECTION] = a.reflection.pdf(o, h) * jacobian;
            } else if i.z < 0.0 && facet_agrees(h, o, i, false) {
                d[GLOSSY_TRANSMISSION] = a.transmission.pdf(o, h) * jacobian;
            }
        }
        d.map(|x| if x.is_finite() { x } else { 0.0 })
    }

    /// Lobe `k`'s direction for the point `u`, for a viewer `o` on the
    /// front.
    fn draw(a: &At, o: Vec3, k: usize, u: Vec2) -> Option<Vec3> {
        let i = match k {
            DIFFUSE_REFLECTION => square_to_cosine_hemisphere(u),
            DIFFUSE_TRANSMISSION => -square_to_cosine_hemisphere(u),
            _ => {
                let d = if k == GLOSSY_REFLECTION { &a.reflection } else { &a.transmission };
                let (m, pdf_m) = d.sample(o, u);
                if pdf_m.is_nan() || pdf_m <= 0.0 {
                    return None;
                }
                let r = 2.0 * o.dot(m) * m - o;
                if k == GLOSSY_REFLECTION {
                    r
                } else {
                    Vec3::new(r.x, r.y, -r.z)
                }
            }
        };
        let ok = if k == DIFFUSE_REFLECTION || k == GLOSSY_REFLECTION {
            i.z > 0.0
        } else {
            i.z < 0.0
        };
        (ok && i.is_finite()).then_some(i)
    }

    fn mixture(p: &[f32; 4], d: &[f32; 4]) -> f32 {
        p[DIFFUSE_REFLECTION] * d[DIFFUSE_REFLECTION]
            + p[DIFFUSE_TRANSMISSION] * d[DIFFUSE_TRANSMISSION]
            + p[GLOSSY_TRANSMISSION] * d[GLOSSY_TRANSMISSION]
            + p[GLOSSY_REFLECTION] * d[GLOSSY_REFLECTION]
    }
}

fn sum(v: &[Rgb; 4]) -> Rgb {
    v[DIFFUSE_REFLECTION] + v[DIFFUSE_TRANSMISSION] + v[GLOSSY_TRANSMISSION] + v[GLOSSY_REFLECTION]
}

impl BsdfModel for PrincipledThin {
    const NAME: &'static str = "principledthin";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "principledthin",
        what: "thin principled material",
        doc: "Burley's principled material for a thin sheet: diffuse reflection and transmission, GGX reflection and straight transmission",
        mitsuba: &["principledthin"],
        params: &[
            BASE_COLOR,
            ROUGHNESS,
            ANISOTROPIC,
            weight_param("spec_trans", "0", "the share of the specular lobes; 0 turns them off"),
            Param::new("eta", Type::NumberTexture, "1.5", "the sheet's relative index of refraction").range(Range::Positive),
            SPEC_TINT,
            SHEEN,
            SHEEN_TINT,
            FLATNESS,
            Param::new("diff_trans", Type::NumberTexture, "0", "twice the share of the diffuse base that crosses the sheet: 0 reflects it all, 2 transmits it all").range(Range::Between(0.0, 2.0)),
            rate_param("specular_reflectance_sampling_rate", "the weight of the specular reflection in the choice of a lobe to sample"),
            rate_param("specular_transmittance_sampling_rate", "the weight of the specular transmission in the choice of a lobe to sample"),
            rate_param("diffuse_reflectance_sampling_rate", "the weight of the diffuse reflection in the choice of a lobe to sample"),
            rate_param("diffuse_transmittance_sampling_rate", "the weight of the diffuse transmission in the choice of a lobe to sample"),
            SAMPLE_VISIBLE,
        ],
    };

    const MITSUBA: Mitsuba = Mitsuba::differs("`sample_visible` is Penumbra's");

    fn build(p: &Props, d: &Defaults) -> Result<PrincipledThin, Invalid> {
        let t = d.textures;
        let diff_trans = match t.number(p, "diff_trans")? {
            None => Weight {
                value: Texture::Constant(Rgb::ZERO),
                on: false,
            },
            Some(v) => {
                let (lo, hi, on, value) = match v {
                    NumberOr::Number(x) => (x, x, x != 0.0, Texture::Constant(Rgb::splat(x))),
                    NumberOr::Texture(t) => {
                        let (lo, hi) = t.bounds_1();
                        (lo, hi, true, t)
                    }
                };
                if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi <= 2.0) {
                    return Err(p.error("diff_trans", format!("must be between 0 and 2, got {lo} to {hi}")));
                }
                Weight { value, on }
            }
        };
        let eta = match t.number(p, "eta")? {
            None => Texture::Constant(Rgb::splat(1.5)),
            Some(v) => {
                let (lo, hi, value) = match v {
                    NumberOr::Number(x) => (x, x, Texture::Constant(Rgb::splat(x))),
                    NumberOr::Texture(t) => {
                        let (lo, hi) = t.bounds_1();
                        (lo, hi, t)
                    }
                };
                if !(lo.is_finite() && hi.is_finite() && lo > 0.0) {
                    return Err(p.error("eta", format!("must be a finite number > 0, got {lo} to {hi}")));
                }
                value
            }
        };
        Ok(PrincipledThin(Box::new(Params {
            base_color: reflectance_texture(p, t, "base_color", Rgb::splat(0.5))?,
            roughness: read_weight(p, t, "roughness", 0.5)?,
            anisotropic: read_weight(p, t, "anisotropic", 0.0)?,
            spec_trans: read_weight(p, t, "spec_trans", 0.0)?,
            spec_tint: read_weight(p, t, "spec_tint", 0.0)?,
            sheen: read_weight(p, t, "sheen", 0.0)?,
            sheen_tint: read_weight(p, t, "sheen_tint", 0.0)?,
            flatness: read_weight(p, t, "flatness", 0.0)?,
            diff_trans,
            eta,
            rates: [
                read_rate(p, "specular_reflectance_sampling_rate", 1.0)?,
                read_rate(p, "specular_transmittance_sampling_rate", 1.0)?,
                read_rate(p, "diffuse_reflectance_sampling_rate", 1.0)?,
                read_rate(p, "diffuse_transmittance_sampling_rate", 1.0)?,
            ],
            sample_visible: p.bool("sample_visible")?.unwrap_or(true),
        })))
    }

    /// Mitsuba's `eval_diffuse_reflectance`: the base colour.
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, _wo: Vec3) -> Rgb {
        self.base_color.eval(si)
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[DIFFUSE_REFLECTION] = FLAGS[DIFFUSE_REFLECTION];
        if self.diff_trans.on {
            l.flags[DIFFUSE_TRANSMISSION] = FLAGS[DIFFUSE_TRANSMISSION];
        }
        if self.spec_trans.on {
            l.flags[GLOSSY_TRANSMISSION] = FLAGS[GLOSSY_TRANSMISSION];
            l.flags[GLOSSY_REFLECTION] = FLAGS[GLOSSY_REFLECTION];
        }
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        let frame = si.shading_frame();
        let Some(q) = Self::pair(frame.to_local(wo), frame.to_local(wi)) else {
            return Rgb::ZERO;
        };
        sum(&self.values(si, &self.at(si), &q))
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let frame = si.shading_frame();
        let o0 = frame.to_local(wo);
        if o0.z == 0.0 {
            return None;
        }
        let side = if o0.z < 0.0 { -1.0 } else { 1.0 };
        let o = o0 * side;
        let a = self.at(si);
        let sq = u.square();
        let (k, v) = match lobe {
            Some(k) => {
                if k >= FLAGS.len() || self.lobes().flags[k].is_empty() {
                    return None;
                }
                (k, sq)
            }
            None => {
                let p = self.choice(&a)?;
                // Mitsuba's order: the specular reflection, the specular
                // transmission, the diffuse reflection, the diffuse
                // transmission.
                let (mut start, mut pick) = (0.0, None);
                for k in [GLOSSY_REFLECTION, GLOSSY_TRANSMISSION, DIFFUSE_REFLECTION, DIFFUSE_TRANSMISSION] {
                    let pk = p[k];
                    if pk > 0.0 {
                        pick = Some((k, pk, start));
                        if sq.x < start + pk {
                            break;
                        }
                    }
                    start += pk;
                }
                let (k, pk, start) = pick?;
                let x = ((sq.x - start) / pk).clamp(0.0, 1.0 - f32::EPSILON);
                (k, Vec2::new(x, sq.y))
            }
        };
        let i = Self::draw(&a, o, k, v)?;
        let wi = frame.to_world(i * side);
        let q = Self::pair(o0, frame.to_local(wi))?;
        let values = self.values(si, &a, &q);
        let d = self.densities(&a, &q);
        // A direction its own lobe cannot give (the mirrored transmission
        // leaving on the facet's near side) is refused, as Mitsuba refuses
        // it by the drawn normal: the lobe's density counts only the
        // others.
        if d[k].is_nan() || d[k] <= 0.0 {
            return None;
        }
        let (value, pdf) = match lobe {
            Some(k) => (values[k], d[k]),
            None => (sum(&values), Self::mixture(&self.choice(&a)?, &d)),
        };
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = value * (q.i.z.abs() / pdf);
        weight.is_finite().then_some(BsdfSample {
            wi,
            weight,
            pdf,
            flags: FLAGS[k],
            lobe: k,
            eta: 1.0,
        })
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        let frame = si.shading_frame();
        let Some(q) = Self::pair(frame.to_local(wo), frame.to_local(wi)) else {
            return 0.0;
        };
        let a = self.at(si);
        match self.choice(&a) {
            Some(p) => Self::mixture(&p, &self.densities(&a, &q)),
            None => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{
        self, albedo, build, check_weights, interaction, model_p_value, views,
    };
    use crate::bsdf::principled::Principled;

    const SETS: [&str; 6] = [
        "",
        "base_color = [0.8, 0.4, 0.2]\nroughness = 0.3\nsheen = 0.7\nsheen_tint = 0.5\nflatness = 0.6\ndiff_trans = 0.8",
        "spec_trans = 1\nroughness = 0.4\neta = 1.5\nbase_color = [1, 1, 1]",
        "spec_trans = 0.6\nroughness = 0.5\nanisotropic = 0.7\nspec_tint = 0.5\ndiff_trans = 1.2\neta = 1.33\nbase_color = [0.2, 0.7, 0.4]",
        "spec_trans = 0.3\nroughness = 0.2\ndiff_trans = 2\nspecular_transmittance_sampling_rate = 3\nsample_visible = false",
        "spec_trans = 0.8\nroughness = 0.7\neta = 2.2\ndiffuse_reflectance_sampling_rate = 0.2",
    ];

    fn models() -> Vec<(String, PrincipledThin)> {
        SETS.iter()
            .map(|t| (t.to_string(), build::<PrincipledThin>(t).unwrap_or_else(|e| panic!("{t}: {e}"))))
            .collect()
    }

    /// The sampler's directions follow its pdf, from both sides.
    #[test]
    fn sampling_passes_chi2() {
        let si = interaction(Vec3::Z);
        chi2::assert_samplers_pass(models(), &views(), &si, model_p_value);
    }

    /// Weights are eval·cos/pdf, for the mixture and each lobe alone; the
    /// sheet is the same from both sides; energy-conserving settings
    /// (white, no retro-reflection surplus: a specular sheet, a diffuse
    /// transmitter) keep the albedo at most 1.
    #[test]
    fn weights_sides_and_energy() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        for (text, m) in models() {
            for wo in views().map(|v| frame.to_world(v)) {
                check_weights(&m, &si, wo, 20_000);
                let mut rng = crate::sampling::Rng::new(5);
                for _ in 0..300 {
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    for k in 0..4 {
                        let Some(s) = m.sample(&si, wo, Some(k), u) else { continue };
                        let q = PrincipledThin::pair(frame.to_local(wo), frame.to_local(s.wi)).unwrap();
                        let a = m.at(&si);
                        let want = m.values(&si, &a, &q)[k] * (s.wi.dot(n).abs() / s.pdf);
                        assert!((s.weight - want).abs().max_element() <= 1e-3 * want.max_element().max(1e-2), "{text} lobe {k}");
                    }
                }
                for wi in views().map(|v| frame.to_world(Vec3::new(-v.y, v.x, v.z))) {
                    let (a, b) = (m.eval(&si, wo, wi), m.eval(&si, -wo, -wi));
                    assert!((a - b).abs().max_element() <= 1e-5 * a.max_element().max(1.0), "{text}");
                    assert!((m.pdf(&si, wo, wi) - m.pdf(&si, -wo, -wi)).abs() <= 1e-4, "{text}");
                }
            }
        }
        for text in [
            "spec_trans = 1\nroughness = 0.4\neta = 1.5\nbase_color = [1, 1, 1]",
            "spec_trans = 1\nroughness = 0.6\neta = 1.2\nbase_color = [1, 1, 1]\nanisotropic = 0.5",
            "diff_trans = 2\nbase_color = [1, 1, 1]",
        ] {
            let m = build::<PrincipledThin>(text).unwrap();
            for wo in views().map(|v| frame.to_world(v)) {
                let (a, err) = albedo(&m, &si, wo, 360_000);
                let (s, serr) = chi2::sampled_albedo(&m, &si, wo, 200_000);
                eprintln!("{}: albedo {:.4} ± {err:.4}, sampled {:.4} ± {serr:.4}", text.replace('\n', ", "), a.max_element(), s.max_element());
                assert!(a.max_element() <= 1.0 + 4.0 * err + 2e-3, "{text}: albedo {a:?} ± {err}");
                assert!((s - a).abs().max_element() <= 4.0 * (err + serr) + 2e-3, "{text}: {s:?} vs {a:?}");
            }
        }
    }

    /// With no specular share the diffuse reflection is `principled`'s
    /// base (with no main reflection) times `1 − diff_trans/2`, and the diffuse transmission the
    /// rest as a Lambertian lobe; a white diffuse transmitter
    /// (`diff_trans = 2`) transmits exactly 1.
    #[test]
    fn the_base_is_the_principled_one() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        let keys = "base_color = [0.8, 0.4, 0.2]\nroughness = 0.3\nsheen = 0.7\nsheen_tint = 0.5\nflatness = 0.6";
        // `specular = 0` is an index of 1: no main reflection.
        let full = build::<Principled>(&format!("{keys}\nspecular = 0")).unwrap();
        let thin = build::<PrincipledThin>(&format!("{keys}\ndiff_trans = 0.5")).unwrap();
        for wo in views().map(|v| frame.to_world(v)).into_iter().take(3) {
            for v in views() {
                let wi = frame.to_world(Vec3::new(-v.y, v.x, v.z));
                let (t, f) = (thin.eval(&si, wo, wi), full.eval(&si, wo, wi));
                if v.z > 0.0 {
                    let want = f * 0.75;
                    assert!((t - want).abs().max_element() <= 1e-5 * want.max_element().max(1e-3), "{t:?} vs {want:?}");
                } else {
                    let want = Rgb::new(0.8, 0.4, 0.2) * (0.25 * FRAC_1_PI);
                    assert!((t - want).abs().max_element() <= 1e-6, "{t:?} vs {want:?}");
                }
            }
        }
        let white = build::<PrincipledThin>("diff_trans = 2\nbase_color = [1, 1, 1]").unwrap();
        for wo in views().map(|v| frame.to_world(v)) {
            let (s, serr) = chi2::sampled_albedo(&white, &si, wo, 10_000);
            assert!((s.max_element() - 1.0).abs() <= 1e-4 && serr <= 1e-4, "{s:?}");
        }
    }

    /// Parameters are Mitsuba's, and bad values are refused at their place.
    #[test]
    fn parameters() {
        let m = build::<PrincipledThin>("").unwrap();
        assert_eq!(m.eta, Texture::Constant(Rgb::splat(1.5)));
        assert_eq!(m.base_color, Texture::Constant(Rgb::splat(0.5)));
        assert!(!m.spec_trans.on && !m.diff_trans.on);
        assert_eq!(m.rates, [1.0; 4]);
        assert!(m.lobes().flags[GLOSSY_REFLECTION].is_empty() && m.lobes().flags[DIFFUSE_TRANSMISSION].is_empty());
        for (text, want) in [
            ("diff_trans = 2.5", "must be between 0 and 2"),
            ("eta = 0", "must be a finite number > 0"),
            ("spec_trans = 1.5", "must be between 0 and 1"),
            ("specular_reflectance_sampling_rate = -1", "must be a finite number ≥ 0"),
        ] {
            let e = build::<PrincipledThin>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
