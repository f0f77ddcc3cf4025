//! `envmap`: radiance arriving from every direction at infinity, read from
//! an equirectangular (latitude-longitude) image (Mitsuba 3's `envmap`).
//! Rays that hit nothing see it, interpolated bilinearly between pixel
//! centres as Mitsuba looks it up; the integrators that follow paths sample
//! it by importance: a direction is drawn with a density proportional to
//! the bilinear interpolant of the pixels' luminance · sin θ
//! ([`Bilinear2D`]), so a small bright sun is found by most samples.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | path | **required** | the image: OpenEXR, Radiance HDR, PNG or JPEG (8-bit files are sRGB-decoded) |
//! | `scale` | number ≥ 0 | 1 | factor on every pixel's radiance |
//! | `to_world` | 4×4 rows | identity | orientation (its linear part, a rotation or reflection) |
//! | `mis_compensation` | bool | false | sample `max(luminance − mean, 0)` instead of the luminance (Karlík et al. 2019) |
//!
//! The orientation is Mitsuba's: in the map's own frame the top row is
//! `+y` (θ = 0), and the column at `u` (0 at the left edge, 1 at the
//! right) lies at azimuth φ = 2π u, the direction
//! `(sin φ sin θ, cos θ, −cos φ sin θ)` with θ = π v (v from the top): the
//! image's centre looks along `+z`, its left edge along `−z`.
//!
//! The lookup is Mitsuba's too. Across, pixel `x` of `W` holds the value at
//! its centre, `u = (x + ½) / W`, and the map wraps around (between the
//! last column's centre and the first's it blends the two). Down, row `y`
//! of `H` holds the value at `v = y / (H − 1)`: the first row is the
//! zenith, the last the nadir, and `v` is clamped to them. Between these
//! points the radiance is interpolated bilinearly. A map narrower than 2
//! pixels or lower than 3 is first padded by repeating its last column and
//! row, as Mitsuba pads it.
//!
//! Sampling follows Mitsuba's warp: a grid of `W + 1` by `H` values, the
//! luminance of each pixel (the first column repeated at the end, so the
//! grid closes around the sphere) times sin θ of its row, drawn from with
//! a density proportional to their bilinear interpolant and shifted half a
//! pixel across, onto the pixels' centres. With `mis_compensation` the
//! luminance less its mean over the map (at least 0) is used instead,
//! unless the map is nearly uniform: directions darker than the mean are
//! then left to the other techniques multiple importance sampling combines
//! with this one (a BSDF's samples), where the map is dim anyway.
//!
//! The `sky` emitter's maps are looked up by their nearest pixel and
//! sampled piecewise-constant ([`Envmap::nearest`]): a sky's pixels hold
//! what lies around their centres, its sun's radiance is normalised over
//! them.

use std::path::Path;

use crate::texture::Textures;
use std::sync::Arc;

use crate::description::check::range;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::input::image::{read_image, Encoding};
use crate::math::{Mat3, Rgb, Vec2, Vec3};
use crate::sampling::bilinear2d::Bilinear2D;
use crate::sampling::piecewise2d::Piecewise2D;

use super::model::{EmitterModel, EmitterPlugin};
use super::sample::{ray_from_infinity, EmittedRay};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct Envmap {
    map: Arc<Map>,
    /// Map frame to world, and back (orthogonal).
    to_world: Mat3,
    to_local: Mat3,
}

/// The pixels (times `scale`) and their distribution, shared by the clones.
#[derive(Debug)]
struct Map {
    width: usize,
    height: usize,
    radiance: Vec<Rgb>,
    lookup: Lookup,
}

/// How a map is read between its pixels, with the distribution sampling it.
#[derive(Debug)]
enum Lookup {
    /// Mitsuba's: bilinear between pixel centres (rows at `v = y / (H −
    /// 1)`), sampled over the `(W + 1)` × `H` grid shifted half a pixel.
    Bilinear(Bilinear2D),
    /// Each pixel constant over it, sampled cell by cell.
    Nearest(Piecewise2D),
}

impl Envmap {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "envmap",
        what: "environment map",
        doc: "radiance from every direction read from an equirectangular image, importance-sampled",
        mitsuba: &["envmap"],
        params: &[
            Param::new(
                "filename",
                Type::Path,
                "required",
                "the equirectangular image (EXR, HDR, PNG, JPEG), relative to the scene file",
            ),
            Param::new("scale", Type::Number, "1", "factor on the radiance, ≥ 0")
                .range(Range::NonNegative),
            Param::new(
                "to_world",
                Type::Matrix4,
                "identity",
                "orientation: a rotation (or reflection) as 4 rows",
            ),
            Param::new(
                "mis_compensation",
                Type::Bool,
                "false",
                "sample the luminance less its mean over the map (at least 0), leaving dim directions to the BSDF's samples under multiple importance sampling",
            ),
        ],
    };

    /// How Mitsuba's `envmap` maps onto it.
    pub const MITSUBA: Mitsuba = Mitsuba::differs(
        "`to_world` must be a rotation or reflection; the `bitmap` parameter is refused",
    );

    /// The emitter of a scene's parameters; `base_dir` anchors a relative
    /// `filename`.
    pub fn build(p: &Props, base_dir: &Path) -> Result<Envmap, Invalid> {
        let Some(file) = p.string("filename")? else {
            return Err(p.node_error("the environment map needs `filename`"));
        };
        let scale = range(p, "scale", 1.0, 0.0, f32::MAX)?;
        let mis_compensation = p.bool("mis_compensation")?.unwrap_or(false);
        let to_world = match p.matrix4("to_world")? {
            None => Mat3::IDENTITY,
            Some(rows) => {
                let m = Mat3::from_cols_array_2d(&[
                    [rows[0][0], rows[1][0], rows[2][0]],
                    [rows[0][1], rows[1][1], rows[2][1]],
                    [rows[0][2], rows[1][2], rows[2][2]],
                ]);
                let off = (m.transpose() * m - Mat3::IDENTITY).to_cols_array();
                if off.iter().any(|v| !v.is_finite() || v.abs() >= 1e-3) {
                    return Err(p.error(
                        "to_world",
                        "an environment map's `to_world` must be a rotation (or a reflection), \
                         without scale or shear",
                    ));
                }
                m
            }
        };
        let path = base_dir.join(file);
        let image = read_image(&path, Encoding::Srgb)
            .map_err(|e| p.error("filename", format!("cannot read the environment map: {e}")))?;
        let (w, h) = (image.width as usize, image.height as usize);
        let mut radiance = Vec::with_capacity(w * h);
        for y in 0..image.height {
            for x in 0..image.width {
                let [r, g, b] = image.rgb(x, y);
                if !([r, g, b].iter().all(|v| v.is_finite() && *v >= 0.0)) {
                    return Err(p.error(
                        "filename",
                        format!(
                            "{}: pixel ({x}, {y}) is ({r}, {g}, {b}): radiance must be finite and ≥ 0",
                            path.display()
                        ),
                    ));
                }
                radiance.push(Rgb::new(r, g, b) * scale);
            }
        }
        Ok(Envmap::new(w, h, radiance, to_world, mis_compensation))
    }

    /// The map of `width` × `height` pixels of `radiance` (row by row from
    /// the top, each finite and ≥ 0) oriented by `to_world` (orthogonal),
    /// looked up and sampled as Mitsuba's `envmap` does; with
    /// `mis_compensation`, sampled by the luminance less its mean.
    pub fn new(
        width: usize,
        height: usize,
        radiance: Vec<Rgb>,
        to_world: Mat3,
        mis_compensation: bool,
    ) -> Envmap {
        let (width, height, radiance) = padded(width, height, radiance);
        let lum: Vec<f32> = radiance.iter().map(|l| luminance(*l)).collect();
        let offset = if mis_compensation {
            let mean = (lum.iter().map(|&l| f64::from(l)).sum::<f64>() / lum.len() as f64) as f32;
            let min = lum.iter().copied().fold(f32::INFINITY, f32::min);
            // A (nearly) uniform map keeps its luminance.
            if mean - min <= 0.01 * mean {
                0.0
            } else {
                mean
            }
        } else {
            0.0
        };
        // Row y at θ = π y / (H − 1); the first column again at the end.
        let step = PI / (height - 1) as f32;
        let mut values = Vec::with_capacity((width + 1) * height);
        for y in 0..height {
            let sin_t = (y as f32 * step).sin().max(0.0);
            for x in 0..=width {
                let l = lum[y * width + x % width];
                values.push((l - offset).max(0.0) * sin_t);
            }
        }
        // A black map is drawn from uniformly (every sample brings 0).
        let distribution = Bilinear2D::new(width + 1, height, values)
            .or_else(|| Bilinear2D::new(width + 1, height, vec![1.0; (width + 1) * height]))
            .expect("a grid of ones");
        Envmap::with(
            width,
            height,
            radiance,
            Lookup::Bilinear(distribution),
            to_world,
        )
    }

    /// The map of `width` × `height` pixels of `radiance` (as for
    /// [`new`](Self::new)), each pixel's radiance constant over it, sampled
    /// piecewise-constant by luminance · sin θ at the pixel's centre: the
    /// `sky`'s maps.
    pub fn nearest(width: usize, height: usize, radiance: Vec<Rgb>, to_world: Mat3) -> Envmap {
        let weights = radiance
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let theta = PI * ((i / width) as f32 + 0.5) / height as f32;
                l.luminance().max(0.0) * theta.sin()
            })
            .collect();
        // A black map is drawn from uniformly (every sample brings 0).
        let distribution = Piecewise2D::new(width, height, weights)
            .or_else(|| Piecewise2D::new(width, height, vec![1.0; width * height]))
            .expect("a grid of ones");
        Envmap::with(
            width,
            height,
            radiance,
            Lookup::Nearest(distribution),
            to_world,
        )
    }

    fn with(
        width: usize,
        height: usize,
        radiance: Vec<Rgb>,
        lookup: Lookup,
        to_world: Mat3,
    ) -> Envmap {
        Envmap {
            map: Arc::new(Map {
                width,
                height,
                radiance,
                lookup,
            }),
            to_world,
            to_local: to_world.transpose(),
        }
    }

    /// The direction in the map's own frame of the point `(u, v)` of the
    /// image (u right, v down, each in [0, 1]).
    #[inline]
    pub fn map_direction(u: f32, v: f32) -> Vec3 {
        let (sin_t, cos_t) = (PI * v).sin_cos();
        let (sin_p, cos_p) = (2.0 * PI * u).sin_cos();
        Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t)
    }

    /// The point of the image (u right, v down, each in [0, 1]) a world
    /// direction looks at, and sin θ there. A map read bilinearly takes θ
    /// from sin θ and cos θ together, precise near the poles too, where the
    /// density is its row's weight over sin θ and both must agree; a map
    /// read by the nearest pixel takes it from cos θ alone.
    #[inline]
    fn uv(&self, dir: Vec3) -> (Vec2, f32) {
        let d = (self.to_local * dir).normalize_or_zero();
        let u = d.x.atan2(-d.z) / (2.0 * PI);
        let u = if u < 0.0 { u + 1.0 } else { u };
        let sin_t = d.x.hypot(d.z);
        let v = match self.map.lookup {
            Lookup::Bilinear(_) => sin_t.atan2(d.y) / PI,
            Lookup::Nearest(_) => d.y.clamp(-1.0, 1.0).acos() / PI,
        };
        (Vec2::new(u, v), sin_t)
    }

    #[inline]
    fn pixel(&self, uv: Vec2) -> Rgb {
        let m = &self.map;
        let x = ((uv.x * m.width as f32) as usize).min(m.width - 1);
        let y = ((uv.y * m.height as f32) as usize).min(m.height - 1);
        m.radiance[y * m.width + x]
    }

    /// The radiance at the point `(u, v)` of the image interpolated
    /// bilinearly between the pixels' points (`u` wraps, `v` is clamped).
    #[inline]
    fn bilinear(&self, u: f32, v: f32) -> Rgb {
        let m = &self.map;
        let (w, h) = (m.width, m.height);
        let x = (u - u.floor()) * w as f32 - 0.5;
        let x0 = x.floor();
        let tx = x - x0;
        // x0 runs from −1 (left of the first centre: the last column) to
        // W − 1 (right of the last: blended with the first).
        let i0 = if x0 < 0.0 {
            w - 1
        } else {
            (x0 as usize).min(w - 1)
        };
        let i1 = if i0 + 1 == w { 0 } else { i0 + 1 };
        let y = v.clamp(0.0, 1.0) * (h - 1) as f32;
        let j0 = (y as usize).min(h - 2);
        let ty = y - j0 as f32;
        let at = |i: usize, j: usize| m.radiance[j * w + i];
        let top = at(i0, j0) * (1.0 - tx) + at(i1, j0) * tx;
        let bottom = at(i0, j0 + 1) * (1.0 - tx) + at(i1, j0 + 1) * tx;
        top * (1.0 - ty) + bottom * ty
    }

    /// The radiance at the point `uv` of the image, as the map is read.
    #[inline]
    fn lookup(&self, uv: Vec2) -> Rgb {
        match self.map.lookup {
            Lookup::Bilinear(_) => self.bilinear(uv.x, uv.y),
            Lookup::Nearest(_) => self.pixel(uv),
        }
    }

    /// The radiance arriving along the world direction `dir` (toward the
    /// map).
    #[inline]
    pub fn eval(&self, dir: Vec3) -> Rgb {
        self.lookup(self.uv(dir).0)
    }

    /// The direction toward the map for the point `u` of the unit square,
    /// the radiance from there and the solid-angle density it was drawn
    /// with; `None` at the poles, where the density is not finite.
    pub fn sample(&self, u: Vec2) -> Option<(Vec3, Rgb, f32)> {
        let (uv, pdf_uv) = match &self.map.lookup {
            Lookup::Bilinear(d) => {
                let (p, pdf) = d.sample(u);
                (Vec2::new(p.x + self.half_pixel(), p.y), pdf)
            }
            Lookup::Nearest(d) => d.sample(u),
        };
        let sin_t = (PI * uv.y).sin();
        if !(sin_t > 0.0 && pdf_uv > 0.0) {
            return None;
        }
        let local = Envmap::map_direction(uv.x, uv.y);
        let dir = (self.to_world * local).normalize();
        let pdf = pdf_uv / (2.0 * PI * PI * sin_t);
        Some((dir, self.lookup(uv), pdf))
    }

    /// Half a pixel's width in `u`: the bilinear warp's grid starts at the
    /// first pixel's centre.
    #[inline]
    fn half_pixel(&self) -> f32 {
        0.5 / self.map.width as f32
    }

    /// The power it brings into a scene of bounding radius `radius`:
    /// `π r² ∫ L dω` (mean over the colour channels), as pbrt-v4 counts a
    /// light at infinity. A map read bilinearly integrates exactly: across,
    /// a row's integral is its pixels' mean (the interpolation wraps); down,
    /// each row weighs by the integral of sin θ under its tent. A map read by
    /// the nearest pixel sums its pixels, each of solid angle
    /// `sin θ · (2π / width) · (π / height)`.
    pub fn power(&self, radius: f32) -> f32 {
        let m = &self.map;
        let row_mean = |y: usize| {
            m.radiance[y * m.width..][..m.width]
                .iter()
                .map(|l| f64::from(super::bounds::mean(*l)))
                .sum::<f64>()
                / m.width as f64
        };
        match m.lookup {
            Lookup::Bilinear(_) => {
                use std::f64::consts::PI;
                let h = m.height;
                let at = |y: usize| y as f64 / (h - 1) as f64;
                // ∫ sin(πv) and ∫ v sin(πv) over [a, b].
                let i0 = |a: f64, b: f64| ((PI * a).cos() - (PI * b).cos()) / PI;
                let prim = |v: f64| -v * (PI * v).cos() / PI + (PI * v).sin() / (PI * PI);
                let i1 = |a: f64, b: f64| prim(b) - prim(a);
                let mut weights = vec![0.0f64; h];
                for y in 0..h - 1 {
                    let (a, b) = (at(y), at(y + 1));
                    let (s0, s1) = (i0(a, b), i1(a, b));
                    weights[y] += (b * s0 - s1) / (b - a);
                    weights[y + 1] += (s1 - a * s0) / (b - a);
                }
                let sum: f64 = (0..h).map(|y| weights[y] * row_mean(y)).sum();
                (PI * f64::from(radius).powi(2) * 2.0 * PI * PI * sum) as f32
            }
            Lookup::Nearest(_) => {
                let cell = (2.0 * PI / m.width as f32) * (PI / m.height as f32);
                let mut sum = 0.0f64;
                for (i, l) in m.radiance.iter().enumerate() {
                    let theta = PI * ((i / m.width) as f32 + 0.5) / m.height as f32;
                    sum += f64::from(super::bounds::mean(*l) * theta.sin());
                }
                PI * radius * radius * (sum as f32) * cell
            }
        }
    }

    /// The solid-angle density with which [`sample`](Self::sample) draws
    /// the world direction `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let (uv, sin_t) = self.uv(dir);
        if sin_t <= 0.0 {
            return 0.0;
        }
        let pdf_uv = match &self.map.lookup {
            Lookup::Bilinear(d) => {
                let x = uv.x - self.half_pixel();
                d.pdf(Vec2::new(x - x.floor(), uv.y))
            }
            Lookup::Nearest(d) => d.pdf(uv),
        };
        pdf_uv / (2.0 * PI * PI * sin_t)
    }
}

/// The luminance of a linear sRGB colour as Mitsuba weighs a map's pixels.
#[inline]
fn luminance(l: Rgb) -> f32 {
    (0.212671 * l.r + 0.715160 * l.g + 0.072169 * l.b).max(0.0)
}

/// The map at least 2 pixels wide and 3 high, its last column and then its
/// last row repeated (Mitsuba pads a map so before reading it).
fn padded(width: usize, height: usize, radiance: Vec<Rgb>) -> (usize, usize, Vec<Rgb>) {
    if width >= 2 && height >= 3 {
        return (width, height, radiance);
    }
    let (w, h) = (width.max(2), height.max(3));
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h {
        let row = &radiance[y.min(height - 1) * width..][..width];
        out.extend((0..w).map(|x| row[x.min(width - 1)]));
    }
    (w, h, out)
}

impl EmitterPlugin for Envmap {
    type Built = Envmap;

    fn build(p: &Props, textures: &Textures) -> Result<Envmap, Invalid> {
        Envmap::build(p, &textures.base_dir)
    }
}

impl EmitterModel for Envmap {
    #[inline]
    fn is_infinite(&self) -> bool {
        true
    }

    fn power(&self, radius: f32) -> f32 {
        Envmap::power(self, radius)
    }

    #[inline]
    fn eval_miss(&self, dir: Vec3) -> Rgb {
        Envmap::eval(self, dir)
    }

    fn sample_direction(&self, u: Vec2) -> Option<(Vec3, Rgb, f32)> {
        Envmap::sample(self, u)
    }

    fn pdf_direction(&self, dir: Vec3) -> f32 {
        Envmap::pdf(self, dir)
    }

    /// A ray from infinity: its direction drawn as
    /// [`sample_direction`](EmitterModel::sample_direction) draws it, its
    /// origin on the disk of the scene's bounding sphere facing it.
    fn sample_ray(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        _: f32,
        sphere: (Vec3, f32),
    ) -> Option<EmittedRay> {
        let (to, l, pdf) = self.sample_direction(u_dir)?;
        ray_from_infinity(to, l, pdf, u_pos, sphere)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::sampling::warp::square_to_uniform_sphere;
    use crate::sampling::Rng;

    /// A map of `w` × `h` pixels with a smooth sky and a few bright spots.
    fn sky(w: usize, h: usize) -> Vec<Rgb> {
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                let l = 0.2 + (x * 0.7).sin().abs() + 0.3 * y;
                let spot = if i % 7 == 3 { 6.0 } else { 0.0 };
                Rgb::new(l + spot, 0.5 * l, 0.1 + spot)
            })
            .collect()
    }

    /// A rotation by `deg` degrees about an oblique axis.
    fn turned(deg: f32) -> Mat3 {
        Mat3::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), deg.to_radians())
    }

    /// A rotation by `deg` degrees about the y axis.
    fn about_y(deg: f32) -> Mat3 {
        Mat3::from_rotation_y(deg.to_radians())
    }

    /// Mitsuba's orientation and lookup: the image's centre looks along
    /// +z, its quarter columns along +x and −x, its edges (blended across
    /// the seam) along −z, the top row along +y, the bottom row along −y;
    /// between pixel centres the map is interpolated. Red is the column
    /// squared, green the row.
    #[test]
    fn the_orientation_is_mitsubas() {
        let (w, h) = (8, 5);
        let pixels = |w: usize, h: usize| -> Vec<Rgb> {
            (0..w * h)
                .map(|i| Rgb::new(((i % w) * (i % w)) as f32, (i / w) as f32, 1.0))
                .collect()
        };
        let e = Envmap::new(w, h, pixels(w, h), Mat3::IDENTITY, false);
        let close = |got: Rgb, r: f32, g: f32| {
            assert!(
                (got.r - r).abs() < 1e-4 * r.max(1.0) && (got.g - g).abs() < 1e-4,
                "{got:?} vs ({r}, {g})"
            );
        };
        // On the horizon (v = ½, row 2): u = ½ lies between columns 3 and
        // 4 (9 and 16), u = ¼ between 1 and 2, u = ¾ between 5 and 6, the
        // seam between 7 and 0.
        close(e.eval(Vec3::Z), 12.5, 2.0);
        close(e.eval(Vec3::X), 2.5, 2.0);
        close(e.eval(-Vec3::X), 30.5, 2.0);
        close(e.eval(-Vec3::Z), 24.5, 2.0);
        // The poles are the first and last rows (whatever the column).
        assert!((e.eval(Vec3::Y).g).abs() < 1e-4);
        assert!((e.eval(-Vec3::Y).g - 4.0).abs() < 1e-4);
        // At column 4's centre, a quarter of the way down: row 1.
        close(e.eval(Envmap::map_direction(4.5 / 8.0, 0.25)), 16.0, 1.0);
        // Turned by 90° about y, +z of the map looks along +x of the world.
        let t = Envmap::new(w, h, pixels(w, h), about_y(90.0), false);
        close(t.eval(Vec3::X), 12.5, 2.0);
        close(t.eval(-Vec3::X), 24.5, 2.0);
        close(t.eval(Vec3::Z), 30.5, 2.0);
    }

    /// The bilinear lookup returns each pixel at its point (`u` at the
    /// centre of its column, `v = y / (H − 1)`) and blends linearly between
    /// neighbours, across the seam too; `v` outside [0, 1] is clamped and
    /// `u` wraps.
    #[test]
    fn the_lookup_is_exact_at_centres_and_linear_between() {
        let (w, h) = (6, 5);
        let radiance = sky(w, h);
        let e = Envmap::new(w, h, radiance.clone(), Mat3::IDENTITY, false);
        let px = |x: usize, y: usize| radiance[y * w + x];
        let near = |a: Rgb, b: Rgb| {
            let d = (a - b).abs().max_element();
            assert!(d <= 2e-6 * b.max_element().max(1.0), "{a:?} vs {b:?}");
        };
        let (fw, fh) = (w as f32, (h - 1) as f32);
        for y in 0..h {
            for x in 0..w {
                let (u, v) = ((x as f32 + 0.5) / fw, y as f32 / fh);
                assert_eq!(e.bilinear(u, v), px(x, y), "pixel ({x}, {y})");
                // A quarter of the way to the right neighbour (the first
                // column after the last), 0.6 of the way to the one below.
                let (x1, t) = ((x + 1) % w, 0.25);
                let blended = px(x, y) * (1.0 - t) + px(x1, y) * t;
                near(e.bilinear(u + t / fw, v), blended);
                if y + 1 < h {
                    let s = 0.6;
                    let below = px(x, y + 1) * (1.0 - t) + px(x1, y + 1) * t;
                    near(
                        e.bilinear(u + t / fw, v + s / fh),
                        blended * (1.0 - s) + below * s,
                    );
                }
                // u wraps; v is clamped to the first and last rows.
                near(e.bilinear(u + 1.0, v), px(x, y));
                near(e.bilinear(u - 2.0, v), px(x, y));
            }
            // Left of the first centre: 0.4 of the way from the last
            // column to the first.
            let v = y as f32 / fh;
            near(e.bilinear(0.1 / fw, v), px(w - 1, y) * 0.4 + px(0, y) * 0.6);
        }
        near(e.bilinear(2.5 / fw, -0.3), px(2, 0));
        near(e.bilinear(2.5 / fw, 1.7), px(2, h - 1));
        // Along a line between centres the lookup is linear: equal steps,
        // equal differences.
        let at = |k: usize| e.bilinear((1.5 + k as f32 / 8.0) / fw, 0.3);
        let step = at(1) - at(0);
        for k in 1..8 {
            near(at(k + 1) - at(k), step);
        }
    }

    /// A map narrower than 2 or lower than 3 pixels is padded by its last
    /// column and row (Mitsuba's `pad_to`): one pixel is a uniform map.
    #[test]
    fn small_maps_are_padded() {
        let e = Envmap::new(1, 1, vec![Rgb::new(1.0, 2.0, 3.0)], Mat3::IDENTITY, false);
        assert_eq!((e.map.width, e.map.height), (2, 3));
        for d in [Vec3::X, -Vec3::Y, Vec3::new(0.3, 0.5, -0.8).normalize()] {
            assert_eq!(e.eval(d), Rgb::new(1.0, 2.0, 3.0));
        }
        let two_rows = vec![
            Rgb::splat(1.0),
            Rgb::splat(2.0),
            Rgb::splat(3.0),
            Rgb::splat(4.0),
        ];
        let e = Envmap::new(2, 2, two_rows, Mat3::IDENTITY, false);
        // Rows 0, 1 and 1 again at v = 0, ½ and 1.
        assert_eq!(e.bilinear(0.25, 0.0), Rgb::splat(1.0));
        assert_eq!(e.bilinear(0.25, 0.5), Rgb::splat(3.0));
        assert_eq!(e.bilinear(0.75, 1.0), Rgb::splat(4.0));
    }

    /// Every sampled direction's density is what `pdf` gives for it and its
    /// radiance what `eval` gives (both continuous now: equal but for
    /// rounding), on a turned map.
    #[test]
    fn the_sampled_pdf_is_the_evaluated_pdf() {
        let (w, h) = (12, 7);
        let e = Envmap::new(w, h, sky(w, h), turned(35.0), false);
        let mut rng = Rng::new(21);
        let mut worst = (0.0f32, 0.0f32);
        for _ in 0..200_000 {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let Some((d, l, pdf)) = e.sample(u) else {
                continue;
            };
            let p = e.pdf(d);
            let l2 = e.eval(d);
            worst.0 = worst.0.max((pdf - p).abs() / pdf);
            worst.1 = worst.1.max((l - l2).abs().max_element() / l.max_element());
        }
        eprintln!(
            "envmap: sampled vs evaluated, pdf {:.1e}, radiance {:.1e}",
            worst.0, worst.1
        );
        assert!(worst.0 < 1e-4 && worst.1 < 1e-4, "{worst:?}");
    }

    /// Pearson's χ² of 3 · 10⁶ sampled directions, found back in the
    /// warp's coordinates (`u` less half a pixel, `v`) and binned by 3 × 3
    /// sub-cells of each of its patches, against the density integrated
    /// over each sub-cell (its area times the density at its centre: exact
    /// for a bilinear density), on a turned map, with MIS compensation and
    /// without; with the expectations of the likeliest sub-cell's patch 5%
    /// off, the test fails.
    #[test]
    fn samples_follow_the_bilinear_pdf() {
        let (w, h) = (12, 6);
        for compensated in [false, true] {
            let e = Envmap::new(w, h, sky(w, h), turned(35.0), compensated);
            let Lookup::Bilinear(dist) = &e.map.lookup else {
                unreachable!("a map read bilinearly")
            };
            let sub = 3;
            let (bx, by) = (sub * w, sub * (h - 1));
            let n = 3_000_000;
            let mut counts = vec![0u32; bx * by];
            let mut rng = Rng::new(7);
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let Some((d, _, _)) = e.sample(u) else {
                    continue;
                };
                let (uv, _) = e.uv(d);
                let x = uv.x - 0.5 / w as f32;
                let x = x - x.floor();
                let (i, j) = (
                    ((x * bx as f32) as usize).min(bx - 1),
                    ((uv.y * by as f32) as usize).min(by - 1),
                );
                counts[j * bx + i] += 1;
            }
            let expected: Vec<f64> = (0..bx * by)
                .map(|k| {
                    let c = Vec2::new(
                        ((k % bx) as f32 + 0.5) / bx as f32,
                        ((k / bx) as f32 + 0.5) / by as f32,
                    );
                    f64::from(dist.pdf(c)) * n as f64 / (bx * by) as f64
                })
                .collect();
            let chi2 = |expected: &[f64]| pooled_chi2(&counts, expected);
            let (good, q) = chi2(&expected);
            let likeliest = (0..expected.len())
                .max_by(|&a, &b| expected[a].total_cmp(&expected[b]))
                .unwrap();
            let patch = |k: usize| ((k % bx) / sub, (k / bx) / sub);
            let off: Vec<f64> = (0..expected.len())
                .map(|k| {
                    if patch(k) == patch(likeliest) {
                        1.05 * expected[k]
                    } else {
                        expected[k]
                    }
                })
                .collect();
            let (bad, _) = chi2(&off);
            eprintln!(
                "envmap χ² (MIS compensation {compensated}): {good:.1} as drawn, {bad:.1} with a patch 5% off (0.999 quantile {q:.0})"
            );
            assert!(good < q, "χ² {good} (0.999 quantile {q})");
            assert!(bad > q, "χ² {bad} with a 5% error");
        }
    }

    /// With MIS compensation the map is sampled by its luminance less the
    /// mean: none where four neighbouring pixels are all below it, in
    /// proportion to the excess at the pixels' points; a uniform map is
    /// sampled as without it.
    #[test]
    fn mis_compensation_samples_the_excess_over_the_mean() {
        let (w, h) = (8, 5);
        // Luminance 1 but for column 5, of 9: the mean is 2.
        let radiance: Vec<Rgb> = (0..w * h)
            .map(|i| Rgb::splat(if i % w == 5 { 9.0 } else { 1.0 }))
            .collect();
        let e = Envmap::new(w, h, radiance, Mat3::IDENTITY, true);
        let point =
            |x: f32, y: f32| Envmap::map_direction((x + 0.5) / w as f32, y / (h - 1) as f32);
        // Between columns 1 and 2 (both below the mean): nothing.
        assert_eq!(e.pdf(point(1.5, 2.0)), 0.0);
        assert_eq!(e.pdf(point(1.0, 1.3)), 0.0);
        // At column 5 and halfway to column 6, in the same row: 2 to 1.
        let (a, b) = (e.pdf(point(5.0, 2.0)), e.pdf(point(5.5, 2.0)));
        assert!(a > 0.0 && (a / b - 2.0).abs() < 1e-4, "{a} {b}");
        // Without compensation the dim columns are sampled too.
        let plain = Envmap::new(w, h, e.map.radiance.clone(), Mat3::IDENTITY, false);
        assert!(plain.pdf(point(1.5, 2.0)) > 0.0);
        // A uniform map keeps its density.
        let flat = vec![Rgb::splat(3.0); w * h];
        let (c, u) = (
            Envmap::new(w, h, flat.clone(), turned(10.0), true),
            Envmap::new(w, h, flat, turned(10.0), false),
        );
        for d in [Vec3::X, Vec3::new(0.2, -0.7, 0.3).normalize()] {
            assert_eq!(c.pdf(d), u.pdf(d));
        }
    }

    /// The radiance a diffuse point facing `n` receives, `E / π` with `E =
    /// ∫ L cos⁺ dω`, estimated from 10⁶ samples of the map's importance
    /// sampling, lies within 3 standard errors of the same integral by
    /// quadrature over the sphere (1600 × 800 midpoints in `(u, v)`, the
    /// map interpolated there by a formula of its own: a sum of tents over
    /// the pixels), for a turned map and two normals.
    #[test]
    fn irradiance_matches_quadrature() {
        let (w, h) = (8, 5);
        let radiance = sky(w, h);
        let to_world = turned(20.0);
        let e = Envmap::new(w, h, radiance.clone(), to_world, false);
        // The map at (u, v): every pixel weighted by a tent around its
        // point (wrapping across, clamped down).
        let reference = |u: f64, v: f64| -> f64 {
            let mut sum = 0.0;
            for y in 0..h {
                let ty = (1.0 - (v * (h - 1) as f64 - y as f64).abs()).max(0.0);
                if ty == 0.0 {
                    continue;
                }
                for x in 0..w {
                    let mut dx = (u * w as f64 - (x as f64 + 0.5)).abs();
                    dx = dx.min(w as f64 - dx);
                    let tx = (1.0 - dx).max(0.0);
                    sum += tx * ty * f64::from(radiance[y * w + x].r);
                }
            }
            sum
        };
        for n in [
            Vec3::new(0.3, 0.9, -0.2).normalize(),
            Vec3::new(-0.6, -0.3, 0.7).normalize(),
        ] {
            let (nu, nv) = (1600, 800);
            let mut quad = 0.0f64;
            for j in 0..nv {
                let v = (j as f64 + 0.5) / nv as f64;
                let sin_t = (std::f64::consts::PI * v).sin();
                for i in 0..nu {
                    let u = (i as f64 + 0.5) / nu as f64;
                    let d = to_world * Envmap::map_direction(u as f32, v as f32);
                    let cos = f64::from(d.dot(n).max(0.0));
                    quad += reference(u, v) * cos * sin_t;
                }
            }
            let quad =
                quad * 2.0 * std::f64::consts::PI.powi(2) / (nu * nv) as f64 / std::f64::consts::PI;
            let mut rng = Rng::new(5);
            let m = 1_000_000;
            let (mut sum, mut square) = (0.0f64, 0.0f64);
            for _ in 0..m {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let x = match e.sample(u) {
                    Some((d, l, pdf)) => {
                        f64::from(l.r * d.dot(n).max(0.0) / pdf) / std::f64::consts::PI
                    }
                    None => 0.0,
                };
                sum += x;
                square += x * x;
            }
            let mean = sum / m as f64;
            let sigma = ((square / m as f64 - mean * mean) / (m - 1) as f64).sqrt();
            eprintln!(
                "envmap irradiance / π toward {n:?}: sampled {mean:.5} ± {sigma:.5}, quadrature {quad:.5}"
            );
            assert!(sigma < 0.01 * quad, "too noisy to tell: {sigma} of {quad}");
            assert!(
                (mean - quad).abs() < 3.0 * sigma,
                "{mean} ± {sigma} vs {quad}"
            );
        }
    }

    /// The power of a bilinear map is `π r² ∫ L dω` integrated exactly:
    /// 4π L for a uniform map, and for a map brighter toward the bottom the
    /// integral of its rows' tents (checked against a fine midpoint sum).
    #[test]
    fn the_power_integrates_the_interpolated_map() {
        let (w, h) = (6, 5);
        let flat = Envmap::new(w, h, vec![Rgb::splat(0.5); w * h], turned(30.0), false);
        let want = PI * 4.0 * 4.0 * PI * 0.5;
        assert!(
            (flat.power(2.0) / want - 1.0).abs() < 1e-5,
            "{} vs {want}",
            flat.power(2.0)
        );
        let rows: Vec<Rgb> = (0..w * h)
            .map(|i| Rgb::splat((i / w) as f32 * (i / w) as f32))
            .collect();
        let e = Envmap::new(w, h, rows, Mat3::IDENTITY, false);
        let n = 100_000;
        let mut integral = 0.0f64;
        for k in 0..n {
            let v = (k as f64 + 0.5) / n as f64;
            let y = v * (h - 1) as f64;
            let j = (y as usize).min(h - 2);
            let t = y - j as f64;
            let l = (1.0 - t) * (j * j) as f64 + t * ((j + 1) * (j + 1)) as f64;
            integral += l * (std::f64::consts::PI * v).sin();
        }
        let integral = integral / n as f64 * 2.0 * std::f64::consts::PI.powi(2);
        let want = std::f64::consts::PI * integral;
        assert!(
            (f64::from(e.power(1.0)) / want - 1.0).abs() < 1e-5,
            "{} vs {want}",
            e.power(1.0)
        );
    }

    /// The cells of a map read by the nearest pixel.
    fn cells(e: &Envmap) -> &Piecewise2D {
        match &e.map.lookup {
            Lookup::Nearest(d) => d,
            Lookup::Bilinear(_) => unreachable!("a map read by the nearest pixel"),
        }
    }

    /// The counts of `n` directions sampled from `e` (a map read by the
    /// nearest pixel, stream `seed`),
    /// binned by `sub` × `sub` sub-cells of the map's pixels (found back
    /// from the world direction), row by row; every sample's density must
    /// be what `pdf` gives for its direction and its radiance what `eval`
    /// gives (but for rounding: at most 100 differ).
    pub(crate) fn sampled_counts(e: &Envmap, n: usize, sub: usize, seed: u64) -> Vec<u32> {
        let (sw, sh) = (sub * e.map.width, sub * e.map.height);
        let mut counts = vec![0u32; sw * sh];
        let mut rng = Rng::new(seed);
        let mut differ = 0;
        for _ in 0..n {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let Some((d, l, pdf)) = e.sample(u) else {
                continue;
            };
            // Equal but for rounding (a direction on a pixel's edge may
            // come back in its neighbour).
            if (pdf - e.pdf(d)).abs() > 1e-2 * pdf || l != e.eval(d) {
                differ += 1;
            }
            let (uv, _) = e.uv(d);
            let (x, y) = (
                ((uv.x * sw as f32) as usize).min(sw - 1),
                ((uv.y * sh as f32) as usize).min(sh - 1),
            );
            counts[y * sw + x] += 1;
        }
        assert!(differ < 100, "{differ} samples unlike pdf or eval");
        counts
    }

    /// Pearson's χ² of `counts` ([`sampled_counts`] of `n` samples, `sub`
    /// × `sub` sub-cells a pixel) against the density integrated over each
    /// sub-cell (the pixel's probability over `sub`², the density being
    /// uniform over a pixel in the map's coordinates), with the pixel
    /// `off` (if any) given 5% more; cells expecting fewer than 5 samples
    /// are pooled into one (too few to count: then they may hold no more
    /// than 10). The statistic and its 0.999 quantile.
    pub(crate) fn sampling_chi2(
        e: &Envmap,
        counts: &[u32],
        n: usize,
        sub: usize,
        off: Option<usize>,
    ) -> (f64, f64) {
        let (w, h) = (e.map.width, e.map.height);
        let sw = sub * w;
        let mut probs: Vec<f64> = (0..counts.len())
            .map(|i| {
                let (x, y) = (i % sw / sub, i / sw / sub);
                let p = f64::from(cells(e).cell_pdf(x, y)) / (w * h * sub * sub) as f64;
                if off == Some(y * w + x) {
                    1.05 * p
                } else {
                    p
                }
            })
            .collect();
        let total: f64 = probs.iter().sum();
        probs.iter_mut().for_each(|p| *p *= n as f64 / total);
        pooled_chi2(counts, &probs)
    }

    /// Pearson's χ² of `counts` against `expected`, the cells expecting
    /// fewer than 5 samples pooled into one (too few to count: then they
    /// may hold no more than 10); the statistic and its 0.999 quantile.
    fn pooled_chi2(counts: &[u32], expected: &[f64]) -> (f64, f64) {
        use statrs::distribution::{ChiSquared, ContinuousCDF};
        let (mut stat, mut cells, mut pool_e, mut pool_o) = (0.0, 0usize, 0.0, 0.0);
        for (&c, &expect) in counts.iter().zip(expected) {
            if expect < 5.0 {
                pool_e += expect;
                pool_o += f64::from(c);
            } else {
                stat += (f64::from(c) - expect).powi(2) / expect;
                cells += 1;
            }
        }
        if pool_e >= 5.0 {
            stat += (pool_o - pool_e).powi(2) / pool_e;
            cells += 1;
        } else {
            assert!(
                pool_o <= 10.0,
                "{pool_o} samples where {pool_e} were expected"
            );
        }
        let q = ChiSquared::new((cells - 1) as f64)
            .expect("degrees of freedom")
            .inverse_cdf(0.999);
        (stat, q)
    }

    /// The pixel `sampling_chi2` puts 5% off: the most likely one.
    pub(crate) fn likeliest_pixel(e: &Envmap) -> usize {
        let (w, h) = (e.map.width, e.map.height);
        (0..w * h)
            .max_by(|&a, &b| {
                let p = |i: usize| cells(e).cell_pdf(i % w, i / w);
                p(a).total_cmp(&p(b))
            })
            .expect("pixels")
    }

    /// A map read by the nearest pixel: χ² of 4 · 10⁶ sampled directions,
    /// binned by 3 × 3 sub-cells of the map's pixels, against the density
    /// integrated over each sub-cell ([`sampling_chi2`]), on a turned map;
    /// and with the likeliest pixel's density 5% off, the test fails.
    #[test]
    fn nearest_samples_follow_the_pdf() {
        let (w, h) = (12, 6);
        let e = Envmap::nearest(w, h, sky(w, h), turned(35.0));
        let n = 4_000_000;
        let counts = sampled_counts(&e, n, 3, 9);
        // 647 degrees of freedom: the 0.999 quantile is about 767.
        let (good, q) = sampling_chi2(&e, &counts, n, 3, None);
        assert!(good < q, "χ² {good} (0.999 quantile {q})");
        let (bad, _) = sampling_chi2(&e, &counts, n, 3, Some(likeliest_pixel(&e)));
        eprintln!(
            "envmap χ²: {good:.1} as drawn, {bad:.1} with a pixel 5% off (0.999 quantile {q:.0})"
        );
        assert!(bad > q, "χ² {bad} with a 5% error");
    }

    /// The density integrates to 1 over the sphere (uniform directions:
    /// the mean of 4π · pdf is 1), read bilinearly (with MIS compensation
    /// and without) or by the nearest pixel.
    #[test]
    fn the_pdf_integrates_to_one() {
        let maps = [
            Envmap::new(16, 8, sky(16, 8), turned(-70.0), false),
            Envmap::new(16, 8, sky(16, 8), turned(-70.0), true),
            Envmap::nearest(16, 8, sky(16, 8), turned(-70.0)),
        ];
        for e in maps {
            let mut rng = Rng::new(2);
            let n = 400_000;
            let mut sum = 0.0f64;
            for _ in 0..n {
                let d = square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                sum += f64::from(e.pdf(d)) * 4.0 * std::f64::consts::PI;
            }
            let mean = sum / f64::from(n);
            assert!((mean - 1.0).abs() < 0.01, "{mean}");
        }
    }

    /// A sky of radiance 0.05 and a sun of 0.5° across, 30° from the
    /// zenith, 10⁵ times brighter: the irradiance on a surface facing up
    /// estimated from 16 samples of the map (its variance measured over
    /// 4000 estimates, its mean the map's irradiance summed pixel by pixel)
    /// has at least 20 times less variance than from 16 uniform directions
    /// (whose variance is summed pixel by pixel: a uniform direction meets
    /// the sun so rarely that a measured variance would miss it). So for
    /// the map read by the nearest pixel; read bilinearly, the same pixels
    /// make a slightly different map (rows at `y / (H − 1)`, the sun
    /// blended with the sky around it), whose irradiance lies within 1% of
    /// the pixel sum.
    #[test]
    fn a_sun_is_found_by_importance_sampling() {
        let (w, h) = (2048, 1024);
        let sun_dir = Vec3::new(30f32.to_radians().sin(), 30f32.to_radians().cos(), 0.0);
        let cos_sun = (0.25f32).to_radians().cos();
        let (sky_l, sun_l) = (0.05, 5000.0);
        let mut radiance = Vec::with_capacity(w * h);
        let (mut exact, mut square) = (0.0f64, 0.0f64);
        for y in 0..h {
            for x in 0..w {
                let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let (theta, phi) = (PI * v, 2.0 * PI * u);
                let d = Vec3::new(
                    phi.sin() * theta.sin(),
                    theta.cos(),
                    -phi.cos() * theta.sin(),
                );
                let l = if d.dot(sun_dir) > cos_sun {
                    sun_l
                } else {
                    sky_l
                };
                radiance.push(Rgb::splat(l));
                let solid = (2.0 * PI * PI * theta.sin()) / (w * h) as f32;
                exact += f64::from(l * d.y.max(0.0) * solid);
                // E[f²] of f = 4π L cos⁺ under the density 1/4π.
                square +=
                    4.0 * std::f64::consts::PI * f64::from((l * d.y.max(0.0)).powi(2) * solid);
            }
        }
        let maps = [
            (
                "nearest",
                Envmap::nearest(w, h, radiance.clone(), Mat3::IDENTITY),
            ),
            (
                "bilinear",
                Envmap::new(w, h, radiance, Mat3::IDENTITY, false),
            ),
        ];
        for (name, e) in maps {
            let mut rng = Rng::new(4);
            let trials = 4000;
            let mut imp = Vec::new();
            for _ in 0..trials {
                let mut a = 0.0f64;
                for _ in 0..16 {
                    let u = Vec2::new(rng.next_f32(), rng.next_f32());
                    if let Some((d, l, pdf)) = e.sample(u) {
                        a += f64::from(l.r * d.y.max(0.0) / pdf);
                    }
                }
                imp.push(a / 16.0);
            }
            let mi = imp.iter().sum::<f64>() / f64::from(trials);
            let vi = imp.iter().map(|x| (x - mi).powi(2)).sum::<f64>() / f64::from(trials - 1);
            let vu = (square - exact * exact) / 16.0;
            eprintln!("sun ({name}): irradiance {mi:.4} (pixel sum {exact:.4}), variance at 16 samples {vi:.3e} (importance) vs {vu:.3e} (uniform): {:.0}×", vu / vi);
            assert!((mi / exact - 1.0).abs() < 0.01, "{name}: {mi} vs {exact}");
            assert!(
                vu > 20.0 * vi,
                "{name}: variance {vi} importance, {vu} uniform"
            );
        }
    }
}
