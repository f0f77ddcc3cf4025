//! The inputs the [lowering](super::lower) reads: a TOML text, parsed by
//! the toml crate, and a JSON value (a Python dict's). Each is handed to
//! the lowering as its root table's entries, in the order of the input,
//! and each entry's value is read into the tree ([`Located`] values with
//! their key paths and places) straight from the parser's value when the
//! lowering reaches it: no copy of the whole document is made on the way.
//! Values the tree cannot hold (a JSON `null`, an integer beyond 64 bits)
//! are refused there, at their key path.

use std::ops::Range;
use std::path::PathBuf;

use toml::de::{DeFloat, DeInteger, DeTable, DeValue};
use toml::Spanned;

use super::error::{Invalid, KeyPath, Location, Origin, SceneError};
use super::nesting;
use super::source::Source;
use super::tree::{Located, Prop, Value};

/// Arrays and objects of a JSON value nest at most this deep (serde_json's
/// own parser stops at 128; a value built in code may go deeper).
pub const MAX_JSON_DEPTH: usize = 128;

/// A key of the root table, where it is written, and its value as the
/// input holds it.
pub(crate) struct Entry<V> {
    pub key: String,
    pub key_at: Option<Location>,
    pub value: V,
}

/// Parses a TOML text: its root table, at its place. Syntax errors are
/// located at the parser's span; the parser's errors without one (keys of
/// too many dotted parts) at the key that has them.
pub(crate) fn parse_toml<'a>(source: &Source<'a>) -> Result<(Location, DeTable<'a>), SceneError> {
    let root = DeTable::parse(source.text()).map_err(|e| toml_error(source, &e))?;
    let at = source.location(root.span().start);
    Ok((at, root.into_inner()))
}

/// A TOML table's entries in file order (the parser's tables are sorted by
/// key), each key placed.
pub(crate) fn toml_entries<'a>(
    table: DeTable<'a>,
    source: &Source<'_>,
) -> Vec<Entry<Spanned<DeValue<'a>>>> {
    let mut entries: Vec<_> = table.into_iter().collect();
    entries.sort_by_key(|(k, _)| k.span().start);
    entries
        .into_iter()
        .map(|(key, value)| Entry {
            key_at: Some(source.location(key.span().start)),
            key: key.into_inner().into_owned(),
            value,
        })
        .collect()
}

/// A TOML value into the tree at `path`, every value inside it with its
/// own path and place.
pub(crate) fn toml_located(
    value: Spanned<DeValue<'_>>,
    path: KeyPath,
    source: &Source<'_>,
) -> Result<Located<Value>, Invalid> {
    let origin = Origin::new(path, Some(source.location(value.span().start)));
    let value = match value.into_inner() {
        DeValue::String(s) => Value::String(s.into_owned()),
        DeValue::Integer(i) => match toml_int(&i) {
            Ok(n) => Value::Int(n),
            Err(text) => return Err(big_int(&origin, &text)),
        },
        DeValue::Float(f) => match toml_float(&f) {
            Ok(x) => Value::Float(x),
            Err(text) => {
                return Err(Invalid::at(
                    &origin,
                    format!("number `{text}` is out of range of a 64-bit float"),
                ))
            }
        },
        DeValue::Boolean(b) => Value::Bool(b),
        DeValue::Datetime(d) => Value::Datetime(d.to_string()),
        DeValue::Array(items) => Value::Array(
            items
                .into_iter()
                .enumerate()
                .map(|(i, item)| toml_located(item, origin.path.index(i), source))
                .collect::<Result<_, _>>()?,
        ),
        DeValue::Table(table) => Value::Table(
            toml_entries(table, source)
                .into_iter()
                .map(|e| {
                    let path = origin.path.key(&e.key);
                    let key = Origin::new(path.clone(), e.key_at);
                    let value = toml_located(e.value, path, source)?;
                    Ok(Prop::new(e.key, key, value))
                })
                .collect::<Result<_, Invalid>>()?,
        ),
    };
    Ok(Located::new(value, origin))
}

/// A TOML table as the JSON of the dict that says the same: keys in file
/// order, a datetime as its text, numbers beyond 64 bits as their text, a
/// float that is not finite `null`.
pub(crate) fn toml_json(table: DeTable<'_>, source: &Source<'_>) -> serde_json::Value {
    use serde_json::Value as J;
    J::Object(
        toml_entries(table, source)
            .into_iter()
            .map(|e| (e.key, toml_json_value(e.value.into_inner(), source)))
            .collect(),
    )
}

fn toml_json_value(value: DeValue<'_>, source: &Source<'_>) -> serde_json::Value {
    use serde_json::Value as J;
    let number = |x: f64| serde_json::Number::from_f64(x).map_or(J::Null, J::Number);
    match value {
        DeValue::String(s) => J::String(s.into_owned()),
        DeValue::Integer(i) => toml_int(&i).map_or_else(J::String, J::from),
        DeValue::Float(f) => toml_float(&f).map_or_else(J::String, number),
        DeValue::Boolean(b) => J::Bool(b),
        DeValue::Datetime(d) => J::String(d.to_string()),
        DeValue::Array(items) => J::Array(
            items
                .into_iter()
                .map(|v| toml_json_value(v.into_inner(), source))
                .collect(),
        ),
        DeValue::Table(t) => toml_json(t, source),
    }
}

/// A TOML integer, or its text when it does not fit in 64 bits.
fn toml_int(i: &DeInteger<'_>) -> Result<i64, String> {
    i64::from_str_radix(i.as_str(), i.radix()).map_err(|_| i.to_string())
}

/// A TOML float, or its text when it is beyond the range of `f64` (`inf`
/// and `nan` are written so; any other infinity overflowed).
fn toml_float(f: &DeFloat<'_>) -> Result<f64, String> {
    match f.as_str().parse::<f64>() {
        Ok(x) if x.is_finite() || f.as_str().contains(['i', 'n']) => Ok(x),
        _ => Err(f.as_str().to_string()),
    }
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

/// A JSON object's entries in the map's order: no places.
pub(crate) fn json_entries(
    object: &serde_json::Map<String, serde_json::Value>,
) -> Vec<Entry<&serde_json::Value>> {
    object
        .iter()
        .map(|(key, value)| Entry {
            key: key.clone(),
            key_at: None,
            value,
        })
        .collect()
}

/// A JSON value into the tree at `path`, `depth` arrays and objects deep
/// (the root's is 0), every value inside it with its own path.
pub(crate) fn json_located(
    value: &serde_json::Value,
    path: KeyPath,
    depth: usize,
) -> Result<Located<Value>, Invalid> {
    use serde_json::Value as J;
    let origin = Origin::unlocated(path);
    let nested = matches!(value, J::Array(_) | J::Object(_));
    let value = match value {
        _ if nested && depth >= MAX_JSON_DEPTH => {
            return Err(Invalid::at(
                &origin,
                format!("arrays and tables nest more than {MAX_JSON_DEPTH} deep"),
            ))
        }
        J::Null => {
            return Err(Invalid::at(
                &origin,
                "invalid type: null, expected a value (leave the key out for its default)",
            ))
        }
        J::Bool(b) => Value::Bool(*b),
        J::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => Value::Int(i),
            (None, Some(x)) if !n.is_u64() => Value::Float(x),
            _ => return Err(big_int(&origin, &n.to_string())),
        },
        J::String(s) => Value::String(s.clone()),
        J::Array(items) => Value::Array(
            items
                .iter()
                .enumerate()
                .map(|(i, item)| json_located(item, origin.path.index(i), depth + 1))
                .collect::<Result<_, _>>()?,
        ),
        J::Object(object) => Value::Table(
            object
                .iter()
                .map(|(k, v)| {
                    let path = origin.path.key(k);
                    let key = Origin::unlocated(path.clone());
                    Ok(Prop::new(k.clone(), key, json_located(v, path, depth + 1)?))
                })
                .collect::<Result<_, Invalid>>()?,
        ),
    };
    Ok(Located::new(value, origin))
}

fn big_int(origin: &Origin, text: &str) -> Invalid {
    Invalid::at(
        origin,
        format!("integer `{text}` is out of range of a 64-bit integer"),
    )
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;
    use std::sync::Arc;

    use super::*;

    fn source(text: &str) -> Source<'_> {
        Source::new(text, Arc::new(PathBuf::from("t.toml")))
    }

    /// The root table's entries, each value read at its key.
    fn toml(text: &str) -> (Location, Vec<(Option<Location>, Prop)>) {
        let src = source(text);
        let (at, table) = parse_toml(&src).unwrap();
        let entries = toml_entries(table, &src)
            .into_iter()
            .map(|e| {
                let path = KeyPath::root().key(&e.key);
                let value = toml_located(e.value, path.clone(), &src).unwrap();
                let key = Origin::new(path, e.key_at.clone());
                (e.key_at, Prop::new(e.key, key, value))
            })
            .collect();
        (at, entries)
    }

    fn props(value: &Located<Value>) -> &[Prop] {
        match &value.value {
            Value::Table(t) => t,
            other => panic!("not a table: {other:?}"),
        }
    }

    fn place(at: &Option<Location>) -> (u32, u32) {
        let at = at.as_ref().unwrap();
        (at.line, at.column)
    }

    #[test]
    fn toml_keys_keep_the_file_order_and_their_places() {
        let (at, root) =
            toml("[materials.zinc]\n[materials.amber]\nior = 1.5\n[render]\nwidth = 3\n");
        assert_eq!((at.line, at.column), (1, 1));
        assert_eq!(root[0].1.name, "materials");
        assert_eq!(root[1].1.name, "render");
        let materials = props(&root[0].1.value);
        let names: Vec<_> = materials.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["zinc", "amber"]);
        // A header's table is at its header, a value at its first character.
        assert_eq!(place(&materials[1].value.origin.at), (2, 1));
        let ior = &props(&materials[1].value)[0];
        assert_eq!(
            (place(&ior.key.at), place(&ior.value.origin.at)),
            ((3, 1), (3, 7))
        );
        assert_eq!(ior.value.value, Value::Float(1.5));
        assert_eq!(ior.value.origin.path.to_string(), "materials.amber.ior");
    }

    #[test]
    fn toml_values_of_every_kind_are_read() {
        let (_, root) = toml(
            "a = true\nb = 0x1f\nc = -2.5e3\nd = 'x'\ne = 1979-05-27\nf = [1, [2]]\ng = { h = 1 }\n\
             i = inf\nj = nan\nm = 1_000\n",
        );
        let values: Vec<_> = root.iter().map(|(_, p)| &p.value.value).collect();
        assert_eq!(values[0], &Value::Bool(true));
        assert_eq!(values[1], &Value::Int(31));
        assert_eq!(values[2], &Value::Float(-2500.0));
        assert_eq!(values[3], &Value::String("x".into()));
        assert_eq!(values[4], &Value::Datetime("1979-05-27".into()));
        assert!(matches!(values[5], Value::Array(a) if a.len() == 2));
        assert!(matches!(values[6], Value::Table(t) if t[0].name == "h"));
        assert_eq!(values[7], &Value::Float(f64::INFINITY));
        assert!(matches!(values[8], Value::Float(x) if x.is_nan()));
        assert_eq!(values[9], &Value::Int(1000));
        let Value::Array(f) = values[5] else {
            unreachable!()
        };
        assert_eq!(f[1].origin.path.to_string(), "f[1]");
        assert_eq!(place(&f[1].origin.at), (6, 9));
    }

    #[test]
    fn toml_numbers_beyond_64_bits_are_refused_and_kept_as_text_in_json() {
        for (text, message) in [
            (
                "k = 99999999999999999999\n",
                "integer `99999999999999999999` is out of range of a 64-bit integer",
            ),
            (
                "l = 1e400\n",
                "number `1e400` is out of range of a 64-bit float",
            ),
        ] {
            let src = source(text);
            let (_, table) = parse_toml(&src).unwrap();
            let e = toml_entries(table, &src).pop().unwrap();
            let err = toml_located(e.value, KeyPath::root().key(&e.key), &src).unwrap_err();
            assert_eq!(err.message, message);
            assert_eq!(place(&err.origin.at), (1, 5));
        }
        let src = source("k = 99999999999999999999\nl = 1e400\nm = inf\nn = 1979-05-27\n");
        let (_, table) = parse_toml(&src).unwrap();
        assert_eq!(
            toml_json(table, &src),
            serde_json::json!({
                "k": "99999999999999999999", "l": "1e400", "m": null, "n": "1979-05-27"
            })
        );
    }

    #[test]
    fn json_values_have_no_places() {
        let v: serde_json::Value =
            serde_json::from_str(r#"{"c": -3, "d": 0.5, "e": [{"f": "g"}]}"#).unwrap();
        let serde_json::Value::Object(o) = &v else {
            unreachable!()
        };
        let entries = json_entries(o);
        assert!(entries.iter().all(|e| e.key_at.is_none()));
        let read: Vec<_> = entries
            .into_iter()
            .map(|e| json_located(e.value, KeyPath::root().key(&e.key), 1).unwrap())
            .collect();
        assert_eq!(read[0].value, Value::Int(-3));
        assert_eq!(read[1].value, Value::Float(0.5));
        let Value::Array(items) = &read[2].value else {
            unreachable!()
        };
        let f = &props(&items[0])[0];
        assert_eq!(f.value.origin.path.to_string(), "e[0].f");
        assert!(f.value.origin.at.is_none() && f.key.at.is_none());
        let refused = |v: serde_json::Value| json_located(&v, KeyPath::root(), 0).unwrap_err();
        assert!(refused(serde_json::Value::Null).message.contains("null"));
        assert!(refused(serde_json::json!(18446744073709551615u64))
            .message
            .contains("`18446744073709551615` is out of range"));
        let mut deep = serde_json::Value::from(1);
        for _ in 0..1000 {
            deep = serde_json::Value::Array(vec![deep]);
        }
        let e = refused(deep);
        assert_eq!(e.origin.path.segments().len(), MAX_JSON_DEPTH);
        assert!(e.message.contains("nest more than 128 deep"), "{e}");
    }

    #[test]
    fn syntax_errors_are_located_at_the_parser_span() {
        let text = "[render]\nwidth = = 3\n";
        let e = parse_toml(&source(text)).unwrap_err();
        assert_eq!(e.file.as_deref(), Some(std::path::Path::new("t.toml")));
        assert_eq!(e.position.map(|p| p.0), Some(2));
        assert!(!e.message.is_empty());
    }
}
