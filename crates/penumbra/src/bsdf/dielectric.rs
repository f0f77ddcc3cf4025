//! `dielectric`: a smooth interface between two dielectrics (glass, water),
//! Mitsuba 3's `dielectric`: a delta reflection weighted by the Fresnel
//! reflectance F and a delta refraction weighted by `1 − F`. Two-sided:
//! the normal points to the outside (index `ext_ior`), the other side is
//! the inside (`int_ior`), and light may arrive from either.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `int_ior` | number > 0 or a name | `bk7` (1.5046) | index of the inside ([`ior`] lists the names) |
//! | `ext_ior` | number > 0 or a name | `air` (1.000277) | index of the outside |
//! | `specular_reflectance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the reflection (1 for realism) |
//! | `specular_transmittance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the transmission (1 for realism) |
//!
//! Its lobes, by slot:
//!
//! | slot | lobe | weight of its ray |
//! |---|---|---|
//! | 0 | delta reflection about the shading normal | `specular_reflectance · F` |
//! | 1 | delta refraction (Snell) | `specular_transmittance · (1 − F) · (η_viewer / η_far)²` |
//!
//! The Whitted integrator traces one ray of each lobe and weighs it so.
//! With no lobe asked for, `sample` reflects with probability F (the point's
//! first coordinate) and refracts otherwise, the weight divided by that
//! probability. Transmitted radiance is scaled by the square of the ratio
//! of the indices, as Mitsuba does in radiance mode (radiance in a medium
//! of index η is η² times its value in vacuum): a ray entering glass from
//! air sees `(1 − F) / η²` of the radiance inside, and one leaving sees
//! `(1 − F) · η²`, so a slab or a closed object passes `(1 − F)²` of what is
//! behind it. Under total internal reflection the refraction lobe gives no
//! ray and F = 1. Shadow rays do not cross the surface (as in Mitsuba's
//! path tracer: light through glass arrives by refraction only).

use super::conductor::{factor, SPECULAR_REFLECTANCE};
use super::fresnel;
use super::ior;
use super::{BsdfModel, Defaults};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;
use crate::texture::{Texture, Textures};

/// The smooth dielectric (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Dielectric {
    /// `int_ior / ext_ior`.
    pub eta: f32,
    pub specular_reflectance: Texture,
    pub specular_transmittance: Texture,
}

/// The schema entries of the two indices, shared by the dielectrics.
pub const IOR_PARAMS: [Param; 2] = [
    Param::new("int_ior", Type::NumberOrChoice("index of refraction", &ior::DIELECTRIC_NAMES), "bk7 (1.5046)", "index of refraction of the inside (the side the normal points away from): a number > 0 or a name (`water`, `diamond`, …)").range(Range::Positive),
    Param::new("ext_ior", Type::NumberOrChoice("index of refraction", &ior::DIELECTRIC_NAMES), "air (1.000277)", "index of refraction of the outside: a number > 0 or a name").range(Range::Positive),
];

/// The schema entry of `specular_transmittance`.
pub const SPECULAR_TRANSMITTANCE: Param = Param::new(
    "specular_transmittance",
    Type::ColourTexture,
    "[1, 1, 1]",
    "a factor on the transmission, each channel in [0, 1] (1 for realism)",
).range(Range::Unit);

/// What a smooth interface reads: the relative index and the factors on
/// reflection and transmission.
pub fn read_interface(p: &Props, textures: &Textures) -> Result<(f32, Texture, Texture), Invalid> {
    Ok((
        read_eta(p)?,
        factor(p, textures, "specular_reflectance")?,
        factor(p, textures, "specular_transmittance")?,
    ))
}

/// The relative index `int_ior / ext_ior` of a scene's parameters.
pub fn read_eta(p: &Props) -> Result<f32, Invalid> {
    let int = ior::read_dielectric(p, "int_ior", "bk7")?;
    let ext = ior::read_dielectric(p, "ext_ior", "air")?;
    Ok(int / ext)
}

const REFLECTION: BsdfFlags = BsdfFlags::DELTA.union(BsdfFlags::REFLECTION);
const TRANSMISSION: BsdfFlags = BsdfFlags::DELTA.union(BsdfFlags::TRANSMISSION);

/// The direction refracted from the unit `wo` (toward the viewer) at the
/// unit normal `n`, given the interface's [`fresnel::dielectric`] answer
/// `f` for `cos_i = wo · n`.
pub fn refract(wo: Vec3, n: Vec3, f: &fresnel::Dielectric) -> Vec3 {
    let cos_i = wo.dot(n);
    (n * (f.eta_ti * cos_i + f.cos_t) - wo * f.eta_ti).normalize()
}

impl Dielectric {
    /// Lobe `k`'s direction and weight for the view `wo` (not divided by a
    /// choice); `None` where the lobe sends nothing.
    fn lobe(&self, si: &SurfaceInteraction, wo: Vec3, k: usize) -> Option<(Vec3, Rgb, BsdfFlags)> {
        let n = si.n;
        let cos_i = wo.dot(n);
        let f = fresnel::dielectric(cos_i, self.eta);
        match k {
            0 if f.r > 0.0 => Some((2.0 * cos_i * n - wo, self.specular_reflectance.eval(si) * f.r, REFLECTION)),
            1 if f.r < 1.0 => {
                let weight = self.specular_transmittance.eval(si) * ((1.0 - f.r) * f.eta_ti * f.eta_ti);
                Some((refract(wo, n, &f), weight, TRANSMISSION))
            }
            _ => None,
        }
    }
}

impl BsdfModel for Dielectric {
    const NAME: &'static str = "dielectric";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "dielectric",
        what: "dielectric material",
        doc: "a smooth dielectric interface: Fresnel-weighted delta reflection and refraction",
        mitsuba: &["dielectric"],
        params: &[IOR_PARAMS[0], IOR_PARAMS[1], SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE],
    };

    fn build(p: &Props, d: &Defaults) -> Result<Dielectric, Invalid> {
        let (eta, specular_reflectance, specular_transmittance) = read_interface(p, d.textures)?;
        Ok(Dielectric {
            eta,
            specular_reflectance,
            specular_transmittance,
        })
    }

    fn lobes(&self) -> Lobes {
        Lobes::reflection_and_transmission(BsdfFlags::DELTA)
    }

    fn eval(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> Rgb {
        Rgb::ZERO
    }

    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample> {
        let (k, p) = match lobe {
            Some(k) => (k, 1.0),
            None => {
                let r = fresnel::dielectric(wo.dot(si.n), self.eta).r;
                if u.square().x < r {
                    (0, r)
                } else {
                    (1, 1.0 - r)
                }
            }
        };
        let (wi, weight, flags) = self.lobe(si, wo, k)?;
        let eta = match k {
            1 => fresnel::dielectric(wo.dot(si.n), self.eta).eta_it,
            _ => 1.0,
        };
        Some(BsdfSample {
            wi,
            weight: weight * (1.0 / p),
            pdf: p,
            flags,
            lobe: k,
            eta,
        })
    }

    fn pdf(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> f32 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{self, build, interaction};
    use crate::math::Vec2;
    use crate::sampling::Rng;

    fn views(n: Vec3) -> Vec<Vec3> {
        let f = crate::geometry::interaction::shading_frame(n, Vec3::X);
        let mut all = Vec::new();
        for c in [1.0f32, 0.9, 0.6, 0.3, 0.05] {
            let s = (1.0 - c * c).sqrt();
            for side in [1.0, -1.0] {
                all.push(f.to_world(Vec3::new(s, 0.2 * s, side * c).normalize()));
            }
        }
        all
    }

    /// The reflection weight and the transmission weight without its
    /// radiance scale add up to 1 from both sides at every angle (F and
    /// 1 − F), total internal reflection included; the directions obey the
    /// law of reflection and Snell's law.
    #[test]
    fn fresnel_weights_sum_to_one_and_directions_are_right() {
        let g = build::<Dielectric>("").unwrap();
        assert!((g.eta - 1.5046 / 1.000277).abs() < 1e-6);
        let n = Vec3::new(0.1, 0.3, 0.95).normalize();
        let si = interaction(n);
        let u = SetPoint::uniform(Vec2::splat(0.5));
        let mut tir = 0;
        for wo in views(n) {
            let cos_i = wo.dot(n);
            let r = g.sample(&si, wo, Some(0), u).unwrap();
            assert!((r.wi.dot(n) - cos_i).abs() < 1e-5 && (r.wi + wo).cross(n).length() < 1e-5);
            let (n1, n2) = if cos_i > 0.0 { (1.0, g.eta) } else { (g.eta, 1.0) };
            match g.sample(&si, wo, Some(1), u) {
                Some(t) => {
                    let scale = (n1 / n2) * (n1 / n2);
                    let sum = r.weight.r + t.weight.r / scale;
                    assert!((sum - 1.0).abs() < 1e-5, "{wo:?}: {sum}");
                    assert!(t.wi.dot(n) * cos_i < 0.0);
                    let sin = |v: Vec3| v.cross(n).length();
                    assert!((n1 * sin(wo) - n2 * sin(t.wi)).abs() < 1e-4, "Snell at {wo:?}");
                }
                None => {
                    tir += 1;
                    assert_eq!(r.weight, Rgb::ONE, "total internal reflection at {wo:?}");
                }
            }
        }
        assert!(tir >= 1, "some view past the critical angle");
        // Light refracted in along one path and out along the same path keeps
        // (1 − F)² of the radiance: the two scales cancel.
        let wo = views(n)[4];
        let t_in = g.sample(&si, wo, Some(1), u).unwrap();
        let t_out = g.sample(&si, t_in.wi, Some(1), u).unwrap();
        let f = fresnel::dielectric(wo.dot(n), g.eta).r;
        let through = t_in.weight.r * t_out.weight.r;
        assert!((through - (1.0 - f) * (1.0 - f)).abs() < 1e-5, "{through}");
        assert!((t_out.wi - wo).length() < 1e-4);
    }

    /// With no lobe asked for, reflection is chosen with probability F
    /// (a χ² test of the two lobes' counts over views from both sides,
    /// 200000 points each), and each weight is divided by its probability;
    /// past the critical angle every point reflects.
    #[test]
    fn sampling_any_lobe_chooses_by_fresnel() {
        let g = build::<Dielectric>("int_ior = \"diamond\"\next_ior = 1").unwrap();
        let n = Vec3::new(0.2, 0.1, 0.97).normalize();
        let si = interaction(n);
        let all = views(n);
        let level = chi2::sidak(all.len());
        for (k, wo) in all.into_iter().enumerate() {
            let f = fresnel::dielectric(wo.dot(n), g.eta);
            let mut rng = Rng::new(k as u64);
            let points = 200_000;
            let mut counts = [0.0; 2];
            for _ in 0..points {
                let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                let s = g.sample(&si, wo, None, u).unwrap();
                counts[s.lobe] += 1.0;
                if s.lobe == 0 {
                    assert!((s.weight.r - 1.0).abs() < 1e-5 && (s.pdf - f.r).abs() < 1e-6);
                } else {
                    assert!((s.weight.r - f.eta_ti * f.eta_ti).abs() < 1e-4 * f.eta_ti * f.eta_ti);
                }
            }
            if f.r >= 1.0 {
                assert_eq!(counts[1], 0.0, "total internal reflection at {wo:?}");
                continue;
            }
            let p = f64::from(f.r);
            let expected = [points as f64 * p, points as f64 * (1.0 - p)];
            let pv = chi2::p_value(&counts, &expected).unwrap();
            assert!(pv > level, "{wo:?}: p = {pv:e}");
        }
    }

    /// Indices are numbers or names; non-physical values are refused at
    /// their place.
    #[test]
    fn parameters() {
        let g = build::<Dielectric>("int_ior = \"water\"\next_ior = \"vacuum\"\nspecular_transmittance = [0.5, 1, 1]").unwrap();
        assert_eq!(g.eta, 1.333);
        assert_eq!(g.specular_transmittance, Texture::Constant(Rgb::new(0.5, 1.0, 1.0)));
        for (text, want) in [
            ("int_ior = -1.5", "int_ior: must be a positive number, got -1.5"),
            ("ext_ior = 0", "ext_ior: must be a positive number, got 0"),
            ("int_ior = \"glass\"", "unknown index of refraction `glass`; valid choices are: vacuum,"),
            ("int_ior = [1.5]", "expected a number or a name"),
            ("specular_reflectance = [1, 1, 2]", "must not exceed 1"),
        ] {
            let e = build::<Dielectric>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
