//! `isotropic`: a medium scattering light alike in every direction, the
//! value `1/4π` (Mitsuba 3's `isotropic`), drawn uniformly over the
//! sphere.

use super::{PhaseModel, PhaseSample};
use crate::description::{Invalid, Kind, Props, Schema};
use crate::math::{Vec2, Vec3};
use crate::volume::Volumes;
use crate::sampling::warp::{square_to_uniform_sphere, square_to_uniform_sphere_pdf};

/// The isotropic phase function (see the [module docs](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Isotropic;

impl PhaseModel for Isotropic {
    const NAME: &'static str = "isotropic";

    const SCHEMA: Schema = Schema {
        kind: Kind::Phase,
        plugin: "isotropic",
        what: "isotropic phase function",
        doc: "every direction alike: 1/4π",
        mitsuba: &["isotropic"],
        params: &[],
    };

    fn build(_: &Props, _: &Volumes) -> Result<Isotropic, Invalid> {
        Ok(Isotropic)
    }

    #[inline]
    fn eval(&self, _p: Vec3, _wo: Vec3, wi: Vec3) -> f32 {
        square_to_uniform_sphere_pdf(wi)
    }

    #[inline]
    fn sample(&self, _p: Vec3, _wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let wi = square_to_uniform_sphere(u);
        Some(PhaseSample {
            wi,
            weight: 1.0,
            pdf: square_to_uniform_sphere_pdf(wi),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::phase::chi2::{check_phase, views};

    /// Uniform directions: the sampler against its density by χ², and
    /// the value integrating to 1.
    #[test]
    fn samples_follow_the_density() {
        for wo in views() {
            check_phase(&Isotropic, wo);
        }
    }
}
