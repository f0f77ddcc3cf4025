//! `thesis`: the material of the thesis, one BSDF of four lobes.
//!
//! The thesis's material is layered (its §2.3 and §3.3): a local part — a
//! Lambertian base and an energy-normalised Phong highlight — weighted by
//! `1 − reflectivity − transparency`, a mirror weighted by `reflectivity`,
//! and a smooth dielectric interface weighted by `transparency`, whose
//! reflection and refraction share it by the Fresnel factor. Its lobes, by
//! slot:
//!
//! | slot | lobe | flags | weight of a sample |
//! |---|---|---|---|
//! | 0 | mirror | delta reflection (glossy if `glossiness` > 0) | `reflectivity` |
//! | 1 | refraction | delta transmission (glossy if `translucency` > 0) | `transparency · (1 − F)` |
//! | 2 | Fresnel reflection | delta reflection (glossy if `translucency` > 0) | `transparency · F` |
//! | 3 | local | diffuse and glossy reflection | `eval · cos / pdf` |
//!
//! A glossy delta lobe is the thesis's blur: a set of rays whose end points
//! are distributed around the perfect direction with the material's radius
//! (`glossiness`, `translucency`), each taking its point as the
//! [`SetPoint`] it samples with, every ray of the set weighted alike. The
//! mirror's set is `reflection_rays` of `reflection_distribution`, the two
//! dielectric lobes' `refraction_rays` of `refraction_distribution`.
//!
//! The material is two-sided: normals are turned to the viewer's side
//! (`wo`), and the dielectric's `ior` is that of the side the geometric
//! normal points away from.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `albedo` | colour in [0, 1] | `[0.8, 0.8, 0.8]` | diffuse reflectance of the local part |
//! | `specular` | number in [0, 1] | `0` | weight of the Phong highlight; `albedo + specular ≤ 1` |
//! | `shininess` | number ≥ 0 | `32` | Phong exponent |
//! | `reflectivity` | number in [0, 1] | `0` | the mirror's weight |
//! | `transparency` | number in [0, 1] | `0` | the dielectric's weight; `reflectivity + transparency ≤ 1` |
//! | `ior` | number 1–10 | `1.5` | index of refraction |
//! | `glossiness` | number ≥ 0 | `(1 − reflectivity) · 0.2` | the mirror's blur radius |
//! | `translucency` | number ≥ 0 | `(1 − transparency) · 0.2` | the dielectric's blur radius |
//! | `reflection_rays`, `refraction_rays`, `reflection_distribution`, `refraction_distribution` | | the render's | the sets' budgets |

mod dielectric;
mod mirror;
mod phong;

pub use dielectric::{fresnel_dielectric, Dielectric, Split};
pub use mirror::Mirror;
pub use phong::Phong;

use super::{BsdfModel, Defaults};
use super::sample::{BsdfFlags, BsdfSample, Lobes, MAX_LOBES};
use crate::description::check::{int, nonneg3, range};
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{reflect, Rgb, Vec3};
use crate::sampling::{Distribution, EffectSpec, SetPoint, MAX_RAYS};

/// The slots of the thesis material's lobes.
const MIRROR: usize = 0;
const REFRACTION: usize = 1;
const FRESNEL: usize = 2;
const LOCAL: usize = 3;

/// The thesis material's parameters, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct ThesisParams {
    pub albedo: Rgb,
    pub specular: f32,
    pub shininess: f32,
    pub reflectivity: f32,
    pub transparency: f32,
    pub ior: f32,
    /// Radius of the reflection distribution (thesis §3.3); 0 is a perfect mirror.
    pub glossiness: f32,
    /// Radius of the refraction distribution; 0 is clear glass.
    pub translucency: f32,
    pub reflection: EffectSpec,
    pub refraction: EffectSpec,
}

impl ThesisParams {
    /// Weight of the local (diffuse + highlight) part.
    pub fn local_weight(&self) -> f32 {
        (1.0 - self.reflectivity - self.transparency).max(0.0)
    }
}

/// The thesis's material (see the [module docs](self)).
#[derive(Clone, Copy, Debug)]
pub struct Thesis {
    local: Phong,
    /// The local part reflects anything.
    lit: bool,
    mirror: Option<Mirror>,
    dielectric: Option<Dielectric>,
}

/// The viewer's side of a hit: shading and geometric normals turned toward
/// `wo`, and whether that is the side the geometric normal points to.
#[derive(Clone, Copy, Debug)]
struct Side {
    n: Vec3,
    ng: Vec3,
    front: bool,
}

impl Side {
    #[inline]
    fn of(si: &SurfaceInteraction, wo: Vec3) -> Side {
        let front = si.ng.dot(wo) >= 0.0;
        let flip = if front { 1.0 } else { -1.0 };
        Side {
            n: si.n * flip,
            ng: si.ng * flip,
            front,
        }
    }
}

impl Thesis {
    pub fn new(m: &ThesisParams) -> Thesis {
        let local = Phong::new(m.albedo, m.specular, m.shininess, m.local_weight());
        Thesis {
            lit: !local.is_black(),
            local,
            mirror: (m.reflectivity > 0.0).then_some(Mirror {
                reflectivity: m.reflectivity,
                glossiness: m.glossiness,
                effect: m.reflection,
            }),
            dielectric: (m.transparency > 0.0).then_some(Dielectric {
                transparency: m.transparency,
                ior: m.ior,
                translucency: m.translucency,
                effect: m.refraction,
            }),
        }
    }
}

impl Thesis {
    /// The sets its lobes ask for, by slot (the thesis's per-material
    /// budgets): the mirror's `reflection_rays` of
    /// `reflection_distribution`, the dielectric's two lobes'
    /// `refraction_rays` of `refraction_distribution`; `None` for absent
    /// lobes and the local part. Read once, when the scene is built, into
    /// the table the integrators look sets up in.
    pub fn sets(&self) -> [Option<EffectSpec>; MAX_LOBES] {
        let mut sets = [None; MAX_LOBES];
        if let Some(m) = &self.mirror {
            sets[MIRROR] = Some(m.effect);
        }
        if let Some(d) = &self.dielectric {
            sets[REFRACTION] = Some(d.effect);
            sets[FRESNEL] = Some(d.effect);
        }
        sets
    }
}

/// `DELTA | kind`, and `GLOSSY` too when the lobe is blurred.
fn delta(kind: BsdfFlags, radius: f32) -> BsdfFlags {
    let blur = if radius > 0.0 {
        BsdfFlags::GLOSSY
    } else {
        BsdfFlags::empty()
    };
    BsdfFlags::DELTA | kind | blur
}

impl ThesisParams {
    /// The parameters of a scene's material, checked and defaulted (the
    /// sets' budgets from `d`).
    pub fn read(p: &Props, d: &Defaults) -> Result<ThesisParams, Invalid> {
        let albedo = nonneg3(p, "albedo", [0.8; 3])?;
        let specular = range(p, "specular", 0.0, 0.0, 1.0)?;
        if (albedo + Rgb::splat(specular)).max_element() > 1.0 {
            return Err(p.error(
                "albedo",
                "albedo + specular must not exceed 1 in any channel (the surface would create light)",
            ));
        }
        let reflectivity = range(p, "reflectivity", 0.0, 0.0, 1.0)?;
        let transparency = range(p, "transparency", 0.0, 0.0, 1.0)?;
        if reflectivity + transparency > 1.0 + 1e-6 {
            return Err(p.error(
                "transparency",
                "reflectivity + transparency must not exceed 1 (the surface would create light)",
            ));
        }
        let effect = |rays: &str, dist: &str, def: EffectSpec| -> Result<EffectSpec, Invalid> {
            Ok(EffectSpec {
                rays: int(p, rays, i64::from(def.rays), 1, i64::from(MAX_RAYS))?,
                distribution: p.distribution(dist)?.unwrap_or(def.distribution),
            })
        };
        Ok(ThesisParams {
            albedo,
            specular,
            shininess: range(p, "shininess", 32.0, 0.0, 1e6)?,
            reflectivity,
            transparency,
            ior: range(p, "ior", 1.5, 1.0, 10.0)?,
            glossiness: range(p, "glossiness", (1.0 - reflectivity) * 0.2, 0.0, 1e3)?,
            translucency: range(p, "translucency", (1.0 - transparency) * 0.2, 0.0, 1e3)?,
            reflection: effect("reflection_rays", "reflection_distribution", d.reflection)?,
            refraction: effect("refraction_rays", "refraction_distribution", d.refraction)?,
        })
    }
}

impl BsdfModel for Thesis {
    const NAME: &'static str = "thesis";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "thesis",
        what: "material",
        doc: "the thesis's layered material: Lambert and Phong, a mirror and a Fresnel dielectric, the last two blurred by distributed sets",
        mitsuba: &[],
        params: &[
            Param::new("albedo", Type::Colour, "[0.8, 0.8, 0.8]", "diffuse reflectance (Lambertian BRDF albedo/π), each channel in [0, 1]").range(Range::Unit),
            Param::new("specular", Type::Number, "0", "weight in [0, 1] of an energy-normalised Phong highlight from lights; `albedo + specular ≤ 1` per channel").range(Range::Unit),
            Param::new("shininess", Type::Number, "32", "Phong exponent, ≥ 0").range(Range::NonNegative),
            Param::new("reflectivity", Type::Number, "0", "fraction of light mirrored, in [0, 1]").range(Range::Unit),
            Param::new("transparency", Type::Number, "0", "fraction of light passing the dielectric interface (Fresnel-weighted reflection and refraction), in [0, 1]; `reflectivity + transparency ≤ 1`").range(Range::Unit),
            Param::new("ior", Type::Number, "1.5", "index of refraction, 1–10").range(Range::Between(1.0, 10.0)),
            Param::new("emission", Type::Colour, "[0, 0, 0]", "emitted radiance (front side), ≥ 0: the objects of the material are area lights, sampled like a light's surface with `render.shadow_rays` (and, unlike a light's surface, they cast shadows)").range(Range::NonNegative),
            Param::new("glossiness", Type::Number, "(1 − reflectivity) · 0.2", "radius ≥ 0 of the reflection distribution (thesis §3.3); 0 is a perfect mirror").range(Range::NonNegative),
            Param::new("translucency", Type::Number, "(1 − transparency) · 0.2", "radius ≥ 0 of the refraction distribution; 0 is clear glass").range(Range::NonNegative),
            Param::new("reflection_rays", Type::Int, "render.reflection_rays", "rays per blurry reflection on this material, 1–65536").range(Range::Between(1.0, 65536.0)),
            Param::new("refraction_rays", Type::Int, "render.refraction_rays", "rays per blurry refraction on this material, 1–65536").range(Range::Between(1.0, 65536.0)),
            Param::new("reflection_distribution", Type::Distribution, "render.reflection_distribution", ""),
            Param::new("refraction_distribution", Type::Distribution, "render.refraction_distribution", ""),
        ],
    };

    fn own_sets(&self) -> Option<[Option<EffectSpec>; MAX_LOBES]> {
        Some(self.sets())
    }

    fn build(p: &Props, d: &Defaults) -> Result<Thesis, Invalid> {
        Ok(Thesis::new(&ThesisParams::read(p, d)?))
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        if let Some(m) = &self.mirror {
            l.flags[MIRROR] = delta(BsdfFlags::REFLECTION, m.glossiness);
        }
        if let Some(d) = &self.dielectric {
            l.flags[REFRACTION] = delta(BsdfFlags::TRANSMISSION, d.translucency);
            l.flags[FRESNEL] = delta(BsdfFlags::REFLECTION, d.translucency);
        }
        if self.lit {
            l.flags[LOCAL] = self.local.flags();
        }
        l
    }

    /// The local part's value (the delta lobes have none).
    #[inline]
    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
        if !self.lit {
            return Rgb::ZERO;
        }
        self.local.eval(Side::of(si, wo).n, wo, wi)
    }

    /// The local part's density times the probability that a sample with
    /// no lobe asked chooses it.
    #[inline]
    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
        if !self.lit {
            return 0.0;
        }
        self.local.pdf(Side::of(si, wo).n, wo, wi) * self.local_share()
    }

    /// With a lobe asked for, that lobe's ray for `u` (a delta lobe's weight
    /// is the same for every point of a set); without, a lobe chosen by
    /// `u`'s first coordinate in proportion to the weights of the mirror,
    /// the dielectric (then by Fresnel) and the local part, its weight
    /// divided by that probability.
    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let s = Side::of(si, wo);
        let d = -wo;
        let one = |lobe: usize, u: &SetPoint| -> Option<(Vec3, Rgb, BsdfFlags)> {
            match lobe {
                MIRROR => {
                    let m = self.mirror?;
                    let w = m.direction(d, s.n, s.ng, u);
                    let flags = delta(BsdfFlags::REFLECTION, m.glossiness);
                    Some((w, Rgb::splat(m.reflectivity), flags))
                }
                REFRACTION | FRESNEL => {
                    let g = self.dielectric?;
                    let split = g.split(d, s.n, s.front);
                    let (w, weight, kind) = if lobe == REFRACTION {
                        let (w, weight) = g.refraction(&split, s.ng, u)?;
                        (w, weight, BsdfFlags::TRANSMISSION)
                    } else {
                        let (w, weight) = g.reflection(&split, s.ng, u)?;
                        (w, weight, BsdfFlags::REFLECTION)
                    };
                    Some((w, Rgb::splat(weight), delta(kind, g.translucency)))
                }
                _ => None,
            }
        };
        match lobe {
            Some(LOCAL) => {
                let mut b = self.local.sample(s.n, wo, u.square())?;
                b.lobe = LOCAL;
                Some(b)
            }
            Some(k) => one(k, &u).map(|(wi, weight, flags)| BsdfSample {
                wi,
                weight,
                pdf: 1.0,
                flags,
                lobe: k,
                eta: 1.0,
            }),
            None => self.sample_any(si, wo, u, one),
        }
    }

    /// A blurred delta lobe's set: its perfect direction, the frame around
    /// it and the viewer's side found once (what [`sample`](Self::sample)
    /// finds again for every point), the directions the same.
    fn sample_set(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: usize,
        (points, d): (&[Vec3], Distribution),
        fallback: Vec3,
        out: &mut Vec<Vec3>,
    ) {
        out.clear();
        let s = Side::of(si, wo);
        let perfect = match lobe {
            MIRROR => self.mirror.map(|m| (reflect(-wo, s.n), m.glossiness, s.ng)),
            REFRACTION | FRESNEL => self.dielectric.and_then(|g| {
                let split = g.split(-wo, s.n, s.front);
                if lobe == REFRACTION {
                    let t = split.refracted.filter(|_| split.fresnel < 1.0)?;
                    Some((t, g.translucency, -s.ng))
                } else {
                    (split.fresnel > 0.0).then_some((split.reflected, g.translucency, s.ng))
                }
            }),
            _ => return super::sample_each(self, si, wo, lobe, (points, d), fallback, out),
        };
        match perfect {
            Some((dir, radius, side)) => mirror::blurred_set(dir, radius, side, (points, d), out),
            None => out.resize(points.len(), fallback),
        }
    }

    fn shadow_transmittance(&self, _si: &SurfaceInteraction) -> f32 {
        self.dielectric.map_or(0.0, |d| d.transparency)
    }

    fn uniform_shadow_transmittance(&self) -> Option<f32> {
        Some(self.dielectric.map_or(0.0, |d| d.transparency))
    }
}

impl Thesis {
    /// The probability that [`sample_any`](Self::sample_any) chooses the
    /// local part: its weight over the mirror's, the dielectric's and its own.
    fn local_share(&self) -> f32 {
        let r = self.mirror.map_or(0.0, |m| m.reflectivity);
        let t = self.dielectric.map_or(0.0, |d| d.transparency);
        let l = self.local.weight();
        l / (r + t + l)
    }

    /// A lobe chosen by `u` (see [`BsdfModel::sample`]).
    fn sample_any(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        u: SetPoint,
        one: impl Fn(usize, &SetPoint) -> Option<(Vec3, Rgb, BsdfFlags)>,
    ) -> Option<BsdfSample> {
        let r = self.mirror.map_or(0.0, |m| m.reflectivity);
        let t = self.dielectric.map_or(0.0, |d| d.transparency);
        let l = if self.lit { self.local.weight() } else { 0.0 };
        let total = r + t + l;
        if total <= 0.0 {
            return None;
        }
        let sq = u.square();
        let x = sq.x * total;
        // The rest of the first coordinate, for the chosen lobe's own use.
        let rescale = |lo: f32, width: f32| {
            let x = ((x - lo) / width).clamp(0.0, 1.0 - f32::EPSILON);
            SetPoint::uniform(crate::math::Vec2::new(x, sq.y))
        };
        let (lobe, p, v) = if x < r {
            (MIRROR, r / total, rescale(0.0, r))
        } else if x < r + t {
            let g = self.dielectric?;
            let s = Side::of(si, wo);
            let f = g.split(-wo, s.n, s.front).fresnel;
            // Reflect with probability F, else refract; the rest of the
            // number within the choice is the point's first coordinate.
            let y = rescale(r, t).square().x;
            let (lobe, p, y) = if y < f {
                (FRESNEL, f, y / f)
            } else {
                (REFRACTION, 1.0 - f, (y - f) / (1.0 - f))
            };
            let y = y.clamp(0.0, 1.0 - f32::EPSILON);
            let v = SetPoint::uniform(crate::math::Vec2::new(y, sq.y));
            (lobe, t / total * p, v)
        } else {
            let mut b = self
                .local
                .sample(Side::of(si, wo).n, wo, rescale(r + t, l).square())?;
            let p = l / total;
            b.weight *= 1.0 / p;
            b.pdf *= p;
            b.lobe = LOCAL;
            return Some(b);
        };
        let (wi, weight, flags) = one(lobe, &v)?;
        Some(BsdfSample {
            wi,
            weight: weight * (1.0 / p),
            pdf: p,
            flags,
            lobe,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::math::Vec2;
    use crate::sampling::{Distribution, Rng};

    fn params(reflectivity: f32, transparency: f32) -> ThesisParams {
        let effect = EffectSpec {
            rays: 4,
            distribution: Distribution::Jitter,
        };
        ThesisParams {
            albedo: Rgb::new(0.5, 0.5, 0.5),
            specular: 0.2,
            shininess: 10.0,
            reflectivity,
            transparency,
            ior: 1.5,
            glossiness: 0.0,
            translucency: 0.1,
            reflection: effect,
            refraction: effect,
        }
    }

    /// A set's directions at once are each point's own `sample`, bit for
    /// bit: every lobe, glossy and sharp, from both sides (so under total
    /// internal reflection too), for 2D and 3D distributions, and the
    /// fallback where a lobe gives nothing.
    #[test]
    fn a_sets_directions_are_each_points_sample() {
        let mut rng = Rng::new(11);
        let fallback = Vec3::new(0.0, 0.0, 7.0);
        for (reflectivity, transparency) in [(0.4, 0.4), (0.0, 0.6), (0.6, 0.0), (0.0, 0.0)] {
            for radius in [0.0, 0.3] {
                let mut p = params(reflectivity, transparency);
                (p.glossiness, p.translucency) = (radius, radius);
                let m = Thesis::new(&p);
                for d in [Distribution::Jitter, Distribution::Random, Distribution::FastRandom] {
                    let mut points = Vec::new();
                    d.generate(16, 1.0, &mut rng, &mut points);
                    for k in 0..20 {
                        let n = Vec3::new(0.3, 1.0, -0.2).normalize();
                        let a = k as f32 * 0.31;
                        let wo = Vec3::new(a.cos(), 0.4 - 0.05 * k as f32, a.sin()).normalize();
                        let si = interaction(n);
                        for lobe in [MIRROR, REFRACTION, FRESNEL, LOCAL] {
                            let mut got = Vec::new();
                            m.sample_set(&si, wo, lobe, (&points, d), fallback, &mut got);
                            let want: Vec<Vec3> = points
                                .iter()
                                .map(|&q| {
                                    let u = SetPoint::new(q, d);
                                    m.sample(&si, wo, Some(lobe), u).map_or(fallback, |b| b.wi)
                                })
                                .collect();
                            let bits = |v: &[Vec3]| -> Vec<[u32; 3]> {
                                v.iter().map(|w| w.to_array().map(f32::to_bits)).collect()
                            };
                            assert_eq!(bits(&got), bits(&want), "lobe {lobe}, {d:?}, wo {wo}");
                        }
                    }
                }
            }
        }
    }

    pub(crate) fn interaction(n: Vec3) -> SurfaceInteraction {
        SurfaceInteraction {
            t: 1.0,
            p: Vec3::ZERO,
            time: 0.0,
            ng: n,
            n,
            uv: Vec2::ZERO,
            dpdu: Vec3::X,
            dpdv: Vec3::Z,
            prim: 0,
            bary: crate::math::Vec2::ZERO,
            object: 0,
            material: 0,
            emitter: None,
        }
    }

    /// A material has the lobes its weights ask for, each of the kind its
    /// slot says, and delta lobes have no value or density.
    #[test]
    fn materials_have_the_lobes_their_weights_ask_for() {
        let plain = Thesis::new(&params(0.0, 0.0)).lobes();
        assert_eq!(plain.iter().map(|(k, ..)| k).collect::<Vec<_>>(), [LOCAL]);
        assert!(plain.any_smooth() && !plain.any_delta());
        let mut glass = params(0.0, 1.0);
        glass.albedo = Rgb::ZERO;
        glass.specular = 0.0;
        let lobes = Thesis::new(&glass).lobes();
        assert_eq!(
            lobes.iter().map(|(k, ..)| k).collect::<Vec<_>>(),
            [REFRACTION, FRESNEL]
        );
        assert!(lobes.flags[REFRACTION]
            .contains(BsdfFlags::DELTA | BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY));
        let mixed = Thesis::new(&params(0.3, 0.3));
        assert_eq!(mixed.lobes().iter().count(), 4);
        let si = interaction(Vec3::Z);
        let wi = Vec3::new(0.0, 0.6, 0.8);
        assert!(mixed.eval(&si, Vec3::Z, wi).max_element() > 0.0);
        let black = Thesis::new(&glass);
        assert_eq!(black.eval(&si, Vec3::Z, wi), Rgb::ZERO);
        assert_eq!(black.pdf(&si, Vec3::Z, wi), 0.0);
        assert_eq!(Thesis::new(&glass).uniform_shadow_transmittance(), Some(1.0));
    }

    /// A smooth direction drawn with no lobe asked has the density `pdf`
    /// gives (the local part's, times the chance of choosing it) and the
    /// weight `eval · cos / pdf`: what multiple importance sampling needs.
    #[test]
    fn sampled_smooth_directions_have_the_models_density() {
        let m = Thesis::new(&params(0.3, 0.4));
        let si = interaction(Vec3::Z);
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        let mut rng = Rng::new(9);
        let mut smooth = 0;
        for _ in 0..2000 {
            let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
            let Some(b) = m.sample(&si, wo, None, u) else {
                continue;
            };
            if !b.flags.is_smooth() {
                continue;
            }
            smooth += 1;
            let pdf = m.pdf(&si, wo, b.wi);
            assert!((b.pdf - pdf).abs() <= 1e-4 * pdf, "{} vs {pdf}", b.pdf);
            let want = m.eval(&si, wo, b.wi) * (b.wi.z / pdf);
            assert!((b.weight - want).abs().max_element() <= 1e-3 * want.max_element());
        }
        // About the local part's share of the lobes' weights (0.3 of 1).
        assert!((450..750).contains(&smooth), "{smooth}");
    }

    /// The material is two-sided: seen from below, it reflects below.
    #[test]
    fn both_sides_reflect() {
        let m = Thesis::new(&params(0.5, 0.0));
        let si = interaction(Vec3::Z);
        let u = SetPoint::new(Vec3::ZERO, Distribution::Grid);
        let wo = Vec3::new(0.6, 0.0, -0.8);
        let s = m.sample(&si, wo, Some(MIRROR), u).unwrap();
        assert!((s.wi - Vec3::new(-0.6, 0.0, -0.8)).length() < 1e-6);
        assert_eq!(s.weight, Rgb::splat(0.5));
        let wi = Vec3::new(0.0, 0.6, -0.8);
        assert_eq!(m.eval(&si, wo, wi), m.eval(&si, -wo, -wi));
    }

    /// Sampling any lobe reflects a mirror, refracts and reflects a
    /// dielectric and samples the local part in proportion to their weights
    /// (and the dielectric's by Fresnel): the mean weight of the delta
    /// samples of each lobe, over all samples, is that lobe's weight
    /// (binomial, 5 sigma).
    #[test]
    fn sampling_any_lobe_chooses_by_weight() {
        let m = Thesis::new(&params(0.3, 0.5));
        let si = interaction(Vec3::Z);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let split = m.dielectric.unwrap().split(-wo, Vec3::Z, true);
        let f = f64::from(split.fresnel);
        let want = [0.3, 0.5 * (1.0 - f), 0.5 * f];
        let mut rng = Rng::new(5);
        let n = 100_000;
        let mut sums = [0.0f64; 4];
        for _ in 0..n {
            let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
            if let Some(s) = m.sample(&si, wo, None, u) {
                sums[s.lobe] += f64::from(s.weight.r);
            }
        }
        for k in 0..3 {
            // A chosen delta sample weighs the total 0.8: variance 0.8 w − w².
            let mean = sums[k] / f64::from(n);
            let sigma = ((0.8 * want[k] - want[k] * want[k]) / f64::from(n)).sqrt();
            assert!(
                (mean - want[k]).abs() < 5.0 * sigma,
                "lobe {k}: {mean} vs {}",
                want[k]
            );
        }
    }
}
