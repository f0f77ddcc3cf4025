//! `homogeneous`: a medium of the same extinction everywhere (Mitsuba 3's
//! `homogeneous`). Its extinction is `scale · sigma_t`, its
//! scattering `albedo` times that; it fills all space its boundaries
//! enclose, its majorant is its extinction, and every collision drawn in
//! it is real. `sigma_t` is a number or an RGB triple; `albedo` may also
//! be a volume (as Mitsuba's), looked up at each collision: a medium of
//! one extinction whose scattering varies through space.

use super::{Coefficients, MediumModel, COMMON, SCALE, SPECTRAL_EXTINCTION};
use crate::description::mitsuba::Mitsuba;
use crate::description::props::Scale;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Rgb, Vec3};
use crate::sampling::Rng;
use crate::volume::{Volume, Volumes};

/// The homogeneous medium (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Homogeneous {
    /// The extinction, `scale · sigma_t`.
    pub sigma_t: Rgb,
    /// The single-scattering albedo (boxed, as volumes are large beside
    /// the rest).
    pub albedo: Box<Volume>,
    /// The extinction differs between channels and is sampled so.
    pub spectral: bool,
}

/// A number or an RGB triple, each ≥ 0 and finite.
fn colour(p: &Props, name: &str, default: f32) -> Result<Rgb, Invalid> {
    let v = match p.scale(name)? {
        None => Rgb::splat(default),
        Some(Scale::Uniform(x)) => Rgb::splat(x),
        Some(Scale::PerAxis(v)) => Rgb::from_array(v),
    };
    if v.is_finite() && v.min_element() >= 0.0 {
        Ok(v)
    } else {
        let [r, g, b] = v.to_array();
        Err(p.error(
            name,
            format!("must be a number or 3 numbers, each finite and ≥ 0, got [{r}, {g}, {b}]"),
        ))
    }
}

impl MediumModel for Homogeneous {
    const NAME: &'static str = "homogeneous";

    const SCHEMA: Schema = Schema {
        kind: Kind::Medium,
        plugin: "homogeneous",
        what: "homogeneous medium",
        doc: "the same extinction everywhere, the albedo a number, a colour or a volume",
        mitsuba: &["homogeneous"],
        params: &[
            Param::new(
                "sigma_t",
                Type::Scale,
                "1",
                "extinction per unit length: a number or 3 (RGB); times `scale`",
            )
            .range(Range::NonNegative),
            Param::new(
                "albedo",
                Type::Volume,
                "0.75",
                "the share of extinction that scatters: a number or 3 (RGB), or a volume looked \
                 up at each collision",
            ),
            SCALE,
            SPECTRAL_EXTINCTION,
            COMMON[0],
        ],
    };

    const MITSUBA: Mitsuba = Mitsuba::differs(
        "`sigma_t` is a float, an RGB or a spectrum (as RGB), not a volume; `albedo` is also a \
         volume",
    );

    fn build(p: &Props, volumes: &Volumes) -> Result<Homogeneous, Invalid> {
        let sigma_t = colour(p, "sigma_t", 1.0)?;
        let albedo = Box::new(volumes.volume(p, "albedo", Rgb::splat(0.75))?);
        let scale = p.f32("scale")?.unwrap_or(1.0);
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(p.error("scale", format!("must be a finite number ≥ 0, got {scale}")));
        }
        let spectral = p.bool("has_spectral_extinction")?.unwrap_or(true);
        Ok(Homogeneous {
            sigma_t: sigma_t * scale,
            albedo,
            spectral,
        })
    }

    #[inline]
    fn is_homogeneous(&self) -> bool {
        true
    }

    #[inline]
    fn has_spectral_extinction(&self) -> bool {
        self.spectral
    }

    #[inline]
    fn intersect_aabb(&self, _o: Vec3, _d: Vec3) -> Option<(f32, f32)> {
        Some((0.0, f32::INFINITY))
    }

    #[inline]
    fn majorant(&self, _p: Vec3) -> Rgb {
        self.sigma_t
    }

    #[inline]
    fn coefficients(&self, p: Vec3) -> Coefficients {
        Coefficients {
            sigma_s: self.sigma_t * self.albedo.eval(p),
            sigma_n: Rgb::ZERO,
            sigma_t: self.sigma_t,
        }
    }

    /// Exact: `exp(−σt · tmax)`.
    #[inline]
    fn transmittance(&self, _ray: (Vec3, Vec3), tmax: f32, _rng: &mut Rng) -> Rgb {
        self.sigma_t.map(|s| if s > 0.0 { (-s * tmax).exp() } else { 1.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::Model;

    /// Tentative collisions drawn against the majorant fall at
    /// `−ln(1 − u) / σ̄` of the channel asked for, every one real (σn =
    /// 0), and their distances follow the exponential law: the share past
    /// `d` is `exp(−σ d)`, as the exact transmittance says.
    #[test]
    fn distances_follow_the_exponential_law() {
        let m = Homogeneous {
            sigma_t: Rgb::new(0.5, 1.0, 2.0),
            albedo: Box::new(Volume::constant(Rgb::splat(0.6))),
            spectral: true,
        };
        let model = Model::Homogeneous(m.clone());
        let (o, d) = (Vec3::new(1.0, 2.0, 3.0), Vec3::Z);
        let mut rng = Rng::new(11);
        for channel in 0..3 {
            let sigma = m.sigma_t.to_array()[channel];
            let n = 100_000;
            let far = 1.3;
            let mut past = 0;
            for _ in 0..n {
                let mi = model.sample_interaction((o, d), far, rng.next_f32(), channel);
                if !mi.is_valid() {
                    past += 1;
                    continue;
                }
                assert!(mi.t <= far && (mi.p - (o + d * mi.t)).length() < 1e-5);
                assert_eq!(mi.sigma.sigma_n, Rgb::ZERO);
                assert_eq!(mi.sigma.sigma_s, m.sigma_t * 0.6);
            }
            let want = (-sigma * far).exp();
            let got = past as f32 / n as f32;
            let sd = (want * (1.0 - want) / n as f32).sqrt();
            assert!((got - want).abs() < 4.0 * sd, "channel {channel}: {got} vs {want}");
            let exact = model.transmittance((o, d), far, &mut rng).to_array()[channel];
            assert!((exact - want).abs() < 1e-6);
        }
    }
}
