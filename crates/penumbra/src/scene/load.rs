//! Reading TOML scenes, built-in scenes and JSON into a description, and
//! building it with errors located in the source. Opening a file by name
//! and reading Mitsuba scenes (`SceneSource::open`, `from_xml`,
//! `from_mitsuba_dict`) sit in the integrator layer (`integrator::sources`),
//! whose registry of plugins names the integrators too.

use std::path::{Path, PathBuf};

use super::build::build;
use super::context::BuildContext;
use super::lights;
use super::reuse::WorldCache;
use super::schemas;
use super::Scene;
use crate::description::{self, Location, Node, SceneError, Source};
use crate::input::{self, InputError};

/// Largest scene file read unless `--max-file-size` or
/// `PENUMBRA_MAX_FILE_SIZE` says otherwise. Real scenes are a few kilobytes
/// (meshes live in files of their own); parsing holds the whole document,
/// with every value's place: about 80 bytes of memory for each byte of an
/// array of numbers, 240 for one of small inline tables (the most
/// measured), most of it the TOML parser's tokens, events and tables; this
/// bound keeps a hostile scene's parse under 1 GiB.
pub const MAX_SCENE_FILE_SIZE: u64 = 4 << 20;

/// Options that affect where a scene's external files come from.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// The Stanford bunny for `path = "@bunny"`. The library looks nowhere
    /// else: the front ends fill it from `--bunny`, `bunny=` or
    /// [`default_bunny_path`].
    pub bunny: Option<PathBuf>,
    /// `name = value` parameters of a Mitsuba XML scene (`-D`), which win
    /// over its `<default>`s; a TOML scene has none.
    pub defines: Vec<(String, String)>,
    /// A Mitsuba XML scene's parameters Penumbra does not read are
    /// warnings rather than errors (`--lenient`); a TOML scene has none.
    pub lenient: bool,
    /// Folders where a Mitsuba XML scene's files are looked for after its
    /// `<path>` folders and before its own folder (`-a`).
    pub search: Vec<PathBuf>,
    /// Which of a Mitsuba XML scene's sensors renders, from 0 (`--sensor`).
    pub sensor: usize,
}

/// The bunny named by `$PENUMBRA_BUNNY`, if set: what the command line and
/// Python use when no path is given.
pub fn default_bunny_path() -> Option<PathBuf> {
    std::env::var_os("PENUMBRA_BUNNY").map(PathBuf::from)
}

/// A scene's description (its tree of plugins, see
/// [`description`](crate::description)) together with where it came from.
pub struct SceneSource {
    /// The tree; front ends change it before building (render options).
    pub root: Node,
    /// The file the tree was read from and its text.
    text: Option<(PathBuf, String)>,
    pub(super) ctx: BuildContext,
    /// Things to tell the user once about reading the scene (a Mitsuba
    /// scene's upgrade, parameters without effect) or changing it (an
    /// integrator replaced): the built scene's warnings start with them.
    pub warnings: Vec<String>,
}

impl SceneSource {
    /// The description a Mitsuba reader made (`from_xml` and
    /// `from_mitsuba_dict`, in `integrator::sources`, whose registry names
    /// the integrators too), its tree checked and its warnings kept.
    pub(crate) fn from_mitsuba(
        loaded: description::mitsuba::Loaded,
        base_dir: &Path,
        opts: &LoadOptions,
    ) -> Result<SceneSource, SceneError> {
        // The integrator is checked when the scene is built (as for every
        // scene): Mitsuba's (`path`) may yet be replaced by `--integrator`.
        schemas::check(&loaded.root)?;
        let mut source = SceneSource::from_tree(loaded.root, base_dir, opts);
        source.warnings = loaded.warnings;
        Ok(source)
    }

    /// Parses TOML text; `file` names it in errors, `base_dir` anchors mesh paths.
    pub fn from_toml(
        text: &str,
        file: &Path,
        base_dir: &Path,
        opts: &LoadOptions,
    ) -> Result<SceneSource, SceneError> {
        let mut root = description::from_toml(text, file)?;
        lights::lower(&mut root);
        schemas::check(&root)?;
        Ok(SceneSource {
            root,
            text: Some((file.to_path_buf(), text.to_string())),
            ctx: context(base_dir, opts),
            warnings: Vec::new(),
        })
    }

    /// Reads a scene given as JSON (a Python dict's, shaped like a scene
    /// file): errors name key paths.
    pub fn from_json(
        value: &serde_json::Value,
        base_dir: &Path,
        opts: &LoadOptions,
    ) -> Result<SceneSource, SceneError> {
        let mut root = description::from_json(value)?;
        lights::lower(&mut root);
        schemas::check(&root)?;
        Ok(SceneSource::from_tree(root, base_dir, opts))
    }

    /// The file the description was read from (as errors name it) and its
    /// text; `None` for a description made in code.
    pub fn text(&self) -> Option<(&Path, &str)> {
        self.text.as_ref().map(|(f, t)| (f.as_path(), t.as_str()))
    }

    /// A description made in code (no file: errors name the key path only).
    pub fn from_tree(root: Node, base_dir: &Path, opts: &LoadOptions) -> SceneSource {
        SceneSource {
            root,
            text: None,
            ctx: context(base_dir, opts),
            warnings: Vec::new(),
        }
    }

    /// Validates the description but for its integrator and builds the
    /// scene, taking the world from `worlds` when one was built there from
    /// the same geometry (objects, light shapes, material names, mesh
    /// files) and keeping a newly built one there. `build` and
    /// `build_reusing` (`integrator::plugins`) read the integrator first.
    pub fn build_scene(&self, worlds: Option<&mut WorldCache>) -> Result<Scene, SceneError> {
        let mut scene = build(&self.root, &self.ctx, worlds).map_err(SceneError::from)?;
        scene.warnings.splice(0..0, self.warnings.iter().cloned());
        Ok(scene)
    }
}

/// Whether a scene file is Mitsuba XML, by its extension (any case).
pub(crate) fn is_xml(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

fn context(base_dir: &Path, opts: &LoadOptions) -> BuildContext {
    BuildContext {
        base_dir: base_dir.to_path_buf(),
        bunny: opts.bunny.clone(),
        points: None,
    }
}

/// The text of the scene file `path`, within the size limit, as UTF-8.
pub(crate) fn read_text(path: &Path) -> Result<String, SceneError> {
    let err = |e: InputError| SceneError {
        file: Some(path.to_path_buf()),
        position: None,
        message: e.to_string(),
    };
    let limit = input::size_limit(MAX_SCENE_FILE_SIZE).map_err(err)?;
    let bytes = input::read_file_within(path, limit).map_err(|e| match e {
        // The message names the file itself: keep it once.
        InputError::Io { source, .. } => SceneError {
            file: Some(path.to_path_buf()),
            position: None,
            message: source.to_string(),
        },
        e => SceneError {
            file: None,
            position: None,
            message: e.to_string(),
        },
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
        let file = std::sync::Arc::new(path.to_path_buf());
        let Location { line, column, .. } = Source::new(&text, file).location(offset);
        SceneError {
            file: Some(path.to_path_buf()),
            position: Some((line as usize, column as usize)),
            message: "the scene file is not valid UTF-8".into(),
        }
    })
}
