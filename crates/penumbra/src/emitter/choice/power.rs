//! `power`: each emitter in proportion to its power, wherever the shading
//! point is (pbrt-v4's `PowerLightSampler`): a discrete table over the
//! emitters' [`power`](crate::emitter::Emitter::power), an emitter at
//! infinity counted by the power it brings into the scene's bounding
//! sphere. Emitters that emit nothing are never chosen; when none emits,
//! every emitter is chosen uniformly.

use crate::emitter::Emitter;
use crate::sampling::Discrete;

/// The table of the emitters' powers.
#[derive(Clone, Debug, PartialEq)]
pub struct PowerSampler {
    /// `None` without emitters.
    table: Option<Discrete>,
}

impl PowerSampler {
    /// The table over `emitters`, those at infinity measured through the
    /// sphere of radius `radius`.
    pub fn new(emitters: &[Emitter], radius: f32) -> PowerSampler {
        let power = |e: &Emitter| {
            let p = e.power(radius);
            if p.is_finite() {
                p.max(0.0)
            } else {
                0.0
            }
        };
        let table = Discrete::new(emitters.iter().map(power))
            .or_else(|| Discrete::new(emitters.iter().map(|_| 1.0)));
        PowerSampler { table }
    }

    #[inline]
    pub fn sample(&self, u: f32) -> Option<(u32, f32)> {
        let (k, pmf, _) = self.table.as_ref()?.sample(u);
        Some((k as u32, pmf))
    }

    #[inline]
    pub fn pmf(&self, emitter: u32) -> f32 {
        match &self.table {
            Some(t) if (emitter as usize) < t.len() => t.pmf(emitter as usize),
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::emitter::{Constant, Envmap};
    use crate::math::{Mat3, Rgb, Vec3};

    /// The table's probabilities are the powers' shares: a rectangle of
    /// area 4 and radiance 1 (power 4π) beside a point light of intensity
    /// 1 (power 4π) and one of intensity 2.
    #[test]
    fn probabilities_are_shares_of_power() {
        let quad = crate::geometry::quad::Quad::new(Vec3::ZERO, 2.0 * Vec3::X, 2.0 * Vec3::Z);
        let emitters = [
            super::super::tests::area(crate::geometry::Shape::Quad(quad), 1.0),
            Emitter::Point(crate::emitter::Point {
                position: Vec3::Y,
                intensity: Rgb::ONE,
            }),
            Emitter::Point(crate::emitter::Point {
                position: Vec3::Y,
                intensity: Rgb::splat(2.0),
            }),
        ];
        let s = PowerSampler::new(&emitters, 1.0);
        for (k, want) in [0.25, 0.25, 0.5].into_iter().enumerate() {
            assert!(
                (s.pmf(k as u32) - want).abs() < 1e-6,
                "{k}: {}",
                s.pmf(k as u32)
            );
        }
        // Nothing emits: uniform.
        let dark = vec![
            Emitter::Constant(Constant {
                radiance: Rgb::ZERO
            });
            4
        ];
        let s = PowerSampler::new(&dark, 1.0);
        assert!((0..4).all(|k| s.pmf(k) == 0.25));
        assert!(PowerSampler::new(&[], 1.0).sample(0.5).is_none());
    }

    /// An environment map of one radiance everywhere brings the power of
    /// the constant emitter of that radiance: its pixels' solid angles sum
    /// to 4π.
    #[test]
    fn a_uniform_map_has_the_constant_emitters_power() {
        let map = Envmap::new(
            64,
            32,
            vec![Rgb::splat(0.7); 64 * 32],
            Mat3::IDENTITY,
            false,
        );
        let constant = Constant {
            radiance: Rgb::splat(0.7),
        };
        let (a, b) = (map.power(3.0), constant.power(3.0));
        assert!((a / b - 1.0).abs() < 1e-3, "{a} vs {b}");
    }
}
