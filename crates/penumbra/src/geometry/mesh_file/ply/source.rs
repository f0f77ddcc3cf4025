//! Value sources for PLY bodies. The element readers are generic over [`Source`] so
//! the same vertex and face logic serves ASCII and binary files, and monomorphisation
//! keeps the binary path free of dynamic dispatch.

use std::fmt;
use std::path::Path;

use super::header::{Element, Header, PropKind, Scalar};
use crate::geometry::mesh_file::error::{Location, MeshError};
use crate::geometry::mesh_file::text::{parse_i64, quote, Lines, Tokens};

/// Errors are boxed inside the body readers so that the per-value results on the hot
/// path stay two words wide and travel in registers.
pub(crate) type Fallible<T> = Result<T, Box<MeshError>>;

pub(crate) trait Source {
    /// Called before each element's records, so errors can name the element.
    fn start_element(&mut self, element: &Element);
    /// How many records to reserve room for: the declared count when the remaining
    /// input could hold it, otherwise less, so a lying header cannot force a huge allocation.
    fn capacity(&self, element: &Element) -> usize;
    fn begin_record(&mut self, index: u64) -> Fallible<()>;
    fn number(&mut self, t: Scalar, prop: &str) -> Fallible<f64>;
    fn integer(&mut self, t: Scalar, prop: &str) -> Fallible<i64>;
    fn skip(&mut self, kind: PropKind, prop: &str) -> Fallible<()>;
    fn end_record(&mut self) -> Fallible<()>;
    /// An error located at the value read last.
    fn error(&self, message: String) -> Box<MeshError>;
    fn finish(&mut self) -> Fallible<()>;
}

/// The record being read, for messages such as "face 17 of 69451".
#[derive(Default)]
struct Record {
    element: String,
    index: u64,
    count: u64,
}

impl Record {
    fn start(&mut self, element: &Element) {
        self.element.clone_from(&element.name);
        self.count = element.count;
        self.index = 0;
    }
}

impl fmt::Display for Record {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The element's name comes from the file: shown cut to a few dozen characters.
        let name = crate::input::quote::clip(&self.element, crate::input::quote::MAX_QUOTED_CHARS);
        write!(f, "{name} {} of {}", self.index, self.count)
    }
}

pub(crate) struct BinarySource<'a> {
    bytes: &'a [u8],
    pos: usize,
    value_start: usize,
    record_start: usize,
    big_endian: bool,
    path: &'a Path,
    record: Record,
}

/// Reads one `$ty` in the file's byte order.
macro_rules! read_as {
    ($source:ident, $ty:ty) => {{
        let bytes = $source.take::<{ std::mem::size_of::<$ty>() }>()?;
        if $source.big_endian {
            <$ty>::from_be_bytes(bytes)
        } else {
            <$ty>::from_le_bytes(bytes)
        }
    }};
}

impl<'a> BinarySource<'a> {
    pub(crate) fn new(
        bytes: &'a [u8],
        body_start: usize,
        big_endian: bool,
        path: &'a Path,
    ) -> Self {
        BinarySource {
            bytes,
            pos: body_start,
            value_start: body_start,
            record_start: body_start,
            big_endian,
            path,
            record: Record::default(),
        }
    }

    fn remaining(&self) -> u64 {
        self.bytes.len().saturating_sub(self.pos) as u64
    }

    /// Reports the start of the incomplete record, the first byte a user would inspect.
    #[cold]
    #[inline(never)]
    fn truncated(&self) -> Box<MeshError> {
        let place = if self.record_start >= self.bytes.len() {
            "before"
        } else {
            "inside"
        };
        let message = format!("file ends {place} {} (truncated?)", self.record);
        Box::new(MeshError::parse(
            self.path,
            Location::ByteOffset(self.record_start as u64),
            message,
        ))
    }

    #[inline(always)]
    fn take<const N: usize>(&mut self) -> Fallible<[u8; N]> {
        self.value_start = self.pos;
        let chunk = self
            .pos
            .checked_add(N)
            .and_then(|end| self.bytes.get(self.pos..end));
        match chunk.and_then(|c| <[u8; N]>::try_from(c).ok()) {
            Some(array) => {
                self.pos += N;
                Ok(array)
            }
            None => Err(self.truncated()),
        }
    }

    fn advance(&mut self, count: u64) -> Fallible<()> {
        self.value_start = self.pos;
        if count > self.remaining() {
            return Err(self.truncated());
        }
        // `count` fits in the slice, hence in usize.
        self.pos += count as usize;
        Ok(())
    }
}

impl Source for BinarySource<'_> {
    fn start_element(&mut self, element: &Element) {
        self.record.start(element);
    }

    fn capacity(&self, element: &Element) -> usize {
        let min = element.min_bytes() as u64;
        let fits = min > 0
            && element
                .count
                .checked_mul(min)
                .is_some_and(|need| need <= self.remaining());
        if fits {
            usize::try_from(element.count).unwrap_or(0)
        } else {
            0
        }
    }

    fn begin_record(&mut self, index: u64) -> Fallible<()> {
        self.record.index = index;
        self.record_start = self.pos;
        Ok(())
    }

    #[inline(always)]
    fn number(&mut self, t: Scalar, _: &str) -> Fallible<f64> {
        Ok(match t {
            Scalar::F32 => f64::from(read_as!(self, f32)),
            Scalar::F64 => read_as!(self, f64),
            integer => self.integer(integer, "")? as f64,
        })
    }

    #[inline(always)]
    fn integer(&mut self, t: Scalar, _: &str) -> Fallible<i64> {
        Ok(match t {
            Scalar::I8 => i64::from(read_as!(self, i8)),
            Scalar::U8 => i64::from(read_as!(self, u8)),
            Scalar::I16 => i64::from(read_as!(self, i16)),
            Scalar::U16 => i64::from(read_as!(self, u16)),
            Scalar::I32 => i64::from(read_as!(self, i32)),
            Scalar::U32 => i64::from(read_as!(self, u32)),
            // The header only lets integer types through here; saturate rather than fail.
            Scalar::F32 => read_as!(self, f32) as i64,
            Scalar::F64 => read_as!(self, f64) as i64,
        })
    }

    fn skip(&mut self, kind: PropKind, prop: &str) -> Fallible<()> {
        match kind {
            PropKind::Scalar(t) => self.advance(t.size() as u64),
            PropKind::List { count, item } => {
                let len = self.integer(count, prop)?;
                let Ok(len) = u64::try_from(len) else {
                    return Err(self.error(format!(
                        "{}: negative list length {len} for `{prop}`",
                        self.record
                    )));
                };
                let bytes = len.saturating_mul(item.size() as u64);
                self.advance(bytes)
            }
        }
    }

    fn end_record(&mut self) -> Fallible<()> {
        Ok(())
    }

    fn error(&self, message: String) -> Box<MeshError> {
        Box::new(MeshError::parse(
            self.path,
            Location::ByteOffset(self.value_start as u64),
            message,
        ))
    }

    /// Bytes after the last element are ignored: some writers pad files, and nothing
    /// the header declared is missing.
    fn finish(&mut self) -> Fallible<()> {
        Ok(())
    }
}

/// ASCII bodies hold one record per line; blank lines between records are tolerated.
pub(crate) struct AsciiSource<'a> {
    lines: Lines<'a>,
    tokens: Tokens<'a>,
    value_column: usize,
    total_len: usize,
    path: &'a Path,
    record: Record,
}

impl<'a> AsciiSource<'a> {
    pub(crate) fn new(bytes: &'a [u8], header: &Header, path: &'a Path) -> Self {
        AsciiSource {
            lines: Lines::new(bytes, header.body_start, header.end_line),
            tokens: Tokens::new(b""),
            value_column: 1,
            total_len: bytes.len(),
            path,
            record: Record::default(),
        }
    }

    fn error_at(&self, column: usize, message: String) -> Box<MeshError> {
        let line = self.lines.number;
        Box::new(MeshError::parse(
            self.path,
            Location::LineColumn { line, column },
            message,
        ))
    }

    fn token(&mut self, prop: &str) -> Fallible<&'a [u8]> {
        match self.tokens.next() {
            Some((column, token)) => {
                self.value_column = column;
                Ok(token)
            }
            None => {
                self.value_column = self.tokens.end_column();
                Err(self.error(format!(
                    "{}: the line ends before property `{prop}`",
                    self.record
                )))
            }
        }
    }
}

impl Source for AsciiSource<'_> {
    fn start_element(&mut self, element: &Element) {
        self.record.start(element);
    }

    fn capacity(&self, element: &Element) -> usize {
        // Each value takes at least a digit and a separator.
        let per_record = 2 * element.props.len().max(1);
        let remaining = self.total_len.saturating_sub(self.lines.offset);
        usize::try_from(element.count)
            .unwrap_or(usize::MAX)
            .min(remaining / per_record)
    }

    fn begin_record(&mut self, index: u64) -> Fallible<()> {
        self.record.index = index;
        for line in self.lines.by_ref() {
            if !line.trim_ascii().is_empty() {
                self.tokens = Tokens::new(line);
                return Ok(());
            }
        }
        let line = self.lines.number + 1;
        let message = format!("file ends before {} (truncated?)", self.record);
        Err(Box::new(MeshError::parse(
            self.path,
            Location::LineColumn { line, column: 1 },
            message,
        )))
    }

    fn number(&mut self, t: Scalar, prop: &str) -> Fallible<f64> {
        if t.is_integer() {
            return Ok(self.integer(t, prop)? as f64);
        }
        let token = self.token(prop)?;
        let value = std::str::from_utf8(token)
            .ok()
            .and_then(|s| s.parse::<f64>().ok());
        value.ok_or_else(|| {
            self.error(format!(
                "{}: expected a number for `{prop}`, found {}",
                self.record,
                quote(token)
            ))
        })
    }

    fn integer(&mut self, t: Scalar, prop: &str) -> Fallible<i64> {
        let token = self.token(prop)?;
        let Some(value) = parse_i64(token) else {
            return Err(self.error(format!(
                "{}: expected an integer for `{prop}`, found {}",
                self.record,
                quote(token)
            )));
        };
        let (min, max) = t.integer_range();
        if value < min || value > max {
            let message = format!(
                "{}: {value} does not fit `{prop}`, declared {}",
                self.record,
                t.name()
            );
            return Err(self.error(message));
        }
        Ok(value)
    }

    fn skip(&mut self, kind: PropKind, prop: &str) -> Fallible<()> {
        match kind {
            PropKind::Scalar(_) => self.token(prop).map(drop),
            PropKind::List { count, .. } => {
                let len = self.integer(count, prop)?;
                if len < 0 {
                    return Err(self.error(format!(
                        "{}: negative list length {len} for `{prop}`",
                        self.record
                    )));
                }
                // Each pass consumes a token or fails, so a huge count ends at the line's end.
                for _ in 0..len {
                    self.token(prop)?;
                }
                Ok(())
            }
        }
    }

    fn end_record(&mut self) -> Fallible<()> {
        match self.tokens.next() {
            Some((column, extra)) => Err(self.error_at(
                column,
                format!("{}: unexpected extra value {}", self.record, quote(extra)),
            )),
            None => Ok(()),
        }
    }

    fn error(&self, message: String) -> Box<MeshError> {
        self.error_at(self.value_column, message)
    }

    /// Leftover lines mean the header's counts disagree with the body, so the data is
    /// probably not what the writer meant; refuse rather than guess.
    fn finish(&mut self) -> Fallible<()> {
        while let Some(line) = self.lines.next() {
            if let Some((column, token)) = Tokens::new(line).next() {
                let message = format!("unexpected data after the last element: {}", quote(token));
                return Err(self.error_at(column, message));
            }
        }
        Ok(())
    }
}
