//! The scenes the explorer may open: the built-ins, and the files named on
//! its command line. A request names one by its place in this list (or its
//! name); no other file is ever opened.

use std::path::{Path, PathBuf};

use penumbra::description::Node;
use penumbra::scene::builtin::{self, Builtin};
use penumbra::scene::{LoadOptions, SceneSource};
use serde_json::{json, Value as Json};

enum Entry {
    Builtin(&'static Builtin),
    /// A scene file, as named on the command line.
    File(PathBuf),
}

pub struct Catalogue {
    entries: Vec<Entry>,
}

impl Catalogue {
    /// The built-ins, then each of `named` that is a file (a name that is no
    /// file but a built-in's picks that built-in). Also returns the index of
    /// the first named scene (or of the default, `showcase`).
    pub fn new(named: &[String]) -> Result<(Catalogue, usize), String> {
        let mut entries: Vec<Entry> = builtin::SCENES.iter().map(Entry::Builtin).collect();
        let mut first = None;
        for name in named {
            let path = Path::new(name);
            let index = if path.is_file() {
                entries.push(Entry::File(path.to_path_buf()));
                entries.len() - 1
            } else if let Some(i) = builtin::SCENES.iter().position(|b| b.name == name) {
                i
            } else {
                let names: Vec<&str> = builtin::SCENES.iter().map(|b| b.name).collect();
                return Err(format!(
                    "{name}: no such file, and not a built-in scene (built-ins: {})",
                    names.join(", ")
                ));
            };
            first.get_or_insert(index);
        }
        let default = builtin::SCENES
            .iter()
            .position(|b| b.name == "showcase")
            .unwrap_or(0);
        Ok((Catalogue { entries }, first.unwrap_or(default)))
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// The name the page shows, and a request may use.
    pub fn name(&self, index: usize) -> String {
        match self.entries.get(index) {
            Some(Entry::Builtin(b)) => b.name.to_string(),
            Some(Entry::File(p)) => p.display().to_string(),
            None => String::new(),
        }
    }

    /// The index of the scene named `name`, if listed.
    pub fn find(&self, name: &str) -> Option<usize> {
        (0..self.len()).find(|&i| self.name(i) == name)
    }

    /// The list for the page.
    pub fn json(&self) -> Json {
        let items: Vec<Json> = self
            .entries
            .iter()
            .enumerate()
            .map(|(i, e)| match e {
                Entry::Builtin(b) => json!({
                    "index": i, "name": b.name, "builtin": true,
                    "description": b.description, "needs_bunny": b.needs_bunny,
                }),
                Entry::File(_) => json!({ "index": i, "name": self.name(i), "builtin": false }),
            })
            .collect();
        Json::Array(items)
    }

    /// The description of the scene at `index` and the folder its files
    /// are found from.
    pub fn open(&self, index: usize, load: &LoadOptions) -> Result<(Node, PathBuf), String> {
        let source = match self.entries.get(index) {
            // Never a file of the built-in's name: the text compiled in.
            Some(Entry::Builtin(b)) => {
                let label = PathBuf::from(format!("<built-in scene {}>", b.name));
                SceneSource::from_toml(b.toml, &label, Path::new("."), load)
            }
            Some(Entry::File(path)) => SceneSource::open(&path.to_string_lossy(), load),
            None => return Err(format!("no scene {index}: there are {}", self.len())),
        }
        .map_err(|e| e.to_string())?;
        let base = match self.entries.get(index) {
            Some(Entry::File(path)) => path
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
            _ => PathBuf::from("."),
        };
        Ok((source.root, base))
    }
}
