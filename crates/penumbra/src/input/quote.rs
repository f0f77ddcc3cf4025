//! Input quoted in messages, bounded: a value from a file is cut to a few
//! dozen characters, and a whole message to a few lines, so that a
//! one-megabyte string in a scene never comes back whole on stderr.

use std::borrow::Cow;

/// At most this many characters of a quoted value are shown.
pub const MAX_QUOTED_CHARS: usize = 40;

/// At most this many characters of a message are shown (the longest
/// message the renderer makes itself, a list of the keys a table takes, is
/// about 600).
pub const MAX_MESSAGE_CHARS: usize = 1000;

/// At most this many lines of a message are shown.
pub const MAX_LINES: usize = 4;

/// The first `max` characters of `s`, with `…` if anything was cut.
pub fn clip(s: &str, max: usize) -> Cow<'_, str> {
    match s.char_indices().nth(max) {
        None => Cow::Borrowed(s),
        Some((end, _)) => Cow::Owned(format!("{}…", &s[..end])),
    }
}

/// A value from an input in backticks, cut to [`MAX_QUOTED_CHARS`]: `` `abc` ``.
pub fn quote(s: &str) -> String {
    format!("`{}`", clip(s, MAX_QUOTED_CHARS))
}

/// [`quote`] for bytes that need not be UTF-8.
pub fn quote_bytes(b: &[u8]) -> String {
    let shown = b.get(..MAX_QUOTED_CHARS * 4).unwrap_or(b);
    let text = String::from_utf8_lossy(shown);
    let mut q = quote(&text);
    if shown.len() < b.len() && !q.ends_with("…`") {
        q.insert(q.len() - 1, '…');
    }
    q
}

/// A message made safe to print, whatever input it quotes: every run quoted
/// in backticks or double quotes is cut to [`MAX_QUOTED_CHARS`], and the
/// message to [`MAX_LINES`] lines and [`MAX_MESSAGE_CHARS`] characters. Cuts
/// are marked with `…`; a message within the bounds is returned unchanged.
pub fn bounded(message: &str) -> Cow<'_, str> {
    let within = message.len() <= MAX_QUOTED_CHARS && !message.contains('\n');
    if within {
        return Cow::Borrowed(message);
    }
    let quoted = cut_quotes(message);
    let mut lines = String::with_capacity(quoted.len().min(MAX_MESSAGE_CHARS * 4));
    for (i, line) in quoted.split('\n').enumerate() {
        if i == MAX_LINES {
            lines.push_str("\n…");
            break;
        }
        if i > 0 {
            lines.push('\n');
        }
        lines.push_str(line);
    }
    let out = clip(&lines, MAX_MESSAGE_CHARS);
    if out == message {
        Cow::Borrowed(message)
    } else {
        Cow::Owned(out.into_owned())
    }
}

/// Cuts every quoted run longer than [`MAX_QUOTED_CHARS`]. A double-quoted
/// run may hold `\"` (Rust's and TOML's escapes); a backtick run ends at the
/// next backtick. An unclosed quote runs to the end of the message.
fn cut_quotes(message: &str) -> String {
    let mut out = String::new();
    let mut quote: Option<char> = None;
    let mut shown = 0usize;
    let mut escaped = false;
    for c in message.chars() {
        match quote {
            None => {
                out.push(c);
                if c == '`' || c == '"' {
                    quote = Some(c);
                    shown = 0;
                    escaped = false;
                }
            }
            Some(q) => {
                let closes = c == q && !escaped;
                escaped = q == '"' && c == '\\' && !escaped;
                if closes {
                    if shown > MAX_QUOTED_CHARS {
                        out.push('…');
                    }
                    out.push(c);
                    quote = None;
                } else {
                    shown += 1;
                    if shown <= MAX_QUOTED_CHARS {
                        out.push(c);
                    }
                }
            }
        }
    }
    if quote.is_some() && shown > MAX_QUOTED_CHARS {
        out.push('…');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_counts_characters_not_bytes() {
        assert_eq!(clip("abc", 3), "abc");
        assert_eq!(clip("abcd", 3), "abc…");
        assert_eq!(clip("ééééé", 2), "éé…");
    }

    #[test]
    fn quoting_bounds_values_and_bytes() {
        assert_eq!(quote("abc"), "`abc`");
        assert!(quote(&"x".repeat(1000)).chars().count() < 50);
        assert_eq!(quote_bytes(&[0xff]), "`\u{fffd}`");
        let q = quote_bytes(&[b'y'; 100_000]);
        assert!(q.chars().count() < 50 && q.ends_with("…`"), "{q}");
    }

    #[test]
    fn short_messages_are_unchanged() {
        let m = "render.width: must be an integer from 1 to 32768, got 0";
        assert_eq!(bounded(m), m);
        let m = "unknown field `x`, expected one of `render`, `camera`";
        assert_eq!(bounded(m), m);
    }

    #[test]
    fn long_quoted_values_are_cut_with_an_ellipsis() {
        let long = "a".repeat(1_000_000);
        for m in [
            format!("invalid type: string \"{long}\", expected i64"),
            format!("unknown object type `{long}`; valid choices are: sphere"),
            format!("unclosed `{long}"),
        ] {
            let b = bounded(&m);
            assert!(b.len() < 200, "{}", b.len());
            assert!(b.contains("aaa…"), "{b}");
        }
        let m = format!("invalid type: string \"{long}\", expected i64");
        let b = bounded(&m);
        assert!(b.ends_with("…\", expected i64"), "{b}");
    }

    #[test]
    fn escaped_quotes_stay_inside_the_run() {
        let m = format!("string \"{}\\\"{}\" here", "b".repeat(20), "c".repeat(50));
        let b = bounded(&m);
        assert!(b.ends_with("…\" here"), "{b}");
    }

    #[test]
    fn messages_are_cut_to_a_few_lines_of_bounded_length() {
        let words = "word ".repeat(100_000);
        let lines = "line\n".repeat(1000);
        for m in [words, lines] {
            let b = bounded(&m);
            assert!(b.lines().count() <= MAX_LINES + 1, "{b}");
            assert!(b.chars().count() <= MAX_MESSAGE_CHARS + 1, "{}", b.len());
        }
    }
}
