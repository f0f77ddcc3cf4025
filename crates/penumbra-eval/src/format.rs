//! Number formatting for the report: exact counts with thousands
//! separators, approximate ones in the thesis's `3.5·10⁶` style.

/// `1234567` → `1,234,567`.
pub fn count(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A large approximate value with two significant digits: `3.5·10⁶`;
/// values under 10 000 are written out.
pub fn approx(v: f64) -> String {
    if !v.is_finite() {
        return "–".into();
    }
    if v.abs() < 1e4 {
        return count(v.round().max(0.0) as u64);
    }
    let exp = v.abs().log10().floor() as i32;
    let mantissa = v / 10f64.powi(exp);
    let m = format!("{mantissa:.1}");
    let m = m.strip_suffix(".0").unwrap_or(&m);
    format!("{m}·10{}", superscript(exp))
}

fn superscript(e: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if e < 0 {
        s.push('⁻');
    }
    for c in e.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// "1 ray", "4 rays": a count with its noun, singular or plural.
pub fn rays(n: u32, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun} ray")
    } else {
        format!("{n} {noun} rays")
    }
    .replace("  ", " ")
}

/// A percentage with one decimal (two above 99.9%, so that a saving of
/// 99.98% does not read as 100%).
pub fn pct(v: f64) -> String {
    if v.is_finite() && v > 99.9 && v < 100.0 {
        format!("{v:.2}%")
    } else if v.is_finite() {
        format!("{v:.1}%")
    } else {
        "–".into()
    }
}

/// A ratio such as `15.8×`.
pub fn ratio(v: f64) -> String {
    if v.is_finite() {
        if v >= 100.0 {
            format!("{v:.0}×")
        } else {
            format!("{v:.2}×")
        }
    } else {
        "–".into()
    }
}

/// Seconds with a precision that suits their size.
pub fn seconds(s: f64) -> String {
    if s >= 100.0 {
        format!("{s:.0}")
    } else if s >= 1.0 {
        format!("{s:.1}")
    } else {
        format!("{s:.2}")
    }
}

/// A slope or other small signed number.
pub fn signed(v: f64) -> String {
    if v.is_finite() {
        format!("{v:+.2}").replace('-', "−")
    } else {
        "–".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_approximations() {
        assert_eq!(count(0), "0");
        assert_eq!(count(999), "999");
        assert_eq!(count(1000), "1,000");
        assert_eq!(count(3_446_789), "3,446,789");
        assert_eq!(approx(3.5e6), "3.5·10⁶");
        assert_eq!(approx(2.0e12), "2·10¹²");
        assert_eq!(approx(468.0e6), "4.7·10⁸");
        assert_eq!(approx(9999.4), "9,999");
        assert_eq!(approx(f64::NAN), "–");
        assert_eq!(rays(1, "primary"), "1 primary ray");
        assert_eq!(rays(4, ""), "4 rays");
        assert_eq!(pct(2.54), "2.5%");
        assert_eq!(pct(99.982), "99.98%");
        assert_eq!(ratio(15.83), "15.83×");
        assert_eq!(signed(-0.5), "−0.50");
        assert_eq!(seconds(0.123), "0.12");
    }
}
