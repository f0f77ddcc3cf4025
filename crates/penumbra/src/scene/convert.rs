//! A loaded scene (a Mitsuba XML one, say) as a TOML scene file: what
//! `penumbra convert` writes.
//!
//! The text is [`description::to_toml`] of the scene's tree, with one
//! change: file names (every parameter whose [`Schema`] type is
//! [`Type::Path`], such as a mesh's `path`, in a plugin's node or in a
//! texture or volume written inline, such as a medium's `gridvolume`) are
//! read relative to the scene
//! file's folder, so they stay as they are when the TOML file goes into
//! the same folder and become absolute otherwise (`@` names, such as
//! `@bunny`, are kept). Meshes are referenced, never copied.
//!
//! The text is then read back as a scene file and checked: it must hold
//! the tree that was written, key for key and float for float, so that
//! the TOML scene renders what its source does. A tree no scene file can
//! hold is an error naming its node.

use std::path::{Path, PathBuf};

use super::schemas;
use super::SceneSource;
use crate::description::{self, Kind, Node, Prop, SceneError, Schema, Type, Value};

/// The TOML text of `source`'s scene, to be written into the folder `out_dir`.
pub fn to_toml(source: &SceneSource, out_dir: &Path) -> Result<String, SceneError> {
    let from = &source.ctx.base_dir;
    let same_dir = same_folder(from, out_dir);
    let mut root = source.root.clone();
    if !same_dir {
        rebase(&mut root, from);
    }
    let text = description::to_toml(&root)?;
    let label = Path::new("<converted scene>");
    let reread = description::from_toml(&text, label)
        .map_err(|e| SceneError::new(format!("the written scene does not read back: {e}")))?;
    schemas::check(&reread).map_err(|e| {
        SceneError::new(format!(
            "the written scene does not check: {}",
            SceneError::from(e)
        ))
    })?;
    if !reread.same_as(&root) {
        return Err(SceneError::new(
            "the scene file written does not hold the scene read (a node or property a scene file cannot express)",
        ));
    }
    Ok(text)
}

fn same_folder(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| {
        let p = if p.as_os_str().is_empty() {
            Path::new(".")
        } else {
            p
        };
        p.canonicalize().ok()
    };
    match (canon(a), canon(b)) {
        (Some(x), Some(y)) => x == y,
        _ => false,
    }
}

/// Every relative file name of `node`'s subtree made absolute from `from`.
fn rebase(node: &mut Node, from: &Path) {
    let kind = node.kind;
    for child in &mut node.children {
        if let Ok(schema) = schemas::schema_in(kind, child) {
            rebase_props(&mut child.props, schema, from);
        }
        rebase(child, from);
    }
}

/// The file names among `props`, read by `schema`, and those of the
/// textures and volumes written inline in them (a `gridvolume` as a
/// medium's `sigma_t`, a `bitmap` as a material's `reflectance`).
fn rebase_props(props: &mut [Prop], schema: &Schema, from: &Path) {
    for p in props {
        let is_path = schema.param(&p.name).is_some_and(|q| q.ty == Type::Path);
        match &mut p.value.value {
            Value::String(s)
                if is_path && !s.starts_with('@') && Path::new(s.as_str()).is_relative() =>
            {
                let joined: PathBuf = from.join(&*s);
                let absolute = std::path::absolute(&joined).unwrap_or(joined);
                *s = absolute.to_string_lossy().into_owned();
            }
            Value::Table(inner) => {
                if let Some(nested) = inline_plugin(inner) {
                    rebase_props(inner, nested, from);
                }
            }
            _ => {}
        }
    }
}

/// The schema of the texture or volume an inline table names by its `type`.
fn inline_plugin(props: &[Prop]) -> Option<&'static Schema> {
    let ty = props.iter().find(|p| p.name == "type")?;
    let Value::String(name) = &ty.value.value else {
        return None;
    };
    [Kind::Texture, Kind::Volume]
        .into_iter()
        .flat_map(|k| schemas::of(k).iter().copied())
        .find(|s| s.plugin == name)
}
