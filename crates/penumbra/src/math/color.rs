//! Linear RGB: radiance, reflectance and weights.
//!
//! A type of its own, not a vector alias, so that a colour is never added to a
//! point or normalised by mistake. Arithmetic is per channel, in the order and
//! rounding of three separate `f32` operations (a colour product is the same
//! bits whatever the platform's vector width).

use std::iter::Sum;

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Sub};

/// Linear RGB (Rec. 709 primaries): radiance, reflectance or a weight.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rgb {
    pub r: f32,
    pub g: f32,
    pub b: f32,
}

impl Rgb {
    pub const ZERO: Rgb = Rgb::splat(0.0);
    pub const ONE: Rgb = Rgb::splat(1.0);

    pub const fn new(r: f32, g: f32, b: f32) -> Rgb {
        Rgb { r, g, b }
    }

    /// The grey of value `v` in every channel.
    pub const fn splat(v: f32) -> Rgb {
        Rgb { r: v, g: v, b: v }
    }

    pub const fn from_array([r, g, b]: [f32; 3]) -> Rgb {
        Rgb { r, g, b }
    }

    pub const fn to_array(self) -> [f32; 3] {
        [self.r, self.g, self.b]
    }

    /// Applies `f` to each channel.
    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Rgb {
        Rgb::new(f(self.r), f(self.g), f(self.b))
    }

    pub fn max_element(self) -> f32 {
        self.r.max(self.g).max(self.b)
    }

    pub fn min_element(self) -> f32 {
        self.r.min(self.g).min(self.b)
    }

    /// Channel-wise maximum.
    pub fn max(self, o: Rgb) -> Rgb {
        Rgb::new(self.r.max(o.r), self.g.max(o.g), self.b.max(o.b))
    }

    /// Channel-wise minimum.
    pub fn min(self, o: Rgb) -> Rgb {
        Rgb::new(self.r.min(o.r), self.g.min(o.g), self.b.min(o.b))
    }

    /// The sum of the three channels.
    pub fn element_sum(self) -> f32 {
        self.r + self.g + self.b
    }

    /// Channel-wise absolute value.
    pub fn abs(self) -> Rgb {
        self.map(f32::abs)
    }

    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }

    /// Relative luminance (Rec. 709 weights).
    pub fn luminance(self) -> f32 {
        0.2126 * self.r + 0.7152 * self.g + 0.0722 * self.b
    }
}

impl From<[f32; 3]> for Rgb {
    fn from(a: [f32; 3]) -> Rgb {
        Rgb::from_array(a)
    }
}

impl From<Rgb> for [f32; 3] {
    fn from(c: Rgb) -> [f32; 3] {
        c.to_array()
    }
}

impl Add for Rgb {
    type Output = Rgb;
    #[inline]
    fn add(self, o: Rgb) -> Rgb {
        Rgb::new(self.r + o.r, self.g + o.g, self.b + o.b)
    }
}

impl AddAssign for Rgb {
    #[inline]
    fn add_assign(&mut self, o: Rgb) {
        *self = *self + o;
    }
}

impl Sub for Rgb {
    type Output = Rgb;
    #[inline]
    fn sub(self, o: Rgb) -> Rgb {
        Rgb::new(self.r - o.r, self.g - o.g, self.b - o.b)
    }
}

impl Mul for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, o: Rgb) -> Rgb {
        Rgb::new(self.r * o.r, self.g * o.g, self.b * o.b)
    }
}

impl Mul<f32> for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, s: f32) -> Rgb {
        Rgb::new(self.r * s, self.g * s, self.b * s)
    }
}

impl Mul<Rgb> for f32 {
    type Output = Rgb;
    #[inline]
    fn mul(self, c: Rgb) -> Rgb {
        Rgb::new(self * c.r, self * c.g, self * c.b)
    }
}

impl MulAssign<f32> for Rgb {
    #[inline]
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}

impl MulAssign for Rgb {
    #[inline]
    fn mul_assign(&mut self, o: Rgb) {
        *self = *self * o;
    }
}

impl Div<f32> for Rgb {
    type Output = Rgb;
    #[inline]
    fn div(self, s: f32) -> Rgb {
        Rgb::new(self.r / s, self.g / s, self.b / s)
    }
}

impl Div for Rgb {
    type Output = Rgb;
    #[inline]
    fn div(self, o: Rgb) -> Rgb {
        Rgb::new(self.r / o.r, self.g / o.g, self.b / o.b)
    }
}

impl DivAssign<f32> for Rgb {
    #[inline]
    fn div_assign(&mut self, s: f32) {
        *self = *self / s;
    }
}

impl Sum for Rgb {
    fn sum<I: Iterator<Item = Rgb>>(iter: I) -> Rgb {
        iter.fold(Rgb::ZERO, Add::add)
    }
}

impl<'a> Sum<&'a Rgb> for Rgb {
    fn sum<I: Iterator<Item = &'a Rgb>>(iter: I) -> Rgb {
        iter.fold(Rgb::ZERO, |a, b| a + *b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Channel arithmetic is that of three separate `f32` operations.
    #[test]
    fn channels_are_independent() {
        let (a, b) = (Rgb::new(0.1, 0.2, 0.3), Rgb::new(3.0, 5.0, 7.0));
        assert_eq!((a * b).to_array(), [0.1 * 3.0, 0.2 * 5.0, 0.3 * 7.0]);
        assert_eq!((a + b).to_array(), [0.1 + 3.0, 0.2 + 5.0, 0.3 + 7.0]);
        assert_eq!((b / 3.0).to_array(), [3.0 / 3.0, 5.0 / 3.0, 7.0 / 3.0]);
        assert_eq!((2.0 * a), a * 2.0);
        assert_eq!([a, b].iter().sum::<Rgb>(), Rgb::ZERO + a + b);
        assert_eq!(b.max_element(), 7.0);
        assert_eq!(b.min_element(), 3.0);
        assert!(!Rgb::new(0.0, f32::NAN, 0.0).is_finite());
        assert!((Rgb::ONE.luminance() - 1.0).abs() < 1e-6);
    }
}
