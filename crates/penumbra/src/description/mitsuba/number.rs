//! Numbers in attribute values, as Mitsuba reads them: finite only.

use super::parse::clip;

/// A finite number, as C's `strtod` reads one (no `nan` or `inf`).
pub fn number(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let plain = !t.is_empty()
        && t.bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E'));
    match t.parse::<f64>() {
        Ok(x) if plain && x.is_finite() => Ok(x),
        Ok(_) if plain => Err(format!("`{}` is out of range of a 64-bit float", clip(t))),
        _ => Err(format!("`{}` is not a finite number", clip(t))),
    }
}

/// Numbers separated by spaces or commas.
pub fn numbers(text: &str) -> Result<Vec<f64>, String> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
        .map(number)
        .collect()
}
