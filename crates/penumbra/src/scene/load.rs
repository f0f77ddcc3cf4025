//! Reading scene files and built-in scenes into a description, and building it
//! with errors located in the source.

use std::path::{Path, PathBuf};

use super::build::{build, BuildContext, BuildError};
use super::builtin;
use super::desc::SceneDesc;
use super::error::SceneError;
use super::reuse::WorldCache;
use super::source::SourceMap;
use super::Scene;

/// Largest scene file accepted; real scenes are a few kilobytes.
const MAX_SCENE_BYTES: u64 = 16 << 20;

/// Options that affect where a scene's external files come from.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// The Stanford bunny for `path = "@bunny"`. The library looks nowhere
    /// else: the front ends fill it from `--bunny`, `bunny=` or
    /// [`default_bunny_path`].
    pub bunny: Option<PathBuf>,
}

/// The bunny named by `$PENUMBRA_BUNNY`, if set: what the command line and
/// Python use when no path is given.
pub fn default_bunny_path() -> Option<PathBuf> {
    std::env::var_os("PENUMBRA_BUNNY").map(PathBuf::from)
}

/// A parsed scene description together with where it came from.
pub struct SceneSource {
    pub desc: SceneDesc,
    map: Option<SourceMap>,
    ctx: BuildContext,
}

impl SceneSource {
    /// Opens a scene file, or a built-in scene by name when no such file exists.
    pub fn open(name_or_path: &str, opts: &LoadOptions) -> Result<SceneSource, SceneError> {
        let path = Path::new(name_or_path);
        if !path.exists() {
            if let Some(b) = builtin::find(name_or_path) {
                let label = PathBuf::from(format!("<built-in scene {}>", b.name));
                return SceneSource::from_toml(b.toml, &label, Path::new("."), opts);
            }
            let names: Vec<&str> = builtin::SCENES.iter().map(|b| b.name).collect();
            return Err(SceneError::new(format!(
                "{name_or_path}: no such file, and not a built-in scene (built-ins: {})",
                names.join(", ")
            )));
        }
        let text = read_text(path)?;
        let base = path
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        SceneSource::from_toml(&text, path, &base, opts)
    }

    /// Parses TOML text; `file` names it in errors, `base_dir` anchors mesh paths.
    pub fn from_toml(
        text: &str,
        file: &Path,
        base_dir: &Path,
        opts: &LoadOptions,
    ) -> Result<SceneSource, SceneError> {
        let map = SourceMap::new(file, text.to_string());
        let desc: SceneDesc = toml::from_str(text)
            .map_err(|e| map.error_at(e.span(), e.message().trim().to_string()))?;
        Ok(SceneSource {
            desc,
            map: Some(map),
            ctx: context(base_dir, opts),
        })
    }

    /// A description made in code (no file: errors name the key path only).
    pub fn from_desc(desc: SceneDesc, base_dir: &Path, opts: &LoadOptions) -> SceneSource {
        SceneSource {
            desc,
            map: None,
            ctx: context(base_dir, opts),
        }
    }

    /// Validates the description and builds the scene.
    pub fn build(&self) -> Result<Scene, SceneError> {
        self.build_with(None)
    }

    /// [`build`](Self::build), reusing a world from `worlds` built from the
    /// same geometry (objects, light shapes, material names, mesh files), and
    /// keeping a newly built one there: for many renders of one scene with
    /// other settings. The scene is the same as [`build`](Self::build) gives,
    /// errors included.
    pub fn build_reusing(&self, worlds: &mut WorldCache) -> Result<Scene, SceneError> {
        self.build_with(Some(worlds))
    }

    fn build_with(&self, worlds: Option<&mut WorldCache>) -> Result<Scene, SceneError> {
        build(&self.desc, &self.ctx, worlds).map_err(|e| match e {
            BuildError::Invalid(i) => match &self.map {
                Some(map) => map.locate(i),
                None => SceneError::new(format!("{}: {}", i.path, i.message)),
            },
            BuildError::Mesh { path, error } => {
                let i = super::error::Invalid::new(path, format!("cannot load mesh: {error}"));
                match &self.map {
                    Some(map) => map.locate(i),
                    None => SceneError::new(format!("{}: {}", i.path, i.message)),
                }
            }
        })
    }
}

fn context(base_dir: &Path, opts: &LoadOptions) -> BuildContext {
    BuildContext {
        base_dir: base_dir.to_path_buf(),
        bunny: opts.bunny.clone(),
    }
}

fn read_text(path: &Path) -> Result<String, SceneError> {
    let err = |m: String| SceneError {
        file: Some(path.to_path_buf()),
        position: None,
        message: m,
    };
    let meta = std::fs::metadata(path).map_err(|e| err(e.to_string()))?;
    if meta.len() > MAX_SCENE_BYTES {
        return Err(err(format!(
            "scene file is {} bytes; the limit is {MAX_SCENE_BYTES}",
            meta.len()
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let map = SourceMap::new(path, String::from_utf8_lossy(e.as_bytes()).into_owned());
        map.error_at(Some(offset..offset), "the scene file is not valid UTF-8")
    })
}
