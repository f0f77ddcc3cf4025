//! `sky`: a procedural environment, a gradient sky over a uniform ground
//! with a sun disc, computed when the scene is built into an
//! equirectangular map that then lights the scene as an
//! [`envmap`](super::envmap) does, but read by the nearest pixel and
//! importance-sampled pixel by pixel ([`Envmap::nearest`]): each pixel
//! holds what lies around its centre, and the sun is normalised over the
//! pixels. A scene lit by a sky needs no image file.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `zenith` | colour ≥ 0 | [0.12, 0.25, 0.6] | radiance straight up (`+y`) |
//! | `horizon` | colour ≥ 0 | [0.6, 0.7, 0.85] | radiance just above the horizon |
//! | `ground` | colour ≥ 0 | [0.2, 0.18, 0.16] | radiance of every direction below the horizon |
//! | `sun_direction` | vector ≠ 0 | [1, 1, 1] | toward the sun's centre |
//! | `sun_radius` | degrees, 0.01–90 | 1 | the disc's angular radius (the sun's is about 0.27) |
//! | `sun_irradiance` | colour ≥ 0 | [3, 2.85, 2.6] | irradiance the disc gives a surface facing it; 0: no sun |
//! | `resolution` | even integer, 8–2048 | 512 | rows of the map; it has twice as many columns |
//!
//! The sky is fixed to the world: `+y` is the zenith. Above the horizon,
//! at elevation `e`, its radiance is `horizon + (zenith − horizon) ·
//! √(sin e)`; below it, `ground`. Each pixel of the map holds the value at
//! its centre (the horizon lies between two rows).
//!
//! The sun is the disc of directions within `sun_radius` of
//! `sun_direction`, of one radiance. A pixel holds that radiance times the
//! share of its solid angle the disc covers, measured by 8 × 8 points
//! spread evenly over the pixel's solid angle, and the radiance is the one
//! that makes the disc's irradiance on a surface facing the sun, summed
//! over the map's pixels, exactly `sun_irradiance` (for a disc the map
//! resolves, `sun_irradiance / (π sin² sun_radius)`). A disc too small for
//! the points to meet lies whole in the pixel of its centre. The disc is
//! added to the sky wherever it is, below the horizon too.
//!
//! Penumbra's own: Mitsuba 3's `sunsky` (a physically based sky model) is
//! another thing, which the XML reader refuses; `penumbra convert` never
//! writes a sky.

use crate::texture::Textures;

use std::f32::consts::PI;

use super::envmap::Envmap;
use super::model::EmitterPlugin;
use crate::description::check::{int, nonneg3, nonzero3, range};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Mat3, Rgb, Vec3};

/// Points per pixel side measuring the sun's share of a pixel.
const SUN_POINTS: usize = 8;

/// A gradient sky and a sun disc, to be made into an environment map.
#[derive(Clone, Copy, Debug)]
pub struct Sky {
    pub zenith: Rgb,
    pub horizon: Rgb,
    pub ground: Rgb,
    /// Unit direction toward the sun's centre.
    pub sun_direction: Vec3,
    /// Angular radius of the disc, in radians.
    pub sun_radius: f32,
    pub sun_irradiance: Rgb,
    /// Rows of the map (even); it has twice as many columns.
    pub resolution: usize,
}

impl Default for Sky {
    fn default() -> Sky {
        Sky {
            zenith: Rgb::new(0.12, 0.25, 0.6),
            horizon: Rgb::new(0.6, 0.7, 0.85),
            ground: Rgb::new(0.2, 0.18, 0.16),
            sun_direction: Vec3::ONE.normalize(),
            sun_radius: 1f32.to_radians(),
            sun_irradiance: Rgb::new(3.0, 2.85, 2.6),
            resolution: 512,
        }
    }
}

impl Sky {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "sky",
        what: "sky",
        doc: "a gradient sky and a sun disc, computed into an environment map when the scene is built",
        mitsuba: &[],
        params: &[
            Param::new(
                "zenith",
                Type::Colour,
                "[0.12, 0.25, 0.6]",
                "radiance straight up (+y), ≥ 0",
            ).range(Range::NonNegative),
            Param::new(
                "horizon",
                Type::Colour,
                "[0.6, 0.7, 0.85]",
                "radiance just above the horizon, ≥ 0",
            ).range(Range::NonNegative),
            Param::new(
                "ground",
                Type::Colour,
                "[0.2, 0.18, 0.16]",
                "radiance below the horizon, ≥ 0",
            ).range(Range::NonNegative),
            Param::new(
                "sun_direction",
                Type::Vector,
                "[1, 1, 1]",
                "the direction toward the sun's centre, ≠ 0",
            ),
            Param::new(
                "sun_radius",
                Type::Number,
                "1",
                "the sun's angular radius in degrees, 0.01–90",
            ).range(Range::Between(0.01, 90.0)),
            Param::new(
                "sun_irradiance",
                Type::Colour,
                "[3, 2.85, 2.6]",
                "irradiance of the sun on a surface facing it, ≥ 0",
            ).range(Range::NonNegative),
            Param::new(
                "resolution",
                Type::Int,
                "512",
                "rows of the map (even, 8–2048); twice as many columns",
            ),
        ],
    };

    /// Penumbra's own: no Mitsuba plugin reads as it.
    pub const MITSUBA: Mitsuba = Mitsuba::SAME;

    /// The sky of a scene's parameters.
    pub fn build(p: &Props) -> Result<Sky, Invalid> {
        let d = Sky::default();
        let resolution = int(p, "resolution", 512, 8, 2048)? as usize;
        if !resolution.is_multiple_of(2) {
            return Err(p.error(
                "resolution",
                format!("must be even (the horizon lies between two rows), got {resolution}"),
            ));
        }
        Ok(Sky {
            zenith: nonneg3(p, "zenith", d.zenith.to_array())?,
            horizon: nonneg3(p, "horizon", d.horizon.to_array())?,
            ground: nonneg3(p, "ground", d.ground.to_array())?,
            sun_direction: nonzero3(p, "sun_direction", [1.0; 3])?.normalize(),
            sun_radius: range(p, "sun_radius", 1.0, 0.01, 90.0)?.to_radians(),
            sun_irradiance: nonneg3(p, "sun_irradiance", d.sun_irradiance.to_array())?,
            resolution,
        })
    }

    /// The sky's radiance along the unit direction `dir` (toward the sky),
    /// without the sun.
    pub fn gradient(&self, dir: Vec3) -> Rgb {
        if dir.y < 0.0 {
            self.ground
        } else {
            let t = dir.y.min(1.0).sqrt();
            self.horizon * (1.0 - t) + self.zenith * t
        }
    }

    /// The map's width and height and its pixels, row by row from the top,
    /// in [`Envmap`]'s orientation (the identity `to_world`).
    pub fn pixels(&self) -> (usize, usize, Vec<Rgb>) {
        let (w, h) = (2 * self.resolution, self.resolution);
        let centre = |x: usize, y: usize| {
            Envmap::map_direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32)
        };
        let mut radiance: Vec<Rgb> = (0..w * h)
            .map(|i| self.gradient(centre(i % w, i / w)))
            .collect();
        if self.sun_irradiance.max_element() > 0.0 {
            let share = self.sun_share(w, h);
            // The irradiance of a disc of radiance 1 as the map holds it.
            let irradiance: f64 = share
                .iter()
                .map(|&(i, s)| {
                    let (x, y) = (i % w, i / w);
                    let cos = centre(x, y).dot(self.sun_direction).max(0.0);
                    f64::from(s * cos) * pixel_solid_angle(y, w, h)
                })
                .sum();
            let sun = self.sun_irradiance * (1.0 / irradiance) as f32;
            for (i, s) in share {
                radiance[i] += sun * s;
            }
        }
        (w, h, radiance)
    }

    /// The environment map of the sky.
    pub fn envmap(&self) -> Envmap {
        let (w, h, radiance) = self.pixels();
        Envmap::nearest(w, h, radiance, Mat3::IDENTITY)
    }

    /// The pixels the sun covers (by index) and the share of each one's
    /// solid angle it covers; the pixel of its centre alone if no point
    /// meets it.
    fn sun_share(&self, w: usize, h: usize) -> Vec<(usize, f32)> {
        let cos_r = self.sun_radius.cos();
        // No point of a pixel lies farther than π / h from its centre
        // (half its height along a meridian, then at most half its width
        // along a parallel).
        let reach = (self.sun_radius + PI / h as f32).min(PI).cos();
        let n = SUN_POINTS;
        let mut share = Vec::new();
        for y in 0..h {
            let (c0, c1) = (
                (PI * y as f32 / h as f32).cos(),
                (PI * (y + 1) as f32 / h as f32).cos(),
            );
            for x in 0..w {
                let c =
                    Envmap::map_direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                if c.dot(self.sun_direction) < reach {
                    continue;
                }
                let mut inside = 0;
                for j in 0..n {
                    // Evenly in cos θ: equal solid angles.
                    let cos_t = c0 + (j as f32 + 0.5) / n as f32 * (c1 - c0);
                    let v = cos_t.clamp(-1.0, 1.0).acos() / PI;
                    for i in 0..n {
                        let u = (x as f32 + (i as f32 + 0.5) / n as f32) / w as f32;
                        if Envmap::map_direction(u, v).dot(self.sun_direction) >= cos_r {
                            inside += 1;
                        }
                    }
                }
                if inside > 0 {
                    share.push((y * w + x, inside as f32 / (n * n) as f32));
                }
            }
        }
        if share.is_empty() {
            let d = self.sun_direction;
            let u = (d.x.atan2(-d.z) / (2.0 * PI)).rem_euclid(1.0);
            let v = d.y.clamp(-1.0, 1.0).acos() / PI;
            let x = ((u * w as f32) as usize).min(w - 1);
            let y = ((v * h as f32) as usize).min(h - 1);
            share.push((y * w + x, 1.0));
        }
        share
    }
}

/// The solid angle of a pixel of row `y` of a `w` × `h` map.
fn pixel_solid_angle(y: usize, w: usize, h: usize) -> f64 {
    let theta = |y: usize| std::f64::consts::PI * y as f64 / h as f64;
    std::f64::consts::TAU / w as f64 * (theta(y).cos() - theta(y + 1).cos())
}

impl EmitterPlugin for Sky {
    type Built = Envmap;

    fn build(p: &Props, _textures: &Textures) -> Result<Envmap, Invalid> {
        Ok(Sky::build(p)?.envmap())
    }
}

#[cfg(test)]
mod tests {
    use super::super::envmap::tests::{likeliest_pixel, sampled_counts, sampling_chi2};
    use super::*;
    use crate::math::Vec2;
    use crate::sampling::Rng;

    fn dark(sun_direction: Vec3, radius_deg: f32, resolution: usize) -> Sky {
        Sky {
            zenith: Rgb::ZERO,
            horizon: Rgb::ZERO,
            ground: Rgb::ZERO,
            sun_direction: sun_direction.normalize(),
            sun_radius: radius_deg.to_radians(),
            sun_irradiance: Rgb::new(2.0, 3.0, 4.0),
            resolution,
        }
    }

    /// The gradient's formula: the zenith straight up, the horizon just
    /// above it, √(sin e) of the way at elevation e, the ground below.
    #[test]
    fn the_gradient_runs_from_horizon_to_zenith() {
        let s = Sky::default();
        assert_eq!(s.gradient(Vec3::Y), s.zenith);
        assert_eq!(s.gradient(-Vec3::Y), s.ground);
        assert_eq!(s.gradient(Vec3::new(1.0, -1e-6, 0.0).normalize()), s.ground);
        let near = s.gradient(Vec3::new(1.0, 1e-8, 0.0).normalize());
        assert!(((near - s.horizon).abs()).max_element() < 1e-3, "{near:?}");
        let e30 = Vec3::new(0.0, 0.5, 0.75f32.sqrt());
        let want = s.horizon + (s.zenith - s.horizon) * 0.5f32.sqrt();
        assert!(((s.gradient(e30) - want).abs()).max_element() < 1e-6);
    }

    /// Without a sun, the map looked up at every pixel's centre is the
    /// gradient there: the pixels are laid out as [`Envmap`] reads them.
    #[test]
    fn the_map_holds_the_gradient() {
        let s = Sky {
            sun_irradiance: Rgb::ZERO,
            resolution: 16,
            ..Sky::default()
        };
        let e = s.envmap();
        let (w, h) = (32, 16);
        for y in 0..h {
            for x in 0..w {
                let d =
                    Envmap::map_direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                assert_eq!(e.eval(d), s.gradient(d), "pixel ({x}, {y})");
            }
        }
        // The top rows are near the zenith, the bottom half is ground.
        let top = e.eval(Vec3::new(0.01, 1.0, 0.0).normalize());
        assert!((top - s.zenith).abs().max_element() < 0.1, "{top:?}");
        assert_eq!(e.eval(Vec3::new(0.3, -0.01, 1.0).normalize()), s.ground);
    }

    /// A resolved sun's radiance is `E / (π sin² r)` at its centre and
    /// nothing lies beyond it; suns of every size, at the pole, on the
    /// seam of the map and below the horizon give a surface facing them
    /// their irradiance: summed over the map, and estimated from 10⁵
    /// samples of the map's importance sampling (a second route: the
    /// sampler's densities, not the pixels' solid angles).
    #[test]
    fn the_sun_gives_its_irradiance() {
        let s = dark(Vec3::new(0.3, 0.8, -0.4), 2.0, 512);
        let e = s.envmap();
        let r = s.sun_radius;
        let at_centre = e.eval(s.sun_direction);
        let want = s.sun_irradiance * (1.0 / (PI * r.sin().powi(2)));
        let err = ((at_centre - want) / want).abs().max_element();
        assert!(err < 0.02, "{at_centre:?} vs {want:?}");
        let frame = crate::math::Frame::from_normal(s.sun_direction);
        for k in 0..16 {
            let phi = k as f32 / 16.0 * 2.0 * PI;
            let off = |a: f32| {
                (s.sun_direction * a.cos() + (frame.u * phi.cos() + frame.v * phi.sin()) * a.sin())
                    .normalize()
            };
            assert_eq!(e.eval(off(1.5 * r)), Rgb::ZERO);
            assert!(e.eval(off(0.5 * r)).min_element() > 0.0);
        }
        let suns = [
            (Vec3::new(0.3, 0.8, -0.4), 2.0, 512),
            (Vec3::new(0.0, 1.0, 0.02), 5.0, 64),
            (Vec3::new(-0.01, 0.2, -1.0), 1.0, 256),
            (Vec3::new(1.0, -0.3, 0.2), 30.0, 64),
            (Vec3::new(0.2, 0.5, 0.7), 0.01, 32),
        ];
        let mut rng = Rng::new(31);
        for (dir, deg, res) in suns {
            let s = dark(dir, deg, res);
            let (w, h, pixels) = s.pixels();
            let mut summed = [0.0f64; 3];
            for (i, l) in pixels.iter().enumerate() {
                let (x, y) = (i % w, i / w);
                let c =
                    Envmap::map_direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let cos = f64::from(c.dot(s.sun_direction).max(0.0));
                for (sum, v) in summed.iter_mut().zip(l.to_array()) {
                    *sum += f64::from(v) * cos * pixel_solid_angle(y, w, h);
                }
            }
            let e = Envmap::nearest(w, h, pixels, Mat3::IDENTITY);
            let n = 100_000;
            let mut sampled = Rgb::ZERO;
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                if let Some((d, l, pdf)) = e.sample(u) {
                    sampled += l * (d.dot(s.sun_direction).max(0.0) / pdf);
                }
            }
            let sampled = sampled / n as f32;
            for (c, want) in s.sun_irradiance.to_array().into_iter().enumerate() {
                let got = summed[c] as f32;
                assert!(
                    (got / want - 1.0).abs() < 1e-3,
                    "{dir:?} {deg}°: summed {got} vs {want}"
                );
                let got = sampled.to_array()[c];
                assert!(
                    (got / want - 1.0).abs() < 0.02,
                    "{dir:?} {deg}°: sampled {got} vs {want}"
                );
            }
        }
    }

    /// The map's importance sampling passes the χ² test of file maps
    /// (4 · 10⁶ directions in 3 × 3 sub-cells of each pixel) on a small
    /// sky whose sun covers many pixels, and fails it with the sun's
    /// likeliest pixel 5% off.
    #[test]
    fn a_skys_samples_follow_the_pdf() {
        let s = Sky {
            sun_direction: Vec3::new(1.0, 1.2, -0.5).normalize(),
            sun_radius: 15f32.to_radians(),
            resolution: 12,
            ..Sky::default()
        };
        let e = s.envmap();
        let n = 4_000_000;
        let counts = sampled_counts(&e, n, 3, 5);
        let (good, q) = sampling_chi2(&e, &counts, n, 3, None);
        assert!(good < q, "χ² {good} (0.999 quantile {q})");
        let (bad, _) = sampling_chi2(&e, &counts, n, 3, Some(likeliest_pixel(&e)));
        eprintln!(
            "sky χ²: {good:.1} as drawn, {bad:.1} with a pixel 5% off (0.999 quantile {q:.0})"
        );
        assert!(bad > q, "χ² {bad} with a 5% error");
    }
}
