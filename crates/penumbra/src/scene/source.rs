//! Source positions: turns byte offsets and key paths into `line:column`.

use std::ops::Range;
use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::error::{Invalid, KeyPath, KeySeg, SceneError};
use super::nesting;

/// The text of a scene file, kept to point errors at their place in it.
pub struct SourceMap {
    pub file: PathBuf,
    text: String,
}

impl SourceMap {
    pub fn new(file: &Path, text: String) -> Self {
        SourceMap {
            file: file.to_path_buf(),
            text,
        }
    }

    pub fn text(&self) -> &str {
        &self.text
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = self.text.get(..offset).unwrap_or("");
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before.get(line_start..).map_or(0, |s| s.chars().count()) + 1;
        (line, column)
    }

    /// An error at a byte offset, or at the start of the file (the root
    /// table's place) when the offset is unknown: every error in a file
    /// names a line.
    pub fn error_at(&self, span: Option<Range<usize>>, message: impl Into<String>) -> SceneError {
        SceneError {
            file: Some(self.file.clone()),
            position: Some(self.line_col(span.map_or(0, |s| s.start))),
            message: message.into(),
        }
    }

    /// A TOML syntax or type error, located: at the parser's span with the
    /// key path of the value there (`camera.position: expected 3 numbers,
    /// got 4`), or, for the parser's errors without a span (keys nested too
    /// deeply), at the key that passed the depth.
    pub fn toml_error(&self, e: &toml::de::Error) -> SceneError {
        let message = e.message().trim();
        match e.span() {
            Some(span) => {
                let path = DeTable::parse(&self.text)
                    .ok()
                    .and_then(|root| key_path_at(&root, span.start))
                    .filter(|p| !p.0.is_empty());
                match path {
                    Some(path) => self.error_at(Some(span), format!("{path}: {message}")),
                    None => self.error_at(Some(span), message),
                }
            }
            None => match nesting::deep_key(&self.text, nesting::MAX_KEY_PARTS) {
                Some(key) => self.error_at(
                    Some(key.offset..key.offset),
                    format!(
                        "a key of {} dotted parts; keys and table headers nest at most {} deep",
                        key.parts,
                        nesting::MAX_KEY_PARTS
                    ),
                ),
                None => self.error_at(None, message),
            },
        }
    }

    /// Locates a validation problem: the value at its key path, or the nearest
    /// enclosing table that exists in the file (a missing key is reported at
    /// the table that should have held it).
    pub fn locate(&self, invalid: Invalid) -> SceneError {
        let span = DeTable::parse(&self.text)
            .ok()
            .and_then(|root| span_of(&root, &invalid.path));
        let message = if invalid.path.0.is_empty() {
            invalid.message
        } else {
            format!("{}: {}", invalid.path, invalid.message)
        };
        self.error_at(span, message)
    }
}

/// The key path of the deepest value whose span holds `offset`, or of the
/// table of a key whose span holds it (`None` if none does).
fn key_path_at(root: &Spanned<DeTable<'_>>, offset: usize) -> Option<KeyPath> {
    let mut best = None;
    let mut path = KeyPath::root();
    table_path_at(root.get_ref(), offset, &mut path, &mut best);
    best
}

fn holds(span: &Range<usize>, offset: usize) -> bool {
    span.contains(&offset) || span.start == offset
}

fn keep_deepest(path: &KeyPath, best: &mut Option<KeyPath>) {
    if best.as_ref().is_none_or(|b| b.0.len() < path.0.len()) {
        *best = Some(path.clone());
    }
}

fn table_path_at(
    table: &DeTable<'_>,
    offset: usize,
    path: &mut KeyPath,
    best: &mut Option<KeyPath>,
) {
    for (key, value) in table {
        // An error at a key (unknown, duplicate) belongs to its table.
        if holds(&key.span(), offset) {
            keep_deepest(path, best);
        }
        path.0.push(KeySeg::Key(key.get_ref().to_string()));
        value_path_at(value, offset, path, best);
        path.0.pop();
    }
}

fn value_path_at(
    value: &Spanned<DeValue<'_>>,
    offset: usize,
    path: &mut KeyPath,
    best: &mut Option<KeyPath>,
) {
    if holds(&value.span(), offset) {
        keep_deepest(path, best);
    }
    match value.get_ref() {
        DeValue::Table(t) => table_path_at(t, offset, path, best),
        DeValue::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                path.0.push(KeySeg::Index(i));
                value_path_at(item, offset, path, best);
                path.0.pop();
            }
        }
        _ => {}
    }
}

/// Span of the deepest value along `path` that exists in the parsed document.
fn span_of(root: &Spanned<DeTable<'_>>, path: &KeyPath) -> Option<Range<usize>> {
    let mut span = None;
    let mut table: Option<&DeTable<'_>> = Some(root.get_ref());
    let mut value: Option<&Spanned<DeValue<'_>>> = None;
    for seg in &path.0 {
        let next = match (seg, table, value) {
            (KeySeg::Key(k), Some(t), _) => t.get(k.as_str()),
            (KeySeg::Key(k), None, Some(v)) => v.get_ref().get(k.as_str()),
            (KeySeg::Index(i), _, Some(v)) => v.get_ref().get(*i),
            _ => None,
        };
        let Some(next) = next else { break };
        span = Some(next.span());
        table = None;
        value = Some(next);
    }
    span
}
