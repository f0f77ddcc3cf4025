//! Placements: a transform table as a matrix (see
//! [`description::placement`](crate::description::placement)), and a
//! moving object's two placements as a motion.

use crate::description::{Invalid, Props};
use crate::geometry::motion::{Motion, Similarity};
use crate::math::Mat4;

pub use crate::description::placement::{read, PARAMS};

/// A moving object's motion from `start` to `end` (the placements of
/// `transform` and `transform_end`); shear cannot be interpolated.
pub fn motion(object: &Props, start: &Mat4, end: &Mat4) -> Result<Motion, Invalid> {
    Ok(Motion {
        start: similarity(object, "transform", start)?,
        end: similarity(object, "transform_end", end)?,
    })
}

/// Decomposes a placement for motion interpolation.
fn similarity(object: &Props, name: &str, m: &Mat4) -> Result<Similarity, Invalid> {
    let (scale, rotation, translation) = m.to_scale_rotation_translation();
    let s = Similarity {
        scale,
        rotation,
        translation,
    };
    let size = m
        .abs()
        .to_cols_array()
        .iter()
        .fold(1.0f32, |a, b| a.max(*b));
    if !s.matrix().abs_diff_eq(*m, 1e-4 * size) {
        return Err(object.error(name, "a moving object's transform must not shear"));
    }
    Ok(s)
}
