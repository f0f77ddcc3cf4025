//! Finding the key that nests too deeply: the TOML parser refuses a dotted
//! key or table header of more than [`MAX_KEY_PARTS`] parts with no position,
//! so the TOML reader looks for it here to name its line.

/// Parts of a dotted key or table header the TOML parser reads (`a.b.c` has 3).
pub const MAX_KEY_PARTS: usize = 80;

/// A dotted key and where it starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeepKey {
    /// Byte offset of the key's first character.
    pub offset: usize,
    /// Its number of dotted parts.
    pub parts: usize,
}

/// The first key (of a key/value pair, a table header or an inline table)
/// of more than `limit` dotted parts; else the key of the most parts, if one
/// has any dot. Comments and strings (quoted key parts) are skipped, and a
/// dot between two digits is taken as a number's.
pub fn deep_key(text: &str, limit: usize) -> Option<DeepKey> {
    let b = text.as_bytes();
    let mut start: Option<usize> = None;
    let mut dots = 0usize;
    let mut best: Option<DeepKey> = None;
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        match c {
            b'#' => {
                i = b[i..]
                    .iter()
                    .position(|&x| x == b'\n')
                    .map_or(b.len(), |n| i + n);
                continue;
            }
            b'"' | b'\'' => {
                start.get_or_insert(i);
                i = skip_string(b, i);
                continue;
            }
            b'\n' | b'=' | b',' | b'{' | b'}' | b'[' | b']' => {
                start = None;
                dots = 0;
            }
            b'.' => {
                let digit =
                    |j: Option<usize>| j.and_then(|j| b.get(j)).is_some_and(u8::is_ascii_digit);
                if !(digit(i.checked_sub(1)) && digit(Some(i + 1))) {
                    dots += 1;
                    let key = DeepKey {
                        offset: start.unwrap_or(i),
                        parts: dots + 1,
                    };
                    if key.parts > limit {
                        // Report the key once it is past the limit, with all its parts.
                        let mut k = key;
                        k.parts += count_more_dots(b, i + 1);
                        return Some(k);
                    }
                    if best.is_none_or(|b| b.parts < key.parts) {
                        best = Some(key);
                    }
                }
            }
            c if c.is_ascii_whitespace() => {}
            _ => {
                start.get_or_insert(i);
            }
        }
        i += 1;
    }
    best
}

/// The offset just past the string starting at `i` (basic or literal, on one
/// line or multi-line), or the end of the text if it is not closed.
fn skip_string(b: &[u8], i: usize) -> usize {
    let q = b[i];
    let multi = b.get(i + 1) == Some(&q) && b.get(i + 2) == Some(&q);
    let mut j = if multi { i + 3 } else { i + 1 };
    while j < b.len() {
        match b[j] {
            b'\\' if q == b'"' => j += 2,
            b'\n' if !multi => return j,
            x if x == q => {
                if !multi {
                    return j + 1;
                }
                if b.get(j + 1) == Some(&q) && b.get(j + 2) == Some(&q) {
                    // Up to two more quotes may belong to the string's content.
                    let mut end = j + 3;
                    while end < b.len() && b[end] == q && end < j + 5 {
                        end += 1;
                    }
                    return end;
                }
                j += 1;
            }
            _ => j += 1,
        }
    }
    b.len()
}

/// Key dots after `from` on the same key (to the next `=`, `]`, line end...).
fn count_more_dots(b: &[u8], from: usize) -> usize {
    let mut n = 0;
    let mut i = from;
    while i < b.len() {
        match b[i] {
            b'\n' | b'=' | b',' | b'{' | b'}' | b'[' | b']' | b'#' => break,
            b'"' | b'\'' => {
                i = skip_string(b, i);
                continue;
            }
            b'.' => n += 1,
            _ => {}
        }
        i += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deep(parts: usize) -> String {
        vec!["a"; parts].join(".")
    }

    #[test]
    fn finds_a_deep_key_of_each_kind_on_its_line() {
        let k = deep(100);
        for (text, line) in [
            (format!("x = 1\n{k} = 2\n"), 2),
            (format!("[render]\nwidth = 3\n\n[{k}]\n"), 4),
            (format!("# {k}\n[[{k}]]\n"), 2),
            (format!("s = \"{k}\"\nt = {{ {k} = 1 }}\n"), 2),
        ] {
            let found = deep_key(&text, MAX_KEY_PARTS).expect(&text);
            assert_eq!(found.parts, 100);
            let line_of = text[..found.offset].matches('\n').count() + 1;
            assert_eq!(line_of, line, "{text}");
        }
    }

    #[test]
    fn numbers_strings_and_comments_are_not_keys() {
        let floats = vec!["1.5"; 200].join(", ");
        let text = format!(
            "a = [{floats}]\nb = \"{}\"\nc = '''\n{}\n'''\n# {}\nd.e = 1979-05-27T07:32:00.5\n",
            deep(100),
            deep(100),
            deep(100)
        );
        assert_eq!(
            deep_key(&text, MAX_KEY_PARTS),
            Some(DeepKey {
                offset: text.find("d.e").unwrap(),
                parts: 2
            })
        );
        assert_eq!(deep_key("x = 1\n", MAX_KEY_PARTS), None);
    }

    #[test]
    fn quoted_parts_count_as_parts() {
        let text = format!("\"q.q\".{} = 1", deep(90));
        let found = deep_key(&text, MAX_KEY_PARTS).unwrap();
        assert_eq!((found.offset, found.parts), (0, 91));
    }
}
