//! The document both inputs are read into before [lowering](super::lower):
//! a tree of plain values, each with its place in the file (none for a
//! dict), keys in the order of the input. Nothing here knows what a scene
//! is; values the description cannot hold (a JSON `null`, an integer beyond
//! 64 bits) are kept as such, for the lowering to report at their key path.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::error::{Location, SceneError};
use super::nesting;
use super::source::Source;

/// Arrays and objects of a JSON value nest at most this deep (serde_json's
/// own parser stops at 128; a value built in code may go deeper).
pub const MAX_JSON_DEPTH: usize = 128;

/// A value and its place in the file.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Doc {
    pub value: DocValue,
    pub at: Option<Location>,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum DocValue {
    Bool(bool),
    Int(i64),
    Float(f64),
    String(String),
    Datetime(String),
    Array(Vec<Doc>),
    Table(Vec<DocEntry>),
    /// JSON's `null`.
    Null,
    /// An integer that does not fit in 64 bits, as written.
    BigInt(String),
    /// A float beyond the range of `f64` (`1e400`), as written.
    BigFloat(String),
    /// Arrays and objects below [`MAX_JSON_DEPTH`], not read.
    TooDeep,
}

/// A key of a table, where it is written, and its value.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct DocEntry {
    pub key: String,
    pub key_at: Option<Location>,
    pub value: Doc,
}

/// Parses a TOML text. Syntax errors are located at the parser's span;
/// the parser's errors without one (keys of too many dotted parts) at the
/// key that has them.
pub(crate) fn parse_toml(text: &str, file: &Path) -> Result<Doc, SceneError> {
    let source = Source::new(text, Arc::new(file.to_path_buf()));
    let root = DeTable::parse(text).map_err(|e| toml_error(&source, &e))?;
    let span = root.span();
    Ok(Doc {
        value: toml_table(root.into_inner(), &source),
        at: Some(source.location(span.start)),
    })
}

fn toml_table(table: DeTable<'_>, source: &Source<'_>) -> DocValue {
    // The parser's tables are sorted by key: put them back in file order.
    let mut entries: Vec<_> = table.into_iter().collect();
    entries.sort_by_key(|(k, _)| k.span().start);
    DocValue::Table(
        entries
            .into_iter()
            .map(|(key, value)| DocEntry {
                key_at: Some(source.location(key.span().start)),
                key: key.into_inner().into_owned(),
                value: toml_value(value, source),
            })
            .collect(),
    )
}

fn toml_value(value: Spanned<DeValue<'_>>, source: &Source<'_>) -> Doc {
    let at = Some(source.location(value.span().start));
    let value = match value.into_inner() {
        DeValue::String(s) => DocValue::String(s.into_owned()),
        DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
            Ok(n) => DocValue::Int(n),
            Err(_) => DocValue::BigInt(i.to_string()),
        },
        DeValue::Float(f) => match f.as_str().parse::<f64>() {
            // `inf` and `nan` are written so; any other infinity overflowed.
            Ok(x) if x.is_finite() || f.as_str().contains(['i', 'n']) => DocValue::Float(x),
            _ => DocValue::BigFloat(f.as_str().to_string()),
        },
        DeValue::Boolean(b) => DocValue::Bool(b),
        DeValue::Datetime(d) => DocValue::Datetime(d.to_string()),
        DeValue::Array(a) => {
            DocValue::Array(a.into_iter().map(|v| toml_value(v, source)).collect())
        }
        DeValue::Table(t) => toml_table(t, source),
    };
    Doc { value, at }
}

/// A TOML parser error, located: at its span, or, for the errors without
/// one (keys nested too deeply), at the key that passed the depth.
fn toml_error(source: &Source<'_>, e: &toml::de::Error) -> SceneError {
    let message = e.message().trim();
    match e.span() {
        Some(span) => error_at(source, Some(span), message),
        None => match nesting::deep_key(source.text(), nesting::MAX_KEY_PARTS) {
            Some(key) => error_at(
                source,
                Some(key.offset..key.offset),
                format!(
                    "a key of {} dotted parts; keys and table headers nest at most {} deep",
                    key.parts,
                    nesting::MAX_KEY_PARTS
                ),
            ),
            None => error_at(source, None, message),
        },
    }
}

/// An error at a byte offset, or at the start of the file when the offset
/// is unknown: every error in a file names a line.
fn error_at(
    source: &Source<'_>,
    span: Option<Range<usize>>,
    message: impl Into<String>,
) -> SceneError {
    let (line, column) = source.line_col(span.map_or(0, |s| s.start));
    SceneError {
        file: Some(PathBuf::clone(source.file())),
        position: Some((line as usize, column as usize)),
        message: message.into(),
    }
}

/// Reads a JSON value (a Python dict's): no places, keys in the map's order.
pub(crate) fn from_json(value: &serde_json::Value) -> Doc {
    json_value(value, 0)
}

fn json_value(value: &serde_json::Value, depth: usize) -> Doc {
    use serde_json::Value as J;
    let nested = matches!(value, J::Array(_) | J::Object(_));
    let value = match value {
        _ if nested && depth >= MAX_JSON_DEPTH => DocValue::TooDeep,
        J::Null => DocValue::Null,
        J::Bool(b) => DocValue::Bool(*b),
        J::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => DocValue::Int(i),
            (None, Some(x)) if !n.is_u64() => DocValue::Float(x),
            _ => DocValue::BigInt(n.to_string()),
        },
        J::String(s) => DocValue::String(s.clone()),
        J::Array(a) => DocValue::Array(a.iter().map(|v| json_value(v, depth + 1)).collect()),
        J::Object(o) => DocValue::Table(
            o.iter()
                .map(|(k, v)| DocEntry {
                    key: k.clone(),
                    key_at: None,
                    value: json_value(v, depth + 1),
                })
                .collect(),
        ),
    };
    Doc { value, at: None }
}

impl Doc {
    /// The document as JSON, as a dict of the scene would be written: a
    /// datetime as its text. Values JSON cannot hold (a float that is not
    /// finite) are `null`.
    pub(crate) fn to_json(&self) -> serde_json::Value {
        use serde_json::Value as J;
        match &self.value {
            DocValue::Bool(b) => J::Bool(*b),
            DocValue::Int(i) => J::from(*i),
            DocValue::Float(f) => serde_json::Number::from_f64(*f).map_or(J::Null, J::Number),
            DocValue::String(s) | DocValue::Datetime(s) => J::String(s.clone()),
            DocValue::Array(items) => J::Array(items.iter().map(Doc::to_json).collect()),
            DocValue::Table(entries) => J::Object(
                entries
                    .iter()
                    .map(|e| (e.key.clone(), e.value.to_json()))
                    .collect(),
            ),
            DocValue::Null | DocValue::TooDeep => J::Null,
            DocValue::BigInt(s) | DocValue::BigFloat(s) => J::String(s.clone()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toml(text: &str) -> Doc {
        parse_toml(text, Path::new("t.toml")).unwrap()
    }

    fn entries(doc: &Doc) -> &[DocEntry] {
        match &doc.value {
            DocValue::Table(t) => t,
            other => panic!("not a table: {other:?}"),
        }
    }

    fn place(at: &Option<Location>) -> (u32, u32) {
        let at = at.as_ref().unwrap();
        (at.line, at.column)
    }

    #[test]
    fn toml_keys_keep_the_file_order_and_their_places() {
        let doc = toml("[materials.zinc]\n[materials.amber]\nior = 1.5\n[render]\nwidth = 3\n");
        assert_eq!(place(&doc.at), (1, 1));
        let root = entries(&doc);
        assert_eq!(root[0].key, "materials");
        assert_eq!(root[1].key, "render");
        let materials = entries(&root[0].value);
        let names: Vec<_> = materials.iter().map(|e| e.key.as_str()).collect();
        assert_eq!(names, ["zinc", "amber"]);
        // A header's table is at its header, a value at its first character.
        assert_eq!(place(&materials[1].value.at), (2, 1));
        let ior = &entries(&materials[1].value)[0];
        assert_eq!((place(&ior.key_at), place(&ior.value.at)), ((3, 1), (3, 7)));
        assert_eq!(ior.value.value, DocValue::Float(1.5));
    }

    #[test]
    fn toml_values_of_every_kind_are_read() {
        let doc = toml(
            "a = true\nb = 0x1f\nc = -2.5e3\nd = 'x'\ne = 1979-05-27\nf = [1, [2]]\ng = { h = 1 }\n\
             i = inf\nj = nan\nk = 99999999999999999999\nl = 1e400\nm = 1_000\n",
        );
        let values: Vec<_> = entries(&doc).iter().map(|e| &e.value.value).collect();
        assert_eq!(values[0], &DocValue::Bool(true));
        assert_eq!(values[1], &DocValue::Int(31));
        assert_eq!(values[2], &DocValue::Float(-2500.0));
        assert_eq!(values[3], &DocValue::String("x".into()));
        assert_eq!(values[4], &DocValue::Datetime("1979-05-27".into()));
        assert!(matches!(values[5], DocValue::Array(a) if a.len() == 2));
        assert!(matches!(values[6], DocValue::Table(t) if t[0].key == "h"));
        assert_eq!(values[7], &DocValue::Float(f64::INFINITY));
        assert!(matches!(values[8], DocValue::Float(x) if x.is_nan()));
        assert_eq!(values[9], &DocValue::BigInt("99999999999999999999".into()));
        assert_eq!(values[10], &DocValue::BigFloat("1e400".into()));
        assert_eq!(values[11], &DocValue::Int(1000));
    }

    #[test]
    fn json_values_have_no_places() {
        let v: serde_json::Value = serde_json::from_str(
            r#"{"a": null, "b": 18446744073709551615, "c": -3, "d": 0.5, "e": [{"f": "g"}]}"#,
        )
        .unwrap();
        let doc = from_json(&v);
        assert_eq!(doc.at, None);
        let e = entries(&doc);
        assert_eq!(e[0].value.value, DocValue::Null);
        assert_eq!(
            e[1].value.value,
            DocValue::BigInt("18446744073709551615".into())
        );
        assert_eq!(e[2].value.value, DocValue::Int(-3));
        assert_eq!(e[3].value.value, DocValue::Float(0.5));
        assert!(e.iter().all(|e| e.key_at.is_none()));
        let mut deep = serde_json::Value::from(1);
        for _ in 0..1000 {
            deep = serde_json::Value::Array(vec![deep]);
        }
        let mut doc = from_json(&deep);
        let mut depth = 0;
        while let DocValue::Array(mut a) = doc.value {
            doc = a.remove(0);
            depth += 1;
        }
        assert_eq!((depth, doc.value), (MAX_JSON_DEPTH, DocValue::TooDeep));
    }

    #[test]
    fn syntax_errors_are_located_at_the_parser_span() {
        let e = parse_toml("[render]\nwidth = = 3\n", Path::new("t.toml")).unwrap_err();
        assert_eq!(e.file.as_deref(), Some(Path::new("t.toml")));
        assert_eq!(e.position.map(|p| p.0), Some(2));
        assert!(!e.message.is_empty());
    }
}
