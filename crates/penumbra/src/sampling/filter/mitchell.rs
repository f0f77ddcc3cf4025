//! The Mitchell–Netravali cubic filters (Mitsuba's `mitchell`; its member
//! with `B = 0`, `C = 1/2` is [`catmullrom`](super::catmullrom)).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `B` | number in [0, 1] | 1/3 (`catmullrom`: 0) | blur: 1 with `C = 0` is the cubic B-spline |
//! | `C` | number in [0, 1] | 1/3 (`catmullrom`: 1/2) | ringing: the depth of the negative lobes |
//!
//! The radius is 2 pixels. With `t = |x|`, the profile is
//! `((12 − 9B − 6C)t³ + (−18 + 12B + 6C)t² + 6 − 2B) / 6` for `t < 1`,
//! `((−B − 6C)t³ + (6B + 30C)t² + (−12B − 48C)t + 8B + 24C) / 6` for
//! `1 ≤ t < 2`, and 0 beyond. It integrates to 1 for every `B`, `C`, and
//! is negative between 1 and 2 pixels unless `C = 0`: offsets are drawn
//! with a density proportional to `|f|` (a table of its inverse
//! distribution) and each sample weighs the sign of `f` times `∫|f|/∫f`
//! per axis.

use super::model::{FilterError, FilterModel, FilterParams};

/// A Mitchell–Netravali filter; see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mitchell {
    pub b: f32,
    pub c: f32,
}

impl Default for Mitchell {
    fn default() -> Self {
        Mitchell {
            b: 1.0 / 3.0,
            c: 1.0 / 3.0,
        }
    }
}

impl Mitchell {
    pub const RADIUS: f32 = 2.0;

    /// The Catmull–Rom spline.
    pub const CATMULL_ROM: Mitchell = Mitchell { b: 0.0, c: 0.5 };

    /// The filter of these parameters, or why not (the name of the bad
    /// one and the message).
    pub fn new(b: f32, c: f32) -> Result<Mitchell, (&'static str, String)> {
        for (name, v) in [("B", b), ("C", c)] {
            if !(0.0..=1.0).contains(&v) {
                return Err((name, format!("must be between 0 and 1, got {v}")));
            }
        }
        Ok(Mitchell { b, c })
    }

    /// The profile along one axis.
    pub fn profile(self, x: f64) -> f64 {
        let (b, c) = (f64::from(self.b), f64::from(self.c));
        let t = x.abs();
        let (t2, t3) = (t * t, t * t * t);
        let v = if t < 1.0 {
            (12.0 - 9.0 * b - 6.0 * c) * t3 + (-18.0 + 12.0 * b + 6.0 * c) * t2 + 6.0 - 2.0 * b
        } else if t < 2.0 {
            (-b - 6.0 * c) * t3
                + (6.0 * b + 30.0 * c) * t2
                + (-12.0 * b - 48.0 * c) * t
                + 8.0 * b
                + 24.0 * c
        } else {
            0.0
        };
        v / 6.0
    }
}

impl FilterModel for Mitchell {
    const NAME: &'static str = "mitchell";
    const PARAMS: &'static [&'static str] = &["B", "C"];

    fn build(params: &FilterParams) -> Result<Mitchell, FilterError> {
        let d = Mitchell::default();
        let (b, c) = (params.b.unwrap_or(d.b), params.c.unwrap_or(d.c));
        Mitchell::new(b, c).map_err(|(param, message)| FilterError { param, message })
    }

    fn radius(self) -> f32 {
        Self::RADIUS
    }

    fn eval(self, x: f64) -> f64 {
        self.profile(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Known values: `f(0) = (6 − 2B)/6`, `f(1) = B/6`, `f(2) = 0`; the
    /// pieces meet with equal slopes at 1 (the cubic is C¹); the
    /// Catmull–Rom spline interpolates (1 at 0, 0 at ±1) and dips to
    /// −1/16 at 3/2; the B-spline (B = 1, C = 0) has `f(1/2) = 23/48`.
    #[test]
    fn profile_matches_the_formula() {
        let m = Mitchell::default();
        assert!((m.profile(0.0) - (6.0 - 2.0 / 3.0) / 6.0).abs() < 1e-7);
        assert!((m.profile(1.0) - 1.0 / 18.0).abs() < 1e-7);
        assert!((m.profile(-1.0 + 1e-9) - 1.0 / 18.0).abs() < 1e-7);
        assert!(m.profile(2.0).abs() < 1e-12 && m.profile(1.999_999).abs() < 1e-6);
        let slope = |f: &dyn Fn(f64) -> f64, x: f64| (f(x + 1e-6) - f(x - 1e-6)) / 2e-6;
        let lo = |x: f64| m.profile(x.min(1.0 - 1e-12));
        let hi = |x: f64| m.profile(x.max(1.0));
        assert!((slope(&lo, 1.0 - 2e-6) - slope(&hi, 1.0 + 2e-6)).abs() < 1e-4);
        let cr = Mitchell::CATMULL_ROM;
        assert_eq!(cr.profile(0.0), 1.0);
        assert!(cr.profile(1.0).abs() < 1e-12);
        assert!((cr.profile(1.5) + 1.0 / 16.0).abs() < 1e-12);
        let spline = Mitchell::new(1.0, 0.0).unwrap();
        assert!((spline.profile(0.5) - 23.0 / 48.0).abs() < 1e-12);
    }

    /// Every member integrates to 1 (Simpson's rule, exact for cubics on
    /// each piece).
    #[test]
    fn integrates_to_one() {
        for (b, c) in [(1.0 / 3.0, 1.0 / 3.0), (0.0, 0.5), (1.0, 0.0), (0.2, 0.9)] {
            let m = Mitchell::new(b, c).unwrap();
            let simpson = |a: f64, z: f64| {
                (z - a) / 6.0 * (m.profile(a) + 4.0 * m.profile(0.5 * (a + z)) + m.profile(z))
            };
            let sum = 2.0 * (simpson(0.0, 1.0 - 1e-12) + simpson(1.0, 2.0 - 1e-12));
            assert!((sum - 1.0).abs() < 1e-9, "{b}, {c}: {sum}");
        }
    }

    #[test]
    fn parameters_outside_the_square_are_refused() {
        assert_eq!(Mitchell::new(-0.1, 0.3).unwrap_err().0, "B");
        assert_eq!(Mitchell::new(0.3, 1.5).unwrap_err().0, "C");
        assert!(Mitchell::new(f32::NAN, 0.0).is_err());
    }
}
