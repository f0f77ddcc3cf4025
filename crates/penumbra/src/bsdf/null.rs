//! `null`: a surface that does nothing to light (Mitsuba 3's `null`). A
//! ray meeting it goes straight on, its radiance whole; shadow rays of the
//! volumetric path tracer cross it. It marks where a medium begins and
//! ends (a shape's `interior` and `exterior`) without a visible
//! interface; `whitted` sees through it as through a fully transparent
//! surface. Its one lobe is a pass-through ([`BsdfFlags::NULL`]): a delta
//! transmission that does not bend, which the path tracers do not count as
//! a scattering event where media are tracked (`volpath`), and which needs
//! no next-event estimation.

use super::sample::{BsdfFlags, BsdfSample, Lobes};
use super::{BsdfModel, Defaults};
use crate::description::{Invalid, Kind, Props, Schema};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;

/// The null material (see the [module docs](self)).
#[derive(Clone, Copy, Debug, Default)]
pub struct Null;

/// The pass-through lobe's kind.
pub const PASS: BsdfFlags = BsdfFlags::DELTA
    .union(BsdfFlags::TRANSMISSION)
    .union(BsdfFlags::NULL);

impl BsdfModel for Null {
    const NAME: &'static str = "null";

    const SCHEMA: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "null",
        what: "null material",
        doc: "a surface light passes straight through: the boundary of a medium",
        mitsuba: &["null"],
        params: &[],
    };

    fn build(_: &Props, _: &Defaults) -> Result<Null, Invalid> {
        Ok(Null)
    }

    fn lobes(&self) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = PASS;
        l
    }

    fn eval(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> Rgb {
        Rgb::ZERO
    }

    fn sample(
        &self,
        _: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        _: SetPoint,
    ) -> Option<BsdfSample> {
        if lobe.is_some_and(|k| k != 0) {
            return None;
        }
        Some(BsdfSample {
            wi: -wo,
            weight: Rgb::ONE,
            pdf: 1.0,
            flags: PASS,
            lobe: 0,
            eta: 1.0,
        })
    }

    fn pdf(&self, _: &SurfaceInteraction, _: Vec3, _: Vec3) -> f32 {
        0.0
    }

    fn shadow_transmittance(&self, _: &SurfaceInteraction) -> f32 {
        1.0
    }

    fn uniform_shadow_transmittance(&self) -> Option<f32> {
        Some(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{build, interaction, views};
    use crate::math::Vec2;

    /// Every view passes straight through, whole, with the pass-through
    /// lobe; the surface has no value or density for any pair, and lets
    /// shadow rays through.
    #[test]
    fn light_passes_straight_through() {
        let m: Null = build("type = \"null\"").unwrap();
        let si = interaction(Vec3::new(0.1, 0.2, 0.97).normalize());
        for wo in views() {
            let s = m
                .sample(&si, wo, None, SetPoint::uniform(Vec2::new(0.3, 0.8)))
                .unwrap();
            assert_eq!((s.wi, s.weight, s.eta), (-wo, Rgb::ONE, 1.0));
            assert!(s.flags.contains(BsdfFlags::NULL) && s.flags.is_delta());
            assert_eq!(m.eval(&si, wo, -wo), Rgb::ZERO);
            assert_eq!(m.pdf(&si, wo, -wo), 0.0);
        }
        assert_eq!(m.shadow_transmittance(&si), 1.0);
        assert!(!m.lobes().any_smooth());
    }
}
