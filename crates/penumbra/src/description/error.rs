//! Where a value came from, and the errors that point there.
//!
//! Every value of a [description](super) carries an [`Origin`]: the key path
//! the user wrote (`objects[2].transform.scale`) and, for a file, the line
//! and column of its first character. A problem found anywhere later (by the
//! lowering, a typed reader, the schema check or the builder) is an
//! [`Invalid`] at an origin, and becomes a [`SceneError`] that prints as
//! `file:line:column: path: message`, or `path: message` for a dict.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

use crate::input::quote;

/// One step of a key path such as `objects[2].transform.scale`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum KeySeg {
    Key(String),
    Index(usize),
}

/// The path of a value inside the scene description, as the user wrote it.
///
/// Paths share their beginnings: a path is the path before its last key
/// (shared, by reference count, with every other path that starts so) and
/// up to two array indices after it, kept inline. A table's keys cost one
/// small allocation each; the elements of an array, and of an array of
/// arrays (a matrix), none. Two paths are equal when their steps are.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct KeyPath {
    /// The steps up to the inline indices; `None` at the root.
    head: Option<Arc<Step>>,
    /// Up to two indices after `head`, in order, [`NO_INDEX`] where there
    /// is none (the second only with the first).
    tail: [u32; 2],
}

/// The last step of a path beyond its parent's.
#[derive(PartialEq, Eq, Hash)]
struct Step {
    parent: KeyPath,
    seg: KeySeg,
}

/// An inline index slot that holds none. Larger indices are steps.
const NO_INDEX: u32 = u32::MAX;

impl KeyPath {
    pub fn root() -> Self {
        KeyPath {
            head: None,
            tail: [NO_INDEX; 2],
        }
    }

    /// This path extended by a key.
    pub fn key(&self, k: &str) -> Self {
        self.step(KeySeg::Key(k.to_string()))
    }

    /// This path extended by an array index.
    pub fn index(&self, i: usize) -> Self {
        let Some(small) = u32::try_from(i).ok().filter(|&i| i != NO_INDEX) else {
            return self.step(KeySeg::Index(i));
        };
        match self.tail {
            [NO_INDEX, _] => KeyPath {
                head: self.head.clone(),
                tail: [small, NO_INDEX],
            },
            [first, NO_INDEX] => KeyPath {
                head: self.head.clone(),
                tail: [first, small],
            },
            // Both slots taken: the first index becomes a step of the head.
            [first, second] => {
                let before = KeyPath {
                    head: self.head.clone(),
                    tail: [NO_INDEX; 2],
                };
                KeyPath {
                    head: before.step(KeySeg::Index(first as usize)).head,
                    tail: [second, small],
                }
            }
        }
    }

    /// This path and one step more, held by the head.
    fn step(&self, seg: KeySeg) -> Self {
        KeyPath {
            head: Some(Arc::new(Step {
                parent: self.clone(),
                seg,
            })),
            tail: [NO_INDEX; 2],
        }
    }

    pub fn is_root(&self) -> bool {
        self.head.is_none() && self.tail[0] == NO_INDEX
    }

    /// The steps of the path from the root.
    pub fn segments(&self) -> Vec<KeySeg> {
        let mut reversed = Vec::new();
        let mut path = self;
        loop {
            for &i in path.tail.iter().rev() {
                if i != NO_INDEX {
                    reversed.push(KeySeg::Index(i as usize));
                }
            }
            match &path.head {
                Some(step) => {
                    reversed.push(step.seg.clone());
                    path = &step.parent;
                }
                None => break,
            }
        }
        reversed.reverse();
        reversed
    }
}

impl Default for KeyPath {
    fn default() -> Self {
        KeyPath::root()
    }
}

impl fmt::Debug for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("KeyPath").field(&self.segments()).finish()
    }
}

/// Keys (material names, unknown keys) come from the input: each is shown
/// cut to a few dozen characters.
impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, seg) in self.segments().iter().enumerate() {
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

/// A place in a file: 1-based line and column, the column counted in
/// characters (not bytes).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Location {
    /// The file as errors name it; shared by every location in it.
    pub file: Arc<PathBuf>,
    pub line: u32,
    pub column: u32,
}

/// Where a value, a key or a node came from: its key path and, when it was
/// read from a file, its place there (`None` for a dict and for values set
/// in code).
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Origin {
    pub path: KeyPath,
    pub at: Option<Location>,
}

impl Origin {
    pub fn new(path: KeyPath, at: Option<Location>) -> Self {
        Origin { path, at }
    }

    /// A value without a place in a file (a dict's, or one set in code).
    pub fn unlocated(path: KeyPath) -> Self {
        Origin { path, at: None }
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

/// A problem with a value (or a node), at its origin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invalid {
    pub origin: Origin,
    pub message: String,
}

impl Invalid {
    /// A problem at `origin`.
    pub fn at(origin: &Origin, message: impl Into<String>) -> Self {
        Invalid {
            origin: origin.clone(),
            message: message.into(),
        }
    }
}

impl Invalid {
    /// serde's message for a key a table does not take, at `at` (the key's
    /// place, with the path of its table):
    /// ``unknown field `x`, expected one of `a`, `b` ``. Without a place
    /// (a dict), the path names the key itself, the only pointer there is.
    pub fn unknown_field<'a>(
        at: &Origin,
        key: &str,
        expected: impl IntoIterator<Item = &'a str>,
    ) -> Self {
        let names: Vec<String> = expected.into_iter().map(|n| format!("`{n}`")).collect();
        let message = match names.len() {
            0 => format!("unknown field `{key}`, there are no fields"),
            1 => format!("unknown field `{key}`, expected {}", names[0]),
            _ => format!(
                "unknown field `{key}`, expected one of {}",
                names.join(", ")
            ),
        };
        match at.at {
            Some(_) => Invalid::at(at, message),
            None => Invalid::at(&Origin::unlocated(at.path.key(key)), message),
        }
    }
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        SceneError::from(self.clone()).fmt(f)
    }
}

impl std::error::Error for Invalid {}

/// `path: message` (just `message` at the root), in the origin's file at
/// its line and column when it has one.
impl From<Invalid> for SceneError {
    fn from(invalid: Invalid) -> Self {
        let message = if invalid.origin.path.is_root() {
            invalid.message
        } else {
            format!("{}: {}", invalid.origin.path, invalid.message)
        };
        match invalid.origin.at {
            Some(at) => SceneError {
                file: Some(at.file.as_ref().clone()),
                position: Some((at.line as usize, at.column as usize)),
                message,
            },
            None => SceneError::new(message),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path() -> KeyPath {
        KeyPath::root().key("objects").index(2).key("transform")
    }

    #[test]
    fn key_paths_print_as_written_with_long_keys_cut() {
        assert_eq!(
            path().key("scale").to_string(),
            "objects[2].transform.scale"
        );
        assert_eq!(KeyPath::root().to_string(), "");
        let long = KeyPath::root().key("materials").key(&"m".repeat(1000));
        let shown = long.to_string();
        assert!(shown.starts_with("materials.mmm") && shown.ends_with("m…"));
        assert!(shown.chars().count() < 60, "{shown}");
    }

    #[test]
    fn paths_of_nested_indices_and_large_indices_print_and_compare_by_their_steps() {
        let m = KeyPath::root().key("objects").index(3).key("matrix");
        let deep = m.index(1).index(2).index(3).index(4);
        assert_eq!(deep.to_string(), "objects[3].matrix[1][2][3][4]");
        assert_eq!(deep, m.index(1).index(2).index(3).index(4));
        assert_ne!(deep, m.index(1).index(2).index(3).index(5));
        assert_ne!(m.index(1), m.index(1).index(0));
        let big = m.index(usize::MAX).index(u32::MAX as usize).index(7);
        assert_eq!(
            big.to_string(),
            format!("objects[3].matrix[{}][{}][7]", usize::MAX, u32::MAX)
        );
        assert_eq!(
            big.segments().last(),
            Some(&KeySeg::Index(7)),
            "{:?}",
            big.segments()
        );
        let hash = |p: &KeyPath| {
            use std::hash::{BuildHasher, RandomState};
            let s = RandomState::new();
            (s.hash_one(p), s.hash_one(p.clone()))
        };
        let (a, b) = hash(&deep);
        assert_eq!(a, b);
        assert!(KeyPath::root().is_root() && KeyPath::default().is_root());
        assert!(!KeyPath::root().index(0).is_root());
        assert_eq!(KeyPath::root(), KeyPath::default());
    }

    #[test]
    fn a_located_problem_names_file_line_column_and_path() {
        let at = Location {
            file: Arc::new(PathBuf::from("scene.toml")),
            line: 5,
            column: 12,
        };
        let origin = Origin::new(KeyPath::root().key("camera").key("position"), Some(at));
        let e = SceneError::from(Invalid::at(&origin, "expected 3 numbers, got 4"));
        assert_eq!(
            e.to_string(),
            "scene.toml:5:12: camera.position: expected 3 numbers, got 4"
        );
        assert_eq!(e.position, Some((5, 12)));
    }

    #[test]
    fn a_dict_problem_names_the_path_only() {
        let e = SceneError::from(Invalid::at(
            &Origin::unlocated(path().key("scale")),
            "must not be zero",
        ));
        assert_eq!(
            e,
            SceneError {
                file: None,
                position: None,
                message: "objects[2].transform.scale: must not be zero".into()
            }
        );
        let root = SceneError::from(Invalid::at(&Origin::default(), "unknown field `x`"));
        assert_eq!(root.to_string(), "unknown field `x`");
    }

    #[test]
    fn messages_are_bounded_whatever_they_quote() {
        let long = "x".repeat(100_000);
        let e = SceneError::from(Invalid::at(
            &Origin::unlocated(KeyPath::root().key("render")),
            format!("unknown field `{long}`"),
        ));
        assert!(e.to_string().len() < 100, "{e}");
    }
}
