//! The plugin reference of the docs against the schemas: every plugin of
//! every documented kind has its table in `docs/scene-format.md`, every
//! kind the Mitsuba reader maps through the schemas its table in
//! `docs/mitsuba.md`, and each is what the schemas say.
//!
//! `PENUMBRA_UPDATE_DOCS=1 cargo test --release -p penumbra --test reference`
//! rewrites the tables from the schemas.

use std::path::{Path, PathBuf};

use penumbra::description::{Kind, Range, Type};
use penumbra::scene::reference;
use penumbra::scene::schemas;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn the_docs_tables_are_the_schemas() {
    let update = std::env::var_os("PENUMBRA_UPDATE_DOCS").is_some();
    type Rewrite = fn(&str) -> (String, Vec<String>);
    let docs: [(&str, Rewrite); 2] = [
        ("docs/scene-format.md", reference::scene_format),
        ("docs/mitsuba.md", reference::mitsuba),
    ];
    let mut stale = Vec::new();
    for (file, rewrite) in docs {
        let path = repo().join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        let (fresh, missing) = rewrite(&text);
        assert!(
            missing.is_empty(),
            "{file} has no block for {missing:?}: add `<!-- ID begin -->` and `<!-- ID end -->` \
             lines where each belongs"
        );
        if fresh != text {
            if update {
                std::fs::write(&path, fresh).unwrap();
            } else {
                stale.push(file);
            }
        }
    }
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

/// A Mitsuba plugin name is read as one Penumbra plugin of its kind.
#[test]
fn mitsuba_names_map_to_one_plugin() {
    for kind in Kind::ALL {
        let mut seen = std::collections::HashSet::new();
        for s in schemas::of(kind) {
            for name in s.mitsuba {
                assert!(seen.insert(*name), "{kind:?}: `{name}` twice");
            }
        }
    }
}
