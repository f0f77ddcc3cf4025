//! Opening scene files: a Mitsuba scene is read through the [`registry`]
//! of every plugin, the integrators included, which the scene layer below
//! cannot name; a TOML scene or a built-in one through the scene layer's
//! own readers.

use std::path::{Path, PathBuf};

use super::plugins::registry;
use crate::description::{self, SceneError};
use crate::input;
use crate::scene::{builtin, is_xml, read_text, LoadOptions, SceneSource, MAX_SCENE_FILE_SIZE};

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
        let base = path
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        if is_xml(path) {
            return SceneSource::from_xml(path, &base, opts);
        }
        if !opts.defines.is_empty() {
            return Err(SceneError::new(format!(
                "{}: -D/--define sets parameters of Mitsuba XML scenes; this is not one (.xml)",
                path.display()
            )));
        }
        let text = read_text(path)?;
        SceneSource::from_toml(&text, path, &base, opts)
    }

    /// Reads a Mitsuba 3 XML scene (see
    /// [`description::mitsuba`](crate::description::mitsuba)): `file` names
    /// it in errors, `base_dir` anchors mesh paths, `opts.defines` override
    /// its defaults, `opts.search` and `opts.sensor` as Mitsuba's `-a` and
    /// sensor index.
    pub fn from_xml(
        file: &Path,
        base_dir: &Path,
        opts: &LoadOptions,
    ) -> Result<SceneSource, SceneError> {
        let limit = input::size_limit(MAX_SCENE_FILE_SIZE).map_err(|e| SceneError {
            file: Some(file.to_path_buf()),
            position: None,
            message: e.to_string(),
        })?;
        let read = description::mitsuba::Read {
            defines: &opts.defines,
            lenient: opts.lenient,
            search: &opts.search,
            sensor: opts.sensor,
        };
        let loaded = description::mitsuba::from_xml_file_read(file, &read, limit, registry)?;
        SceneSource::from_mitsuba(loaded, base_dir, opts)
    }

    /// Reads a scene in Mitsuba 3's dict form (`mi.load_dict`'s, see
    /// [`description::mitsuba::dict`]): `base_dir` anchors its file names;
    /// errors name the dict's key paths.
    pub fn from_mitsuba_dict(
        d: &description::mitsuba::dict::DictValue,
        base_dir: &Path,
        opts: &LoadOptions,
    ) -> Result<SceneSource, SceneError> {
        let loaded = description::mitsuba::from_dict(d, base_dir, opts.lenient, registry)?;
        SceneSource::from_mitsuba(loaded, base_dir, opts)
    }
}
