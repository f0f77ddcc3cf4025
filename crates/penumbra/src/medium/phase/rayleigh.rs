//! `rayleigh`: scattering by particles much smaller than the wavelength
//! (air's molecules), unpolarised (Mitsuba 3's `rayleigh`). Its value at
//! scattering angle θ is `3 (1 + cos² θ) / 16π`: as much backward as
//! forward, least at right angles. As in Mitsuba's RGB variants it is the
//! same in every colour channel (the λ⁻⁴ of Rayleigh scattering belongs to
//! the medium's coefficients, not to its phase function).
//!
//! Drawn exactly: the distribution of `μ = cos θ`, `F(μ) = (μ³ + 3μ + 4) /
//! 8`, is inverted by Cardano's formula for the cubic `μ³ + 3μ − 2z = 0`
//! (`z = 4u − 2`), whose one real root is `A − 1/A` with `A = ∛(z +
//! √(z² + 1))`, taken for `|z|` and given `z`'s sign (the root is odd in
//! `z`), so that no difference of near-equal numbers loses the small
//! roots.

use super::{scattered, PhaseModel, PhaseSample};
use crate::description::{Invalid, Kind, Props, Schema};
use crate::math::{Vec2, Vec3};
use crate::volume::Volumes;

/// The Rayleigh phase function (see the [module docs](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rayleigh;

impl Rayleigh {
    /// The value at scattering angle θ (`cos θ = cos_theta`).
    #[inline]
    pub fn value(cos_theta: f32) -> f32 {
        3.0 / 16.0 * std::f32::consts::FRAC_1_PI * (1.0 + cos_theta * cos_theta)
    }

    /// The cosine whose cumulative probability is `u`.
    #[inline]
    pub fn inverse_cdf(u: f32) -> f32 {
        let z = 4.0 * u - 2.0;
        let a = (z.abs() + (z * z + 1.0).sqrt()).cbrt();
        ((a - 1.0 / a).copysign(z)).clamp(-1.0, 1.0)
    }
}

impl PhaseModel for Rayleigh {
    const NAME: &'static str = "rayleigh";

    const SCHEMA: Schema = Schema {
        kind: Kind::Phase,
        plugin: "rayleigh",
        what: "Rayleigh phase function",
        doc: "scattering by particles much smaller than the wavelength: 3 (1 + cos² θ) / 16π",
        mitsuba: &["rayleigh"],
        params: &[],
    };

    fn build(_: &Props, _: &Volumes) -> Result<Rayleigh, Invalid> {
        Ok(Rayleigh)
    }

    #[inline]
    fn eval(&self, _p: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        Rayleigh::value(-wo.dot(wi))
    }

    #[inline]
    fn sample(&self, _p: Vec3, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let cos_theta = Rayleigh::inverse_cdf(u.x);
        Some(PhaseSample {
            wi: scattered(wo, cos_theta, u.y),
            weight: 1.0,
            pdf: Rayleigh::value(cos_theta),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::phase::chi2::{check_phase, views};

    /// The closed form at a few angles: 3/8π straight on and straight
    /// back, 3/16π at right angles, `3 (1 + 1/4) / 16π` at 60°; the same
    /// through `eval` for directions at those angles.
    #[test]
    fn the_closed_form() {
        let pi = std::f32::consts::PI;
        for (cos, want) in [
            (1.0f32, 3.0 / (8.0 * pi)),
            (-1.0, 3.0 / (8.0 * pi)),
            (0.0, 3.0 / (16.0 * pi)),
            (0.5, 3.0 * 1.25 / (16.0 * pi)),
            (-0.5, 3.0 * 1.25 / (16.0 * pi)),
        ] {
            assert!((Rayleigh::value(cos) - want).abs() < 1e-7, "cos {cos}");
            let wo = Vec3::new(0.0, 0.0, 1.0);
            let sin = (1.0 - cos * cos).sqrt();
            let wi = Vec3::new(sin, 0.0, -cos);
            let got = Rayleigh.eval(Vec3::ZERO, wo, wi);
            assert!((got - want).abs() < 1e-6, "cos {cos}: {got} vs {want}");
        }
    }

    /// The inverse of the distribution: its cumulative probability at the
    /// drawn cosine is the number drawn with, to f32 rounding, over [0, 1]
    /// and at its ends.
    #[test]
    fn the_inverse_cdf_inverts() {
        for k in 0..=1000 {
            let u = k as f32 / 1000.0;
            let mu = Rayleigh::inverse_cdf(u);
            let cdf = (mu * mu * mu + 3.0 * mu + 4.0) / 8.0;
            assert!((cdf - u).abs() < 2e-6, "u {u}: μ {mu}, F {cdf}");
        }
        assert_eq!(Rayleigh::inverse_cdf(0.5), 0.0);
    }

    /// The sampler against its density by χ², the value integrating to 1.
    #[test]
    fn samples_follow_the_density() {
        for wo in views() {
            check_phase(&Rayleigh, wo);
        }
    }
}
