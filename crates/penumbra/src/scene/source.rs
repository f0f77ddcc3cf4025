//! Source positions: turns byte offsets and key paths into `line:column`.

use std::ops::Range;
use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::error::{Invalid, KeyPath, KeySeg, SceneError};

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

    /// An error at a byte offset, or at the file when the offset is unknown.
    pub fn error_at(&self, span: Option<Range<usize>>, message: impl Into<String>) -> SceneError {
        SceneError {
            file: Some(self.file.clone()),
            position: span.map(|s| self.line_col(s.start)),
            message: message.into(),
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
