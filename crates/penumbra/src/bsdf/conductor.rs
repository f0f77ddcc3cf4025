//! `conductor`: a perfectly smooth metal, Mitsuba 3's `conductor`: one
//! delta reflection lobe weighted by the conductor Fresnel reflectance of
//! the complex index `eta + i·k` (per RGB channel) times
//! `specular_reflectance`. One-sided, as Mitsuba's: it reflects on the side
//! its shading normal points to and is black from behind.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `material` | `none` or a name of Mitsuba 3's table (`Au`, `Ag`, `Al`, `Cu`, `Cr`, `W`, … 71 of them) | `none` | a preset index ([`ior`]); `none` is a perfect mirror (`eta` 0, `k` 1) |
//! | `eta` | colour ≥ 0 or texture | the material's (`none`: `[0, 0, 0]`) | real part of the index; not with a `material` other than `none` |
//! | `k` | colour ≥ 0 or texture | the material's (`none`: `[1, 1, 1]`) | imaginary part (absorption) |
//! | `specular_reflectance` | colour in [0, 1] or texture | `[1, 1, 1]` | a factor on the reflection (1 for realism) |
//!
//! Its lobe, slot 0, is a delta reflection: the Whitted integrator traces
//! one ray of it, the mirror direction about the shading normal.

use super::ior;
use super::{BsdfModel, Defaults};
use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::fresnel;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{reflect, Rgb, Vec3};
use crate::sampling::SetPoint;
use crate::texture::{Texture, Textures};

/// The smooth conductor (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Conductor {
    /// `None`: the perfect mirror of `material = "none"` (reflectance 1).
    pub index: Option<Index>,
    pub specular_reflectance: Texture,
}

/// The schema entries of the conductor's index, shared with
/// `roughconductor`.
pub const INDEX_PARAMS: [Param; 3] = [
    Param::new("material", Type::Choice("conductor material", &ior::CONDUCTOR_NAMES), "none", "a conductor preset: `none` (a perfect mirror) or a measured material of Mitsuba 3's table (`Au`, `Ag`, `Al`, `Cu`, `Cr`, `W`, …)"),
    Param::new("eta", Type::ColourTexture, "the material's", "real part of the complex index, ≥ 0; not with a `material` other than `none`").range(Range::NonNegative),
    Param::new("k", Type::ColourTexture, "the material's", "imaginary part of the complex index (absorption), ≥ 0").range(Range::NonNegative),
];

/// The schema entry of `specular_reflectance`.
pub const SPECULAR_REFLECTANCE: Param = Param::new(
    "specular_reflectance",
    Type::ColourTexture,
    "[1, 1, 1]",
    "a factor on the reflection, each channel in [0, 1] (1 for realism)",
).range(Range::Unit);

/// A reflectance-like factor `name`, a colour or a texture (each channel
/// in [0, 1]), default 1.
pub fn factor(p: &Props, textures: &Textures, name: &str) -> Result<Texture, Invalid> {
    reflectance_texture(p, textures, name, Rgb::ONE)
}

/// A reflectance `name`, a colour or a texture with each channel in
/// [0, 1]; `default` when it is not there.
pub fn reflectance_texture(
    p: &Props,
    textures: &Textures,
    name: &str,
    default: Rgb,
) -> Result<Texture, Invalid> {
    let t = textures.colour(p, name, default)?;
    let (lo, hi) = t.bounds();
    if hi.max_element() > 1.0 {
        let what = if t.constant().is_some() {
            "must not exceed 1 in any channel (the surface would create light)"
        } else {
            "must not exceed 1 in any channel (the surface would create light); the texture reaches more"
        };
        return Err(p.error(name, what));
    }
    if lo.min_element() < 0.0 {
        return Err(p.error(name, "must not be negative"));
    }
    Ok(t)
}

/// A conductor's complex index `eta + i·k`, per channel, each part a
/// colour or a texture.
#[derive(Clone, Debug)]
pub struct Index {
    pub eta: Texture,
    pub k: Texture,
}

/// The conductor's index as Mitsuba 3 reads it: the preset `material`
/// (default `none`), or `eta` and `k` (defaults 0 and 1, colours or
/// textures, not negative), not both; `None` for the perfect mirror (`eta`
/// 0 and `k` 1, whether by name or by value).
pub fn read_index(p: &Props, textures: &Textures) -> Result<Option<Index>, Invalid> {
    let material = p.choice("material", "conductor material", &ior::CONDUCTOR_NAMES)?;
    if let Some(m) = material.filter(|m| *m != "none") {
        if let Some(at) = ["eta", "k"].into_iter().find(|n| p.has(n)) {
            return Err(p.error(
                at,
                format!("give either `material` or `eta` and `k`, not both (`material` is `{m}`)"),
            ));
        }
    }
    let preset = ior::conductor(material.unwrap_or("none")).expect("a listed name");
    let part = |name: &str, default: Rgb| -> Result<Texture, Invalid> {
        let t = textures.colour(p, name, default)?;
        if t.bounds().0.min_element() < 0.0 {
            return Err(p.error(name, "must not be negative; the texture reaches below 0"));
        }
        Ok(t)
    };
    let (eta, k) = (part("eta", preset.eta)?, part("k", preset.k)?);
    let mirror = eta.constant() == Some(Rgb::ZERO) && k.constant() == Some(Rgb::ONE);
    Ok((!mirror).then_some(Index { eta, k }))
}

/// The Fresnel reflectance of `index` at `si` and the cosine `cos` (1 for
/// the perfect mirror).
pub fn reflectance(index: &Option<Index>, si: &SurfaceInteraction, cos: f32) -> Rgb {
    match index {
        None => Rgb::ONE,
        Some(c) => fresnel::conductor(cos, c.eta.eval(si), c.k.eval(si)),
    }
}

impl BsdfModel for Conductor {
    const NAME: &'static str = "conductor";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "conductor",
        what: "conductor material",
        doc: "a smooth metal: delta reflection weighted by the conductor Fresnel reflectance",
        mitsuba: &["conductor"],
        params: &[INDEX_PARAMS[0], INDEX_PARAMS[1], INDEX_PARAMS[2], SPECULAR_REFLECTANCE],
    };

    fn build(p: &Props, d: &Defaults) -> Result<Conductor, Invalid> {
        Ok(Conductor {
            index: read_index(p, d.textures)?,
            specular_reflectance: factor(p, d.textures, "specular_reflectance")?,
        })
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = BsdfFlags::DELTA | BsdfFlags::REFLECTION;
        l
    }

    fn eval(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> Rgb {
        Rgb::ZERO
    }

    /// The mirror direction about the shading normal and its weight
    /// `specular_reflectance · F(cos θo)`, whether the lobe is asked for or
    /// not; `None` from behind.
    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        _: SetPoint,
    ) -> Option<BsdfSample> {
        let cos = si.n.dot(wo);
        if lobe.is_some_and(|k| k != 0) || cos <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: reflect(-wo, si.n),
            weight: self.specular_reflectance.eval(si) * reflectance(&self.index, si, cos),
            pdf: 1.0,
            flags: BsdfFlags::DELTA | BsdfFlags::REFLECTION,
            lobe: 0,
            eta: 1.0,
        })
    }

    fn pdf(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> f32 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{build, interaction};
    use crate::math::Vec2;

    /// `material = "none"` reflects exactly 1 at every angle; gold reflects
    /// its Fresnel value; from behind nothing; the direction is the mirror
    /// direction about the shading normal.
    #[test]
    fn mirrors_with_the_fresnel_weight() {
        let mirror = build::<Conductor>("").unwrap();
        assert!(mirror.index.is_none());
        let n = Vec3::new(0.2, 0.1, 0.97).normalize();
        let si = interaction(n);
        let u = SetPoint::uniform(Vec2::splat(0.3));
        for wo in [n, Vec3::new(0.7, 0.0, 0.7).normalize(), Vec3::new(-0.1, 0.99, 0.08).normalize()] {
            let s = mirror.sample(&si, wo, Some(0), u).unwrap();
            assert_eq!(s.weight, Rgb::ONE);
            assert!((s.wi - (2.0 * wo.dot(n) * n - wo)).length() < 1e-6);
            assert!((s.wi.dot(n) - wo.dot(n)).abs() < 1e-6);
            assert_eq!(mirror.sample(&si, wo, None, u).unwrap().weight, Rgb::ONE);
        }
        assert!(mirror.sample(&si, -n, None, u).is_none());
        assert!(mirror.sample(&si, n, Some(1), u).is_none());
        assert_eq!(mirror.eval(&si, n, n), Rgb::ZERO);
        assert_eq!(mirror.pdf(&si, n, n), 0.0);
        let gold = build::<Conductor>("material = \"Au\"\nspecular_reflectance = [0.5, 1, 1]").unwrap();
        let s = gold.sample(&si, n, None, u).unwrap();
        let f = fresnel::conductor(1.0, ior::conductor("Au").unwrap().eta, ior::conductor("Au").unwrap().k);
        assert!((s.weight - f * Rgb::new(0.5, 1.0, 1.0)).abs().max_element() < 1e-5);
        assert!(s.weight.max_element() < 1.0);
        assert!(gold.lobes().any_delta() && !gold.lobes().any_smooth());
    }

    /// Values out of range and contradictory parameters are refused at
    /// their place.
    #[test]
    fn bad_parameters_are_refused() {
        for (text, want) in [
            ("specular_reflectance = [1.2, 1, 1]", "must not exceed 1"),
            ("eta = [-1, 0, 0]", "must not be negative"),
            ("material = \"Au\"\neta = [1, 1, 1]", "not both"),
            ("material = \"Xx\"", "unknown conductor material `Xx`"),
        ] {
            let e = build::<Conductor>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
        let c = build::<Conductor>("eta = [0.2, 0.9, 1.1]\nk = [3.9, 2.5, 2.1]").unwrap();
        assert_eq!(c.index.unwrap().k.constant(), Some(Rgb::new(3.9, 2.5, 2.1)));
    }
}
