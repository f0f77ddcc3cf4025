//! Where a scene's files are found: the directory relative paths start from,
//! and the Stanford bunny for scenes that name it.

use std::path::{Path, PathBuf};

use super::error::{Invalid, KeyPath};

/// Where relative mesh paths and the `@bunny` placeholder point.
#[derive(Clone, Debug, Default)]
pub struct BuildContext {
    /// Directory of the scene file; mesh paths are relative to it.
    pub base_dir: PathBuf,
    /// The Stanford bunny, for scenes that say `path = "@bunny"`.
    pub bunny: Option<PathBuf>,
}

/// The bunny placeholder and scene-relative paths.
pub(super) fn resolve_mesh_path(
    p: &KeyPath,
    file: &str,
    ctx: &BuildContext,
) -> Result<PathBuf, Invalid> {
    if file == "@bunny" {
        return ctx.bunny.clone().ok_or_else(|| {
            Invalid::new(
                p.clone(),
                "this scene needs the Stanford bunny (bunny.ply): pass its path (--bunny PATH on the command \
                 line, bunny= in Python) or set PENUMBRA_BUNNY to it",
            )
        });
    }
    let path = Path::new(file);
    Ok(if path.is_absolute() {
        path.to_path_buf()
    } else {
        ctx.base_dir.join(path)
    })
}
