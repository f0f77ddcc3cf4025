//! Byte-level helpers shared by the text readers: lines with their numbers,
//! whitespace-separated tokens with their columns, integer parsing and
//! quoting of offending tokens in messages.

/// Quotes a token from a file for an error message, cut to a few dozen
/// characters (so that a corrupt file with megabytes of garbage on one line
/// cannot produce a megabyte-long error) and tolerating invalid UTF-8.
pub(crate) fn quote(token: &[u8]) -> String {
    crate::input::quote::quote_bytes(token)
}

/// Parses a decimal integer with optional sign straight from bytes: integers dominate
/// mesh text, and skipping UTF-8 validation and `str` parsing roughly halves their cost.
#[inline]
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
    #[inline]
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

    #[inline]
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
    #[inline]
    pub(crate) fn new(line: &'a [u8]) -> Self {
        Tokens { line, offset: 0 }
    }

    /// Column just past the last byte of the line, where a missing value would have gone.
    #[inline]
    pub(crate) fn end_column(&self) -> usize {
        let content = self.line.trim_ascii_end();
        content.len() + 1
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = (usize, &'a [u8]);

    #[inline]
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
