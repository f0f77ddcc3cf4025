//! The plugin reference of the docs against the schemas: every plugin of
//! every documented kind has its table in `docs/scene-format.md`, every
//! kind the Mitsuba reader maps through the schemas its table in
//! `docs/mitsuba.md`, and each is what the schemas say.
//!
//! `PENUMBRA_UPDATE_DOCS=1 cargo test --release -p penumbra --test reference`
//! rewrites the tables from the schemas.

mod common;

use std::path::Path;

use penumbra::description::{Kind, Range, Type};
use penumbra::integrator::plugins::registry;
use penumbra::scene::reference;
use penumbra::scene::schemas;
use penumbra::scene::{LoadOptions, SceneSource};

#[test]
fn the_docs_tables_are_the_schemas() {
    let fresh = |rewrite: fn(&str) -> (String, Vec<String>)| {
        move |text: &str| match rewrite(text) {
            (text, missing) if missing.is_empty() => Ok(text),
            (_, missing) => Err(format!(
                "no block for {missing:?}: add `<!-- ID begin -->` and `<!-- ID end -->` \
                 lines where each belongs"
            )),
        }
    };
    let (format, mitsuba) = (
        fresh(|text| {
            reference::scene_format_with(text, &penumbra::integrator::aov::plugins::SCHEMAS)
        }),
        fresh(|text| reference::mitsuba(text, registry)),
    );
    let stale = common::stale_docs(&[
        ("docs/scene-format.md", &format),
        ("docs/mitsuba.md", &mitsuba),
    ]);
    assert!(
        stale.is_empty(),
        "the plugin tables of {stale:?} differ from the schemas; rerun with \
         PENUMBRA_UPDATE_DOCS=1 to rewrite them"
    );
}

/// Every plugin says what it is, and every parameter has a type the
/// reference names and a range its type can hold.
#[test]
fn every_plugin_and_parameter_is_described() {
    for (kind, schema) in reference::documented() {
        assert!(
            !schema.doc.is_empty(),
            "{kind:?} `{}` has no doc",
            schema.plugin
        );
        for p in schema.params {
            let numeric = matches!(
                p.ty,
                Type::Number
                    | Type::Scale
                    | Type::NumberTexture
                    | Type::Int
                    | Type::Colour
                    | Type::ColourTexture
                    | Type::NumberOrChoice(..)
            );
            assert!(
                p.range == Range::Any || numeric,
                "{kind:?} `{}`: `{}` has a range but is not a number",
                schema.plugin,
                p.name
            );
            assert!(!reference::type_text(p).is_empty());
        }
    }
}

/// A Mitsuba plugin name is read as one Penumbra plugin of its kind, by
/// one entry of the kind's registry, which the plugin's schema names.
#[test]
fn mitsuba_names_map_to_one_plugin() {
    for kind in Kind::ALL {
        let mut seen = std::collections::HashSet::new();
        for s in schemas::of(kind) {
            for name in s.mitsuba {
                assert!(seen.insert(*name), "{kind:?}: `{name}` twice");
            }
        }
        let mut read = std::collections::HashSet::new();
        for p in registry(kind) {
            for name in p.names {
                assert!(read.insert(*name), "{kind:?}: `{name}` read twice");
                assert!(
                    p.schema.mitsuba.contains(name),
                    "{kind:?}: `{name}` is not a Mitsuba name of `{}`",
                    p.schema.plugin
                );
            }
        }
    }
}

/// A value of `p`'s type just outside its range, as a scene file writes it.
fn outside(p: &penumbra::description::Param) -> Option<String> {
    let x = match p.range {
        Range::Any => return None,
        Range::Unit => 1.5,
        Range::NonNegative => -1.0,
        Range::Positive => 0.0,
        Range::Between(lo, _) if lo > 0.0 => lo / 2.0 - 1.0,
        Range::Between(_, hi) => hi + 1.0,
    };
    Some(match p.ty {
        Type::Colour | Type::ColourTexture => format!("[{x:?}, {x:?}, {x:?}]"),
        Type::Int => format!("{}", x.floor() as i64),
        _ => format!("{x:?}"),
    })
}

/// What a required parameter is set to where another is tested; `None`
/// for a plugin that needs a file.
fn filler(name: &str) -> Option<&'static str> {
    Some(match name {
        "origin" | "center" => "[0, 0, 0]",
        "edge_u" => "[1, 0, 0]",
        "edge_v" => "[0, 0, 1]",
        "normal" | "position" => "[0, 1, 0]",
        "radius" => "1",
        "radiance" | "intensity" => "[1, 1, 1]",
        "bsdf" | "bsdf_0" | "bsdf_1" => "\"d\"",
        "normalmap" => "[0.5, 0.5, 1]",
        "texture" => "0.5",
        _ => return None,
    })
}

/// Every builder refuses a value just outside the range its schema
/// states, naming the key: the ranges the reference shows are the ones
/// the scenes are held to.
#[test]
fn builders_refuse_what_the_schemas_ranges_exclude() {
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for (kind, schema) in reference::documented() {
        let required: Vec<&str> = schema
            .params
            .iter()
            .filter(|p| p.default == "required")
            .map(|p| p.name)
            .collect();
        if required.iter().any(|n| filler(n).is_none()) {
            continue;
        }
        for p in schema.params {
            let Some(value) = outside(p) else { continue };
            let mut keys = String::new();
            for r in required.iter().filter(|r| **r != p.name) {
                keys += &format!("{r} = {}\n", filler(r).unwrap());
            }
            // The keys that go together.
            match p.name {
                "alpha_u" => keys += "alpha_v = 0.1\n",
                "alpha_v" => keys += "alpha_u = 0.1\n",
                _ => {}
            }
            keys += &format!("{} = {value}\n", p.name);
            let ty = schema.plugin;
            let (text, path) = match kind {
                Kind::Bsdf => (
                    format!(
                        "[materials.d]\ntype = \"diffuse\"\n[materials.m]\ntype = \"{ty}\"\n{keys}"
                    ),
                    format!("materials.m.{}", p.name),
                ),
                Kind::Texture => (
                    format!("[textures.t]\ntype = \"{ty}\"\n{keys}"),
                    format!("textures.t.{}", p.name),
                ),
                Kind::Sensor => (format!("[camera]\n{keys}"), format!("camera.{}", p.name)),
                Kind::Shape => (
                    format!("[[objects]]\ntype = \"{ty}\"\n{keys}"),
                    format!("objects[0].{}", p.name),
                ),
                Kind::Emitter if ty == "area" => (
                    format!("[[objects]]\ntype = \"sphere\"\n[objects.emitter]\n{keys}"),
                    format!("objects[0].emitter.{}", p.name),
                ),
                Kind::Emitter => (
                    format!("[[lights]]\ntype = \"{ty}\"\n{keys}"),
                    format!("lights[0].{}", p.name),
                ),
                Kind::Medium => (
                    format!("[media.m]\ntype = \"{ty}\"\n{keys}"),
                    format!("media.m.{}", p.name),
                ),
                Kind::Phase => (
                    format!(
                        "[media.m]\ntype = \"homogeneous\"\nphase = {{ type = \"{ty}\", {} }}\n",
                        keys.trim_end().replace('\n', ", ")
                    ),
                    format!("media.m.phase.{}", p.name),
                ),
                _ => continue,
            };
            let built = SceneSource::from_toml(
                &text,
                Path::new("t.toml"),
                dir.path(),
                &LoadOptions::default(),
            )
            .and_then(|s| s.build().map(drop));
            let e = match built {
                Ok(()) => panic!(
                    "{kind:?} `{ty}`: `{}` = {value} is accepted\n{text}",
                    p.name
                ),
                Err(e) => e.to_string(),
            };
            assert!(
                e.contains(&path),
                "{kind:?} `{ty}`: `{}` = {value} is refused elsewhere: {e}",
                p.name
            );
            checked += 1;
        }
    }
    assert!(checked > 40, "{checked} ranges checked");
}
