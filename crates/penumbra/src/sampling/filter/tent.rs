//! The tent (triangle) filter (Mitsuba's `tent`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `radius` | number > 0 | 1 | half-width in pixels |
//!
//! Its profile is `f(x) = 1 − |x|/r` for `|x| ≤ r`, 0 beyond. It is
//! sampled by the analytic inverse of its distribution, so every sample
//! weighs 1.

use super::model::{FilterError, FilterModel, FilterParams};

/// The tent filter; see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tent {
    pub radius: f32,
}

impl Default for Tent {
    fn default() -> Self {
        Tent { radius: 1.0 }
    }
}

impl Tent {
    /// A tent of this radius, or why not.
    pub fn new(radius: f32) -> Result<Tent, String> {
        if radius.is_finite() && radius > 0.0 {
            Ok(Tent { radius })
        } else {
            Err(format!("must be a positive number, got {radius}"))
        }
    }

    /// The profile along one axis.
    pub fn profile(self, x: f64) -> f64 {
        (1.0 - x.abs() / f64::from(self.radius)).max(0.0)
    }

    /// The offset at `u` in `[0, 1]`: increasing in `u`, distributed as the
    /// profile when `u` is uniform (the inverse of its distribution).
    pub fn sample(self, u: f32) -> f32 {
        let u = u.clamp(0.0, 1.0);
        let x = if u < 0.5 {
            (2.0 * u).sqrt() - 1.0
        } else {
            1.0 - (2.0 * (1.0 - u)).sqrt()
        };
        self.radius * x
    }
}

impl FilterModel for Tent {
    const NAME: &'static str = "tent";
    const PARAMS: &'static [&'static str] = &["radius"];
    const ANALYTIC: bool = true;

    fn build(params: &FilterParams) -> Result<Tent, FilterError> {
        match params.radius {
            Some(r) => Tent::new(r).map_err(FilterError::of("radius")),
            None => Ok(Tent::default()),
        }
    }

    fn radius(self) -> f32 {
        self.radius
    }

    fn eval(self, x: f64) -> f64 {
        self.profile(x)
    }

    #[inline]
    fn warp(self, p: f32) -> Option<f32> {
        Some(self.sample(p + 0.5))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_is_a_triangle() {
        let t = Tent::new(2.0).unwrap();
        assert_eq!(t.profile(0.0), 1.0);
        assert_eq!(t.profile(1.0), 0.5);
        assert_eq!(t.profile(-1.5), 0.25);
        assert_eq!(t.profile(2.0), 0.0);
        assert_eq!(t.profile(3.0), 0.0);
        assert_eq!(Tent::default().profile(0.25), 0.75);
    }

    /// The inverse distribution against the distribution
    /// `F(x) = (1 + x/r)²/2` for `x ≤ 0`.
    #[test]
    fn sample_inverts_the_distribution() {
        let t = Tent::new(1.5).unwrap();
        for k in 0..=10 {
            let x = -1.5 + 0.15 * k as f64;
            let u = 0.5 * (1.0 + x / 1.5).powi(2);
            assert!((f64::from(t.sample(u as f32)) - x).abs() < 1e-5);
            assert!((f64::from(t.sample(1.0 - u as f32)) + x).abs() < 1e-5);
        }
    }

    #[test]
    fn radius_must_be_positive() {
        for r in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(Tent::new(r).is_err(), "{r}");
        }
    }
}
