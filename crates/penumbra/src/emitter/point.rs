//! A point light: intensity (W/sr per channel) in every direction. It has no
//! surface: both penumbra models send its one shadow ray to its position.

use crate::math::Rgb;

/// Intensity toward any direction.
#[inline]
pub(super) fn intensity(power: Rgb) -> Rgb {
    power
}
