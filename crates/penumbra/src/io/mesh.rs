//! The mesh data the file readers produce and the errors they report.
//!
//! Readers return plain arrays rather than scene objects so that parsing stays
//! independent of how the renderer later transforms and accelerates geometry.

use std::fmt;
use std::path::{Path, PathBuf};

use super::{obj, ply};

/// Plain mesh data as read from a file, before any transform.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    /// Per-vertex normals when the file has them for every vertex (PLY nx/ny/nz, OBJ vn referenced consistently); otherwise None.
    pub normals: Option<Vec<[f32; 3]>>,
    pub triangles: Vec<[u32; 3]>,
}

/// Where in a file a problem was found, so users can open the file at that spot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// 1-based, as editors count; the column counts bytes.
    LineColumn {
        line: usize,
        column: usize,
    },
    /// Binary bodies have no lines, so the offset from the start of the file is reported.
    ByteOffset(u64),
    Unknown,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::LineColumn { line, column } => write!(f, "{line}:{column}"),
            Location::ByteOffset(offset) => write!(f, "byte {offset}"),
            Location::Unknown => f.write_str("unknown location"),
        }
    }
}

/// Text after the path in an error message: `:12:5` for text, `: byte 10234` for binary,
/// matching the `file:line:column:` convention that editors and terminals make clickable.
fn location_suffix(location: &Location) -> String {
    match location {
        Location::LineColumn { .. } => format!(":{location}"),
        Location::ByteOffset(_) => format!(": {location}"),
        Location::Unknown => String::new(),
    }
}

#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A problem at a known place. Text formats give line and column (1-based); binary PLY bodies give the byte offset.
    #[error("{path}{}: {message}", location_suffix(.location))]
    Parse {
        path: PathBuf,
        location: Location,
        message: String,
    },
}

impl MeshError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        MeshError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    pub(crate) fn parse(path: &Path, location: Location, message: impl Into<String>) -> Self {
        MeshError::Parse {
            path: path.to_path_buf(),
            location,
            message: message.into(),
        }
    }
}

/// Reads a triangle mesh, choosing the format by extension because neither PLY nor
/// OBJ content is reliably recognisable from a few leading bytes (OBJ has no magic).
pub fn read_mesh(path: &Path) -> Result<MeshData, MeshError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("ply") => ply::read_ply(path),
        Some("obj") => obj::read_obj(path),
        Some(other) => Err(MeshError::parse(
            path,
            Location::Unknown,
            format!("unsupported mesh format `.{other}`; supported: .ply, .obj"),
        )),
        None => Err(MeshError::parse(
            path,
            Location::Unknown,
            "mesh file has no extension; supported: .ply, .obj",
        )),
    }
}

/// At most this many bytes of a token are quoted in a message, so that a corrupt file
/// with megabytes of garbage on one line cannot produce a megabyte-long error.
const MAX_QUOTED: usize = 40;

/// Quotes a token from a file for an error message, tolerating invalid UTF-8.
pub(crate) fn quote(token: &[u8]) -> String {
    let shown = token.get(..MAX_QUOTED).unwrap_or(token);
    let mut text = String::from_utf8_lossy(shown).into_owned();
    if shown.len() < token.len() {
        text.push('…');
    }
    format!("`{text}`")
}

/// Parses a decimal integer with optional sign straight from bytes: integers dominate
/// mesh text, and skipping UTF-8 validation and `str` parsing roughly halves their cost.
pub(crate) fn parse_i64(token: &[u8]) -> Option<i64> {
    let (negative, digits) = match token.split_first()? {
        (b'-', rest) => (true, rest),
        (b'+', rest) => (false, rest),
        _ => (false, token),
    };
    if digits.is_empty() {
        return None;
    }
    let mut value: i64 = 0;
    for &b in digits {
        let digit = i64::from(b.wrapping_sub(b'0'));
        if digit > 9 {
            return None;
        }
        // Accumulating negatively reaches i64::MIN, whose magnitude has no positive twin.
        let signed = if negative { -digit } else { digit };
        value = value.checked_mul(10)?.checked_add(signed)?;
    }
    Some(value)
}

/// Splits text into lines, counting them from 1, so both text formats report the same
/// line numbers an editor shows. The `\n` is removed; a `\r` before it is left for
/// the tokenizer, which treats it as whitespace.
pub(crate) struct Lines<'a> {
    text: &'a [u8],
    /// Offset of the next unread line.
    pub(crate) offset: usize,
    /// Number of the line most recently returned.
    pub(crate) number: usize,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(text: &'a [u8], offset: usize, number: usize) -> Self {
        Lines {
            text,
            offset,
            number,
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = &'a [u8];

    fn next(&mut self) -> Option<&'a [u8]> {
        let rest = self.text.get(self.offset..).filter(|r| !r.is_empty())?;
        let (line, consumed) = match rest.iter().position(|&b| b == b'\n') {
            Some(end) => (rest.get(..end).unwrap_or(rest), end + 1),
            None => (rest, rest.len()),
        };
        self.offset += consumed;
        self.number += 1;
        Some(line)
    }
}

/// Splits a line at ASCII whitespace, yielding each token with its 1-based byte column.
pub(crate) struct Tokens<'a> {
    line: &'a [u8],
    offset: usize,
}

impl<'a> Tokens<'a> {
    pub(crate) fn new(line: &'a [u8]) -> Self {
        Tokens { line, offset: 0 }
    }

    /// Column just past the last byte of the line, where a missing value would have gone.
    pub(crate) fn end_column(&self) -> usize {
        let content = self.line.trim_ascii_end();
        content.len() + 1
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<(usize, &'a [u8])> {
        let rest = self.line.get(self.offset..)?;
        let start = self.offset + rest.iter().position(|b| !b.is_ascii_whitespace())?;
        let tail = self.line.get(start..)?;
        let len = tail
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(tail.len());
        self.offset = start + len;
        Some((start + 1, tail.get(..len)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_error(location: Location) -> String {
        MeshError::parse(Path::new("bunny.ply"), location, "something is wrong").to_string()
    }

    #[test]
    fn messages_follow_the_file_line_column_convention() {
        let at_line = parse_error(Location::LineColumn {
            line: 12,
            column: 5,
        });
        assert_eq!(at_line, "bunny.ply:12:5: something is wrong");
        let at_byte = parse_error(Location::ByteOffset(10234));
        assert_eq!(at_byte, "bunny.ply: byte 10234: something is wrong");
        assert_eq!(
            parse_error(Location::Unknown),
            "bunny.ply: something is wrong"
        );
    }

    #[test]
    fn io_errors_name_the_file() {
        let missing = Path::new("definitely/not/here.ply");
        let error = read_mesh(missing).unwrap_err();
        assert!(matches!(error, MeshError::Io { .. }), "{error:?}");
        assert!(error.to_string().starts_with("definitely/not/here.ply: "));
    }

    #[test]
    fn extension_dispatch_is_case_insensitive() {
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join("tri.OBJ");
        std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert_eq!(read_mesh(&obj).unwrap().triangles, vec![[0, 1, 2]]);
        let ply = dir.path().join("tri.Ply");
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                    property float y\nproperty float z\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n\
                    0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        std::fs::write(&ply, text).unwrap();
        assert_eq!(read_mesh(&ply).unwrap().triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn unknown_extensions_list_the_supported_ones() {
        for name in ["model.stl", "model"] {
            let error = read_mesh(Path::new(name)).unwrap_err();
            let MeshError::Parse {
                location, message, ..
            } = &error
            else {
                panic!("expected a parse error, got {error:?}");
            };
            assert_eq!(*location, Location::Unknown);
            assert!(
                message.contains(".ply") && message.contains(".obj"),
                "{message}"
            );
        }
    }

    #[test]
    fn tokens_carry_one_based_columns() {
        let tokens: Vec<_> = Tokens::new(b"  v 1.5\t-2 \r").collect();
        assert_eq!(
            tokens,
            vec![(3, &b"v"[..]), (5, &b"1.5"[..]), (9, &b"-2"[..])]
        );
        assert_eq!(Tokens::new(b"v 1 2\r").end_column(), 6);
    }

    #[test]
    fn lines_are_counted_from_one() {
        let mut lines = Lines::new(b"a\r\nb\n\nc", 0, 0);
        assert_eq!(lines.next(), Some(&b"a\r"[..]));
        assert_eq!((lines.next(), lines.number), (Some(&b"b"[..]), 2));
        assert_eq!(lines.next(), Some(&b""[..]));
        assert_eq!((lines.next(), lines.number), (Some(&b"c"[..]), 4));
        assert_eq!(lines.next(), None);
    }

    #[test]
    fn integers_parse_like_the_standard_library() {
        let cases = [
            "0",
            "-0",
            "+7",
            "-12",
            "9223372036854775807",
            "-9223372036854775808",
            "9223372036854775808",
            "",
            "-",
            "+",
            "1.0",
            "1e3",
            "12a",
            " 1",
            "--1",
            "0x10",
            "00012",
        ];
        for case in cases {
            assert_eq!(
                parse_i64(case.as_bytes()),
                case.parse::<i64>().ok(),
                "{case:?}"
            );
        }
    }

    #[test]
    fn quoting_limits_length_and_tolerates_bad_utf8() {
        assert_eq!(quote(b"abc"), "`abc`");
        assert_eq!(quote(&[0xff]), "`\u{fffd}`");
        assert!(quote(&[b'x'; 1000]).chars().count() < 50);
    }
}
