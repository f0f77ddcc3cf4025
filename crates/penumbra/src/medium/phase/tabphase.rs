//! `tabphase`: a phase function given as a table of values over the
//! cosine of the scattering angle (Mitsuba 3's `tabphase`). The values
//! lie evenly from `cos θ = −1` (straight back) to `cos θ = 1` (straight
//! on, the light going on in the direction it came in: the physicists'
//! convention Mitsuba's table keeps), linear between them, and are
//! normalised so that the function integrates to 1 over the sphere: its
//! value is the table's density over `cos θ` divided by `2π`.
//!
//! Drawn exactly: `cos θ` from the piecewise-linear distribution of the
//! table ([`Linear1D`]), the azimuth uniform.

use super::{scattered, PhaseModel, PhaseSample};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::math::{Vec2, Vec3};
use crate::sampling::Linear1D;
use crate::volume::Volumes;

/// The tabulated phase function (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct TabPhase {
    /// The density over `cos θ` in [−1, 1].
    pub cos_theta: Linear1D,
}

/// `1 / 2π`: a density over `cos θ` to one over the sphere.
const INV_2PI: f32 = 0.5 * std::f32::consts::FRAC_1_PI;

impl TabPhase {
    /// The phase function of the table `values`, from `cos θ = −1` to 1;
    /// `Err` saying what is wrong with a table of fewer than 2 values, a
    /// negative or non-finite value, or only zeros.
    pub fn new(values: &[f32]) -> Result<TabPhase, String> {
        if values.len() < 2 {
            return Err(format!(
                "needs at least 2 values (at cos θ = −1 and 1), got {}",
                values.len()
            ));
        }
        if let Some((i, v)) = values
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(format!(
                "every value must be finite and ≥ 0, but value {} is {v}",
                i + 1
            ));
        }
        Linear1D::new(values, (-1.0, 1.0))
            .map(|cos_theta| TabPhase { cos_theta })
            .ok_or_else(|| "the values are all 0: there is nothing to scatter".to_string())
    }

    /// The value at scattering angle θ (`cos θ = cos_theta`).
    #[inline]
    pub fn value(&self, cos_theta: f32) -> f32 {
        self.cos_theta.pdf(cos_theta.clamp(-1.0, 1.0)) * INV_2PI
    }
}

/// The numbers of a list separated by commas or white space.
fn numbers(text: &str) -> Result<Vec<f32>, String> {
    text.split([',', ' ', '\t', '\n', '\r'])
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f32>()
                .map_err(|_| format!("`{s}` is not a number"))
        })
        .collect()
}

impl PhaseModel for TabPhase {
    const NAME: &'static str = "tabphase";

    const SCHEMA: Schema = Schema {
        kind: Kind::Phase,
        plugin: "tabphase",
        what: "tabulated phase function",
        doc: "a table of values over the cosine of the scattering angle, linear between them",
        mitsuba: &["tabphase"],
        params: &[Param::new(
            "values",
            Type::String,
            "required",
            "the values, separated by commas, at evenly spaced cos θ from −1 (straight back) to 1 \
             (straight on); at least 2, each ≥ 0, normalised",
        )],
    };

    fn build(p: &Props, _: &Volumes) -> Result<TabPhase, Invalid> {
        let Some(text) = p.string("values")? else {
            return Err(p.node_error("missing field `values` (the table of the phase function)"));
        };
        let values = numbers(text).map_err(|e| p.error("values", e))?;
        TabPhase::new(&values).map_err(|e| p.error("values", e))
    }

    #[inline]
    fn eval(&self, _p: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        self.value(-wo.dot(wi))
    }

    #[inline]
    fn sample(&self, _p: Vec3, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let (cos_theta, density) = self.cos_theta.sample(u.x);
        let pdf = density * INV_2PI;
        (pdf > 0.0).then(|| PhaseSample {
            wi: scattered(wo, cos_theta, u.y),
            weight: 1.0,
            pdf,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::phase::chi2::{check_phase, views};
    use crate::medium::phase::isotropic::Isotropic;
    use crate::sampling::Rng;

    /// A constant table, however long, is the isotropic phase function:
    /// the same value for every pair of directions.
    #[test]
    fn a_constant_table_is_isotropic() {
        let mut rng = Rng::new(9);
        for values in [vec![1.0, 1.0], vec![0.3; 7]] {
            let t = TabPhase::new(&values).unwrap();
            for _ in 0..100 {
                let wo = crate::sampling::warp::square_to_uniform_sphere(Vec2::new(
                    rng.next_f32(),
                    rng.next_f32(),
                ));
                let wi = crate::sampling::warp::square_to_uniform_sphere(Vec2::new(
                    rng.next_f32(),
                    rng.next_f32(),
                ));
                let (got, want) = (t.eval(Vec3::ZERO, wo, wi), Isotropic.eval(Vec3::ZERO, wo, wi));
                assert!((got - want).abs() < 1e-6 * want, "{got} vs {want}");
            }
            for wo in views() {
                check_phase(&t, wo);
            }
        }
    }

    /// The table's direction: its last value is straight on (`wi = −wo`,
    /// the light going on as it came), its first straight back; a table
    /// rising toward the end scatters forward (mean cosine > 0), by the
    /// closed form of its normalisation.
    #[test]
    fn the_last_value_is_straight_on() {
        // 1 at cos θ = −1, 3 at 1: density (2 + cos θ) / 4 over cos θ.
        let t = TabPhase::new(&[1.0, 3.0]).unwrap();
        let wo = Vec3::new(0.0, 0.0, 1.0);
        let on = t.eval(Vec3::ZERO, wo, -wo);
        let back = t.eval(Vec3::ZERO, wo, wo);
        assert!((on - 0.75 * INV_2PI).abs() < 1e-6, "{on}");
        assert!((back - 0.25 * INV_2PI).abs() < 1e-6, "{back}");
        // Sampled directions go on forward on average: E[cos θ] = 1/6.
        let mut rng = Rng::new(2);
        let n = 200_000;
        let mean: f64 = (0..n)
            .map(|_| {
                let s = t
                    .sample(Vec3::ZERO, wo, Vec2::new(rng.next_f32(), rng.next_f32()))
                    .unwrap();
                f64::from(-wo.dot(s.wi))
            })
            .sum::<f64>()
            / n as f64;
        assert!((mean - 1.0 / 6.0).abs() < 5e-3, "{mean}");
    }

    /// Asymmetric tables (a forward peak, a zero stretch, a backward
    /// lobe): the sampler against its density by χ², the value
    /// integrating to 1.
    #[test]
    fn samples_follow_the_density() {
        for values in [
            "0.1, 0.2, 0.4, 1.0, 3.0, 12.0",
            "5, 0, 0, 0.5, 1, 2, 0.25",
            "0 2",
        ] {
            let t = TabPhase::new(&numbers(values).unwrap()).unwrap();
            for wo in views() {
                check_phase(&t, wo);
            }
        }
    }

    /// Bad tables are refused with what is wrong.
    #[test]
    fn bad_tables_are_refused() {
        let err = |v: &str| match numbers(v).and_then(|v| TabPhase::new(&v)) {
            Ok(_) => panic!("{v:?} accepted"),
            Err(e) => e,
        };
        assert!(err("1").contains("at least 2"));
        assert!(err("").contains("at least 2"));
        assert!(err("1, -2, 3").contains("value 2 is -2"));
        assert!(err("1, NaN").contains("value 2 is NaN"));
        assert!(err("0, 0, 0").contains("all 0"));
        assert!(err("1, x").contains("`x` is not a number"));
    }
}
