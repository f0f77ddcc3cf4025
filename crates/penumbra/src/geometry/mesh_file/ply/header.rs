//! The PLY header: a text preamble declaring how the body is laid out.

use std::path::Path;

use crate::geometry::mesh_file::error::{Location, MeshError};
use crate::geometry::mesh_file::text::{quote, Lines, Tokens};

/// A PLY scalar type. Both the classic names (`uchar`) and the sized ones (`uint8`)
/// occur in the wild, often from the same tool in different versions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &[u8]) -> Option<Self> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    pub(crate) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(crate) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// Values an ASCII body may hold for this type; text can spell any number, so the
    /// declared type has to be enforced by hand.
    pub(crate) fn integer_range(self) -> (i64, i64) {
        match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => (i64::MIN, i64::MAX),
        }
    }

    pub(crate) fn name(self) -> &'static str {
        match self {
            Scalar::I8 => "char",
            Scalar::U8 => "uchar",
            Scalar::I16 => "short",
            Scalar::U16 => "ushort",
            Scalar::I32 => "int",
            Scalar::U32 => "uint",
            Scalar::F32 => "float",
            Scalar::F64 => "double",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PropKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

impl PropKind {
    /// Fewest bytes a binary value can occupy (an empty list still stores its count);
    /// used to reject element counts that the remaining file could never hold.
    pub(crate) fn min_bytes(self) -> usize {
        match self {
            PropKind::Scalar(t) => t.size(),
            PropKind::List { count, .. } => count.size(),
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Property {
    pub(crate) name: String,
    pub(crate) kind: PropKind,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Element {
    pub(crate) name: String,
    pub(crate) count: u64,
    pub(crate) props: Vec<Property>,
    /// Header line declaring the element, for errors about what it lacks.
    pub(crate) line: usize,
}

impl Element {
    pub(crate) fn min_bytes(&self) -> usize {
        self.props.iter().map(|p| p.kind.min_bytes()).sum()
    }

    pub(crate) fn location(&self) -> Location {
        Location::LineColumn {
            line: self.line,
            column: 1,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Format {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Header {
    pub(crate) format: Format,
    pub(crate) elements: Vec<Element>,
    /// Offset of the first body byte, just past the `end_header` line.
    pub(crate) body_start: usize,
    /// Number of the `end_header` line; ASCII bodies continue counting from here.
    pub(crate) end_line: usize,
}

/// Reads the header, validating everything that does not depend on the body.
pub(crate) fn parse_header(bytes: &[u8], path: &Path) -> Result<Header, MeshError> {
    let mut lines = Lines::new(bytes, 0, 0);
    let magic = lines.next().map(<[u8]>::trim_ascii);
    if magic != Some(b"ply") {
        let at = Location::LineColumn { line: 1, column: 1 };
        return Err(MeshError::parse(
            path,
            at,
            "not a PLY file: the first line must be `ply`",
        ));
    }
    let mut parser = HeaderParser {
        path,
        format: None,
        elements: Vec::new(),
    };
    while let Some(line) = lines.next() {
        if parser.line(line, lines.number)? {
            return parser.finish(lines.offset, lines.number);
        }
    }
    let at = Location::LineColumn {
        line: lines.number + 1,
        column: 1,
    };
    Err(MeshError::parse(
        path,
        at,
        "the header has no `end_header` line",
    ))
}

struct HeaderParser<'p> {
    path: &'p Path,
    format: Option<Format>,
    elements: Vec<Element>,
}

impl HeaderParser<'_> {
    fn error(&self, line: usize, column: usize, message: String) -> MeshError {
        MeshError::parse(self.path, Location::LineColumn { line, column }, message)
    }

    /// Handles one header line; returns true at `end_header`.
    fn line(&mut self, text: &[u8], line: usize) -> Result<bool, MeshError> {
        let mut tokens = Tokens::new(text);
        let Some((column, keyword)) = tokens.next() else {
            return Ok(false);
        };
        // No valid line has more than 5 arguments; a sixth is enough to report extras,
        // and stopping there keeps a garbage line from costing memory.
        let args: Vec<(usize, &[u8])> = tokens.take(6).collect();
        match keyword {
            b"comment" | b"obj_info" => {}
            b"format" => self.format(&args, line, column)?,
            b"element" => self.element(&args, line, column)?,
            b"property" => self.property(&args, line, column)?,
            b"end_header" => {
                self.no_more(&args, line)?;
                return Ok(true);
            }
            other => {
                let message = format!("unknown header keyword {}", quote(other));
                return Err(self.error(line, column, message));
            }
        }
        Ok(false)
    }

    fn no_more(&self, args: &[(usize, &[u8])], line: usize) -> Result<(), MeshError> {
        match args.first() {
            Some(&(column, extra)) => {
                let message = format!("unexpected {} at the end of the line", quote(extra));
                Err(self.error(line, column, message))
            }
            None => Ok(()),
        }
    }

    /// Fetches argument `index`, or reports what was expected at the end of the line.
    fn arg<'t>(
        &self,
        args: &[(usize, &'t [u8])],
        index: usize,
        line: usize,
        usage: &str,
    ) -> Result<(usize, &'t [u8]), MeshError> {
        args.get(index).copied().ok_or_else(|| {
            let column = args.last().map_or(1, |&(c, t)| c + t.len());
            self.error(line, column, format!("incomplete line; expected `{usage}`"))
        })
    }

    fn format(
        &mut self,
        args: &[(usize, &[u8])],
        line: usize,
        column: usize,
    ) -> Result<(), MeshError> {
        const USAGE: &str = "format ascii|binary_little_endian|binary_big_endian 1.0";
        if self.format.is_some() {
            return Err(self.error(line, column, "second `format` line".into()));
        }
        let (name_column, name) = self.arg(args, 0, line, USAGE)?;
        let format = match name {
            b"ascii" => Format::Ascii,
            b"binary_little_endian" => Format::BinaryLittleEndian,
            b"binary_big_endian" => Format::BinaryBigEndian,
            other => {
                let message = format!("unknown format {}; expected `{USAGE}`", quote(other));
                return Err(self.error(line, name_column, message));
            }
        };
        let (version_column, version) = self.arg(args, 1, line, USAGE)?;
        if version != b"1.0" {
            let message = format!(
                "unsupported PLY version {}; only 1.0 exists",
                quote(version)
            );
            return Err(self.error(line, version_column, message));
        }
        self.no_more(args.get(2..).unwrap_or_default(), line)?;
        self.format = Some(format);
        Ok(())
    }

    fn element(&mut self, args: &[(usize, &[u8])], line: usize, _: usize) -> Result<(), MeshError> {
        const USAGE: &str = "element NAME COUNT";
        let (_, name) = self.arg(args, 0, line, USAGE)?;
        let (count_column, count_text) = self.arg(args, 1, line, USAGE)?;
        let count = std::str::from_utf8(count_text)
            .ok()
            .filter(|t| t.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|t| t.parse::<u64>().ok())
            .ok_or_else(|| {
                let message = format!("invalid element count {}", quote(count_text));
                self.error(line, count_column, message)
            })?;
        self.no_more(args.get(2..).unwrap_or_default(), line)?;
        self.elements.push(Element {
            name: String::from_utf8_lossy(name).into_owned(),
            count,
            props: Vec::new(),
            line,
        });
        Ok(())
    }

    fn scalar(&self, arg: (usize, &[u8]), line: usize) -> Result<Scalar, MeshError> {
        let (column, name) = arg;
        Scalar::from_name(name).ok_or_else(|| {
            let message = format!("unknown property type {}", quote(name));
            self.error(line, column, message)
        })
    }

    fn property(
        &mut self,
        args: &[(usize, &[u8])],
        line: usize,
        column: usize,
    ) -> Result<(), MeshError> {
        const USAGE: &str = "property TYPE NAME` or `property list COUNTTYPE ITEMTYPE NAME";
        let first = self.arg(args, 0, line, USAGE)?;
        let (kind, name_index) = if first.1 == b"list" {
            let count_arg = self.arg(args, 1, line, USAGE)?;
            let count = self.scalar(count_arg, line)?;
            if !count.is_integer() {
                let message = format!(
                    "list count type must be an integer type, not {}",
                    count.name()
                );
                return Err(self.error(line, count_arg.0, message));
            }
            let item = self.scalar(self.arg(args, 2, line, USAGE)?, line)?;
            (PropKind::List { count, item }, 3)
        } else {
            (PropKind::Scalar(self.scalar(first, line)?), 1)
        };
        let (_, name) = self.arg(args, name_index, line, USAGE)?;
        self.no_more(args.get(name_index + 1..).unwrap_or_default(), line)?;
        let Some(element) = self.elements.last_mut() else {
            return Err(self.error(line, column, "`property` before any `element`".into()));
        };
        let name = String::from_utf8_lossy(name).into_owned();
        element.props.push(Property { name, kind });
        Ok(())
    }

    fn finish(self, body_start: usize, end_line: usize) -> Result<Header, MeshError> {
        let Some(format) = self.format else {
            let message = "the header has no `format` line".to_string();
            return Err(self.error(end_line, 1, message));
        };
        Ok(Header {
            format,
            elements: self.elements,
            body_start,
            end_line,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(text: &str) -> Result<Header, MeshError> {
        parse_header(text.as_bytes(), Path::new("h.ply"))
    }

    /// Asserts a header error at `line:column` whose message contains `needle`.
    fn assert_error(text: &str, line: usize, column: usize, needle: &str) {
        match header(text) {
            Err(MeshError::Parse {
                location, message, ..
            }) => {
                assert_eq!(location, Location::LineColumn { line, column }, "{message}");
                assert!(message.contains(needle), "{message:?} lacks {needle:?}");
            }
            other => panic!("expected a parse error for {text:?}, got {other:?}"),
        }
    }

    #[test]
    fn parses_elements_properties_and_both_type_spellings() {
        let text = "ply\r\nformat binary_big_endian 1.0\r\ncomment hi there\r\nobj_info x\r\n\
                    element vertex 3\r\nproperty int16 x\r\nproperty uchar y\r\n\
                    element face 7\r\nproperty list uint8 uint vertex_index\r\nend_header\r\nBODY";
        let h = header(text).unwrap();
        assert_eq!(h.format, Format::BinaryBigEndian);
        assert_eq!(&text.as_bytes()[h.body_start..], b"BODY");
        assert_eq!(h.end_line, 10);
        let [vertex, face] = &h.elements[..] else {
            panic!("{h:?}")
        };
        assert_eq!(
            (vertex.name.as_str(), vertex.count, vertex.line),
            ("vertex", 3, 5)
        );
        assert_eq!(vertex.props[0].kind, PropKind::Scalar(Scalar::I16));
        assert_eq!(vertex.props[1].kind, PropKind::Scalar(Scalar::U8));
        let list = PropKind::List {
            count: Scalar::U8,
            item: Scalar::U32,
        };
        assert_eq!(
            (face.count, face.props[0].kind, face.min_bytes()),
            (7, list, 1)
        );
    }

    #[test]
    fn every_type_name_is_known() {
        let names = [
            "char", "int8", "uchar", "uint8", "short", "int16", "ushort", "uint16", "int", "int32",
            "uint", "uint32", "float", "float32", "double", "float64",
        ];
        for name in names {
            assert!(Scalar::from_name(name.as_bytes()).is_some(), "{name}");
        }
        assert_eq!(Scalar::from_name(b"int64"), None);
    }

    #[test]
    fn header_errors_point_at_the_offending_token() {
        assert_error(
            "plx\nformat ascii 1.0\nend_header\n",
            1,
            1,
            "not a PLY file",
        );
        assert_error("", 1, 1, "not a PLY file");
        assert_error(
            "ply\nformat binary_middle_endian 1.0\n",
            2,
            8,
            "unknown format",
        );
        assert_error("ply\nformat ascii 2.0\nend_header\n", 2, 14, "version");
        assert_error("ply\nformat ascii\nend_header\n", 2, 13, "incomplete");
        let bad_type = "ply\nformat ascii 1.0\nelement vertex 1\nproperty flaot x\nend_header\n";
        assert_error(bad_type, 4, 10, "unknown property type `flaot`");
        let float_count =
            "ply\nformat ascii 1.0\nelement f 1\nproperty list float int v\nend_header\n";
        assert_error(float_count, 4, 15, "integer");
        assert_error(
            "ply\nformat ascii 1.0\nelement vertex -3\n",
            3,
            16,
            "invalid element count",
        );
        assert_error(
            "ply\nformat ascii 1.0\nproperty float x\n",
            3,
            1,
            "before any",
        );
        assert_error(
            "ply\nformat ascii 1.0\nvertices 3\n",
            3,
            1,
            "unknown header keyword",
        );
        assert_error("ply\nelement vertex 0\nend_header\n", 3, 1, "no `format`");
        assert_error(
            "ply\nformat ascii 1.0 x\nend_header\n",
            2,
            18,
            "unexpected `x`",
        );
        assert_error(
            "ply\nformat ascii 1.0\nend_header junk\n",
            3,
            12,
            "unexpected `junk`",
        );
        assert_error(
            "ply\nformat ascii 1.0\nelement vertex 1\n",
            4,
            1,
            "end_header",
        );
    }
}
