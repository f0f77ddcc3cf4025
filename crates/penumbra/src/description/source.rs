//! Byte offsets of a text as `line:column`, each in logarithmic time: the
//! lowering asks for the place of every key and value, and a 4 MiB file of
//! 100,000 values (or one line of 2 million numbers) must not cost a scan
//! of the text per value.

use std::path::PathBuf;
use std::sync::Arc;

use super::error::Location;

/// Bytes between two checkpoints of the character count.
const CHECKPOINT: usize = 64;

/// A file's text with the index that places its offsets.
pub struct Source<'a> {
    text: &'a str,
    file: Arc<PathBuf>,
    /// Byte offset of the start of every line.
    line_starts: Vec<usize>,
    /// Characters before every `CHECKPOINT`-th byte; `None` for an ASCII
    /// text, where characters are bytes.
    chars_before: Option<Vec<u32>>,
}

impl<'a> Source<'a> {
    pub fn new(text: &'a str, file: Arc<PathBuf>) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(
            text.bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
        let chars_before = (!text.is_ascii()).then(|| {
            let mut count = 0u32;
            let mut marks = Vec::with_capacity(text.len() / CHECKPOINT + 1);
            for chunk in text.as_bytes().chunks(CHECKPOINT) {
                marks.push(count);
                count += chunk.iter().filter(|&&b| starts_char(b)).count() as u32;
            }
            marks.push(count);
            marks
        });
        Source {
            text,
            file,
            line_starts,
            chars_before,
        }
    }

    pub fn text(&self) -> &'a str {
        self.text
    }

    pub fn file(&self) -> &Arc<PathBuf> {
        &self.file
    }

    /// 1-based line and column (in characters) of a byte offset; an offset
    /// past the end is taken as the end.
    pub fn line_col(&self, offset: usize) -> (u32, u32) {
        let offset = offset.min(self.text.len());
        // The last line start at or before the offset.
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        let start = self.line_starts[line];
        let column = self.chars_to(offset) - self.chars_to(start) + 1;
        (saturate(line + 1), saturate(column))
    }

    /// The place of a byte offset.
    pub fn location(&self, offset: usize) -> Location {
        let (line, column) = self.line_col(offset);
        Location {
            file: self.file.clone(),
            line,
            column,
        }
    }

    /// Characters that start before `offset`.
    fn chars_to(&self, offset: usize) -> usize {
        match &self.chars_before {
            None => offset,
            Some(marks) => {
                let mark = offset / CHECKPOINT;
                let from = mark * CHECKPOINT;
                let rest = &self.text.as_bytes()[from..offset];
                marks[mark] as usize + rest.iter().filter(|&&b| starts_char(b)).count()
            }
        }
    }
}

/// Whether a byte of UTF-8 starts a character (is not a continuation byte).
fn starts_char(b: u8) -> bool {
    b & 0xC0 != 0x80
}

fn saturate(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What the place of an offset means, counted the slow way.
    fn slow(text: &str, offset: usize) -> (u32, u32) {
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let start = before.rfind('\n').map_or(0, |i| i + 1);
        (line as u32, before[start..].chars().count() as u32 + 1)
    }

    fn source(text: &str) -> Source<'_> {
        Source::new(text, Arc::new(PathBuf::from("t.toml")))
    }

    #[test]
    fn every_offset_is_placed_as_counted_by_hand() {
        let long = format!("é{}x = \"ü\"\n", "a".repeat(200));
        for text in [
            "",
            "a = 1\nb = 2\n",
            "[render]\nwidth = 3\n\n",
            "x = \"héllo wörld\"\ny = '日本語'\n",
            long.as_str(),
            "\n\n\n",
        ] {
            let src = source(text);
            for (offset, _) in text.char_indices().chain([(text.len(), ' ')]) {
                assert_eq!(
                    src.line_col(offset),
                    slow(text, offset),
                    "{text:?} {offset}"
                );
            }
        }
    }

    #[test]
    fn columns_count_characters_on_long_lines() {
        let text = format!("{}= 1", "ü".repeat(1000));
        let src = source(&text);
        assert_eq!(src.line_col(text.len() - 3), (1, 1001));
        assert_eq!(src.line_col(text.len() + 5), (1, 1004));
        let loc = src.location(0);
        assert_eq!((loc.line, loc.column), (1, 1));
        assert_eq!(loc.file.as_path(), std::path::Path::new("t.toml"));
    }
}
