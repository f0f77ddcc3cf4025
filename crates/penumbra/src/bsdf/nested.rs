//! What the models holding other models (`twosided`, `mask`, `blendbsdf`,
//! `normalmap`, `bumpmap`) share: reading a held model by its material
//! name, reading a share in [0, 1] that may be a texture, choosing between
//! models with one random point, and the schema type of the parameters
//! that hold models ([`Type::Material`], which the scene builder reads to
//! build the held materials first).
//!
//! A held model is a material of the scene named by a string parameter
//! (`bsdf = "paint"`); Mitsuba XML's nested `<bsdf>`s and `<ref>`s become
//! such materials. A material may not hold itself, directly or through
//! others.

use std::sync::Arc;

use super::Bsdf;
use super::Defaults;
use crate::description::{Invalid, Param, Props, Type};
use crate::math::{Rgb, Vec2};
use crate::sampling::SetPoint;
use crate::texture::{NumberOr, Texture, Textures};

/// The schema type of a parameter naming a material.
pub const MATERIAL: Type = Type::Material;

/// A schema entry of a parameter naming a held material.
pub const fn param(name: &'static str, default: &'static str, doc: &'static str) -> Param {
    Param::new(name, MATERIAL, default, doc)
}

/// The material named by `name`, required; an error at the value when no
/// material has that name (or it is not built yet: a material holding
/// itself).
pub fn read(p: &Props, name: &str, d: &Defaults) -> Result<Arc<Bsdf>, Invalid> {
    read_optional(p, name, d)?.ok_or_else(|| {
        p.node_error(format!(
            "missing field `{name}` (the name of the material it holds)"
        ))
    })
}

/// The material named by `name`, if the parameter is given.
pub fn read_optional(p: &Props, name: &str, d: &Defaults) -> Result<Option<Arc<Bsdf>>, Invalid> {
    let Some(id) = p.string(name)? else {
        return Ok(None);
    };
    match d.materials.get(id) {
        Some(m) => Ok(Some(Arc::clone(m))),
        None => Err(p.error(name, format!("no material named `{id}`"))),
    }
}

/// A share in [0, 1] (`mask`'s opacity, `blendbsdf`'s weight): a number,
/// a texture's table or a texture's name (read as one value, Mitsuba's
/// `eval_1`); `default` when it is not there. A number is a constant grey
/// texture.
pub fn share(p: &Props, textures: &Textures, name: &str, default: f32) -> Result<Texture, Invalid> {
    let v = textures
        .number(p, name)?
        .unwrap_or(NumberOr::Number(default));
    let (lo, hi) = match &v {
        NumberOr::Number(x) => (*x, *x),
        NumberOr::Texture(t) => t.bounds_1(),
    };
    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi <= 1.0) {
        return Err(p.error(
            name,
            if lo == hi {
                format!("must be between 0 and 1, got {lo}")
            } else {
                format!("must be between 0 and 1; the texture's values span {lo} to {hi}")
            },
        ));
    }
    Ok(match v {
        NumberOr::Number(x) => Texture::Constant(Rgb::splat(x)),
        NumberOr::Texture(t) => t,
    })
}

/// Chooses the first of two options with probability `p` by the first
/// coordinate of `u`: the choice, and a point for the chosen model whose
/// first coordinate is the used one stretched back over [0, 1) (uniform
/// again). The point is a plain square point: a held model asked to choose
/// its own lobe draws from the unit square, not the set's distribution.
pub fn choose(u: SetPoint, p: f32) -> (bool, SetPoint) {
    let s = u.square();
    let first = s.x < p;
    let x = if first {
        s.x / p
    } else {
        (s.x - p) / (1.0 - p)
    };
    let x = x.clamp(0.0, 1.0 - f32::EPSILON / 2.0);
    (first, SetPoint::uniform(Vec2::new(x, s.y)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The choice takes the first option for a share `p` of the square and
    /// leaves the chosen point uniform.
    #[test]
    fn a_choice_keeps_the_point_uniform() {
        let n = 10_000;
        let mut firsts = 0;
        let mut sum = 0.0f64;
        for i in 0..n {
            let u = SetPoint::uniform(Vec2::new((i as f32 + 0.5) / n as f32, 0.25));
            let (first, v) = choose(u, 0.3);
            firsts += usize::from(first);
            let s = v.square();
            assert!((0.0..1.0).contains(&s.x) && (s.y - 0.25).abs() < 1e-6);
            sum += f64::from(s.x);
        }
        assert_eq!(firsts, 3000);
        assert!((sum / n as f64 - 0.5).abs() < 1e-3);
        assert!(choose(SetPoint::uniform(Vec2::new(0.5, 0.5)), 1.0).0);
        assert!(!choose(SetPoint::uniform(Vec2::new(0.0, 0.5)), 0.0).0);
    }
}
