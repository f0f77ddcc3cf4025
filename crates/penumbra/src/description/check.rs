//! Reading a property and checking its range in one step: each reader
//! takes the property's default, reads it through [`Props`] (so type
//! errors are the reader's) and names the value in the message when it is
//! out of range (`must be a positive number, got -1`), at the value.

use super::error::Invalid;
use super::props::Props;
use crate::math::{Rgb, Vec3};

pub type Check<T> = Result<T, Invalid>;

/// A number in `[lo, hi]` (finite).
pub fn range(p: &Props, name: &str, default: f32, lo: f32, hi: f32) -> Check<f32> {
    let v = p.f32(name)?.unwrap_or(default);
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(p.error(name, format!("must be between {lo} and {hi}, got {v}")))
    }
}

/// A finite number > 0.
pub fn positive(p: &Props, name: &str, default: f32) -> Check<f32> {
    let v = p.f32(name)?.unwrap_or(default);
    positive_value(p, name, v)
}

/// `v`, the value of `name`, if it is a finite number > 0.
pub fn positive_value(p: &Props, name: &str, v: f32) -> Check<f32> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(p.error(name, format!("must be a positive number, got {v}")))
    }
}

/// An integer in `[lo, hi]`.
pub fn int(p: &Props, name: &str, default: i64, lo: i64, hi: i64) -> Check<u32> {
    let v = p.int(name)?.unwrap_or(default);
    if (lo..=hi).contains(&v) {
        u32::try_from(v).map_err(|_| p.error(name, "out of range"))
    } else {
        Err(p.error(
            name,
            format!("must be an integer from {lo} to {hi}, got {v}"),
        ))
    }
}

/// 3 finite numbers.
pub fn finite3(p: &Props, name: &str, default: [f32; 3]) -> Check<Vec3> {
    let v = p.numbers::<3>(name)?.unwrap_or(default);
    finite3_value(p, name, v)
}

/// `v`, the value of `name`, if its numbers are finite.
pub fn finite3_value(p: &Props, name: &str, v: [f32; 3]) -> Check<Vec3> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(Vec3::from_array(v))
    } else {
        Err(p.error(name, format!("expected finite numbers, got {v:?}")))
    }
}

/// A colour: 3 finite numbers, none negative.
pub fn nonneg3(p: &Props, name: &str, default: [f32; 3]) -> Check<Rgb> {
    let v = p.numbers::<3>(name)?.unwrap_or(default);
    let x = Rgb::from_array(finite3_value(p, name, v)?.to_array());
    if x.min_element() < 0.0 {
        return Err(p.error(name, format!("must not be negative, got {v:?}")));
    }
    Ok(x)
}

/// 3 finite numbers, not all 0.
pub fn nonzero3(p: &Props, name: &str, default: [f32; 3]) -> Check<Vec3> {
    let v = p.numbers::<3>(name)?.unwrap_or(default);
    nonzero3_value(p, name, v)
}

/// `v`, the value of `name`, if it is finite and not the zero vector.
pub fn nonzero3_value(p: &Props, name: &str, v: [f32; 3]) -> Check<Vec3> {
    let x = finite3_value(p, name, v)?;
    if x.length_squared() <= 0.0 {
        return Err(p.error(name, "must not be the zero vector"));
    }
    Ok(x)
}

/// A property a plugin cannot do without: its value, or an error at the
/// node saying that a `kind` needs it.
pub fn required<T>(p: &Props, v: Option<T>, name: &str, kind: &str) -> Check<T> {
    v.ok_or_else(|| p.node_error(format!("a {kind} needs `{name}`")))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::description::{from_toml, Kind};

    fn camera(text: &str) -> crate::description::Node {
        let root = from_toml(&format!("[camera]\n{text}"), Path::new("t.toml")).unwrap();
        root.child(Kind::Sensor).unwrap().clone()
    }

    #[test]
    fn values_out_of_range_are_named_at_the_value() {
        let node = camera("fov = -3\naperture = 1e300\nup = [0, 0, 0]\nposition = [1, nan, 0]\n");
        let p = Props::new(&node);
        let e = range(&p, "fov", 40.0, 0.01, 179.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.toml:2:7: camera.fov: must be between 0.01 and 179, got -3"
        );
        let e = positive(&p, "aperture", 1.0).unwrap_err();
        assert!(
            e.to_string().contains("must be a positive number, got inf"),
            "{e}"
        );
        let e = nonzero3(&p, "up", [0.0, 1.0, 0.0]).unwrap_err();
        assert!(
            e.to_string()
                .ends_with("camera.up: must not be the zero vector"),
            "{e}"
        );
        let e = finite3(&p, "position", [0.0; 3]).unwrap_err();
        assert!(e.to_string().contains("expected finite numbers"), "{e}");
        assert_eq!(
            finite3(&p, "look_at", [1.0, 2.0, 3.0]).unwrap(),
            Vec3::new(1.0, 2.0, 3.0)
        );
        let e = required(&p, None::<f32>, "focal_distance", "camera").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.toml:1:1: camera: a camera needs `focal_distance`"
        );
        let e = int(&p, "fov", 1, 0, 10).unwrap_err();
        assert!(
            e.to_string()
                .ends_with("must be an integer from 0 to 10, got -3"),
            "{e}"
        );
    }
}
