use std::fmt;
use std::path::PathBuf;

use crate::input::quote;

/// One step of a key path such as `objects[2].transform.scale`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum KeySeg {
    Key(String),
    Index(usize),
}

/// The path of a value inside the scene description, used to point at it in
/// the source file (or, without a file, to name it).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct KeyPath(pub Vec<KeySeg>);

impl KeyPath {
    pub fn root() -> Self {
        KeyPath(Vec::new())
    }

    /// This path extended by a key.
    pub fn key(&self, k: &str) -> Self {
        let mut p = self.clone();
        p.0.push(KeySeg::Key(k.to_string()));
        p
    }

    /// This path extended by an array index.
    pub fn index(&self, i: usize) -> Self {
        let mut p = self.clone();
        p.0.push(KeySeg::Index(i));
        p
    }
}

/// Keys (material names, unknown keys) come from the file: each is shown
/// cut to a few dozen characters.
impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, seg) in self.0.iter().enumerate() {
            let clip = |k: &str| quote::clip(k, quote::MAX_QUOTED_CHARS).into_owned();
            match seg {
                KeySeg::Key(k) if i == 0 => write!(f, "{}", clip(k))?,
                KeySeg::Key(k) => write!(f, ".{}", clip(k))?,
                KeySeg::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// An invalid scene: names the file and, where known, the line and column
/// (1-based) of the offending value. Every scene error is a user-input error
/// (the CLI exits with status 2). Displayed bounded, whatever the input: a
/// quoted value is cut to a few dozen characters, the message to a few lines
/// ([`quote::bounded`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    pub file: Option<PathBuf>,
    pub position: Option<(usize, usize)>,
    pub message: String,
}

impl SceneError {
    pub fn new(message: impl Into<String>) -> Self {
        SceneError {
            file: None,
            position: None,
            message: message.into(),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}:", file.display())?;
            if let Some((line, col)) = self.position {
                write!(f, "{line}:{col}:")?;
            }
            write!(f, " ")?;
        }
        f.write_str(&quote::bounded(&self.message))
    }
}

impl std::error::Error for SceneError {}

/// A validation problem before it is located in a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invalid {
    pub path: KeyPath,
    pub message: String,
}

impl Invalid {
    pub fn new(path: KeyPath, message: impl Into<String>) -> Self {
        Invalid {
            path,
            message: message.into(),
        }
    }
}
