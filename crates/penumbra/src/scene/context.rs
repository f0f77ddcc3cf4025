//! Where a scene's files are found: the directory relative paths start from,
//! and the Stanford bunny for scenes that name it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::description::{Invalid, Props};

/// Where relative mesh paths and the `@bunny` placeholder point.
#[derive(Clone, Debug, Default)]
pub struct BuildContext {
    /// Directory of the scene file; mesh paths are relative to it.
    pub base_dir: PathBuf,
    /// The Stanford bunny, for scenes that say `path = "@bunny"`.
    pub bunny: Option<PathBuf>,
    /// The `custom` distribution's points when given in code (Python's
    /// `points=`), which win over the sampler's `points` file.
    pub points: Option<Arc<crate::sampling::PointTable>>,
}

/// The bunny placeholder and scene-relative paths.
pub(super) fn resolve_mesh_path(
    p: &Props,
    file: &str,
    ctx: &BuildContext,
) -> Result<PathBuf, Invalid> {
    mesh_path(file, ctx).ok_or_else(|| {
        p.error(
            "path",
            "this scene needs the Stanford bunny (bunny.ply): pass its path (--bunny PATH on the command \
             line, bunny= in Python) or set PENUMBRA_BUNNY to it",
        )
    })
}

/// Where a mesh path points: the bunny for `@bunny` (`None` without one),
/// else the path, relative to the scene's folder.
pub(super) fn mesh_path(file: &str, ctx: &BuildContext) -> Option<PathBuf> {
    if file == "@bunny" {
        return ctx.bunny.clone();
    }
    let path = Path::new(file);
    Some(if path.is_absolute() {
        path.to_path_buf()
    } else {
        ctx.base_dir.join(path)
    })
}
