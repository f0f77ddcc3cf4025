//! `hg`: Henyey and Greenstein's phase function (Mitsuba 3's `hg`), a
//! lobe whose mean cosine of the scattering angle is `g`: forward
//! scattering for `g > 0`, backward for `g < 0`, isotropic at 0. Its value
//! at scattering angle θ is `(1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2})`,
//! drawn exactly by inverting its distribution in `cos θ`.

use super::{scattered, PhaseModel, PhaseSample};
use crate::description::check::range;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Vec2, Vec3};
use crate::volume::Volumes;

/// The Henyey–Greenstein phase function (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hg {
    /// The mean cosine of the scattering angle, in (−1, 1).
    pub g: f32,
}

/// The largest `|g|` a scene may give: Mitsuba refuses ±1, whose lobe is a
/// delta.
const G_MAX: f64 = 0.9999;

impl Hg {
    /// The value at scattering angle θ (`cos θ = cos_theta`).
    #[inline]
    pub fn value(&self, cos_theta: f32) -> f32 {
        let g = self.g;
        let d = 1.0 + g * g - 2.0 * g * cos_theta;
        std::f32::consts::FRAC_1_PI * 0.25 * (1.0 - g * g) / (d * d.max(0.0).sqrt())
    }
}

impl PhaseModel for Hg {
    const NAME: &'static str = "hg";

    const SCHEMA: Schema = Schema {
        kind: Kind::Phase,
        plugin: "hg",
        what: "Henyey-Greenstein phase function",
        doc: "Henyey and Greenstein's lobe of mean cosine `g`",
        mitsuba: &["hg"],
        params: &[Param::new(
            "g",
            Type::Number,
            "0.8",
            "the mean cosine of the scattering angle: > 0 forward, < 0 backward, 0 isotropic",
        )
        .range(Range::Between(-G_MAX, G_MAX))],
    };

    fn build(p: &Props, _: &Volumes) -> Result<Hg, Invalid> {
        let g = range(p, "g", 0.8, -G_MAX as f32, G_MAX as f32)?;
        Ok(Hg { g })
    }

    #[inline]
    fn eval(&self, _p: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        self.value(-wo.dot(wi))
    }

    #[inline]
    fn sample(&self, _p: Vec3, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let g = self.g;
        let cos_theta = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
            ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
        };
        let wi = scattered(wo, cos_theta, u.y);
        let pdf = self.value(cos_theta);
        (pdf > 0.0).then_some(PhaseSample {
            wi,
            weight: 1.0,
            pdf,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::phase::chi2::{check_phase, views};

    /// Forward, backward, near-isotropic and strongly peaked lobes: the
    /// sampler against its density by χ², the value integrating to 1 and
    /// its mean cosine `g`.
    #[test]
    fn samples_follow_the_density() {
        for g in [0.8, -0.5, 0.0005, 0.3, 0.95] {
            let hg = Hg { g };
            for wo in views() {
                check_phase(&hg, wo);
            }
            // The mean cosine of the scattering angle, by quadrature.
            let n = 200_000;
            let mut mean = 0.0f64;
            for i in 0..n {
                let c = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                mean += c * f64::from(hg.value(c as f32)) * 2.0 * std::f64::consts::PI * 2.0
                    / n as f64;
            }
            assert!((mean - f64::from(g)).abs() < 2e-3, "g {g}: mean cosine {mean}");
        }
    }
}
