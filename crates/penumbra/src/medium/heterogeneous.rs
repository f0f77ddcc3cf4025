//! `heterogeneous`: a medium whose extinction and albedo vary through
//! space, read from volumes (Mitsuba 3's `heterogeneous`). Its extinction
//! at a point is `scale · sigma_t(p)`, its scattering `albedo(p)` times
//! that; it fills the world box of its `sigma_t` volume (for a plain number
//! or colour, the unit cube), and holds nothing outside it.
//!
//! Distances are drawn by delta tracking against a majorant. Mitsuba takes
//! one for the whole medium, `scale` times the largest value of `sigma_t`;
//! Penumbra by default divides the medium's box into a grid of
//! `majorant_resolution`³ cells, each with a bound of the extinction inside
//! it ([`MajorantGrid`]), and walks a ray through them cell by cell: in
//! thin regions the steps are long and the null collisions fewer, the
//! estimates the same. `majorant_resolution = 1` is Mitsuba's single
//! majorant. Either way the majorant is the same in every colour channel.
//!
//! A tentative collision is drawn with one random number: it sets the
//! optical depth `−ln(1 − u)` to cross, which the walk spends segment by
//! segment (a segment's majorant times its length) until it runs out
//! inside one, or the ray leaves the medium or reaches its end.

use super::{channel_of, Coefficients, Interaction, MediumModel, COMMON, SCALE, SPECTRAL_EXTINCTION};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Aabb, Rgb, Vec3};
use crate::sampling::Rng;
use crate::volume::majorant::{clip_to_box, DEFAULT_RESOLUTION};
use crate::volume::tracking::single_segment;
use crate::volume::{MajorantGrid, Segment, Volume, Volumes};

/// How the medium bounds its extinction along a ray.
#[derive(Clone, Debug, PartialEq)]
pub enum Majorant {
    /// One majorant over the whole box (Mitsuba's).
    Global(f32),
    /// A majorant per cell of a grid over the box.
    Grid(MajorantGrid),
}

/// The heterogeneous medium (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Heterogeneous {
    /// The extinction before `scale` (boxed, as volumes are large beside
    /// the other media).
    pub sigma_t: Box<Volume>,
    /// The single-scattering albedo.
    pub albedo: Box<Volume>,
    /// Multiplies `sigma_t`.
    pub scale: f32,
    /// The extinction differs between channels and is sampled so.
    pub spectral: bool,
    /// Where the medium is: the world box of `sigma_t`.
    pub bbox: Aabb,
    /// The bound of the extinction tracking walks against.
    pub majorant: Majorant,
}

/// The walks of a ray through the medium stop after this many tentative
/// collisions: a majorant far above the extinction would otherwise loop
/// long.
const MAX_COLLISIONS: usize = 100_000;

impl Heterogeneous {
    /// The majorant segments of the ray from `o` along `d` within
    /// `[0, tmax]`, in order.
    fn segments(&self, o: Vec3, d: Vec3, tmax: f32) -> impl Iterator<Item = Segment> + '_ {
        let (grid, global) = match &self.majorant {
            Majorant::Grid(g) => (Some(g.segments(o, d, 0.0, tmax)), None),
            Majorant::Global(m) => (None, single_segment(&self.bbox, o, d, 0.0, tmax, *m)),
        };
        grid.into_iter().flatten().chain(global)
    }

    /// The extinction at `p`, scaled.
    #[inline]
    fn sigma_t_at(&self, p: Vec3) -> Rgb {
        self.sigma_t.eval(p) * self.scale
    }
}

impl MediumModel for Heterogeneous {
    const NAME: &'static str = "heterogeneous";

    const SCHEMA: Schema = Schema {
        kind: Kind::Medium,
        plugin: "heterogeneous",
        what: "heterogeneous medium",
        doc: "extinction and albedo that vary through space, read from volumes",
        mitsuba: &["heterogeneous"],
        params: &[
            Param::new(
                "sigma_t",
                Type::Volume,
                "1",
                "extinction per unit length: a volume, or a number or 3 (RGB) filling the unit \
                 cube; times `scale`. The medium fills this volume's box",
            ),
            Param::new(
                "albedo",
                Type::Volume,
                "0.75",
                "the share of extinction that scatters: a volume, a number or 3 (RGB)",
            ),
            SCALE,
            SPECTRAL_EXTINCTION,
            Param::new(
                "majorant_resolution",
                Type::Int,
                "16",
                "cells of the majorant grid along each axis, each bounding the extinction in it; \
                 1: one majorant for the whole medium, `scale` times the largest `sigma_t` \
                 (Mitsuba's)",
            )
            .penumbra_only()
            .range(Range::Between(1.0, 256.0)),
            COMMON[0],
        ],
    };

    const MITSUBA: Mitsuba = Mitsuba::differs(
        "`sigma_t` and `albedo` are a float, an RGB, a spectrum (as RGB) or a volume; distances \
         are tracked against a 16³ grid of majorants rather than one (`majorant_resolution = 1` \
         is Mitsuba's); a microflake phase function is not read",
    );

    fn build(p: &Props, volumes: &Volumes) -> Result<Heterogeneous, Invalid> {
        let sigma_t = volumes.volume(p, "sigma_t", Rgb::ONE)?;
        let albedo = volumes.volume(p, "albedo", Rgb::splat(0.75))?;
        let scale = p.f32("scale")?.unwrap_or(1.0);
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(p.error("scale", format!("must be a finite number ≥ 0, got {scale}")));
        }
        let spectral = p.bool("has_spectral_extinction")?.unwrap_or(true);
        let n = p
            .int("majorant_resolution")?
            .unwrap_or(i64::from(DEFAULT_RESOLUTION[0]));
        if !(1..=256).contains(&n) {
            return Err(p.error(
                "majorant_resolution",
                format!("must be an integer from 1 to 256, got {n}"),
            ));
        }
        let majorant = if n == 1 {
            Majorant::Global(scale * sigma_t.max())
        } else {
            Majorant::Grid(sigma_t.majorant_grid(scale, [n as u32; 3]))
        };
        Ok(Heterogeneous {
            bbox: sigma_t.bbox(),
            sigma_t: Box::new(sigma_t),
            albedo: Box::new(albedo),
            scale,
            spectral,
            majorant,
        })
    }

    #[inline]
    fn is_homogeneous(&self) -> bool {
        false
    }

    #[inline]
    fn has_spectral_extinction(&self) -> bool {
        self.spectral
    }

    fn intersect_aabb(&self, o: Vec3, d: Vec3) -> Option<(f32, f32)> {
        clip_to_box(&self.bbox, o, d, f32::NEG_INFINITY, f32::INFINITY)
    }

    /// The majorant of the cell holding `p` (the global one, or 0 outside
    /// the box).
    fn majorant(&self, p: Vec3) -> Rgb {
        match &self.majorant {
            Majorant::Global(m) => Rgb::splat(*m),
            Majorant::Grid(g) => {
                let extent = g.bounds.max - g.bounds.min;
                let c = (p - g.bounds.min) / extent;
                if !(c.min_element() >= 0.0 && c.max_element() <= 1.0) {
                    return Rgb::ZERO;
                }
                let [x, y, z] = [0, 1, 2].map(|a| {
                    let n = g.resolution[a];
                    ((c[a] * n as f32) as u32).min(n - 1)
                });
                Rgb::splat(g.cell(x, y, z))
            }
        }
    }

    fn coefficients(&self, p: Vec3) -> Coefficients {
        let sigma_t = self.sigma_t_at(p);
        Coefficients {
            sigma_s: sigma_t * self.albedo.eval(p),
            sigma_n: self.majorant(p) - sigma_t,
            sigma_t,
        }
    }

    /// Walks the majorant segments, spending the optical depth `−ln(1 − u)`;
    /// the collision's majorant is its segment's, and its `mint` the
    /// segment's start. No collision reports a majorant of 0, so that a
    /// caller's transmittance over its drawing density is 1 (the majorant
    /// is grey: the ratio of channels is 1 whatever the length).
    fn sample_interaction(
        &self,
        (o, d): (Vec3, Vec3),
        tmax: f32,
        u: f32,
        _channel: usize,
    ) -> Interaction {
        let mut depth = -(1.0 - u).ln();
        for s in self.segments(o, d, tmax) {
            if !(s.majorant.is_finite() && s.majorant > 0.0) {
                continue;
            }
            let across = s.majorant * (s.t1 - s.t0);
            if depth < across {
                let t = s.t0 + depth / s.majorant;
                let p = o + d * t;
                let sigma_t = self.sigma_t_at(p);
                let m = Rgb::splat(s.majorant);
                return Interaction {
                    t,
                    p,
                    mint: s.t0,
                    sigma: Coefficients {
                        sigma_s: sigma_t * self.albedo.eval(p),
                        sigma_n: m - sigma_t,
                        sigma_t,
                    },
                    majorant: m,
                };
            }
            depth -= across;
        }
        Interaction {
            t: f32::INFINITY,
            p: o,
            mint: 0.0,
            sigma: Coefficients::default(),
            majorant: Rgb::ZERO,
        }
    }

    /// Ratio tracking over the majorant segments: the product, channel by
    /// channel, of `1 − σt / σ̄` at each tentative collision.
    fn transmittance(&self, (o, d): (Vec3, Vec3), tmax: f32, rng: &mut Rng) -> Rgb {
        let mut tr = Rgb::ONE;
        let mut collisions = 0;
        for s in self.segments(o, d, tmax) {
            if !(s.majorant.is_finite() && s.majorant > 0.0) {
                continue;
            }
            let mut t = s.t0;
            loop {
                t -= (1.0 - rng.next_f32()).ln() / s.majorant;
                if t >= s.t1 {
                    break;
                }
                tr *= Rgb::ONE - self.sigma_t_at(o + d * t) / s.majorant;
                collisions += 1;
                if collisions >= MAX_COLLISIONS || channel_of(tr.abs(), 0).is_nan() {
                    return tr;
                }
                if tr.max_element() <= 0.0 {
                    return Rgb::ZERO;
                }
            }
        }
        tr
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A medium whose extinction rises along z through its box `[0, 1]³`
    /// (a constant volume cannot, so a grid of 2×2×n voxels, nearest
    /// lookup being exact on its cells).
    fn ramp(resolution: u32) -> Heterogeneous {
        use crate::volume::gridvolume::{Filter, GridVolume};
        use crate::volume::vol_file::VolGrid;
        let n = 32;
        let data: Vec<f32> = (0..n)
            .flat_map(|z| std::iter::repeat_n(4.0 * (z as f32 + 0.5) / n as f32, 4))
            .collect();
        let grid = VolGrid {
            resolution: [2, 2, n],
            channels: 1,
            bbox: Aabb::new(Vec3::ZERO, Vec3::ONE),
            data,
        };
        let sigma_t = Volume::GridVolume(GridVolume::new(
            std::sync::Arc::new(grid),
            Filter::Nearest,
            crate::texture::bitmap::Wrap::Clamp,
            crate::math::Mat4::IDENTITY,
        ));
        let majorant = if resolution == 1 {
            Majorant::Global(sigma_t.max())
        } else {
            Majorant::Grid(sigma_t.majorant_grid(1.0, [resolution; 3]))
        };
        Heterogeneous {
            bbox: sigma_t.bbox(),
            sigma_t: Box::new(sigma_t),
            albedo: Box::new(Volume::constant(Rgb::splat(0.5))),
            scale: 1.0,
            spectral: true,
            majorant,
        }
    }

    /// Delta tracking through the cells (one number per tentative
    /// collision, real ones kept with probability σt / σ̄) lets a ray
    /// through the slab with probability `exp(−∫ σt)`, and ratio tracking
    /// averages the same; with the grid, fewer null collisions than with
    /// the one majorant.
    #[test]
    fn grid_and_global_tracking_give_the_transmittance() {
        let (o, d) = (Vec3::new(0.3, 0.6, -1.0), Vec3::Z);
        // The voxels' values are 4 (z + 0.5) / 32 for z in 0..32: ∫ = 2.
        let want = (-2.0f64).exp();
        let mut nulls_by = Vec::new();
        for resolution in [16, 1] {
            let m = ramp(resolution);
            let mut rng = Rng::new(5);
            let n = 100_000;
            let (mut through, mut nulls) = (0usize, 0usize);
            for _ in 0..n {
                let mut from = 0.0f32;
                loop {
                    let mi = m.sample_interaction((o + d * from, d), 5.0 - from, rng.next_f32(), 0);
                    if !mi.is_valid() {
                        through += 1;
                        break;
                    }
                    assert!((-1e-5..=1.0 + 1e-5).contains(&mi.p.z), "{:?}", mi.p);
                    assert!(mi.sigma.sigma_n.min_element() >= -1e-5, "{:?}", mi.sigma);
                    if rng.next_f32() < mi.sigma.sigma_t.r / mi.majorant.r {
                        break;
                    }
                    nulls += 1;
                    from += mi.t;
                }
            }
            let got = through as f64 / n as f64;
            let sd = (want * (1.0 - want) / n as f64).sqrt();
            assert!((got - want).abs() < 4.0 * sd, "{resolution}: {got} vs {want}");
            let (mut sum, mut sq) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let tr = f64::from(m.transmittance((o, d), 5.0, &mut rng).r);
                sum += tr;
                sq += tr * tr;
            }
            let mean = sum / n as f64;
            let se = ((sq / n as f64 - mean * mean) / n as f64).sqrt().max(1e-6);
            assert!((mean - want).abs() < 4.0 * se, "{resolution}: {mean} ± {se} vs {want}");
            nulls_by.push(nulls);
        }
        assert!(nulls_by[0] * 2 < nulls_by[1], "{nulls_by:?}");
    }

    /// Outside its box the medium holds nothing: a ray that misses it
    /// passes whole, with no collision.
    #[test]
    fn nothing_outside_the_box() {
        let m = ramp(16);
        let (o, d) = (Vec3::new(2.0, 0.5, -1.0), Vec3::Z);
        let mut rng = Rng::new(1);
        assert!(m.intersect_aabb(o, d).is_none());
        assert!(!m.sample_interaction((o, d), 10.0, 0.999, 0).is_valid());
        assert_eq!(m.transmittance((o, d), 10.0, &mut rng), Rgb::ONE);
        assert_eq!(m.majorant(o), Rgb::ZERO);
    }
}
