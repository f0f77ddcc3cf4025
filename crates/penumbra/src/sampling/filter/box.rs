//! The box filter: every sample within the pixel counts the same, the
//! thesis's supersampling over the pixel (Mitsuba's `box`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | (none) | | | the radius is 1/2 pixel |
//!
//! Its profile is `f(x) = 1` for `|x| ≤ 1/2`, 0 beyond. Film points in
//! `[-1/2, 1/2]²` are its samples as they are, each of weight 1.

use super::model::{FilterError, FilterModel, FilterParams};

/// The box filter; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BoxFilter;

impl BoxFilter {
    pub const RADIUS: f32 = 0.5;

    /// The profile along one axis.
    pub fn profile(self, x: f64) -> f64 {
        if x.abs() <= f64::from(Self::RADIUS) {
            1.0
        } else {
            0.0
        }
    }
}

impl FilterModel for BoxFilter {
    const NAME: &'static str = "box";
    const ANALYTIC: bool = true;

    fn build(_: &FilterParams) -> Result<BoxFilter, FilterError> {
        Ok(BoxFilter)
    }

    fn radius(self) -> f32 {
        Self::RADIUS
    }

    fn eval(self, x: f64) -> f64 {
        self.profile(x)
    }

    /// The film point as it is.
    #[inline]
    fn warp(self, p: f32) -> Option<f32> {
        Some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_is_one_within_half_a_pixel() {
        for x in [-0.5, -0.25, 0.0, 0.3, 0.5] {
            assert_eq!(BoxFilter.profile(x), 1.0);
        }
        for x in [-0.500_001, 0.6, 2.0] {
            assert_eq!(BoxFilter.profile(x), 0.0);
        }
    }
}
