//! The Gaussian filter (Mitsuba's `gaussian`), cut at 4 standard
//! deviations and shifted down to reach 0 there.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `stddev` | number > 0 | 0.5 | standard deviation σ in pixels; the radius is 4σ |
//!
//! Its profile is `f(x) = exp(−x²/2σ²) − exp(−r²/2σ²)` for `|x| ≤ r = 4σ`,
//! 0 beyond. It is sampled through a table of its inverse distribution;
//! it is never negative, so every sample weighs 1.

use super::model::{FilterError, FilterModel, FilterParams};

/// The Gaussian filter; see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gaussian {
    pub stddev: f32,
}

impl Default for Gaussian {
    fn default() -> Self {
        Gaussian { stddev: 0.5 }
    }
}

impl Gaussian {
    /// A Gaussian of this standard deviation, or why not.
    pub fn new(stddev: f32) -> Result<Gaussian, String> {
        if stddev.is_finite() && stddev > 0.0 {
            Ok(Gaussian { stddev })
        } else {
            Err(format!("must be a positive number, got {stddev}"))
        }
    }

    /// Where the profile reaches 0: 4σ.
    pub fn radius(self) -> f32 {
        4.0 * self.stddev
    }

    /// The profile along one axis.
    pub fn profile(self, x: f64) -> f64 {
        let s = f64::from(self.stddev);
        let r = f64::from(self.radius());
        let g = |x: f64| (-x * x / (2.0 * s * s)).exp();
        if x.abs() > r {
            0.0
        } else {
            (g(x) - g(r)).max(0.0)
        }
    }
}

impl FilterModel for Gaussian {
    const NAME: &'static str = "gaussian";
    const PARAMS: &'static [&'static str] = &["stddev"];

    fn build(params: &FilterParams) -> Result<Gaussian, FilterError> {
        match params.stddev {
            Some(s) => Gaussian::new(s).map_err(FilterError::of("stddev")),
            None => Ok(Gaussian::default()),
        }
    }

    fn radius(self) -> f32 {
        Gaussian::radius(self)
    }

    fn eval(self, x: f64) -> f64 {
        self.profile(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_is_a_shifted_gaussian() {
        let g = Gaussian::new(0.5).unwrap();
        assert_eq!(g.radius(), 2.0);
        let tail = (-8.0f64).exp();
        assert!((g.profile(0.0) - (1.0 - tail)).abs() < 1e-15);
        // One standard deviation out: e^(−1/2).
        assert!((g.profile(-0.5) - ((-0.5f64).exp() - tail)).abs() < 1e-15);
        assert_eq!(g.profile(2.0), 0.0);
        assert_eq!(g.profile(2.5), 0.0);
        let wide = Gaussian::new(2.0).unwrap();
        assert_eq!(wide.radius(), 8.0);
        assert!((wide.profile(2.0) - ((-0.5f64).exp() - tail)).abs() < 1e-15);
    }

    #[test]
    fn stddev_must_be_positive() {
        for s in [0.0, -0.5, f32::NAN, f32::INFINITY] {
            assert!(Gaussian::new(s).is_err(), "{s}");
        }
    }
}
