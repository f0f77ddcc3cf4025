//! The Lanczos-windowed sinc filter (Mitsuba's `lanczos`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `lobes` | integer in 1..=32 | 3 | lobes of the sinc kept; the radius is `lobes` pixels |
//!
//! Its profile is `f(x) = sinc(x) · sinc(x/a)` for `|x| ≤ a`, `a` the
//! lobes, `sinc(x) = sin(πx)/(πx)`, and 0 beyond. It is negative between
//! 1 and 2 pixels (and every other lobe on): offsets are drawn with a
//! density proportional to `|f|` (a table of its inverse distribution) and
//! each sample weighs the sign of `f` times `∫|f|/∫f` per axis.

use std::f64::consts::PI;

use super::model::{FilterError, FilterModel, FilterParams, CELLS};

/// The Lanczos filter; see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanczos {
    pub lobes: u32,
}

impl Default for Lanczos {
    fn default() -> Self {
        Lanczos { lobes: 3 }
    }
}

impl Lanczos {
    /// The most lobes a filter may keep.
    pub const MAX_LOBES: i64 = 32;

    /// The filter of this many lobes, or why not.
    pub fn new(lobes: i64) -> Result<Lanczos, String> {
        match u32::try_from(lobes) {
            Ok(n) if (1..=Self::MAX_LOBES).contains(&lobes) => Ok(Lanczos { lobes: n }),
            _ => Err(format!(
                "must be an integer from 1 to {}, got {lobes}",
                Self::MAX_LOBES
            )),
        }
    }

    pub fn radius(self) -> f32 {
        self.lobes as f32
    }

    /// The profile along one axis.
    pub fn profile(self, x: f64) -> f64 {
        let a = f64::from(self.lobes);
        let t = x.abs();
        if t > a {
            return 0.0;
        }
        if t < 1e-9 {
            return 1.0;
        }
        let px = PI * t;
        (px.sin() / px) * ((px / a).sin() / (px / a))
    }
}

impl FilterModel for Lanczos {
    const NAME: &'static str = "lanczos";
    const PARAMS: &'static [&'static str] = &["lobes"];

    fn build(params: &FilterParams) -> Result<Lanczos, FilterError> {
        match params.lobes {
            Some(n) => Lanczos::new(n).map_err(FilterError::of("lobes")),
            None => Ok(Lanczos::default()),
        }
    }

    fn radius(self) -> f32 {
        Lanczos::radius(self)
    }

    fn eval(self, x: f64) -> f64 {
        self.profile(x)
    }

    /// 512 cells per lobe, at least 1024: its profile has a lobe
    /// per pixel of its radius.
    fn cells(self) -> usize {
        (CELLS / 2 * self.lobes as usize).max(CELLS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1 at 0, 0 at every other whole pixel and at the radius, the
    /// product of the two sincs between.
    #[test]
    fn profile_is_a_windowed_sinc() {
        let l = Lanczos::default();
        assert_eq!(l.profile(0.0), 1.0);
        for k in 1..=3 {
            assert!(l.profile(f64::from(k)).abs() < 1e-15, "{k}");
        }
        assert_eq!(l.profile(3.5), 0.0);
        let x = 0.5;
        let want = (2.0 / PI) * ((PI / 6.0).sin() / (PI / 6.0));
        assert!((l.profile(x) - want).abs() < 1e-15);
        assert!((l.profile(-x) - want).abs() < 1e-15);
        // The first negative lobe.
        assert!(l.profile(1.5) < 0.0 && l.profile(2.5) > 0.0);
    }

    #[test]
    fn lobes_are_counted_from_one() {
        for n in [0, -3, 33] {
            assert!(Lanczos::new(n).is_err(), "{n}");
        }
        assert_eq!(Lanczos::new(32).unwrap().radius(), 32.0);
    }
}
