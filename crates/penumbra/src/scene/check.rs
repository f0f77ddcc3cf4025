//! Small validation helpers: each checks one value and names its key path.

use super::error::{Invalid, KeyPath};
use crate::math::{Rgb, Vec3};

pub type Check<T> = Result<T, Invalid>;

pub fn finite3(path: &KeyPath, v: [f32; 3]) -> Check<Vec3> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(Vec3::from_array(v))
    } else {
        Err(Invalid::new(
            path.clone(),
            format!("expected finite numbers, got {v:?}"),
        ))
    }
}

pub fn nonneg3(path: &KeyPath, v: [f32; 3]) -> Check<Rgb> {
    let x = Rgb::from_array(finite3(path, v)?.to_array());
    if x.min_element() < 0.0 {
        return Err(Invalid::new(
            path.clone(),
            format!("must not be negative, got {v:?}"),
        ));
    }
    Ok(x)
}

pub fn nonzero3(path: &KeyPath, v: [f32; 3]) -> Check<Vec3> {
    let x = finite3(path, v)?;
    if x.length_squared() <= 0.0 {
        return Err(Invalid::new(path.clone(), "must not be the zero vector"));
    }
    Ok(x)
}

/// A float in `[lo, hi]`.
pub fn range(path: &KeyPath, v: f32, lo: f32, hi: f32) -> Check<f32> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(Invalid::new(
            path.clone(),
            format!("must be between {lo} and {hi}, got {v}"),
        ))
    }
}

pub fn positive(path: &KeyPath, v: f32) -> Check<f32> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Invalid::new(
            path.clone(),
            format!("must be a positive number, got {v}"),
        ))
    }
}

/// An integer in `[lo, hi]`.
pub fn int(path: &KeyPath, v: i64, lo: i64, hi: i64) -> Check<u32> {
    if (lo..=hi).contains(&v) {
        u32::try_from(v).map_err(|_| Invalid::new(path.clone(), "out of range"))
    } else {
        Err(Invalid::new(
            path.clone(),
            format!("must be an integer from {lo} to {hi}, got {v}"),
        ))
    }
}

/// A required key of a given object or light type.
pub fn required<T: Copy>(path: &KeyPath, v: Option<T>, key: &str, kind: &str) -> Check<T> {
    v.ok_or_else(|| Invalid::new(path.clone(), format!("a {kind} needs `{key}`")))
}

/// Rejects keys that are set but mean nothing for this type.
pub fn only_keys(path: &KeyPath, kind: &str, set: &[(&str, bool)], allowed: &[&str]) -> Check<()> {
    for (key, present) in set {
        if *present && !allowed.contains(key) {
            return Err(Invalid::new(
                path.key(key),
                format!(
                    "`{key}` does not apply to a {kind}; a {kind} takes: {}",
                    allowed.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// One of a closed set of names.
pub fn one_of<'a>(path: &KeyPath, v: &str, what: &str, choices: &[&'a str]) -> Check<&'a str> {
    choices.iter().copied().find(|c| *c == v).ok_or_else(|| {
        Invalid::new(
            path.clone(),
            format!(
                "unknown {what} `{v}`; valid choices are: {}",
                choices.join(", ")
            ),
        )
    })
}
