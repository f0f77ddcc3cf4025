//! Every texture-typed parameter of every model, driven by a checkerboard:
//! at a point of each square the model answers as the same model with the
//! square's value as a plain parameter, and the two squares differ (but
//! for a bump map's heights, which act through their gradient, 0 on a
//! checkerboard's squares: `bumpmap.rs` drives them with a bitmap).

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use super::{Bsdf, Defaults};
use crate::description::{from_toml, Kind, Props, Type};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::{Distribution, EffectSpec, SetPoint};
use crate::texture::checkerboard::Checkerboard;
use crate::texture::{Texture, TextureModel};
use crate::texture::{Textures, UvTransform};

/// The model `plugin` of the TOML keys `keys`.
fn model(plugin: &str, keys: &str) -> Bsdf {
    let text = format!("[materials.m]\ntype = \"{plugin}\"\n{keys}\n");
    let root = from_toml(&text, Path::new("t.toml")).unwrap_or_else(|e| panic!("{e}"));
    let node = root.child(Kind::Bsdf).expect("a material");
    let set = EffectSpec {
        rays: 1,
        distribution: Distribution::Jitter,
    };
    let textures = Textures::default();
    let materials = held();
    let d = Defaults {
        reflection: set,
        refraction: set,
        textures: &textures,
        materials: &materials,
    };
    let p = Props::new(node);
    let m = Bsdf::build(plugin, &p, &d)
        .expect("a model")
        .unwrap_or_else(|e| panic!("{plugin}: {keys}: {e}"));
    p.finish(plugin).unwrap_or_else(|e| panic!("{e}"));
    m
}

/// What the model answers at `uv`: for a few views, `eval` and `pdf`
/// toward fixed directions and a few samples' directions and weights.
fn response(m: &Bsdf, uv: Vec2) -> Vec<f32> {
    let n = Vec3::new(0.1, -0.2, 0.97).normalize();
    let mut si = crate::bsdf::thesis::tests::interaction(n);
    si.uv = uv;
    let si: SurfaceInteraction = si;
    let mut out = Vec::new();
    let dirs = [
        Vec3::new(0.3, 0.2, 0.9),
        Vec3::new(-0.6, 0.1, 0.7),
        Vec3::new(0.1, 0.5, -0.8),
        Vec3::new(0.05, 0.05, 1.0),
    ]
    .map(Vec3::normalize);
    for wo in dirs {
        for wi in dirs {
            let f = m.eval(&si, wo, wi);
            out.extend([f.r, f.g, f.b, m.pdf(&si, wo, wi)]);
        }
        // Each lobe alone and the lobe the point chooses.
        for lobe in [None, Some(0), Some(1)] {
            for k in 0..16 {
                let u = Vec2::new((k % 4) as f32 / 4.0 + 0.1, (k / 4) as f32 / 4.0 + 0.1);
                if let Some(s) = m.sample(&si, wo, lobe, SetPoint::uniform(u)) {
                    out.extend([
                        s.wi.x, s.wi.y, s.wi.z, s.weight.r, s.weight.g, s.weight.b, s.pdf,
                    ]);
                } else {
                    out.push(-1.0);
                }
            }
        }
    }
    out
}

fn same(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-5 * x.abs().max(y.abs()).max(1.0))
}

/// The materials the models holding others hold here.
fn held() -> HashMap<String, Arc<Bsdf>> {
    use super::chi2::build;
    let rough = build::<super::roughconductor::RoughConductor>("alpha = 0.2\nmaterial = \"Cu\"");
    let paint = build::<super::diffuse::Diffuse>("reflectance = [0.7, 0.5, 0.3]");
    HashMap::from([
        ("rough".to_string(), Arc::new(rough.unwrap().into())),
        ("paint".to_string(), Arc::new(paint.unwrap().into())),
    ])
}

/// The keys written beside the texture of `name` of `plugin`: its partner
/// for a roughness given per tangent; the materials a model holds; a
/// conductor's `eta` beside its `k`.
fn partner(plugin: &str, name: &str) -> &'static str {
    match (plugin, name) {
        (_, "alpha_u") => "alpha_v = 0.3",
        (_, "alpha_v") => "alpha_u = 0.3",
        ("mask", _) => "bsdf = \"rough\"",
        ("blendbsdf", _) => "bsdf_0 = \"rough\"\nbsdf_1 = \"paint\"",
        ("normalmap" | "bumpmap", _) => "bsdf = \"rough\"",
        // With `eta` 0 every `k` reflects everything.
        ("conductor" | "roughconductor", "k") => "eta = [0.5, 0.6, 0.7]",
        ("principled", "sheen_tint") => "sheen = 0.5\nbase_color = [0.8, 0.3, 0.1]",
        ("principled", "clearcoat_gloss") => "clearcoat = 0.5",
        ("principledthin", "sheen_tint") => "sheen = 0.5\nbase_color = [0.8, 0.3, 0.1]",
        ("principledthin", "anisotropic" | "eta" | "spec_tint") => "spec_trans = 0.5",
        _ => "",
    }
}

#[test]
fn every_texture_typed_parameter_follows_a_checkerboard() {
    let mut driven = Vec::new();
    for schema in Bsdf::SCHEMAS {
        for param in schema.params {
            let (c0, c1) = match param.ty {
                Type::ColourTexture => (Rgb::new(0.9, 0.8, 0.7), Rgb::new(0.2, 0.3, 0.1)),
                Type::NumberTexture => (Rgb::splat(0.05), Rgb::splat(0.6)),
                _ => continue,
            };
            let board = Checkerboard {
                color0: Box::new(Texture::Constant(c0)),
                color1: Box::new(Texture::Constant(c1)),
                to_uv: UvTransform::IDENTITY,
            };
            let (name, plugin) = (param.name, schema.plugin);
            let rgb = |c: Rgb| format!("[{}, {}, {}]", c.r, c.g, c.b);
            let textured = model(
                plugin,
                &format!(
                    "{name} = {{ type = \"checkerboard\", color0 = {}, color1 = {} }}\n{}",
                    rgb(c0),
                    rgb(c1),
                    partner(plugin, name)
                ),
            );
            // The value of each square, as a plain parameter.
            let plain = |uv: Vec2| {
                let value = match param.ty {
                    Type::ColourTexture => rgb(board.eval(uv)),
                    _ => board.eval_1(uv).to_string(),
                };
                model(
                    plugin,
                    &format!("{name} = {value}\n{}", partner(plugin, name)),
                )
            };
            let (a, b) = (Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25));
            let (ra, rb) = (response(&textured, a), response(&textured, b));
            assert!(
                same(&ra, &response(&plain(a), a)),
                "{plugin}.{name}: at {a} not the square's value"
            );
            assert!(
                same(&rb, &response(&plain(b), b)),
                "{plugin}.{name}: at {b} not the square's value"
            );
            let by_gradient = plugin == "bumpmap";
            assert!(
                by_gradient || !same(&ra, &rb),
                "{plugin}.{name}: the squares answer alike"
            );
            // The other squares of the board, and beyond the unit square.
            assert!(same(&ra, &response(&textured, Vec2::new(0.75, 0.75))));
            assert!(same(&rb, &response(&textured, Vec2::new(1.25, 0.75))));
            driven.push(format!("{plugin}.{name}"));
        }
    }
    for want in [
        "diffuse.reflectance",
        "conductor.specular_reflectance",
        "conductor.eta",
        "conductor.k",
        "roughconductor.eta",
        "roughconductor.k",
        "roughconductor.alpha",
        "roughconductor.alpha_u",
        "roughconductor.alpha_v",
        "roughconductor.specular_reflectance",
        "dielectric.specular_reflectance",
        "dielectric.specular_transmittance",
        "roughdielectric.alpha",
        "roughdielectric.alpha_u",
        "roughdielectric.specular_transmittance",
        "thindielectric.specular_reflectance",
        "thindielectric.specular_transmittance",
        "plastic.diffuse_reflectance",
        "plastic.specular_reflectance",
        "roughplastic.diffuse_reflectance",
        "roughplastic.specular_reflectance",
        "mask.opacity",
        "blendbsdf.weight",
        "normalmap.normalmap",
        "bumpmap.texture",
        "principled.base_color",
        "principled.roughness",
        "principled.anisotropic",
        "principled.metallic",
        "principled.spec_trans",
        "principled.spec_tint",
        "principled.sheen",
        "principled.sheen_tint",
        "principled.flatness",
        "principled.clearcoat",
        "principled.clearcoat_gloss",
        "principledthin.base_color",
        "principledthin.roughness",
        "principledthin.anisotropic",
        "principledthin.spec_trans",
        "principledthin.eta",
        "principledthin.spec_tint",
        "principledthin.sheen",
        "principledthin.sheen_tint",
        "principledthin.flatness",
        "principledthin.diff_trans",
    ] {
        assert!(
            driven.iter().any(|d| d == want),
            "{want} is not texture-typed"
        );
    }
}

/// A texture whose values leave a parameter's range is refused at the
/// parameter, as a plain value is.
#[test]
fn textures_out_of_range_are_refused() {
    for (plugin, keys, want) in [
        (
            "diffuse",
            "reflectance = { type = \"checkerboard\", color0 = [1.5, 0, 0] }",
            "t.toml:3:15: materials.m.reflectance: must not exceed 1",
        ),
        (
            "roughconductor",
            "alpha = { type = \"checkerboard\", color1 = [200, 200, 200] }",
            "t.toml:3:9: materials.m.alpha: must be between 0 and 100; the texture's values span 0.4 to 200",
        ),
        (
            "diffuse",
            "reflectance = { type = \"checkerboard\", color0 = [-1, 0, 0] }",
            "t.toml:3:49: materials.m.reflectance.color0: must not be negative, got [-1.0, 0.0, 0.0]",
        ),
        (
            "diffuse",
            "reflectance = { type = \"bricks\" }",
            "t.toml:3:24: materials.m.reflectance.type: unknown texture `bricks`; valid choices are: checkerboard, bitmap",
        ),
        (
            "diffuse",
            "reflectance = { color0 = [0, 0, 0] }",
            "t.toml:3:15: materials.m.reflectance: missing field `type`",
        ),
        (
            "diffuse",
            "reflectance = { type = \"checkerboard\", colour0 = [0, 0, 0] }",
            "t.toml:3:40: materials.m.reflectance: unknown field `colour0`, expected one of `color0`, `color1`, `to_uv`",
        ),
        (
            "diffuse",
            "reflectance = \"wood\"",
            "t.toml:3:15: materials.m.reflectance: no texture named `wood`; the scene declares none",
        ),
    ] {
        let text = format!("[materials.m]\ntype = \"{plugin}\"\n{keys}\n");
        let root = from_toml(&text, Path::new("t.toml")).unwrap();
        let node = root.child(Kind::Bsdf).unwrap();
        let textures = Textures::default();
        let set = EffectSpec {
            rays: 1,
            distribution: Distribution::Jitter,
        };
        let d = Defaults {
            reflection: set,
            refraction: set,
            textures: &textures,
            materials: &Default::default(),
        };
        let e = Bsdf::build(plugin, &Props::new(node), &d)
            .unwrap()
            .map(drop)
            .unwrap_err();
        let e = crate::description::SceneError::from(e).to_string();
        assert!(e.starts_with(want), "{keys}:\n{e}\n{want}");
    }
}
