//! Microfacet normal distributions: Beckmann and GGX (Trowbridge–Reitz),
//! isotropic or anisotropic, as Mitsuba 3's `MicrofacetDistribution`
//! (Walter et al. 2007, "Microfacet Models for Refraction through Rough
//! Surfaces"; Heitz 2014, "Understanding the Masking-Shadowing Function").
//!
//! Everything is in the shading frame: `z` the macro-surface normal, `x`
//! along `dp/du` (roughness `alpha_u`), `y` the bitangent (`alpha_v`).
//! Both distributions are *stretch-invariant*: the slopes of an
//! anisotropic one are those of the distribution of roughness 1 scaled by
//! `(alpha_u, alpha_v)`, which every sampler here uses.
//!
//! | function | what |
//! |---|---|
//! | [`Microfacet::d`] | the distribution D(m), normalised so that ∫ D(m) cos θm dω = 1 |
//! | [`Microfacet::g1`], [`Microfacet::g`] | Smith's masking G1(v, m) = χ⁺ / (1 + Λ(v)) (Λ exact for both, with erf for Beckmann), and the separable G = G1 · G1 Mitsuba uses |
//! | [`Microfacet::sample`], [`Microfacet::pdf`] | a normal drawn from the visible normals of `wo` (`sample_visible`) or from D cos θm, and its density |
//! | visible normals of GGX | Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (a hemisphere section of the stretched view) |
//! | visible normals of Beckmann | the slope along the view of the roughness-1 distribution, whose density ∝ e^(−x²) (1 − x tan θ) is inverted numerically (its CDF is `1 + erf x + tan θ e^(−x²)/√π`, as in Jakob 2014), the other slope normal |
//!
//! The shared parameters of rough models (their schema entries below):
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `distribution` | `beckmann` or `ggx` | `beckmann` | the normal distribution |
//! | `alpha` | number ≥ 0 or texture | `0.1` | roughness (the RMS slope for Beckmann); both `alpha_u` and `alpha_v` |
//! | `alpha_u`, `alpha_v` | number ≥ 0 or texture | `alpha` | roughness along the tangent and the bitangent; both or neither, not with `alpha` |
//! | `sample_visible` | bool | `true` | sample the visible normals (else the whole distribution) |
//!
//! Roughness below 1e-4 is raised to 1e-4, as Mitsuba does. A textured
//! roughness ([`Roughness`]) is read as one value ([`Texture::eval_1`])
//! at each interaction.

use std::f64::consts::PI as PI64;

use statrs::function::erf::{erf, erf_inv};

use crate::description::{Invalid, Param, Props, Range, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Vec2, Vec3};
use crate::texture::{NumberOr, Texture, Textures};

/// The kind of normal distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Beckmann,
    Ggx,
}

/// The smallest roughness: below it the distributions are too sharp for
/// `f32` (Mitsuba's clamp).
pub const MIN_ALPHA: f32 = 1e-4;

/// A microfacet normal distribution with its roughness and sampling
/// technique (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    pub kind: Kind,
    pub alpha_u: f32,
    pub alpha_v: f32,
    pub sample_visible: bool,
}

/// The schema entries of the parameters [`Microfacet::read`] reads.
pub const PARAMS: [Param; 5] = [
    Param::new(
        "distribution",
        Type::Choice("microfacet distribution", &["beckmann", "ggx"]),
        "beckmann",
        "the microfacet normal distribution",
    ),
    Param::new(
        "alpha",
        Type::NumberTexture,
        "0.1",
        "roughness ≥ 0 (RMS slope for Beckmann), along both tangents",
    )
    .range(Range::Between(0.0, 100.0)),
    Param::new(
        "alpha_u",
        Type::NumberTexture,
        "alpha",
        "roughness ≥ 0 along the tangent `dp/du`; with `alpha_v`, not with `alpha`",
    )
    .range(Range::Between(0.0, 100.0)),
    Param::new(
        "alpha_v",
        Type::NumberTexture,
        "alpha",
        "roughness ≥ 0 along the bitangent; with `alpha_u`, not with `alpha`",
    )
    .range(Range::Between(0.0, 100.0)),
    Param::new(
        "sample_visible",
        Type::Bool,
        "true",
        "sample the normals visible from the viewer (else the whole distribution)",
    ),
];

/// A rough model's distribution: fixed, or with its roughness textured
/// (`alpha_u`, `alpha_v` looked up at each interaction).
#[derive(Clone, Debug, PartialEq)]
pub struct Roughness {
    /// The distribution; its roughness is the one used unless textured.
    pub base: Microfacet,
    /// The textures of `alpha_u` and `alpha_v`, if either varies.
    pub textures: Option<Box<[Texture; 2]>>,
}

impl Roughness {
    /// A fixed distribution.
    pub fn fixed(base: Microfacet) -> Roughness {
        Roughness {
            base,
            textures: None,
        }
    }

    /// The distribution at the interaction.
    #[inline]
    pub fn at(&self, si: &SurfaceInteraction) -> Microfacet {
        match &self.textures {
            None => self.base,
            Some(t) => Microfacet::new(
                self.base.kind,
                t[0].eval_1(si),
                t[1].eval_1(si),
                self.base.sample_visible,
            ),
        }
    }
}

/// The largest roughness a scene may ask for.
const MAX_ALPHA: f32 = 100.0;

impl Microfacet {
    /// A distribution of roughness `(alpha_u, alpha_v)`, each raised to
    /// [`MIN_ALPHA`].
    pub fn new(kind: Kind, alpha_u: f32, alpha_v: f32, sample_visible: bool) -> Microfacet {
        Microfacet {
            kind,
            alpha_u: alpha_u.max(MIN_ALPHA),
            alpha_v: alpha_v.max(MIN_ALPHA),
            sample_visible,
        }
    }

    /// The distribution of a rough model's parameters ([`PARAMS`]) for a
    /// model whose roughness is not textured: `alpha`, or both `alpha_u`
    /// and `alpha_v`; each a number in [0, 100].
    pub fn read(p: &Props) -> Result<Microfacet, Invalid> {
        let r = Microfacet::read_textured(p, &Textures::default())?;
        match r.textures {
            None => Ok(r.base),
            Some(_) => {
                let name = ["alpha", "alpha_u"].into_iter().find(|n| p.has(n));
                Err(p.error(
                    name.unwrap_or("alpha"),
                    "this model takes a number here, not a texture",
                ))
            }
        }
    }

    /// The distribution of a rough model's parameters ([`PARAMS`]) whose
    /// roughness may be textured: `alpha`, or both `alpha_u` and
    /// `alpha_v`, each a number or a texture with values in [0, 100].
    pub fn read_textured(p: &Props, textures: &Textures) -> Result<Roughness, Invalid> {
        let kind = match p.choice(
            "distribution",
            "microfacet distribution",
            &["beckmann", "ggx"],
        )? {
            Some("ggx") => Kind::Ggx,
            _ => Kind::Beckmann,
        };
        let (has_u, has_v) = (p.has("alpha_u"), p.has("alpha_v"));
        let one = |name: &str| -> Result<NumberOr, Invalid> {
            let v = textures.number(p, name)?.unwrap_or(NumberOr::Number(0.1));
            let (lo, hi) = match &v {
                NumberOr::Number(x) => (*x, *x),
                NumberOr::Texture(t) => t.bounds_1(),
            };
            if lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi <= MAX_ALPHA {
                Ok(v)
            } else if lo == hi {
                Err(p.error(name, format!("must be between 0 and {MAX_ALPHA}, got {lo}")))
            } else {
                Err(p.error(
                    name,
                    format!(
                        "must be between 0 and {MAX_ALPHA}; the texture's values span {lo} to {hi}"
                    ),
                ))
            }
        };
        let (au, av) = if has_u || has_v {
            if p.has("alpha") {
                return Err(p.error(
                    "alpha",
                    "give either `alpha` or `alpha_u` and `alpha_v`, not both",
                ));
            }
            if !(has_u && has_v) {
                let missing = if has_u { "alpha_v" } else { "alpha_u" };
                return Err(p.node_error(format!(
                    "`alpha_u` and `alpha_v` go together: `{missing}` is missing"
                )));
            }
            (one("alpha_u")?, one("alpha_v")?)
        } else {
            let a = one("alpha")?;
            (a.clone(), a)
        };
        let visible = p.bool("sample_visible")?.unwrap_or(true);
        Ok(match (au, av) {
            (NumberOr::Number(u), NumberOr::Number(v)) => Roughness {
                base: Microfacet::new(kind, u, v, visible),
                textures: None,
            },
            (u, v) => {
                let texture = |x: NumberOr| match x {
                    NumberOr::Number(x) => Texture::Constant(crate::math::Rgb::splat(x)),
                    NumberOr::Texture(t) => t,
                };
                Roughness {
                    base: Microfacet::new(kind, 0.1, 0.1, visible),
                    textures: Some(Box::new([texture(u), texture(v)])),
                }
            }
        })
    }

    /// True if the two roughnesses differ.
    pub fn is_anisotropic(&self) -> bool {
        self.alpha_u != self.alpha_v
    }

    /// The distribution of normals D(m) (0 below the surface).
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.alpha_u, m.y / self.alpha_v);
        let z2 = m.z * m.z;
        let norm = std::f32::consts::PI * self.alpha_u * self.alpha_v;
        let d = match self.kind {
            Kind::Beckmann => (-(x * x + y * y) / z2).exp() / (norm * z2 * z2),
            Kind::Ggx => {
                let t = x * x + y * y + z2;
                1.0 / (norm * t * t)
            }
        };
        if (d * m.z).is_finite() && d * m.z > 1e-20 {
            d
        } else {
            0.0
        }
    }

    /// Smith's Λ(v) for a direction above the surface (v.z > 0).
    fn lambda(&self, v: Vec3) -> f32 {
        let xy = (self.alpha_u * v.x).powi(2) + (self.alpha_v * v.y).powi(2);
        if xy <= 0.0 {
            return 0.0;
        }
        // tan²θ scaled by the roughness along v's azimuth.
        let t2 = f64::from(xy) / f64::from(v.z * v.z);
        let l = match self.kind {
            Kind::Ggx => 0.5 * ((1.0 + t2).sqrt() - 1.0),
            Kind::Beckmann => {
                let a = 1.0 / t2.sqrt();
                0.5 * (erf(a) - 1.0) + (-a * a).exp() / (2.0 * a * PI64.sqrt())
            }
        };
        l as f32
    }

    /// Smith's masking of the normal `m` seen from `v`: 0 if `v` sees its
    /// back or lies on the other side of the surface than `m` faces.
    pub fn g1(&self, v: Vec3, m: Vec3) -> f32 {
        if v.dot(m) * v.z <= 0.0 || v.z == 0.0 {
            return 0.0;
        }
        let v = if v.z < 0.0 { -v } else { v };
        1.0 / (1.0 + self.lambda(v))
    }

    /// The separable shadowing-masking G1(wo, m) · G1(wi, m).
    pub fn g(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        self.g1(wo, m) * self.g1(wi, m)
    }

    /// A normal for the point `u` of the unit square, with its density
    /// ([`pdf`](Self::pdf)): a normal visible from `wo` (`wo.z > 0`) when
    /// `sample_visible`, else one of D cos θm.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let m = if self.sample_visible {
            self.sample_visible_normal(wo, u)
        } else {
            self.sample_normal(u)
        };
        (m, self.pdf(wo, m))
    }

    /// The density of [`sample`](Self::sample) drawing `m`, per solid angle
    /// of normals: D(m) G1(wo, m) (wo · m) / cos θo for visible normals,
    /// D(m) cos θm for the whole distribution.
    pub fn pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        if self.sample_visible {
            if wo.z <= 0.0 {
                return 0.0;
            }
            self.d(m) * self.g1(wo, m) * wo.dot(m).max(0.0) / wo.z
        } else {
            self.d(m) * m.z.max(0.0)
        }
    }

    /// A normal of the whole distribution (density D(m) cos θm): one of
    /// roughness 1, stretched.
    pub fn sample_normal(&self, u: Vec2) -> Vec3 {
        let u1 = f64::from(u.x).min(1.0 - 1e-9);
        let tan2 = match self.kind {
            Kind::Beckmann => -(1.0 - u1).ln(),
            Kind::Ggx => u1 / (1.0 - u1),
        };
        let cos = 1.0 / (1.0 + tan2).sqrt();
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI64 * f64::from(u.y);
        let m = Vec3::new(
            (sin * phi.cos()) as f32 * self.alpha_u,
            (sin * phi.sin()) as f32 * self.alpha_v,
            cos as f32,
        );
        m.normalize()
    }

    /// A normal of the distribution of normals visible from `wo`
    /// (`wo.z > 0`), density D(m) G1(wo, m) (wo · m)⁺ / cos θo.
    pub fn sample_visible_normal(&self, wo: Vec3, u: Vec2) -> Vec3 {
        // The view in the stretched configuration of roughness 1.
        let v = Vec3::new(self.alpha_u * wo.x, self.alpha_v * wo.y, wo.z.max(1e-7)).normalize();
        match self.kind {
            Kind::Ggx => {
                // Heitz 2018: the visible normals of roughness 1 are the
                // hemisphere around `v` seen along `v`: a disk point,
                // squeezed onto the half the hemisphere hides, lifted.
                let len2 = v.x * v.x + v.y * v.y;
                let t1 = if len2 > 0.0 {
                    Vec3::new(-v.y, v.x, 0.0) / len2.sqrt()
                } else {
                    Vec3::X
                };
                let t2 = v.cross(t1);
                let r = u.x.sqrt();
                let phi = std::f32::consts::TAU * u.y;
                let p1 = r * phi.cos();
                let s = 0.5 * (1.0 + v.z);
                let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
                let h = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * v;
                Vec3::new(self.alpha_u * h.x, self.alpha_v * h.y, h.z.max(1e-7)).normalize()
            }
            Kind::Beckmann => {
                let (x, y) = beckmann_visible_slopes(f64::from(v.z), u);
                // Rotate the slopes to the view's azimuth, then unstretch.
                let len = (v.x * v.x + v.y * v.y).sqrt();
                let (c, s) = if len > 0.0 {
                    (f64::from(v.x / len), f64::from(v.y / len))
                } else {
                    (1.0, 0.0)
                };
                let sx = (c * x - s * y) as f32 * self.alpha_u;
                let sy = (s * x + c * y) as f32 * self.alpha_v;
                Vec3::new(-sx, -sy, 1.0).normalize()
            }
        }
    }
}

/// The slopes `(x, y)` of a normal of the Beckmann distribution of
/// roughness 1 visible from a view in the x–z plane at cosine `cos_t`
/// (normal `(−x, −y, 1)` normalised): `y` is normal of variance 1/2,
/// and `x` has the density ∝ e^(−x²) (1 − x tan θ) on x < cot θ, whose
/// CDF ∝ C(x) = 1 + erf x + tan θ e^(−x²)/√π is inverted by Newton steps
/// kept within a shrinking bracket.
fn beckmann_visible_slopes(cos_t: f64, u: Vec2) -> (f64, f64) {
    let clamp = |t: f32| f64::from(t).clamp(1e-7, 1.0 - 1e-7);
    let (u1, u2) = (clamp(u.x), clamp(u.y));
    let y = erf_inv(2.0 * u2 - 1.0);
    let cos_t = cos_t.clamp(1e-7, 1.0);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    if sin_t < 1e-6 {
        return (erf_inv(2.0 * u1 - 1.0), y);
    }
    let tan_t = sin_t / cos_t;
    let cot_t = cos_t / sin_t;
    let k = 1.0 / PI64.sqrt();
    let cdf = |x: f64| 1.0 + erf(x) + tan_t * k * (-x * x).exp();
    let target = u1 * cdf(cot_t);
    let (mut lo, mut hi) = ((-8.0f64).min(cot_t - 1.0), cot_t);
    let mut x = erf_inv(2.0 * u1 - 1.0).clamp(lo, hi);
    for _ in 0..100 {
        let f = cdf(x) - target;
        if f > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let df = 2.0 * k * (-x * x).exp() * (1.0 - x * tan_t);
        let mut next = if df > 0.0 { x - f / df } else { f64::NAN };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - x).abs() < 1e-12 || hi - lo < 1e-12 {
            x = next;
            break;
        }
        x = next;
    }
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{self, Chi2};
    use crate::math::Vec2;
    use crate::sampling::Rng;

    fn distributions() -> Vec<Microfacet> {
        let mut all = Vec::new();
        for kind in [Kind::Beckmann, Kind::Ggx] {
            for (au, av) in [(0.1, 0.1), (0.5, 0.5), (0.2, 0.6), (1.0, 0.3)] {
                all.push(Microfacet::new(kind, au, av, true));
            }
        }
        all
    }

    /// A midpoint rule over (θ, φ) of the upper hemisphere, fine near the
    /// pole where the sharpest distributions live.
    fn integrate(f: impl Fn(Vec3) -> f64) -> f64 {
        let (nt, np) = (2000, 400);
        let mut sum = 0.0;
        for i in 0..nt {
            // θ = (π/2) s², denser near the pole: dθ = π s ds.
            let s = (i as f64 + 0.5) / nt as f64;
            let theta = std::f64::consts::FRAC_PI_2 * s * s;
            let dtheta = PI64 * s / nt as f64;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * 2.0 * PI64;
                let v = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    (theta.sin() * phi.sin()) as f32,
                    theta.cos() as f32,
                );
                sum += f(v) * theta.sin() * dtheta * 2.0 * PI64 / np as f64;
            }
        }
        sum
    }

    /// ∫ D(m) cos θm dω = 1, and the visible normals of any view have a
    /// density integrating to 1 (∫ G1 (wo·m)⁺ D dω = cos θo).
    #[test]
    fn d_and_the_visible_normals_are_normalised() {
        for m in distributions() {
            let total = integrate(|v| f64::from(m.d(v) * v.z));
            assert!((total - 1.0).abs() < 2e-3, "{m:?}: ∫D cos = {total}");
            for wo in [
                Vec3::Z,
                Vec3::new(0.6, 0.0, 0.8),
                Vec3::new(-0.3, 0.9, 0.3).normalize(),
            ] {
                let total = integrate(|v| f64::from(m.pdf(wo, v)));
                assert!((total - 1.0).abs() < 3e-3, "{m:?} {wo:?}: ∫pdf = {total}");
            }
        }
    }

    /// Both samplers draw normals distributed as their pdf says (χ² over
    /// a grid of directions and roughnesses).
    #[test]
    fn both_samplers_pass_chi2() {
        let mut tests = Vec::new();
        for visible in [true, false] {
            for m in distributions() {
                let m = Microfacet {
                    sample_visible: visible,
                    ..m
                };
                let views: &[Vec3] = if visible {
                    &[
                        Vec3::new(0.0, 0.0, 1.0),
                        Vec3::new(0.7, 0.1, 0.7),
                        Vec3::new(-0.2, 0.95, 0.1),
                    ]
                } else {
                    &[Vec3::Z]
                };
                for &wo in views {
                    tests.push((m, wo.normalize()));
                }
            }
        }
        let chi2 = Chi2::default();
        let alpha = chi2::sidak(tests.len());
        let mut failed = Vec::new();
        for (k, (m, wo)) in tests.iter().enumerate() {
            let p = chi2
                .run(
                    k as u64,
                    |u| Some(m.sample(*wo, u).0),
                    |v| f64::from(m.pdf(*wo, v)),
                )
                .unwrap_or_else(|e| panic!("{m:?} {wo:?}: {e}"));
            eprintln!("{m:?} {wo:?}: p = {p:e}");
            if p <= alpha {
                failed.push(format!("{m:?} {wo:?}: p = {p:e} < {alpha:e}"));
            }
        }
        assert!(failed.is_empty(), "{failed:#?}");
    }

    /// G1 is 1 at normal incidence, falls toward grazing, and is 0 for a
    /// back-facing normal; the exact Beckmann Λ is within Mitsuba's
    /// rational fit's 0.35%.
    #[test]
    fn masking_behaves() {
        let m = Microfacet::new(Kind::Beckmann, 0.4, 0.4, true);
        assert_eq!(m.g1(Vec3::Z, Vec3::Z), 1.0);
        let v = Vec3::new(0.8, 0.0, 0.6);
        let g = m.g1(v, Vec3::Z);
        let a = 0.6 / (0.8 * 0.4f32);
        let fit = (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
        assert!((g - fit).abs() < 4e-3 * fit, "{g} vs {fit}");
        assert_eq!(m.g1(v, Vec3::new(-0.9, 0.0, 0.1).normalize()), 0.0);
        let ggx = Microfacet::new(Kind::Ggx, 0.4, 0.4, true);
        let t2 = (0.4f32 * 0.8 / 0.6).powi(2);
        assert!((ggx.g1(v, Vec3::Z) - 2.0 / (1.0 + (1.0 + t2).sqrt())).abs() < 1e-6);
        let mut rng = Rng::new(3);
        for _ in 0..1000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let n = ggx.sample_visible_normal(v, u);
            assert!(n.z > 0.0 && (n.length() - 1.0).abs() < 1e-5);
        }
    }
}
