//! `principled`: Mitsuba 3's `principled`, Burley's "Disney" material
//! (Burley 2012, "Physically Based Shading at Disney"; 2015, "Extending
//! the Disney BRDF to a BSDF with Integrated Subsurface Scattering") in
//! Mitsuba's formulas: a diffuse base with retro-reflection, a fake
//! subsurface term and sheen; a GGX reflection whose Fresnel factor blends
//! the dielectric reflectance with Schlick's toward `base_color` (metal)
//! and toward its hue (tint); a GGX transmission tinted by
//! `√base_color`; and a clearcoat of the GTR1 distribution.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `base_color` | colour in [0, 1] or texture | `[0.5, 0.5, 0.5]` | the colour of the diffuse base, the metal and the tints |
//! | `roughness` | number in [0, 1] or texture | `0.5` | the roughness of the main lobes (GGX `α = roughness²`, at least 0.001) |
//! | `anisotropic` | number in [0, 1] or texture | `0` | the anisotropy of the main lobes |
//! | `metallic` | number in [0, 1] or texture | `0` | the share of the metal |
//! | `spec_trans` | number in [0, 1] or texture | `0` | the share of the non-metal that transmits |
//! | `eta` | number > 0 | from `specular` | the relative index of refraction (not with `specular`) |
//! | `specular` | number in [0, 1] | `0.5` | the index as a reflectance: `η = 2 / (1 − √(0.08 specular)) − 1` |
//! | `spec_tint` | number in [0, 1] or texture | `0` | how much the dielectric reflection takes the hue of `base_color` |
//! | `sheen`, `sheen_tint` | number in [0, 1] or texture | `0` | the sheen at grazing angles, and its tint toward the hue |
//! | `flatness` | number in [0, 1] or texture | `0` | the blend from the diffuse term to the fake subsurface one |
//! | `clearcoat`, `clearcoat_gloss` | number in [0, 1] or texture | `0` | the clearcoat's strength and glossiness (GTR1 `α` from 0.1 to 0.001) |
//! | `main_specular_sampling_rate`, `clearcoat_sampling_rate`, `diffuse_reflectance_sampling_rate` | number ≥ 0 | `1` | the weights of the lobes in the choice of a lobe to sample |
//! | `sample_visible` | bool | `true` | sample the visible normals of the main lobes (Penumbra's; Mitsuba always does) |
//!
//! As in Mitsuba, a weight given as the number 0 (or not given) turns its
//! lobe off: `spec_trans` the transmission (and the inside: light from
//! behind the normal sees nothing unless it is on), `clearcoat` the
//! clearcoat; with transmission on, an `eta` of 1 is raised to 1.001 and
//! a `specular` of 0 to 0.001. The values, with `wo` toward the viewer,
//! `wi` toward the light and `h` their half vector (the refraction half
//! vector `wo + η wi` through the surface), are Mitsuba's to the letter,
//! including its clearcoat, which lacks the `1 / (4 cos θo cos θi)` of a
//! microfacet lobe, and its sheen, which counts where the diffuse base does.
//!
//! Its lobes, by slot as Mitsuba's components: 0 diffuse reflection (the
//! base and the sheen, drawn by the cosine), 1 the clearcoat (drawn from
//! GTR1's normals), 2 the transmission, 3 the main reflection (both drawn
//! from GGX's normals visible from `wo`). With no lobe asked for, a lobe
//! is chosen with Mitsuba's weights: from outside, `rate·brdf` for the
//! base (`brdf = (1 − metallic)(1 − spec_trans)`), `rate·clearcoat/4` for
//! the clearcoat and, for the main lobes together, their rate, split
//! between reflection and transmission as `1 − bsdf (1 − F)` to
//! `bsdf (1 − F)` (`bsdf = (1 − metallic) spec_trans`); from inside, `F`
//! to `1 − F`. Mitsuba takes `F` at the normal it drew, which needs a
//! third random number a set point does not carry; here `F` is the
//! dielectric reflectance at the macro normal kept within [0.1, 0.9].
//! Both are unbiased; the weight is `eval · |cos| / pdf` with the density
//! of the whole mixture.

use super::conductor::reflectance_texture;
use super::fresnel;
use super::microfacet::{Kind as Distribution, Microfacet};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::{BsdfModel, Defaults};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::sampling::SetPoint;
use crate::texture::{NumberOr, Texture, Textures};

use std::f32::consts::{FRAC_1_PI, PI};

/// A number parameter of the principled models: its texture (a constant
/// for a number) and whether it turns its lobe on, as Mitsuba's
/// `get_flag`: given, and not as the number 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Weight {
    pub value: Texture,
    pub on: bool,
}

impl Weight {
    /// The value at the interaction; 0 when off.
    #[inline]
    pub fn at(&self, si: &SurfaceInteraction) -> f32 {
        if self.on {
            self.value.eval_1(si)
        } else {
            0.0
        }
    }
}

/// The number or texture `name` in [0, 1], `default` when absent.
pub fn read_weight(p: &Props, textures: &Textures, name: &str, default: f32) -> Result<Weight, Invalid> {
    let Some(v) = textures.number(p, name)? else {
        return Ok(Weight {
            value: Texture::Constant(Rgb::splat(default)),
            on: false,
        });
    };
    let (lo, hi, on) = match &v {
        NumberOr::Number(x) => (*x, *x, *x != 0.0),
        NumberOr::Texture(t) => {
            let (lo, hi) = t.bounds_1();
            (lo, hi, true)
        }
    };
    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi <= 1.0) {
        return Err(if lo == hi {
            p.error(name, format!("must be between 0 and 1, got {lo}"))
        } else {
            p.error(
                name,
                format!("must be between 0 and 1; the texture's values span {lo} to {hi}"),
            )
        });
    }
    let value = match v {
        NumberOr::Number(x) => Texture::Constant(Rgb::splat(x)),
        NumberOr::Texture(t) => t,
    };
    Ok(Weight { value, on })
}

/// The number `name` ≥ 0, `default` when absent.
pub fn read_rate(p: &Props, name: &str, default: f32) -> Result<f32, Invalid> {
    match p.f32(name)? {
        None => Ok(default),
        Some(x) if x.is_finite() && x >= 0.0 => Ok(x),
        Some(x) => Err(p.error(name, format!("must be a finite number ≥ 0, got {x}"))),
    }
}

/// A schema entry of a weight in [0, 1].
pub const fn weight_param(name: &'static str, default: &'static str, doc: &'static str) -> Param {
    Param::new(name, Type::NumberTexture, default, doc).range(Range::Unit)
}

/// A schema entry of a sampling rate.
pub const fn rate_param(name: &'static str, doc: &'static str) -> Param {
    Param::new(name, Type::Number, "1", doc).range(Range::NonNegative)
}

/// Mitsuba's luminance of a linear sRGB colour.
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    0.212671 * c.r + 0.715160 * c.g + 0.072169 * c.b
}

/// `a + (b − a) t`.
#[inline]
pub fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// Schlick's weight `(1 − cos)⁵`, the cosine clamped to [0, 1].
#[inline]
pub fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Schlick's reflectance of normal reflectance `r0` at the facet cosine
/// `cos` (signed by side) of an interface of index `eta`: the cosine on
/// the denser side counts (the refracted one when light leaves toward
/// a lower index), as Mitsuba's `calc_schlick`.
#[inline]
pub fn schlick(r0: Rgb, cos: f32, eta: f32) -> Rgb {
    let eta_it = if cos >= 0.0 { eta } else { 1.0 / eta };
    let w = if eta_it > 1.0 {
        schlick_weight(cos.abs())
    } else {
        let eta_ti = 1.0 / eta_it;
        let cos_t2 = 1.0 - (1.0 - cos * cos) * eta_ti * eta_ti;
        schlick_weight(cos_t2.max(0.0).sqrt())
    };
    r0 * (1.0 - w) + Rgb::splat(w)
}

/// The normal reflectance `((η − 1)/(η + 1))²` Schlick's form takes.
#[inline]
pub fn schlick_r0(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// `base_color` divided by its luminance (its hue); white for black.
#[inline]
pub fn hue(base: Rgb) -> Rgb {
    let lum = luminance(base);
    if lum > 0.0 {
        base * (1.0 / lum)
    } else {
        Rgb::ONE
    }
}

/// The GGX roughness of the main lobes, Mitsuba's `calc_dist_params`:
/// `roughness²`, stretched along the tangent and shrunk along the
/// bitangent by `√(1 − 0.9 anisotropic)`, each at least 0.001.
pub fn ggx(roughness: f32, anisotropic: Option<f32>, sample_visible: bool) -> Microfacet {
    let r2 = roughness * roughness;
    let (au, av) = match anisotropic {
        None => (r2.max(0.001), r2.max(0.001)),
        Some(a) => {
            let aspect = (1.0 - 0.9 * a).sqrt();
            ((r2 / aspect).max(0.001), (r2 * aspect).max(0.001))
        }
    };
    Microfacet::new(Distribution::Ggx, au, av, sample_visible)
}

/// Burley's GTR1 distribution of the clearcoat's normals (isotropic,
/// `α` from 0.1 at gloss 0 to 0.001 at gloss 1), sampled by `D cos θ`.
#[derive(Clone, Copy, Debug)]
pub struct Gtr1 {
    alpha: f32,
}

impl Gtr1 {
    pub fn of_gloss(gloss: f32) -> Gtr1 {
        Gtr1 {
            alpha: lerp(0.1, 0.001, gloss),
        }
    }

    /// D(m).
    pub fn d(&self, m: Vec3) -> f32 {
        let a2 = self.alpha * self.alpha;
        let d = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * m.z * m.z));
        if d * m.z > 1e-20 {
            d
        } else {
            0.0
        }
    }

    /// The density of [`sample`](Self::sample): D(m) cos θm.
    pub fn pdf(&self, m: Vec3) -> f32 {
        if m.z < 0.0 {
            0.0
        } else {
            m.z * self.d(m)
        }
    }

    pub fn sample(&self, u: Vec2) -> Vec3 {
        let (sin_phi, cos_phi) = (2.0 * PI * u.x).sin_cos();
        let a2 = self.alpha * self.alpha;
        let cos2 = (1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2);
        let sin = (1.0 - cos2).max(0.0).sqrt();
        let cos = cos2.max(0.0).sqrt();
        Vec3::new(cos_phi * sin, sin_phi * sin, cos)
    }
}

/// Smith's GGX masking of roughness `alpha` for the clearcoat.
pub fn smith_ggx1(v: Vec3, m: Vec3, alpha: f32) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let c2 = v.z * v.z;
    let t2 = (1.0 - c2) / c2;
    2.0 / (1.0 + (1.0 + alpha * alpha * t2).sqrt())
}

/// Whether `m` (on the outside) is a facet both `o` and `i` see from their
/// sides: the same side of it for a reflection, opposite ones for a
/// transmission (Mitsuba's `mac_mic_compatibility`).
#[inline]
pub fn facet_agrees(m: Vec3, o: Vec3, i: Vec3, reflection: bool) -> bool {
    let m = if o.z < 0.0 { -m } else { m };
    o.dot(m) > 0.0 && if reflection { i.dot(m) > 0.0 } else { i.dot(m) < 0.0 }
}

/// The principled material (see the [module docs](self)): its
/// parameters, boxed to keep the enum of models small.
#[derive(Clone, Debug)]
pub struct Principled(Box<Params>);

impl std::ops::Deref for Principled {
    type Target = Params;
    fn deref(&self) -> &Params {
        &self.0
    }
}

/// The parameters of [`Principled`].
#[derive(Clone, Debug)]
pub struct Params {
    pub base_color: Texture,
    pub roughness: Weight,
    pub anisotropic: Weight,
    pub metallic: Weight,
    pub spec_trans: Weight,
    pub spec_tint: Weight,
    pub sheen: Weight,
    pub sheen_tint: Weight,
    pub flatness: Weight,
    pub clearcoat: Weight,
    pub clearcoat_gloss: Weight,
    /// The relative index of refraction, inside over outside.
    pub eta: f32,
    /// The sampling rates of the main lobes, the clearcoat and the base.
    pub rates: [f32; 3],
    pub sample_visible: bool,
}

/// The parameters read at an interaction.
struct At {
    base: Rgb,
    roughness: f32,
    metallic: f32,
    clearcoat: f32,
    /// `(1 − metallic)(1 − spec_trans)`, the base's weight.
    brdf: f32,
    /// `(1 − metallic) spec_trans`, the transmission's weight.
    bsdf: f32,
    ggx: Microfacet,
}

/// A pair of directions in the shading frame and what both lobes of a side
/// see of them.
struct Pair {
    o: Vec3,
    i: Vec3,
    reflect: bool,
    refract: bool,
    /// The relative index of the light's side over the viewer's.
    eta_path: f32,
    /// The half vector, on the outside.
    h: Vec3,
}

const DIFFUSE: BsdfFlags = BsdfFlags::DIFFUSE.union(BsdfFlags::REFLECTION);
const GLOSSY_REFLECTION: BsdfFlags = BsdfFlags::GLOSSY.union(BsdfFlags::REFLECTION);
const GLOSSY_TRANSMISSION: BsdfFlags = BsdfFlags::GLOSSY.union(BsdfFlags::TRANSMISSION);

/// The slots of the lobes.
const BASE: usize = 0;
const CLEARCOAT: usize = 1;
const TRANSMISSION: usize = 2;
const REFLECTION: usize = 3;

/// The bounds of the Fresnel reflectance the choice of a main lobe reads.
const CHOICE: (f32, f32) = (0.1, 0.9);

impl Principled {
    fn at(&self, si: &SurfaceInteraction) -> At {
        let roughness = self.roughness.value.eval_1(si);
        let anisotropic = self.anisotropic.on.then(|| self.anisotropic.value.eval_1(si));
        let (metallic, spec_trans) = (self.metallic.at(si), self.spec_trans.at(si));
        At {
            base: self.base_color.eval(si),
            roughness,
            metallic,
            clearcoat: self.clearcoat.at(si),
            brdf: (1.0 - metallic) * (1.0 - spec_trans),
            bsdf: (1.0 - metallic) * spec_trans,
            ggx: ggx(roughness, anisotropic, self.sample_visible),
        }
    }

    fn pair(&self, o: Vec3, i: Vec3) -> Option<Pair> {
        if o.z == 0.0 {
            return None;
        }
        let reflect = o.z * i.z > 0.0;
        let refract = o.z * i.z < 0.0;
        let eta_path = if o.z > 0.0 { self.eta } else { 1.0 / self.eta };
        let h = (o + i * if reflect { 1.0 } else { eta_path }).normalize();
        let h = if h.z < 0.0 { -h } else { h };
        if !h.is_finite() {
            return None;
        }
        Some(Pair {
            o,
            i,
            reflect,
            refract,
            eta_path,
            h,
        })
    }

    /// The probabilities of choosing each lobe (by slot) for a viewer at
    /// `o`; `None` where no lobe can be chosen.
    fn choice(&self, a: &At, o: Vec3) -> Option<[f32; 4]> {
        let f = fresnel::dielectric(o.z, self.eta).r.clamp(CHOICE.0, CHOICE.1);
        let [rate_main, rate_cc, rate_base] = self.rates;
        let mut p = [0.0; 4];
        if o.z > 0.0 {
            p[BASE] = a.brdf * rate_base;
            if self.clearcoat.on {
                p[CLEARCOAT] = 0.25 * a.clearcoat * rate_cc;
            }
            if self.spec_trans.on {
                p[TRANSMISSION] = rate_main * a.bsdf * (1.0 - f);
            }
            p[REFLECTION] = rate_main * (1.0 - a.bsdf * (1.0 - f));
        } else {
            if !(self.spec_trans.on && a.bsdf > 0.0) {
                return None;
            }
            p[TRANSMISSION] = 1.0 - f;
            p[REFLECTION] = f;
        }
        let total: f32 = p.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        Some(p.map(|x| x / total))
    }

    /// Each lobe's value for the pair (without the cosine of `i`).
    fn values(&self, si: &SurfaceInteraction, a: &At, q: &Pair) -> [Rgb; 4] {
        let mut v = [Rgb::ZERO; 4];
        let (o, i, h) = (q.o, q.i, q.h);
        let front = o.z > 0.0;
        let oh = o.dot(h);
        let f = fresnel::dielectric(oh, self.eta);
        let agrees_r = q.reflect && facet_agrees(h, o, i, true);
        let (cos_o, cos_i) = (o.z.abs(), i.z.abs());
        // The main reflection.
        if agrees_r && f.r > 0.0 {
            let dg = a.ggx.d(h) * a.ggx.g(o, i, h);
            if dg > 0.0 {
                let fp = if front {
                    let mut fs = Rgb::ZERO;
                    if self.metallic.on {
                        fs += schlick(a.base, oh, self.eta) * a.metallic;
                    }
                    let spec_tint = self.spec_tint.at(si);
                    if self.spec_tint.on {
                        let eta_it = if oh >= 0.0 { self.eta } else { 1.0 / self.eta };
                        let r0 = hue(a.base) * schlick_r0(eta_it);
                        fs += schlick(r0, oh, self.eta) * ((1.0 - a.metallic) * spec_tint);
                    }
                    Rgb::splat((1.0 - a.metallic) * (1.0 - spec_tint) * f.r) + fs
                } else {
                    Rgb::splat(a.bsdf * f.r)
                };
                v[REFLECTION] = fp * (dg / (4.0 * cos_o * cos_i));
            }
        }
        // The transmission, in radiance (its η² cancelled).
        if self.spec_trans.on
            && a.bsdf > 0.0
            && q.refract
            && facet_agrees(h, o, i, false)
            && f.r < 1.0
        {
            let dg = a.ggx.d(h) * a.ggx.g(o, i, h);
            let ih = i.dot(h);
            let denom = oh + q.eta_path * ih;
            let t = a.bsdf * ((1.0 - f.r) * dg * oh * ih / (cos_o * cos_i * denom * denom)).abs();
            if t > 0.0 && t.is_finite() {
                v[TRANSMISSION] = a.base.map(f32::sqrt) * t;
            }
        }
        // The clearcoat.
        if self.clearcoat.on && a.clearcoat > 0.0 && agrees_r && front {
            let gtr = Gtr1::of_gloss(self.clearcoat_gloss.value.eval_1(si));
            let fcc = schlick(Rgb::splat(0.04), oh, self.eta).r;
            let g = smith_ggx1(o, h, 0.25) * smith_ggx1(i, h, 0.25);
            v[CLEARCOAT] = Rgb::splat(0.25 * a.clearcoat * fcc * gtr.d(h) * g);
        }
        // The base: diffuse, retro-reflection, fake subsurface; the sheen.
        if a.brdf > 0.0 && q.reflect && front {
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
            let mut base = a.base * (a.brdf * FRAC_1_PI * shape);
            let sheen = self.sheen.at(si);
            if self.sheen.on && sheen > 0.0 && a.metallic < 1.0 {
                let fd = schlick_weight(cos_d.abs());
                let tint = if self.sheen_tint.on {
                    let t = self.sheen_tint.value.eval_1(si);
                    (hue(a.base) - Rgb::ONE) * t + Rgb::ONE
                } else {
                    Rgb::ONE
                };
                base += tint * (sheen * (1.0 - a.metallic) * fd);
            }
            v[BASE] = base;
        }
        v
    }

    /// Each lobe's density of drawing the pair (not times a choice).
    fn densities(&self, si: &SurfaceInteraction, a: &At, q: &Pair) -> [f32; 4] {
        let mut d = [0.0; 4];
        let (o, i, h) = (q.o, q.i, q.h);
        let up = if o.z < 0.0 { -o } else { o };
        let (oh, ih) = (o.dot(h), i.dot(h));
        if q.reflect {
            if o.z > 0.0 {
                d[BASE] = i.z * FRAC_1_PI;
            }
            if facet_agrees(h, o, i, true) {
                let jacobian = (1.0 / (4.0 * ih)).abs();
                d[REFLECTION] = a.ggx.pdf(up, h) * jacobian;
                if self.clearcoat.on && o.z > 0.0 {
                    let gtr = Gtr1::of_gloss(self.clearcoat_gloss.value.eval_1(si));
                    d[CLEARCOAT] = gtr.pdf(h) * jacobian;
                }
            }
        } else if q.refract && self.spec_trans.on && facet_agrees(h, o, i, false) {
            let denom = oh + q.eta_path * ih;
            let jacobian = (q.eta_path * q.eta_path * ih / (denom * denom)).abs();
            d[TRANSMISSION] = a.ggx.pdf(up, h) * jacobian;
        }
        d.map(|x| if x.is_finite() { x } else { 0.0 })
    }

    /// Lobe `k`'s direction for the point `u`, in the shading frame.
    fn draw(&self, si: &SurfaceInteraction, a: &At, o: Vec3, k: usize, u: Vec2) -> Option<Vec3> {
        let up = if o.z < 0.0 { -o } else { o };
        let i = match k {
            BASE => square_to_cosine_hemisphere(u),
            CLEARCOAT => {
                let m = Gtr1::of_gloss(self.clearcoat_gloss.value.eval_1(si)).sample(u);
                2.0 * o.dot(m) * m - o
            }
            _ => {
                let (m, pdf_m) = a.ggx.sample(up, u);
                if pdf_m.is_nan() || pdf_m <= 0.0 {
                    return None;
                }
                let om = o.dot(m);
                if k == REFLECTION {
                    2.0 * om * m - o
                } else {
                    let f = fresnel::dielectric(om, self.eta);
                    if f.r >= 1.0 {
                        return None;
                    }
                    (m * (f.eta_ti * om + f.cos_t) - o * f.eta_ti).normalize()
                }
            }
        };
        let side = o.z * i.z;
        let ok = if k == TRANSMISSION { side < 0.0 } else { side > 0.0 };
        (ok && i.is_finite()).then_some(i)
    }
}

impl BsdfModel for Principled {
    const NAME: &'static str = "principled";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "principled",
        what: "principled material",
        doc: "Burley's principled (Disney) material: diffuse base, sheen, GGX metal and dielectric reflection and transmission, clearcoat",
        mitsuba: &["principled"],
        params: &[
            BASE_COLOR,
            ROUGHNESS,
            ANISOTROPIC,
            weight_param("metallic", "0", "the share of the metal (a Schlick reflection of `base_color`)"),
            weight_param("spec_trans", "0", "the share of the non-metal that transmits; 0 turns the transmission off"),
            Param::new("eta", Type::Number, "from `specular`", "relative index of refraction, inside over outside (not with `specular`)").range(Range::Positive),
            Param::new("specular", Type::Number, "0.5", "the index as a normal reflectance: `eta = 2 / (1 − √(0.08 specular)) − 1`").range(Range::Unit),
            SPEC_TINT,
            SHEEN,
            SHEEN_TINT,
            FLATNESS,
            weight_param("clearcoat", "0", "the strength of the clearcoat; 0 turns it off"),
            weight_param("clearcoat_gloss", "0", "the clearcoat's gloss: its GTR1 roughness from 0.1 (0) to 0.001 (1)"),
            rate_param("main_specular_sampling_rate", "the weight of the main reflection and transmission in the choice of a lobe to sample"),
            rate_param("clearcoat_sampling_rate", "the weight of the clearcoat in the choice of a lobe to sample"),
            rate_param("diffuse_reflectance_sampling_rate", "the weight of the base in the choice of a lobe to sample"),
            SAMPLE_VISIBLE,
        ],
    };

    const MITSUBA: Mitsuba = Mitsuba::differs(CHOICE_DIFFERS);

    fn build(p: &Props, d: &Defaults) -> Result<Principled, Invalid> {
        let t = d.textures;
        let spec_trans = read_weight(p, t, "spec_trans", 0.0)?;
        let eta = match (p.has("eta"), p.has("specular")) {
            (true, true) => {
                return Err(p.error("specular", "give either `eta` or `specular`, not both"));
            }
            (true, false) => {
                let eta = p.f32("eta")?.unwrap_or(1.5);
                if !(eta.is_finite() && eta > 0.0) {
                    return Err(p.error("eta", format!("must be a finite number > 0, got {eta}")));
                }
                if spec_trans.on && eta == 1.0 {
                    1.001
                } else {
                    eta
                }
            }
            (false, _) => {
                let s = p.f32("specular")?.unwrap_or(0.5);
                if !(0.0..=1.0).contains(&s) {
                    return Err(p.error("specular", format!("must be between 0 and 1, got {s}")));
                }
                let s = if spec_trans.on && s == 0.0 { 1e-3 } else { s };
                2.0 / (1.0 - (0.08 * s).sqrt()) - 1.0
            }
        };
        Ok(Principled(Box::new(Params {
            base_color: reflectance_texture(p, t, "base_color", Rgb::splat(0.5))?,
            roughness: read_weight(p, t, "roughness", 0.5)?,
            anisotropic: read_weight(p, t, "anisotropic", 0.0)?,
            metallic: read_weight(p, t, "metallic", 0.0)?,
            spec_trans,
            spec_tint: read_weight(p, t, "spec_tint", 0.0)?,
            sheen: read_weight(p, t, "sheen", 0.0)?,
            sheen_tint: read_weight(p, t, "sheen_tint", 0.0)?,
            flatness: read_weight(p, t, "flatness", 0.0)?,
            clearcoat: read_weight(p, t, "clearcoat", 0.0)?,
            clearcoat_gloss: read_weight(p, t, "clearcoat_gloss", 0.0)?,
            eta,
            rates: [
                read_rate(p, "main_specular_sampling_rate", 1.0)?,
                read_rate(p, "clearcoat_sampling_rate", 1.0)?,
                read_rate(p, "diffuse_reflectance_sampling_rate", 1.0)?,
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
        l.flags[BASE] = DIFFUSE;
        if self.clearcoat.on {
            l.flags[CLEARCOAT] = GLOSSY_REFLECTION;
        }
        if self.spec_trans.on {
            l.flags[TRANSMISSION] = GLOSSY_TRANSMISSION;
        }
        l.flags[REFLECTION] = GLOSSY_REFLECTION;
        l
    }

    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        let frame = si.shading_frame();
        let Some(q) = self.pair(frame.to_local(wo), frame.to_local(wi)) else {
            return Rgb::ZERO;
        };
        let a = self.at(si);
        let v = self.values(si, &a, &q);
        v[BASE] + v[CLEARCOAT] + v[TRANSMISSION] + v[REFLECTION]
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
        if o.z == 0.0 {
            return None;
        }
        let a = self.at(si);
        let sq = u.square();
        let (k, v) = match lobe {
            Some(k) => {
                if k > REFLECTION || self.lobes().flags[k].is_empty() {
                    return None;
                }
                // The base and the clearcoat only face the outside; the
                // inside is seen through the transmission only.
                if o.z < 0.0 && (k < TRANSMISSION || !(self.spec_trans.on && a.bsdf > 0.0)) {
                    return None;
                }
                (k, sq)
            }
            None => {
                let p = self.choice(&a, o)?;
                // The first lobe whose share of [0, 1) holds the point's
                // first coordinate; the last possible one past rounding.
                let (mut start, mut pick) = (0.0, None);
                for (k, &pk) in p.iter().enumerate() {
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
        let i = self.draw(si, &a, o, k, v)?;
        let wi = frame.to_world(i);
        let q = self.pair(o, frame.to_local(wi))?;
        let cos = q.i.z.abs();
        let values = self.values(si, &a, &q);
        let d = self.densities(si, &a, &q);
        // A direction its own lobe's density does not count (its facet
        // seen from the wrong side, up to rounding) is refused, as Mitsuba
        // refuses it by the drawn normal.
        if d[k].is_nan() || d[k] <= 0.0 {
            return None;
        }
        let (value, pdf) = match lobe {
            Some(k) => (values[k], d[k]),
            None => {
                let p = self.choice(&a, o)?;
                let pdf = p[BASE] * d[BASE] + p[CLEARCOAT] * d[CLEARCOAT] + p[TRANSMISSION] * d[TRANSMISSION] + p[REFLECTION] * d[REFLECTION];
                (values[BASE] + values[CLEARCOAT] + values[TRANSMISSION] + values[REFLECTION], pdf)
            }
        };
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = value * (cos / pdf);
        if !weight.is_finite() {
            return None;
        }
        let eta = if k == TRANSMISSION {
            q.eta_path
        } else {
            1.0
        };
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            flags: self.lobes().flags[k],
            lobe: k,
            eta,
        })
    }

    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        let frame = si.shading_frame();
        let Some(q) = self.pair(frame.to_local(wo), frame.to_local(wi)) else {
            return 0.0;
        };
        let a = self.at(si);
        let Some(p) = self.choice(&a, q.o) else {
            return 0.0;
        };
        let d = self.densities(si, &a, &q);
        p[BASE] * d[BASE] + p[CLEARCOAT] * d[CLEARCOAT] + p[TRANSMISSION] * d[TRANSMISSION] + p[REFLECTION] * d[REFLECTION]
    }
}

/// What differs from Mitsuba's principled models, for the reference.
pub const CHOICE_DIFFERS: &str = "the main reflection or transmission is chosen by the Fresnel reflectance at the macro normal (within [0.1, 0.9]), not at the drawn normal: the same expectation, another noise; `sample_visible` is Penumbra's";

/// The schema entries the two principled models share.
pub const BASE_COLOR: Param = Param::new(
    "base_color",
    Type::ColourTexture,
    "[0.5, 0.5, 0.5]",
    "the colour of the diffuse base, of the tints and (in `principled`) of the metal, each channel in [0, 1]",
)
.range(Range::Unit);
pub const ROUGHNESS: Param = weight_param("roughness", "0.5", "roughness of the main lobes (GGX α = roughness², at least 0.001)");
pub const ANISOTROPIC: Param = weight_param("anisotropic", "0", "anisotropy of the main lobes: α along the tangent over α along the bitangent is 1 / (1 − 0.9 anisotropic)");
pub const SPEC_TINT: Param = weight_param("spec_tint", "0", "how much the dielectric reflection takes the hue of `base_color`");
pub const SHEEN: Param = weight_param("sheen", "0", "the strength of the sheen at grazing angles");
pub const SHEEN_TINT: Param = weight_param("sheen_tint", "0", "how much the sheen takes the hue of `base_color`");
pub const FLATNESS: Param = weight_param("flatness", "0", "the blend from the diffuse term (0) to the fake subsurface term (1)");
pub const SAMPLE_VISIBLE: Param = Param::new(
    "sample_visible",
    Type::Bool,
    "true",
    "sample the GGX normals visible from the viewer (else the whole distribution)",
)
.penumbra_only();

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{
        self, albedo, build, check_weights, interaction, model_p_value, views,
    };
    use crate::bsdf::roughconductor::RoughConductor;

    /// Parameter sets exercising every lobe, alone and together.
    const SETS: [&str; 8] = [
        "",
        "base_color = [0.8, 0.4, 0.2]\nroughness = 0.3\nsheen = 0.7\nsheen_tint = 0.5\nflatness = 0.6",
        "metallic = 1\nroughness = 0.5\nbase_color = [0.9, 0.6, 0.3]",
        "metallic = 0.4\nroughness = 0.4\nanisotropic = 0.8\nspec_tint = 0.6\nbase_color = [0.2, 0.7, 0.4]",
        "spec_trans = 1\nroughness = 0.4\neta = 1.5\nbase_color = [1, 1, 1]",
        "spec_trans = 0.5\nroughness = 0.6\nspecular = 0.7\nclearcoat = 0.8\nclearcoat_gloss = 0.3",
        "clearcoat = 1\nclearcoat_gloss = 0.5\nroughness = 0.8\nclearcoat_sampling_rate = 3\nsample_visible = false",
        "spec_trans = 0.7\nmetallic = 0.2\nanisotropic = 0.5\nroughness = 0.3\neta = 0.7\ndiffuse_reflectance_sampling_rate = 0.5",
    ];

    fn models() -> Vec<(String, Principled)> {
        SETS.iter()
            .map(|t| (t.to_string(), build::<Principled>(t).unwrap_or_else(|e| panic!("{t}: {e}"))))
            .collect()
    }

    /// The sampler's directions (every lobe, both sides where the inside
    /// is seen) follow its pdf.
    #[test]
    fn sampling_passes_chi2() {
        let si = interaction(Vec3::Z);
        let (glass, opaque): (Vec<_>, Vec<_>) = models().into_iter().partition(|(_, m)| m.spec_trans.on);
        chi2::assert_samplers_pass(glass, &views(), &si, model_p_value);
        // From inside an opaque one nothing is drawn.
        let below = views()[3];
        for (text, m) in &opaque {
            let u = SetPoint::uniform(Vec2::new(0.3, 0.6));
            assert!(m.sample(&si, below, None, u).is_none() && m.pdf(&si, below, -below) == 0.0, "{text}");
        }
        chi2::assert_samplers_pass(opaque, &views()[..3], &si, model_p_value);
    }

    /// Weights are eval·cos/pdf, for the mixture and for each lobe asked
    /// for alone, whose densities make up the mixture's.
    #[test]
    fn weights_match_eval_and_pdf() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        for (text, m) in models() {
            for wo in views().map(|v| frame.to_world(v)) {
                check_weights(&m, &si, wo, 20_000);
                let mut rng = crate::sampling::Rng::new(5);
                for _ in 0..500 {
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    for k in 0..4 {
                        let Some(s) = m.sample(&si, wo, Some(k), u) else { continue };
                        let o = frame.to_local(wo);
                        let q = m.pair(o, frame.to_local(s.wi)).unwrap();
                        let a = m.at(&si);
                        let want = m.values(&si, &a, &q)[k] * (s.wi.dot(n).abs() / s.pdf);
                        assert!((s.weight - want).abs().max_element() <= 1e-3 * want.max_element().max(1e-2), "{text} lobe {k}");
                        let p = m.choice(&a, o).unwrap();
                        let total: f32 = (0..4).map(|j| p[j] * m.densities(&si, &a, &q)[j]).sum();
                        assert!((total - m.pdf(&si, wo, s.wi)).abs() <= 1e-4 * total.max(1e-3), "{text} lobe {k}");
                    }
                }
            }
        }
    }

    /// Settings that conserve energy reflect at most what arrives (the
    /// albedo by quadrature of `eval`, from outside): metals, rough
    /// glasses, a black base under a tinted reflection and a clearcoat. A
    /// white base does not, by Mitsuba's (and Burley's) formulas: its
    /// retro-reflection and the reflection above it add up past 1 (1.04 at
    /// normal incidence for roughness 0.5), which is checked too. The
    /// sampled albedo (the mean weight) agrees with the quadrature.
    #[test]
    fn energy_is_bounded() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        for (text, bounded) in [
            ("metallic = 1\nroughness = 0.5\nbase_color = [1, 1, 1]", true),
            ("metallic = 1\nroughness = 0.2\nanisotropic = 0.7\nbase_color = [1, 1, 1]", true),
            ("spec_trans = 1\nroughness = 0.5\neta = 1.5\nbase_color = [1, 1, 1]", true),
            ("spec_trans = 1\nroughness = 0.3\neta = 1.33\nbase_color = [1, 1, 1]", true),
            ("spec_tint = 1\nbase_color = [0, 0, 0]\nroughness = 0.5\nclearcoat = 1\nclearcoat_gloss = 0.5", true),
            ("base_color = [1, 1, 1]\nroughness = 0.5", false),
        ] {
            let m = build::<Principled>(text).unwrap();
            for (j, wo) in views().map(|v| frame.to_world(v)).into_iter().take(3).enumerate() {
                let (a, err) = albedo(&m, &si, wo, 360_000);
                let (s, serr) = chi2::sampled_albedo(&m, &si, wo, 200_000);
                eprintln!("{}: albedo {:.4} ± {err:.4}, sampled {:.4} ± {serr:.4}", text.replace('\n', ", "), a.max_element(), s.max_element());
                if bounded {
                    assert!(a.max_element() <= 1.0 + 4.0 * err + 2e-3, "{text}: albedo {a:?} ± {err}");
                } else if j == 0 {
                    assert!(a.max_element() > 1.0 + 4.0 * err, "{text}: albedo {a:?} ± {err}");
                }
                assert!((s - a).abs().max_element() <= 4.0 * (err + serr) + 2e-3, "{text}: {s:?} vs {a:?}");
            }
        }
    }

    /// A metal with no tint is Mitsuba's rough conductor (GGX of
    /// α = roughness², visible normals) whose Fresnel factor is Schlick's
    /// of `base_color` at the facet; anisotropy stretches α by
    /// 1/√(1 − 0.9 a) along the tangent.
    #[test]
    fn a_metal_is_a_rough_conductor_with_schlick_fresnel() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        let base = Rgb::new(0.9, 0.6, 0.3);
        for (extra, au, av) in [("", 0.25f32, 0.25f32), ("anisotropic = 0.5\n", 0.25 / 0.55f32.sqrt(), 0.25 * 0.55f32.sqrt())] {
            let m = build::<Principled>(&format!("{extra}metallic = 1\nroughness = 0.5\nbase_color = [0.9, 0.6, 0.3]")).unwrap();
            let white = build::<RoughConductor>(&format!("distribution = \"ggx\"\nalpha_u = {au}\nalpha_v = {av}")).unwrap();
            for wo in views().map(|v| frame.to_world(v)).into_iter().take(3) {
                for wi in views().map(|v| frame.to_world(Vec3::new(-v.y, v.x, v.z))).into_iter().take(3) {
                    let h = (wo + wi).normalize();
                    let c = wo.dot(h);
                    let w = (1.0 - c).powi(5);
                    let schlick = base * (1.0 - w) + Rgb::splat(w);
                    let want = white.eval(&si, wo, wi) * schlick;
                    let got = m.eval(&si, wo, wi);
                    assert!((got - want).abs().max_element() <= 1e-4 * want.max_element().max(1e-3), "{extra}: {got:?} vs {want:?}");
                    let (p, q) = (m.pdf(&si, wo, wi), white.pdf(&si, wo, wi));
                    assert!((p - q).abs() <= 1e-4 * q.max(1e-3), "{extra}: pdf {p} vs {q}");
                }
            }
        }
    }

    /// A glass (`spec_trans = 1`, white) is reciprocal in reflection, and
    /// in transmission up to the radiance scale: f(o, i) / η(o)² =
    /// f(i, o) / η(i)², the indices of the sides of `o` and `i`.
    #[test]
    fn a_glass_is_reciprocal() {
        let n = Vec3::new(0.1, -0.2, 0.97).normalize();
        let si = interaction(n);
        let frame = si.shading_frame();
        let eta = 1.5;
        let m = build::<Principled>("spec_trans = 1\nroughness = 0.4\neta = 1.5\nbase_color = [1, 1, 1]").unwrap();
        let index = |w: Vec3| if w.dot(n) > 0.0 { 1.0 } else { eta };
        let mut checked = 0;
        for wo in views().map(|v| frame.to_world(v)) {
            for wi in views().map(|v| frame.to_world(Vec3::new(-v.y, v.x, -v.z))).into_iter().chain(views().map(|v| frame.to_world(Vec3::new(v.y, -v.x, v.z)))) {
                let (a, b) = (m.eval(&si, wo, wi), m.eval(&si, wi, wo));
                let (a, b) = (a * (1.0 / (index(wo) * index(wo))), b * (1.0 / (index(wi) * index(wi))));
                assert!((a - b).abs().max_element() <= 1e-4 * a.max_element().max(1e-3), "{wo:?} {wi:?}: {a:?} vs {b:?}");
                checked += usize::from(a.max_element() > 0.0);
            }
        }
        assert!(checked >= 8, "{checked} pairs with a value");
    }

    /// Parameters are Mitsuba's: defaults, `specular` to `eta`, the
    /// flags of a weight given as 0, and refusals at their place.
    #[test]
    fn parameters() {
        let m = build::<Principled>("").unwrap();
        assert_eq!(m.base_color, Texture::Constant(Rgb::splat(0.5)));
        assert_eq!(m.roughness.value, Texture::Constant(Rgb::splat(0.5)));
        assert!(!m.spec_trans.on && !m.clearcoat.on && !m.metallic.on);
        assert!((m.eta - (2.0 / (1.0 - 0.04f32.sqrt()) - 1.0)).abs() < 1e-6);
        assert_eq!(m.rates, [1.0; 3]);
        assert!(m.lobes().flags[CLEARCOAT].is_empty() && m.lobes().flags[TRANSMISSION].is_empty());
        assert!(!build::<Principled>("clearcoat = 0").unwrap().clearcoat.on);
        assert_eq!(build::<Principled>("spec_trans = 1\neta = 1").unwrap().eta, 1.001);
        assert_eq!(build::<Principled>("eta = 1").unwrap().eta, 1.0);
        let s = build::<Principled>("spec_trans = 0.5\nspecular = 0").unwrap().eta;
        assert!((s - (2.0 / (1.0 - 0.00008f32.sqrt()) - 1.0)).abs() < 1e-6);
        for (text, want) in [
            ("eta = 1.5\nspecular = 0.5", "either `eta` or `specular`"),
            ("roughness = 1.5", "must be between 0 and 1"),
            ("metallic = -0.1", "must be between 0 and 1"),
            ("base_color = [1, 2, 1]", "must not exceed 1"),
            ("eta = -1", "must be a finite number > 0"),
            ("specular = 2", "must be between 0 and 1"),
            ("clearcoat_sampling_rate = -1", "must be a finite number ≥ 0"),
        ] {
            let e = build::<Principled>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
