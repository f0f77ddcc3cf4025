//! `normalmap`: a held material whose shading normal is read from a
//! texture, Mitsuba 3's `normalmap`. The texture's colour `c` at the
//! point is a normal in the shading frame (tangent `dp/du`, bitangent,
//! normal), each channel mapped from [0, 1] to [−1, 1]: `n' = normalize(2c
//! − 1)`, so `(0.5, 0.5, 1)` is the unperturbed normal. The held material
//! is then asked through `n'` (see [`super::perturbed`]).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `normalmap` | colour or texture | required | the tangent-space normal: a `bitmap` with `raw = true` (its 8-bit values linear), or a constant colour for a uniform tilt |
//! | `bsdf` | material name | required | the material seen through the normal |
//! | `flip_invalid_normals` | bool | `true` | mirror a normal facing away from the view about the shading normal |
//! | `use_shadowing_function` | bool | `true` | darken light grazing a tilted normal |
//!
//! Its lobes are the held material's. A map whose colour at a point gives
//! no direction (`(0.5, 0.5, 0.5)`) leaves the normal there unperturbed.
//!
//! ```toml
//! [materials.paint]
//! type = "roughplastic"
//! [materials.tiles]
//! type = "normalmap"
//! normalmap = { type = "bitmap", filename = "tiles_normal.png", raw = true }
//! bsdf = "paint"
//! ```

use std::sync::Arc;

use super::nested;
use super::perturbed::{self, Normal, Options};
use super::Bsdf;
use super::{BsdfModel, Defaults};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::texture::Texture;

/// The normal-mapped material (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct NormalMap {
    pub normalmap: Texture,
    pub bsdf: Arc<Bsdf>,
    pub options: Options,
}

impl NormalMap {
    /// The perturbed shading normal at the point, seen from `wo`.
    pub fn normal(&self, si: &SurfaceInteraction, wo: Vec3) -> Normal {
        let c = self.normalmap.eval(si);
        let p = Vec3::new(2.0 * c.r - 1.0, 2.0 * c.g - 1.0, 2.0 * c.b - 1.0);
        perturbed::normal(si, wo, p, self.options)
    }
}

impl BsdfModel for NormalMap {
    const NAME: &'static str = "normalmap";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "normalmap",
        what: "normal-mapped material",
        doc: "a material seen through a normal read from a texture",
        mitsuba: &["normalmap"],
        params: &[
            Param::new(
                "normalmap",
                Type::ColourTexture,
                "required",
                "the normal in the shading frame, each channel in [0, 1] mapped to [−1, 1] (a `bitmap` with `raw = true`)",
            ),
            nested::param("bsdf", "required", "the name of the material seen through the normal"),
            perturbed::PARAMS[0],
            perturbed::PARAMS[1],
        ],
    };

    fn build(p: &Props, d: &Defaults) -> Result<NormalMap, Invalid> {
        if !p.has("normalmap") {
            return Err(p.node_error("missing field `normalmap` (the normal map's texture)"));
        }
        let normalmap = d.textures.colour(p, "normalmap", Rgb::ZERO)?;
        let bsdf = nested::read(p, "bsdf", d)?;
        let options = Options::read(p)?;
        Ok(NormalMap {
            normalmap,
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
    use crate::bsdf::chi2::{self, albedo, build, build_in, check_weights, interaction, sampled_albedo};
    use crate::bsdf::conductor::Conductor;
    use crate::bsdf::diffuse::Diffuse;
    use crate::bsdf::roughconductor::RoughConductor;
    use crate::bsdf::roughplastic::RoughPlastic;
    use crate::math::Vec2;
    use crate::sampling::{Rng, SetPoint};

    fn arc(b: impl Into<Bsdf>) -> Arc<Bsdf> {
        Arc::new(b.into())
    }

    fn inners() -> Vec<(&'static str, Arc<Bsdf>)> {
        vec![
            ("diffuse", arc(build::<Diffuse>("reflectance = [0.7, 0.5, 0.3]").unwrap())),
            ("roughconductor", arc(build::<RoughConductor>("alpha = 0.2\nmaterial = \"Au\"").unwrap())),
            ("roughplastic", arc(build::<RoughPlastic>("alpha = 0.3").unwrap())),
            ("conductor", arc(build::<Conductor>("").unwrap())),
        ]
    }

    /// A constant map of colour `c` around `bsdf`.
    fn map(c: Rgb, bsdf: &Arc<Bsdf>) -> NormalMap {
        NormalMap {
            normalmap: Texture::Constant(c),
            bsdf: Arc::clone(bsdf),
            options: Options::DEFAULT,
        }
    }

    /// [`map`] without the shadowing term.
    fn bare(c: Rgb, bsdf: &Arc<Bsdf>) -> NormalMap {
        NormalMap {
            options: Options {
                flip_invalid_normals: true,
                use_shadowing_function: false,
            },
            ..map(c, bsdf)
        }
    }

    fn views() -> [Vec3; 3] {
        [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.2, 0.77).normalize(),
            Vec3::new(-0.3, 0.4, 0.8).normalize(),
        ]
    }

    /// A flat map, `(0.5, 0.5, 1)`, is the held material: the same values,
    /// densities and samples, bit for bit.
    #[test]
    fn a_flat_map_is_the_held_material() {
        let si = interaction(Vec3::new(0.2, -0.1, 0.97).normalize());
        let mut rng = Rng::new(12);
        for (name, inner) in inners() {
            let m = map(Rgb::new(0.5, 0.5, 1.0), &inner);
            for wo in views().map(|v| si.shading_frame().to_world(v)) {
                assert_eq!(m.normal(&si, wo).world, si.n, "{name}");
                for _ in 0..500 {
                    let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
                    let (a, b) = (m.sample(&si, wo, None, u), inner.sample(&si, wo, None, u));
                    assert_eq!(a.is_some(), b.is_some(), "{name}");
                    let (Some(a), Some(b)) = (a, b) else { continue };
                    assert_eq!((a.wi, a.weight, a.pdf, a.lobe), (b.wi, b.weight, b.pdf, b.lobe));
                    assert_eq!(m.eval(&si, wo, a.wi), inner.eval(&si, wo, a.wi), "{name}");
                    assert_eq!(m.pdf(&si, wo, a.wi), inner.pdf(&si, wo, a.wi), "{name}");
                }
            }
        }
    }

    /// A tilted map tilts the lobe as predicted: a mirror reflects about
    /// the mapped normal `frame · normalize(2c − 1)`, and a Lambertian
    /// surface's value times the cosine to the shading normal is `ρ/π`
    /// times the cosine to the mapped normal, times the shadowing term
    /// when it is on. Seen from behind the mapped normal, the normal is
    /// mirrored about the shading normal (`flip_invalid_normals`).
    #[test]
    fn a_tilted_map_tilts_the_lobe() {
        let si = interaction(Vec3::new(0.1, 0.2, 0.97).normalize());
        let frame = si.shading_frame();
        let c = Rgb::new(0.7, 0.4, 0.9);
        let want = frame.to_world(Vec3::new(0.4, -0.2, 0.8).normalize());
        let all = inners();
        let mirror = map(c, &all[3].1);
        let wo = frame.to_world(Vec3::new(0.3, 0.3, 0.9).normalize());
        assert!((mirror.normal(&si, wo).world - want).length() < 1e-6);
        let behind = frame.to_world(Vec3::new(-0.9, 0.2, 0.2).normalize());
        let mirrored = frame.to_world(Vec3::new(-0.4, 0.2, 0.8).normalize());
        assert!((mirror.normal(&si, behind).world - mirrored).length() < 1e-6);
        let s = mirror.sample(&si, wo, None, SetPoint::uniform(Vec2::splat(0.5))).unwrap();
        let reflected = 2.0 * wo.dot(want) * want - wo;
        assert!((s.wi - reflected).length() < 1e-5, "{:?} vs {reflected:?}", s.wi);
        let (lambert, shadowed) = (bare(c, &all[0].1), map(c, &all[0].1));
        let mut seen = 0;
        for v in [Vec3::new(0.5, -0.3, 0.8), Vec3::new(-0.2, 0.1, 0.95), Vec3::new(0.9, 0.1, 0.3)] {
            let wi = frame.to_world(v.normalize());
            let f = lambert.eval(&si, wo, wi) * wi.dot(si.n);
            let rho = Rgb::new(0.7, 0.5, 0.3);
            let expect = if wi.dot(want) > 0.0 { rho * (wi.dot(want) / std::f32::consts::PI) } else { Rgb::ZERO };
            assert!((f - expect).abs().max_element() < 1e-5, "{wi:?}: {f:?} vs {expect:?}");
            seen += usize::from(expect.max_element() > 0.0);
            // The shadowing term: α² = tan²θ'/8 of the mapped normal, θi of wi.
            let tan2 = |c: f32| (1.0 - c * c) / (c * c);
            let a2 = (tan2(want.dot(si.n)) / 8.0).min(1.0);
            let g = 2.0 / (1.0 + (1.0 + a2 * tan2(wi.dot(si.n))).sqrt());
            let s = shadowed.eval(&si, wo, wi) * wi.dot(si.n);
            assert!((s - expect * g).abs().max_element() < 1e-5, "{wi:?}: {s:?} vs {:?}", expect * g);
            assert!(g < 1.0 || expect == Rgb::ZERO);
        }
        assert!(seen >= 2);
        // A direction above the shading normal but below the mapped one is dark.
        let below = frame.to_world(Vec3::new(-0.9, 0.3, 0.1).normalize());
        assert!(below.dot(want) < 0.0 && below.dot(si.n) > 0.0);
        assert_eq!(lambert.eval(&si, wo, below), Rgb::ZERO);
        assert_eq!(lambert.pdf(&si, wo, below), 0.0);
    }

    /// Through a tilted map the samplers follow their densities (χ²), the
    /// weights are `eval · cos / pdf` with the cosine to the shading normal,
    /// and the albedo by sampling is the albedo by integrating `eval` times
    /// that cosine: the shading normal is used one way throughout.
    #[test]
    fn sampling_through_a_tilted_map() {
        let si = interaction(Vec3::Z);
        let mut models = Vec::new();
        for (name, inner) in inners().into_iter().take(3) {
            for c in [Rgb::new(0.7, 0.4, 0.9), Rgb::new(0.3, 0.6, 0.8)] {
                models.push((format!("{name} {c:?}"), map(c, &inner)));
            }
            models.push((format!("{name} unshadowed"), bare(Rgb::new(0.7, 0.4, 0.9), &inner)));
        }
        chi2::assert_samplers_pass(
            models.iter().map(|(t, m)| (t.clone(), m.clone())).collect(),
            &views(),
            &si,
            chi2::model_p_value,
        );
        for (text, m) in &models {
            for wo in views() {
                check_weights(m, &si, wo, 20_000);
                let (a, ea) = sampled_albedo(m, &si, wo, 200_000);
                let (b, eb) = albedo(m, &si, wo, 250_000);
                assert!((a - b).abs().max_element() <= 4.0 * (ea + eb) + 3e-3, "{text} {wo:?}: {a:?} vs {b:?}");
            }
        }
    }

    /// The map and the held material are required; the map's texture is
    /// read as any colour texture.
    #[test]
    fn parameters() {
        let mut named = HashMap::new();
        named.insert("paint".to_string(), inners().remove(0).1);
        let m = build_in::<NormalMap>("bsdf = \"paint\"\nnormalmap = [0.5, 0.5, 1]", &named).unwrap();
        assert_eq!(m.normalmap.constant(), Some(Rgb::new(0.5, 0.5, 1.0)));
        assert_eq!(m.options, Options::DEFAULT);
        let text = "bsdf = \"paint\"\nnormalmap = [0.5, 0.5, 1]\nflip_invalid_normals = false\nuse_shadowing_function = false";
        let o = build_in::<NormalMap>(text, &named).unwrap().options;
        assert!(!o.flip_invalid_normals && !o.use_shadowing_function);
        assert_eq!(m.lobes(), m.bsdf.lobes());
        for (text, want) in [
            ("bsdf = \"paint\"", "missing field `normalmap`"),
            ("normalmap = [0.5, 0.5, 1]", "missing field `bsdf`"),
            ("bsdf = \"wood\"\nnormalmap = [0.5, 0.5, 1]", "no material named `wood`"),
            ("bsdf = \"paint\"\nnormalmap = [0.5, -0.5, 1]", "must not be negative"),
        ] {
            let e = build_in::<NormalMap>(text, &named).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
