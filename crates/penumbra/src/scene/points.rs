//! Points files of the `custom` distribution: JSON or NumPy `.npy`, read
//! as hostile input (see [`crate::input`]) into a
//! [`PointTable`].
//!
//! * **JSON**: one set, `[[x, y], [x, y], ...]`, or several, `[[[x, y],
//!   ...], [[x, y], ...], ...]`, whose sizes may differ.
//! * **`.npy`** (recognised by its magic bytes, whatever the file's name):
//!   a C-ordered array of little- or big-endian `float32` or `float64` of
//!   shape `(N, 2)` (one set) or `(S, N, 2)` (`S` sets of `N`).
//!
//! Every coordinate must be a number in `[0, 1)`; there must be at least one
//! set, no empty set, and at most
//! [`MAX_POINTS`] points. Errors name
//! the file and, for a JSON syntax error, its line and column; for a bad
//! point, its set and index.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::input::{self, quote};
use crate::sampling::custom::{PointsError, MAX_POINTS};
use crate::sampling::PointTable;

/// Largest points file read: 4 M points as `float64` `.npy` and its
/// header, or as JSON of about 8 characters a coordinate.
pub const MAX_POINTS_FILE_SIZE: u64 = 80 << 20;

/// Where the `custom` distribution's points come from, given outside the
/// scene file.
#[derive(Clone, Debug, PartialEq)]
pub enum Points {
    /// A points file (a relative path is taken from the working directory).
    File(PathBuf),
    /// A table made in code (Python's arrays and functions).
    Table(Arc<PointTable>),
}

/// A points file that cannot be read or is not a valid table.
#[derive(Clone, Debug, PartialEq)]
pub struct PointsFileError {
    pub file: PathBuf,
    /// Line and column (from 1), for a JSON syntax error.
    pub position: Option<(usize, usize)>,
    pub message: String,
}

impl fmt::Display for PointsFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some((line, column)) = self.position {
            write!(f, ":{line}:{column}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for PointsFileError {}

/// Reads a points file (JSON or `.npy`); see the [module docs](self).
pub fn read_points(path: &Path) -> Result<PointTable, PointsFileError> {
    let fail = |position, message: String| PointsFileError {
        file: path.to_path_buf(),
        position,
        message,
    };
    // The input error names the file already.
    let unread = |e: input::InputError| {
        let text = e.to_string();
        let named = format!("{}: ", path.display());
        fail(None, text.strip_prefix(&named).unwrap_or(&text).to_string())
    };
    let limit = input::size_limit(MAX_POINTS_FILE_SIZE).map_err(unread)?;
    let bytes = input::read_file_within(path, limit).map_err(unread)?;
    let sets = if bytes.starts_with(NPY_MAGIC) {
        npy(&bytes).map_err(|m| fail(None, m))?
    } else {
        json(&bytes).map_err(|(p, m)| fail(p, m))?
    };
    PointTable::new(sets).map_err(|e| fail(None, e.to_string()))
}

type Sets = Vec<Vec<[f64; 2]>>;

/// The sets of a JSON document; errors with a position for syntax errors.
fn json(bytes: &[u8]) -> Result<Sets, (Option<(usize, usize)>, String)> {
    let value: serde_json::Value = serde_json::from_slice(bytes).map_err(|e| {
        let message = quote::bounded(&e.to_string()).into_owned();
        let message = message.split(" at line ").next().unwrap_or("").to_string();
        (Some((e.line(), e.column())), message)
    })?;
    let at = |e: PointsError| (None, e.to_string());
    let serde_json::Value::Array(items) = value else {
        return Err((
            None,
            "expected an array of points or of sets of points".into(),
        ));
    };
    // One set if its first item is a point (an array of numbers).
    let one_set = match items.first() {
        Some(serde_json::Value::Array(first)) => first.first().is_none_or(|v| v.is_number()),
        _ => false,
    };
    if one_set {
        return Ok(vec![set(0, &items).map_err(at)?]);
    }
    let mut sets = Vec::with_capacity(items.len());
    for (s, item) in items.iter().enumerate() {
        let serde_json::Value::Array(points) = item else {
            let e = PointsError::new(format!("set {s}: expected an array of [x, y] points"));
            return Err(at(e));
        };
        sets.push(set(s, points).map_err(at)?);
    }
    Ok(sets)
}

/// The points of set `s`, each an array of two numbers.
fn set(s: usize, items: &[serde_json::Value]) -> Result<Vec<[f64; 2]>, PointsError> {
    let mut points = Vec::with_capacity(items.len().min(MAX_POINTS));
    for (i, item) in items.iter().enumerate() {
        let xy = match item {
            serde_json::Value::Array(xy) if xy.len() == 2 => xy[0].as_f64().zip(xy[1].as_f64()),
            _ => None,
        };
        let Some((x, y)) = xy else {
            let text = item.to_string();
            let got = quote::clip(&text, 40);
            return Err(PointsError::new(format!(
                "set {s}, point {i}: expected [x, y] with two numbers, found {got}"
            )));
        };
        points.push([x, y]);
    }
    Ok(points)
}

const NPY_MAGIC: &[u8] = b"\x93NUMPY";

/// The sets of a `.npy` file.
fn npy(bytes: &[u8]) -> Result<Sets, String> {
    let version = bytes.get(6).copied().ok_or("truncated .npy header")?;
    let (len_bytes, start): (usize, usize) = match version {
        1 => (2, 10),
        2 | 3 => (4, 12),
        v => return Err(format!(".npy format version {v} is not known (1 to 3 are)")),
    };
    let len_field = bytes.get(8..8 + len_bytes).ok_or("truncated .npy header")?;
    let header_len = len_field
        .iter()
        .rev()
        .fold(0usize, |n, &b| (n << 8) | usize::from(b));
    let header = bytes
        .get(start..start.saturating_add(header_len))
        .ok_or("the .npy header is longer than the file")?;
    let header = std::str::from_utf8(header).map_err(|_| "the .npy header is not text")?;
    let data = &bytes[start + header_len..];
    let descr = header_value(header, "descr")?;
    let (big, size) = match descr.trim_matches(['\'', '"']) {
        "<f8" => (false, 8),
        "<f4" => (false, 4),
        ">f8" => (true, 8),
        ">f4" => (true, 4),
        d => {
            let d = quote::clip(d, 20);
            return Err(format!(
                "the array holds {d}, not float32 or float64 numbers"
            ));
        }
    };
    if header_value(header, "fortran_order")? != "False" {
        return Err(
            "the array is in Fortran order: save it in C order (numpy.ascontiguousarray)".into(),
        );
    }
    let shape = shape(header_value(header, "shape")?)?;
    let (sets, per_set) = match shape[..] {
        [n, 2] => (1, n),
        [s, n, 2] => (s, n),
        _ => {
            return Err(format!(
            "the array's shape is {shape:?}: it must be (N, 2) for one set or (S, N, 2) for S sets"
        ))
        }
    };
    let points = sets
        .checked_mul(per_set)
        .filter(|&p| p <= MAX_POINTS)
        .ok_or_else(|| {
            format!(
                "the array has more than {MAX_POINTS} points; a table of that size is never needed"
            )
        })?;
    if points == 0 {
        return Err("the array holds no points".into());
    }
    if data.len() != points * 2 * size {
        return Err(format!(
            "the header promises {points} points ({} bytes of data) but the file has {} bytes after it",
            points * 2 * size,
            data.len()
        ));
    }
    let number = |k: usize| -> f64 {
        let b = &data[k * size..][..size];
        match (size, big) {
            (8, false) => f64::from_le_bytes(b.try_into().expect("8 bytes")),
            (8, true) => f64::from_be_bytes(b.try_into().expect("8 bytes")),
            (_, false) => f64::from(f32::from_le_bytes(b.try_into().expect("4 bytes"))),
            (_, true) => f64::from(f32::from_be_bytes(b.try_into().expect("4 bytes"))),
        }
    };
    Ok((0..sets)
        .map(|s| {
            let first = s * per_set;
            (first..first + per_set)
                .map(|p| [number(2 * p), number(2 * p + 1)])
                .collect()
        })
        .collect())
}

/// The text of `key`'s value in the header's dictionary, up to the next
/// top-level comma or the closing brace.
fn header_value<'a>(header: &'a str, key: &str) -> Result<&'a str, String> {
    let missing = || format!("the .npy header has no '{key}'");
    let quoted = format!("'{key}'");
    let after = header.find(&quoted).ok_or_else(missing)? + quoted.len();
    let rest = header[after..].trim_start();
    let rest = rest.strip_prefix(':').ok_or_else(missing)?.trim_start();
    let mut depth = 0usize;
    for (i, c) in rest.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth = depth.saturating_sub(1),
            ',' | '}' if depth == 0 => return Ok(rest[..i].trim()),
            _ => {}
        }
    }
    Err(missing())
}

/// The dimensions of a shape tuple such as `(16, 2)` or `(4, 16, 2,)`.
fn shape(text: &str) -> Result<Vec<usize>, String> {
    let bad = || {
        format!(
            "the .npy shape {} is not a tuple of sizes",
            quote::clip(text, 40)
        )
    };
    let inner = text
        .strip_prefix('(')
        .and_then(|t| t.strip_suffix(')'))
        .ok_or_else(bad)?;
    inner
        .split(',')
        .map(str::trim)
        .filter(|d| !d.is_empty())
        .take(4)
        .map(|d| d.parse::<usize>().map_err(|_| bad()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }

    fn npy_file(descr: &str, shape: &str, data: &[u8]) -> Vec<u8> {
        let mut header =
            format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut bytes = NPY_MAGIC.to_vec();
        bytes.extend([1, 0]);
        bytes.extend((header.len() as u16).to_le_bytes());
        bytes.extend(header.as_bytes());
        bytes.extend(data);
        bytes
    }

    fn f64s(values: &[f64]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    #[test]
    fn json_one_set_and_several() {
        let dir = tempfile::tempdir().unwrap();
        let one = write(dir.path(), "one.json", b"[[0.25, 0.25], [0.75, 0.75]]");
        let t = read_points(&one).unwrap();
        assert_eq!(t.sizes().collect::<Vec<_>>(), [(2, 1)]);
        let many = write(
            dir.path(),
            "m.json",
            b"[[[0.1, 0.2]], [[0.3, 0.4], [0.5, 0.6]], [[0, 0]]]",
        );
        let t = read_points(&many).unwrap();
        assert_eq!(t.sizes().collect::<Vec<_>>(), [(1, 2), (2, 1)]);
    }

    #[test]
    fn npy_of_both_widths_and_shapes() {
        let dir = tempfile::tempdir().unwrap();
        let data = f64s(&[0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8]);
        let p = write(dir.path(), "a.npy", &npy_file("<f8", "(2, 2, 2)", &data));
        assert_eq!(
            read_points(&p).unwrap().sizes().collect::<Vec<_>>(),
            [(2, 2)]
        );
        let f32s: Vec<u8> = [0.5f32, 0.5, 0.25, 0.75]
            .iter()
            .flat_map(|v| v.to_be_bytes())
            .collect();
        // Any name: the magic bytes decide.
        let p = write(dir.path(), "points.bin", &npy_file(">f4", "(2, 2)", &f32s));
        assert_eq!(
            read_points(&p).unwrap().sizes().collect::<Vec<_>>(),
            [(2, 1)]
        );
    }

    fn error(name: &str, bytes: &[u8]) -> String {
        let dir = tempfile::tempdir().unwrap();
        let p = write(dir.path(), name, bytes);
        let e = read_points(&p).unwrap_err();
        assert_eq!(e.file, p);
        let text = e.to_string();
        assert!(text.starts_with(&p.display().to_string()), "{text}");
        text
    }

    #[test]
    fn bad_json_is_located() {
        let e = error("s.json", b"[[0.1, 0.2],\n [0.3 0.4]]");
        assert!(e.contains("s.json:2:7: "), "{e}");
        assert!(error("e.json", b"").contains(":1:0: "));
        assert!(error("o.json", b"{\"a\": 1}").contains("expected an array"));
        assert!(error("z.json", b"[]").contains("no point sets"));
        assert!(error("w.json", b"[[0.1, 0.2, 0.3]]").contains("set 0, point 0: expected [x, y]"));
        assert!(error("r.json", b"[[0.1, 1.5]]").contains("set 0, point 0: (0.1, 1.5) is not in"));
        assert!(error("n.json", b"[[[0.1, 0.2]], 7]").contains("set 1: expected an array"));
        assert!(error("v.json", b"[[[0.1, 0.2]], []]").contains("set 1: a set needs"));
        let deep = format!("{}{}", "[".repeat(10_000), "]".repeat(10_000));
        assert!(error("d.json", deep.as_bytes()).contains("recursion limit"));
    }

    #[test]
    fn bad_npy_is_refused() {
        let nan = npy_file("<f8", "(1, 2)", &f64s(&[f64::NAN, 0.5]));
        assert!(error("nan.npy", &nan).contains("is not in the unit square"));
        let short = npy_file("<f8", "(4, 2)", &f64s(&[0.5, 0.5]));
        assert!(error("short.npy", &short).contains("promises 4 points"));
        let huge = npy_file("<f8", "(4000000000, 4000000000, 2)", &[]);
        assert!(error("huge.npy", &huge).contains("more than"));
        let ints = npy_file("<i8", "(1, 2)", &[0; 16]);
        assert!(error("int.npy", &ints).contains("not float32 or float64"));
        let wide = npy_file("<f8", "(1, 3)", &f64s(&[0.5; 3]));
        assert!(error("wide.npy", &wide).contains("(N, 2)"));
        let empty = npy_file("<f8", "(0, 2)", &[]);
        assert!(error("empty.npy", &empty).contains("no points"));
        let mut lying = npy_file("<f8", "(1, 2)", &f64s(&[0.5, 0.5]));
        lying[8] = 0xff;
        lying[9] = 0xff;
        assert!(error("lie.npy", &lying).contains("longer than the file"));
        assert!(error("cut.npy", &NPY_MAGIC[..6]).contains("truncated"));
    }

    #[test]
    fn directories_and_missing_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        assert!(read_points(dir.path()).is_err());
        assert!(read_points(&dir.path().join("none.json")).is_err());
    }
}
