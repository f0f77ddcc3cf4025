//! `bumpmap`: a held material whose shading normal follows a height field,
//! Mitsuba 3's `bumpmap`. The surface is taken as displaced along its
//! shading normal `n` by `scale · h(u, v)`, `h` the texture read as one
//! value; with the gradient `(h_u, h_v)` of `scale · h` in the surface
//! coordinates, the displaced tangents are
//!
//! `dp/du' = dp/du − n (n·dp/du) + h_u n`, `dp/dv' = dp/dv − n (n·dp/dv) + h_v n`
//!
//! and the perturbed normal is `n' = normalize(dp/du' × dp/dv')`, turned to
//! the geometric normal's side. As Mitsuba's, it leaves out the change of
//! the normal itself over the surface (pbrt's `dn/du` terms), so a constant
//! offset of the heights changes nothing. The held material is then asked
//! through `n'` (see [`super::perturbed`]).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `texture` | number or texture | required | the height field (a `bitmap`, usually with `raw = true`), read as one value |
//! | `scale` | number | `1` | a factor on the heights' gradient |
//! | `bsdf` | material name | required | the material seen through the normal |
//! | `flip_invalid_normals` | bool | `true` | mirror a normal facing away from the view about the shading normal |
//! | `use_shadowing_function` | bool | `true` | darken light grazing a tilted normal |
//!
//! Its lobes are the held material's. The gradient is the texture's own
//! ([`Texture::eval_1_grad`]): a bilinear bitmap's is its interpolation's;
//! a constant's, a nearest bitmap's and a checkerboard's are 0 (no
//! perturbation), where the normal is the shading normal itself.
//!
//! ```toml
//! [materials.paint]
//! type = "roughplastic"
//! [materials.bumpy]
//! type = "bumpmap"
//! texture = { type = "bitmap", filename = "bumps.png", raw = true }
//! scale = 0.5
//! bsdf = "paint"
//! ```

use std::sync::Arc;

use super::nested;
use super::perturbed::{self, Normal, Options};
use super::Bsdf;
use super::{BsdfModel, Defaults};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2, Vec3};
use crate::texture::{NumberOr, Texture};

/// The bump-mapped material (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct BumpMap {
    pub texture: Texture,
    pub scale: f32,
    pub bsdf: Arc<Bsdf>,
    pub options: Options,
}

/// The normal of the surface displaced along `si`'s shading normal by a
/// height of gradient `grad` in `(u, v)` (unit, on the geometric normal's
/// side); the shading normal itself where the gradient is 0, or where the
/// displaced tangents give no normal.
pub fn bumped_normal(si: &SurfaceInteraction, grad: Vec2) -> Vec3 {
    if grad == Vec2::ZERO {
        return si.n;
    }
    let n = si.n;
    let du = si.dpdu + n * (grad.x - n.dot(si.dpdu));
    let dv = si.dpdv + n * (grad.y - n.dot(si.dpdv));
    let b = du.cross(dv).normalize_or_zero();
    let b = if b.dot(si.ng) < 0.0 { -b } else { b };
    if b.is_finite() && b != Vec3::ZERO {
        b
    } else {
        si.n
    }
}

impl BumpMap {
    /// The perturbed shading normal at the point, seen from `wo`.
    pub fn normal(&self, si: &SurfaceInteraction, wo: Vec3) -> Normal {
        let grad = self.texture.eval_1_grad(si) * self.scale;
        let p = if grad == Vec2::ZERO {
            Vec3::Z
        } else {
            si.shading_frame().to_local(bumped_normal(si, grad))
        };
        perturbed::normal(si, wo, p, self.options)
    }
}

impl BsdfModel for BumpMap {
    const NAME: &'static str = "bumpmap";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "bumpmap",
        what: "bump-mapped material",
        doc: "a material seen through the normal of a height field",
        mitsuba: &["bumpmap"],
        params: &[
            Param::new(
                "texture",
                Type::NumberTexture,
                "required",
                "the height field, read as one value (a `bitmap`, usually with `raw = true`)",
            ).any_mitsuba_name(),
            Param::new("scale", Type::Number, "1", "a factor on the heights' gradient"),
            nested::param("bsdf", "required", "the name of the material seen through the normal"),
            perturbed::PARAMS[0],
            perturbed::PARAMS[1],
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<BumpMap, Invalid> {
        let texture = match d.textures.number(p, "texture")? {
            Some(NumberOr::Texture(t)) => t,
            Some(NumberOr::Number(x)) if x.is_finite() => Texture::Constant(Rgb::splat(x)),
            Some(NumberOr::Number(x)) => {
                return Err(p.error("texture", format!("must be a finite number, got {x}")))
            }
            None => {
                return Err(p.node_error("missing field `texture` (the height field)"));
            }
        };
        let scale = p.f32("scale")?.unwrap_or(1.0);
        if !scale.is_finite() {
            return Err(p.error("scale", format!("must be a finite number, got {scale}")));
        }
        let bsdf = nested::read(p, "bsdf", d)?;
        let options = Options::read(p)?;
        Ok(BumpMap {
            texture,
            scale,
            bsdf,
            options,
        })
    }

    perturbed::through_perturbed_normal!();
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::bsdf::chi2::{self, build, build_in, check_weights, interaction};
    use crate::bsdf::diffuse::Diffuse;
    use crate::bsdf::roughconductor::RoughConductor;
    use crate::input::image::Image;
    use crate::math::Vec2;
    use crate::sampling::{Rng, SetPoint};
    use crate::texture::bitmap::{Bitmap, Filter, Wrap};
    use crate::texture::UvTransform;

    fn arc(b: impl Into<Bsdf>) -> Arc<Bsdf> {
        Arc::new(b.into())
    }

    fn inners() -> Vec<(&'static str, Arc<Bsdf>)> {
        vec![
            ("diffuse", arc(build::<Diffuse>("reflectance = [0.7, 0.5, 0.3]").unwrap())),
            ("roughconductor", arc(build::<RoughConductor>("alpha = 0.2\nmaterial = \"Au\"").unwrap())),
        ]
    }

    /// A 4 × 4 raw height field with slopes of both signs in both axes.
    fn heights() -> Texture {
        let values = [
            0.0, 0.2, 0.5, 0.4, //
            0.1, 0.6, 0.9, 0.3, //
            0.3, 0.8, 0.7, 0.2, //
            0.2, 0.4, 0.3, 0.0,
        ];
        let image = Image {
            width: 4,
            height: 4,
            channels: 3,
            pixels: values.iter().flat_map(|&v: &f32| [v; 3]).collect(),
        };
        Texture::Bitmap(Bitmap::new(
            Arc::new(image),
            Filter::Bilinear,
            Wrap::Repeat,
            UvTransform::IDENTITY,
        ))
    }

    /// A point of the plane z = 0 at `uv`, its tangents neither unit nor
    /// orthogonal.
    fn skewed(uv: Vec2) -> SurfaceInteraction {
        let mut si = interaction(Vec3::Z);
        si.dpdu = Vec3::new(2.0, 0.3, 0.0);
        si.dpdv = Vec3::new(-0.4, 1.5, 0.0);
        si.uv = uv;
        si
    }

    /// The bumped normal is the normal of the displaced surface
    /// `p(u, v) + n · s h(u, v)` (the shading normal held fixed, as
    /// Mitsuba's), found by central differences of that surface.
    #[test]
    fn the_normal_is_the_displaced_surface_s() {
        let h = heights();
        let mut r = Rng::new(5);
        let (mut checked, mut tilted) = (0, 0);
        for _ in 0..300 {
            let uv = Vec2::new(r.range(0.0, 1.0), r.range(0.0, 1.0));
            // Away from the kinks of the bilinear interpolation.
            let d = |x: f32| (x * 4.0 - 0.5 - (x * 4.0 - 0.5).round()).abs();
            if d(uv.x) < 0.05 || d(uv.y) < 0.05 {
                continue;
            }
            let si = skewed(uv);
            let scale = 0.7;
            let p = |uv: Vec2| si.p + si.dpdu * (uv.x - si.uv.x) + si.dpdv * (uv.y - si.uv.y) + si.n * (scale * h.eval_1_uv(uv));
            let e = 1e-3;
            let du = (p(uv + Vec2::new(e, 0.0)) - p(uv - Vec2::new(e, 0.0))) / (2.0 * e);
            let dv = (p(uv + Vec2::new(0.0, e)) - p(uv - Vec2::new(0.0, e))) / (2.0 * e);
            let want = du.cross(dv).normalize();
            let m = BumpMap {
                texture: h.clone(),
                scale,
                bsdf: inners().remove(0).1,
                options: Options::DEFAULT,
            };
            let got = bumped_normal(&si, h.eval_1_grad_uv(uv) * scale);
            let seen = m.normal(&si, si.n);
            assert!((seen.world - got).length() < 1e-5 && (si.shading_frame().to_world(seen.local) - got).length() < 1e-5);
            assert!((got - want).length() < 2e-3, "{uv}: {got:?} vs {want:?}");
            tilted += usize::from(got.dot(si.n) < 0.99);
            checked += 1;
        }
        // Not vacuous: most normals are tilted by more than 8°.
        assert!(checked > 150 && tilted > checked / 2, "{tilted} of {checked}");
    }

    /// A constant height field is the held material: the same values,
    /// densities and samples, bit for bit; so is any height at scale 0.
    #[test]
    fn a_constant_height_is_the_held_material() {
        let mut rng = Rng::new(14);
        for (name, inner) in inners() {
            for (texture, scale) in [(Texture::Constant(Rgb::splat(0.4)), 3.0), (heights(), 0.0)] {
                let m = BumpMap {
                    texture,
                    scale,
                    bsdf: Arc::clone(&inner),
                    options: Options::DEFAULT,
                };
                let si = skewed(Vec2::new(0.3, 0.6));
                for _ in 0..1000 {
                    let wo = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.05, 1.0)).normalize();
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    let (a, b) = (m.sample(&si, wo, None, u), inner.sample(&si, wo, None, u));
                    assert_eq!(a.is_some(), b.is_some(), "{name}");
                    let (Some(a), Some(b)) = (a, b) else { continue };
                    assert_eq!((a.wi, a.weight, a.pdf), (b.wi, b.weight, b.pdf), "{name}");
                    assert_eq!(m.eval(&si, wo, a.wi), inner.eval(&si, wo, a.wi), "{name}");
                    assert_eq!(m.pdf(&si, wo, a.wi), inner.pdf(&si, wo, a.wi), "{name}");
                }
            }
        }
    }

    /// Through a height field the samplers follow their densities (χ²) and
    /// the weights are `eval · cos / pdf`, at points of several slopes.
    #[test]
    fn sampling_through_a_height_field() {
        let mut cases = Vec::new();
        for (name, inner) in inners() {
            for uv in [Vec2::new(0.3, 0.2), Vec2::new(0.7, 0.55)] {
                let m = BumpMap {
                    texture: heights(),
                    scale: 0.5,
                    bsdf: Arc::clone(&inner),
                    options: Options::DEFAULT,
                };
                cases.push((name, m, skewed(uv)));
            }
        }
        let views = [Vec3::Z, Vec3::new(0.5, -0.3, 0.8).normalize()];
        let level = chi2::sidak(cases.len() * views.len());
        for (k, (name, m, si)) in cases.iter().enumerate() {
            assert!(m.normal(si, si.n).world.dot(si.n) < 0.99, "{name}: not perturbed");
            for (j, &wo) in views.iter().enumerate() {
                let p = chi2::model_p_value(m, si, wo, (10 * k + j) as u64).unwrap();
                assert!(p > level, "{name} {:?} {wo:?}: p = {p:e}", si.uv);
                check_weights(m, si, wo, 20_000);
            }
        }
    }

    /// Mitsuba's default scale; the texture and the held material are
    /// required.
    #[test]
    fn parameters() {
        let mut named = HashMap::new();
        named.insert("paint".to_string(), inners().remove(0).1);
        let m = build_in::<BumpMap>("bsdf = \"paint\"\ntexture = 0.5", &named).unwrap();
        assert_eq!((m.scale, m.texture.constant()), (1.0, Some(Rgb::splat(0.5))));
        assert_eq!(m.options, Options::DEFAULT);
        for (text, want) in [
            ("bsdf = \"paint\"", "missing field `texture`"),
            ("texture = 0.5", "missing field `bsdf`"),
            ("bsdf = \"paint\"\ntexture = 0.5\nscale = \"big\"", "expected a number"),
        ] {
            let e = build_in::<BumpMap>(text, &named).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
