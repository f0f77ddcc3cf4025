//! `bitmap`: an image file mapped onto `(u, v)` (Mitsuba 3's `bitmap`).
//! PNG, JPEG, OpenEXR and Radiance HDR, read by
//! [`input::image`](crate::input::image): 8- and 16-bit files are decoded
//! from sRGB to linear unless `raw`, float files are linear; alpha is
//! dropped, grey is grey in each channel.
//!
//! Coordinates as Mitsuba's: `(u, v)` (after `to_uv`) is scaled to texels,
//! `(0, 0)` at the top-left corner of the image's first row and `(1, 1)`
//! at the bottom-right corner of its last, with no flip (Mitsuba's OBJ
//! reader flips `v` instead). Texel `(i, j)` has its centre at
//! `((i + ½) / width, (j + ½) / height)`. `nearest` takes the texel the
//! point falls in; `bilinear` weighs the four texels whose centres
//! surround it. Texel indices outside the image wrap by `wrap_mode`:
//! `repeat` tiles the image, `mirror` tiles it flipped every other time
//! (… 1 0 | 0 1 … n−1 | n−1 n−2 …), `clamp` repeats the edge texels.
//! Read as one value (a roughness), a texel is its grey, or the luminance
//! of its colour.
//!
//! `format` is Mitsuba's storage precision of the texels, which rounds
//! their values: `auto` and `variant` keep them as read (32-bit floats; an
//! 8-bit file's values are its bytes decoded), `float16` (or `fp16`) rounds
//! each linear value to half precision (to nearest, ties to even; beyond
//! 65504, infinite), `uint8` keeps 8 bits a channel: an 8- or 16-bit file
//! decoded from sRGB is rounded to 8 bits in sRGB then decoded again (an
//! 8-bit file's values do not change), raw or float values (OpenEXR, HDR)
//! are clamped to [0, 1] and rounded to multiples of 1/255. Mitsuba's
//! `auto` keeps a 16-bit file at half precision; here it keeps it at 32
//! bits (a difference below half's precision, 2⁻¹¹ relative).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `filename` | file | **required** | the image, relative to the scene file |
//! | `raw` | bool | `false` | take 8- and 16-bit values as linear (a roughness or normal map) instead of decoding sRGB |
//! | `filter_type` | `bilinear`, `nearest` | `bilinear` | interpolation between texels |
//! | `wrap_mode` | `repeat`, `mirror`, `clamp` | `repeat` | texel indices outside the image |
//! | `format` | `auto`, `variant`, `float16`, `fp16`, `uint8` | `auto` | the precision texels are kept at (Mitsuba's storage format) |
//! | `to_uv` | table | identity | a map of `(u, v)` before the lookup (see the [module docs](super)) |

use std::sync::Arc;

use super::common::{one, UvTransform, TO_UV};
use super::{TextureModel, Textures};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::input::image::{read_image, srgb_to_linear, Encoding, Image};
use crate::math::{Rgb, Vec2};

const FILTERS: &[&str] = &["bilinear", "nearest"];
const WRAPS: &[&str] = &["repeat", "mirror", "clamp"];
const FORMATS: &[&str] = &["auto", "variant", "float16", "fp16", "uint8"];

/// Its parameters.
const SCHEMA: Schema = Schema {
    kind: Kind::Texture,
    plugin: "bitmap",
    what: "bitmap texture",
    doc: "an image file (PNG, JPEG, OpenEXR, Radiance HDR), sRGB-decoded or raw, nearest or bilinear, repeated, mirrored or clamped",
    mitsuba: &["bitmap"],
    params: &[
        Param::new(
            "filename",
            Type::Path,
            "required",
            "the image file (PNG, JPEG, OpenEXR, Radiance HDR), relative to the scene file",
        ),
        Param::new(
            "raw",
            Type::Bool,
            "false",
            "take 8- and 16-bit values as linear instead of decoding sRGB",
        ),
        Param::new(
            "filter_type",
            Type::Choice("filter type", FILTERS),
            "bilinear",
            "interpolation between texels",
        ),
        Param::new(
            "wrap_mode",
            Type::Choice("wrap mode", WRAPS),
            "repeat",
            "texel indices outside the image: tiled, tiled mirrored, or the edge's",
        ),
        Param::new(
            "format",
            Type::Choice("storage format", FORMATS),
            "auto",
            "the precision texels are kept at: as read (`auto`, `variant`), rounded to half floats (`float16`, `fp16`) or to 8 bits (`uint8`)",
        ),
        TO_UV,
    ],
};

/// `x` rounded to the nearest half-precision float (ties to even), as
/// a float: infinite beyond half's largest, 65504.
pub fn round_to_half(x: f32) -> f32 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    // The exponent of `x`, no lower than half's smallest normal's (−14):
    // half keeps 10 bits below the leading one, and subnormals share the
    // quantum 2⁻²⁴.
    let e = (((x.abs().to_bits() >> 23) & 0xff) as i32 - 127).max(-14);
    let quantum = f32::from_bits(((e - 10 + 127) as u32) << 23);
    let r = (x / quantum).round_ties_even() * quantum;
    if r.abs() > 65504.0 {
        f32::INFINITY.copysign(x)
    } else {
        r
    }
}

/// `x` (linear) kept at 8 bits: rounded in sRGB and decoded again if
/// `srgb`, else clamped to [0, 1] and rounded to a multiple of 1/255.
pub fn round_to_8_bits(x: f32, srgb: bool) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if srgb {
        let s = if x <= 0.0031308 {
            x * 12.92
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        };
        srgb_to_linear((s * 255.0).round().clamp(0.0, 255.0) / 255.0)
    } else {
        (x * 255.0).round() / 255.0
    }
}

/// How texels are interpolated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    Nearest,
    Bilinear,
}

/// What texel indices outside the image become.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    Repeat,
    Mirror,
    Clamp,
}

impl Wrap {
    /// Index `i` of a row or column of `n` texels, wrapped into `0..n`.
    #[inline]
    pub fn index(self, i: i64, n: u32) -> u32 {
        let n = i64::from(n);
        let j = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m >= n {
                    2 * n - 1 - m
                } else {
                    m
                }
            }
        };
        j as u32
    }
}

/// The bitmap texture (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Bitmap {
    pub image: Arc<Image>,
    pub filter: Filter,
    pub wrap: Wrap,
    pub to_uv: UvTransform,
    /// The smallest and largest texel values, channel by channel.
    bounds: (Rgb, Rgb),
    /// The same, read as one value.
    bounds_1: (f32, f32),
}

impl Bitmap {
    /// The texture of an image, its range found.
    pub fn new(image: Arc<Image>, filter: Filter, wrap: Wrap, to_uv: UvTransform) -> Bitmap {
        let mut lo = Rgb::splat(f32::INFINITY);
        let mut hi = Rgb::splat(f32::NEG_INFINITY);
        let (mut lo1, mut hi1) = (f32::INFINITY, f32::NEG_INFINITY);
        for y in 0..image.height {
            for x in 0..image.width {
                let c = Rgb::from_array(image.rgb(x, y));
                lo = lo.min(c);
                hi = hi.max(c);
                lo1 = lo1.min(one(c));
                hi1 = hi1.max(one(c));
            }
        }
        Bitmap {
            image,
            filter,
            wrap,
            to_uv,
            bounds: (lo, hi),
            bounds_1: (lo1, hi1),
        }
    }

    /// Weights over the texel grid, row by row (`width` × `height`), that
    /// a distribution of surface coordinates drawn in proportion to the
    /// texture may take (an area light drawing its points by its
    /// radiance): a texel's value read as one ([`one`]), and, with the
    /// bilinear filter, the largest of it and its eight neighbours (wrapped
    /// as the lookups wrap them), so that a texel is never weighed 0 where
    /// the interpolation reaches a neighbour that is not. `None` unless
    /// `to_uv` is the identity: only then is texel `(x, y)` the square
    /// `[x / width, (x + 1) / width) × [y / height, (y + 1) / height)` of
    /// surface coordinates.
    pub fn sampling_weights(&self) -> Option<(usize, usize, Vec<f32>)> {
        if self.to_uv != UvTransform::IDENTITY {
            return None;
        }
        let (w, h) = (self.image.width, self.image.height);
        let reach: i64 = match self.filter {
            Filter::Nearest => 0,
            Filter::Bilinear => 1,
        };
        let mut weights = Vec::with_capacity(w as usize * h as usize);
        for y in 0..i64::from(h) {
            for x in 0..i64::from(w) {
                let mut most = 0.0f32;
                for dy in -reach..=reach {
                    for dx in -reach..=reach {
                        most = most.max(one(self.texel(x + dx, y + dy)).max(0.0));
                    }
                }
                weights.push(most);
            }
        }
        Some((w as usize, h as usize, weights))
    }

    /// The texel at column `x`, row `y` (any integers; wrapped).
    #[inline]
    fn texel(&self, x: i64, y: i64) -> Rgb {
        let (w, h) = (self.image.width, self.image.height);
        Rgb::from_array(self.image.rgb(self.wrap.index(x, w), self.wrap.index(y, h)))
    }
}

impl TextureModel for Bitmap {
    const NAME: &'static str = "bitmap";
    const SCHEMA: Schema = SCHEMA;
    const MITSUBA: Mitsuba = Mitsuba {
        differences: "`accel` is read with no effect (it asks for a GPU's texture units, which Mitsuba's CPU variants do not use either); an image smaller than 2 × 2 is read as it is (Mitsuba enlarges it); `format=\"auto\"` keeps a 16-bit file at 32 bits (Mitsuba: half precision)",
        reads: &["accel"],
        adapt: None,
    };

    /// The texture of a scene's parameters, its file relative to `base_dir`.
    fn build(p: &Props, textures: &Textures) -> Result<Bitmap, Invalid> {
        let Some(file) = p.string("filename")? else {
            return Err(p.node_error("missing field `filename` (the image file)"));
        };
        let raw = p.bool("raw")?.unwrap_or(false);
        let filter = match p.choice("filter_type", "filter type", FILTERS)? {
            Some("nearest") => Filter::Nearest,
            _ => Filter::Bilinear,
        };
        let wrap = match p.choice("wrap_mode", "wrap mode", WRAPS)? {
            Some("mirror") => Wrap::Mirror,
            Some("clamp") => Wrap::Clamp,
            _ => Wrap::Repeat,
        };
        let format = p
            .choice("format", "storage format", FORMATS)?
            .unwrap_or("auto");
        let to_uv = UvTransform::read(p)?;
        let encoding = if raw { Encoding::Raw } else { Encoding::Srgb };
        let path = textures.base_dir.join(file);
        let mut image =
            read_image(&path, encoding).map_err(|e| p.error("filename", e.to_string()))?;
        match format {
            "float16" | "fp16" => image.pixels.iter_mut().for_each(|x| *x = round_to_half(*x)),
            "uint8" => {
                let float = path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
                    e.eq_ignore_ascii_case("exr") || e.eq_ignore_ascii_case("hdr")
                });
                let srgb = !raw && !float;
                image.pixels.iter_mut().for_each(|x| *x = round_to_8_bits(*x, srgb));
            }
            _ => {}
        }
        if image.width == 0 || image.height == 0 {
            return Err(p.error("filename", "the image has no pixels"));
        }
        let b = Bitmap::new(Arc::new(image), filter, wrap, to_uv);
        if !(b.bounds.0.is_finite() && b.bounds.1.is_finite()) {
            return Err(p.error("filename", "the image holds values that are not finite"));
        }
        Ok(b)
    }

    fn eval(&self, uv: Vec2) -> Rgb {
        let t = self.to_uv.apply(uv);
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        match self.filter {
            Filter::Nearest => self.texel((t.x * w).floor() as i64, (t.y * h).floor() as i64),
            Filter::Bilinear => {
                let (px, py) = (t.x * w - 0.5, t.y * h - 0.5);
                let (fx, fy) = (px.floor(), py.floor());
                let (ax, ay) = (px - fx, py - fy);
                let (x, y) = (fx as i64, fy as i64);
                let top = self.texel(x, y) * (1.0 - ax) + self.texel(x + 1, y) * ax;
                let bottom = self.texel(x, y + 1) * (1.0 - ax) + self.texel(x + 1, y + 1) * ax;
                top * (1.0 - ay) + bottom * ay
            }
        }
    }

    /// One value: the grey, or the luminance of the colour.
    fn eval_1(&self, uv: Vec2) -> f32 {
        one(self.eval(uv))
    }

    /// The derivatives of [`eval_1`](Self::eval_1) in `u` and `v` (Mitsuba's
    /// `eval_1_grad`, what a bump map reads): the bilinear interpolation's,
    /// through `to_uv`; 0 for `nearest`, which is constant within a texel.
    /// On a line through texel centres, where the interpolation has a kink,
    /// the derivative of the side above.
    fn eval_1_grad(&self, uv: Vec2) -> Vec2 {
        if self.filter == Filter::Nearest {
            return Vec2::ZERO;
        }
        let t = self.to_uv.apply(uv);
        let (w, h) = (self.image.width as f32, self.image.height as f32);
        let (px, py) = (t.x * w - 0.5, t.y * h - 0.5);
        let (fx, fy) = (px.floor(), py.floor());
        let (ax, ay) = (px - fx, py - fy);
        let (x, y) = (fx as i64, fy as i64);
        let (t00, t10) = (self.texel(x, y), self.texel(x + 1, y));
        let (t01, t11) = (self.texel(x, y + 1), self.texel(x + 1, y + 1));
        // In texels, then in the coordinates after `to_uv`.
        let dx = (t10 - t00) * (1.0 - ay) + (t11 - t01) * ay;
        let dy = (t01 * (1.0 - ax) + t11 * ax) - (t00 * (1.0 - ax) + t10 * ax);
        let (gx, gy) = (one(dx) * w, one(dy) * h);
        let [[a, b, _], [d, e, _]] = self.to_uv.rows;
        Vec2::new(gx * a + gy * d, gx * b + gy * e)
    }

    fn bounds(&self) -> (Rgb, Rgb) {
        self.bounds
    }

    fn bounds_1(&self) -> (f32, f32) {
        self.bounds_1
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    /// A 3 × 2 image of greys: row 0 is 0, 1, 2; row 1 is 10, 11, 12.
    fn image() -> Arc<Image> {
        let values = [0.0, 1.0, 2.0, 10.0, 11.0, 12.0];
        Arc::new(Image {
            width: 3,
            height: 2,
            channels: 3,
            pixels: values.iter().flat_map(|&v| [v; 3]).collect(),
        })
    }

    fn grey(b: &Bitmap, u: f32, v: f32) -> f32 {
        let c = b.eval(Vec2::new(u, v));
        assert!(c.r == c.g && c.g == c.b);
        c.r
    }

    #[test]
    fn wrap_modes_by_hand() {
        let n = 3;
        let idx = |w: Wrap| (-4..7).map(|i| w.index(i, n)).collect::<Vec<_>>();
        assert_eq!(idx(Wrap::Repeat), [2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0]);
        assert_eq!(idx(Wrap::Clamp), [0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2]);
        assert_eq!(idx(Wrap::Mirror), [2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0]);
        assert_eq!(
            Wrap::Repeat.index(i64::MIN, 3),
            (i64::MIN).rem_euclid(3) as u32
        );
        assert_eq!(Wrap::Mirror.index(0, 1), 0);
        assert_eq!(Wrap::Mirror.index(-1, 1), 0);
    }

    /// Nearest: the texel the point falls in, row 0 at v = 0; outside the
    /// unit square by the wrap mode.
    #[test]
    fn nearest_takes_the_texel_the_point_falls_in() {
        let b = Bitmap::new(
            image(),
            Filter::Nearest,
            Wrap::Repeat,
            UvTransform::IDENTITY,
        );
        assert_eq!(grey(&b, 0.1, 0.1), 0.0);
        assert_eq!(grey(&b, 0.5, 0.1), 1.0);
        assert_eq!(grey(&b, 0.9, 0.9), 12.0);
        assert_eq!(grey(&b, 0.34, 0.6), 11.0);
        assert_eq!(grey(&b, 1.1, 1.1), 0.0);
        assert_eq!(grey(&b, -0.1, 0.1), 2.0);
        let m = Bitmap::new(
            image(),
            Filter::Nearest,
            Wrap::Mirror,
            UvTransform::IDENTITY,
        );
        assert_eq!(grey(&m, -0.1, 0.1), 0.0);
        assert_eq!(grey(&m, 1.1, 1.1), 12.0);
        assert_eq!(grey(&m, 1.5, 0.1), 1.0);
        let c = Bitmap::new(image(), Filter::Nearest, Wrap::Clamp, UvTransform::IDENTITY);
        assert_eq!(grey(&c, 5.0, -3.0), 2.0);
        assert_eq!(grey(&c, -5.0, 3.0), 10.0);
        assert_eq!(b.bounds(), (Rgb::ZERO, Rgb::splat(12.0)));
    }

    /// Bilinear: exact at texel centres, the weighted mean of four between
    /// them, the wrap mode at the border (hand-computed).
    #[test]
    fn bilinear_weighs_the_four_surrounding_centres() {
        let b = Bitmap::new(
            image(),
            Filter::Bilinear,
            Wrap::Clamp,
            UvTransform::IDENTITY,
        );
        let close = |a: f32, b: f32| (a - b).abs() < 1e-5;
        // Texel centres: u = 1/6, 1/2, 5/6; v = 1/4, 3/4.
        assert!(close(grey(&b, 1.0 / 6.0, 0.25), 0.0));
        assert!(close(grey(&b, 0.5, 0.75), 11.0));
        // Halfway between the first two columns, a quarter down toward row 1.
        // x = 0.5 (between 0 and 1), y = 0.25 → (0.5·0 + 0.5·1)·0.75 + (0.5·10 + 0.5·11)·0.25.
        let want = 0.5 * 0.75 + 10.5 * 0.25;
        assert!(close(grey(&b, 2.0 / 6.0, 0.25 + 0.125), want));
        // Clamp at the left border: the edge texel alone.
        assert!(close(grey(&b, 0.0, 0.25), 0.0));
        // Repeat at the left border: halfway between the last column and the first.
        let r = Bitmap::new(
            image(),
            Filter::Bilinear,
            Wrap::Repeat,
            UvTransform::IDENTITY,
        );
        assert!(close(grey(&r, 0.0, 0.25), 1.0));
        // Mirror at the left border: the first column twice.
        let m = Bitmap::new(
            image(),
            Filter::Bilinear,
            Wrap::Mirror,
            UvTransform::IDENTITY,
        );
        assert!(close(grey(&m, 0.0, 0.25), 0.0));
        // Nearest differs from bilinear between centres.
        let n = Bitmap::new(image(), Filter::Nearest, Wrap::Clamp, UvTransform::IDENTITY);
        assert_eq!(grey(&n, 2.0 / 6.0, 0.375), 1.0);
    }

    /// The gradient is the bilinear interpolation's: against central
    /// differences of `eval_1` away from the kinks at texel centres, for
    /// each wrap mode and through a rotating, scaling `to_uv`; 0 for nearest.
    #[test]
    fn gradient_matches_finite_differences() {
        let rotated = UvTransform {
            rows: [[1.5, -0.8, 0.1], [0.6, 2.0, -0.3]],
        };
        let mut r = crate::sampling::Rng::new(8);
        for wrap in [Wrap::Repeat, Wrap::Mirror, Wrap::Clamp] {
            for to_uv in [UvTransform::IDENTITY, rotated] {
                let b = Bitmap::new(image(), Filter::Bilinear, wrap, to_uv);
                let mut checked = 0;
                for _ in 0..400 {
                    let uv = Vec2::new(r.range(-1.0, 2.0), r.range(-1.0, 2.0));
                    let h = 1e-3;
                    // Skip points within a step of a kink (a texel centre line).
                    let near_kink = |uv: Vec2| {
                        let t = to_uv.apply(uv);
                        let (px, py) = (t.x * 3.0 - 0.5, t.y * 2.0 - 0.5);
                        let d = |x: f32| (x - x.round()).abs();
                        d(px) < 0.02 || d(py) < 0.02
                    };
                    if near_kink(uv) {
                        continue;
                    }
                    let g = b.eval_1_grad(uv);
                    let du = (b.eval_1(uv + Vec2::new(h, 0.0)) - b.eval_1(uv - Vec2::new(h, 0.0)))
                        / (2.0 * h);
                    let dv = (b.eval_1(uv + Vec2::new(0.0, h)) - b.eval_1(uv - Vec2::new(0.0, h)))
                        / (2.0 * h);
                    let tol = 2e-2 * (1.0 + du.abs().max(dv.abs()));
                    assert!(
                        (g.x - du).abs() < tol && (g.y - dv).abs() < tol,
                        "{wrap:?} {uv}: {g} vs ({du}, {dv})"
                    );
                    checked += 1;
                }
                assert!(checked > 200, "{checked}");
            }
        }
        let n = Bitmap::new(
            image(),
            Filter::Nearest,
            Wrap::Repeat,
            UvTransform::IDENTITY,
        );
        assert_eq!(n.eval_1_grad(Vec2::new(0.3, 0.4)), Vec2::ZERO);
        // Along a row of 0, 1, 2 (clamped), one texel is 1/3 in u: slope 3.
        let c = Bitmap::new(
            image(),
            Filter::Bilinear,
            Wrap::Clamp,
            UvTransform::IDENTITY,
        );
        assert!((c.eval_1_grad(Vec2::new(0.3, 0.1)).x - 3.0).abs() < 1e-4);
    }

    #[test]
    fn to_uv_maps_before_the_lookup() {
        let t = UvTransform {
            rows: [[1.0, 0.0, 1.0 / 3.0], [0.0, 1.0, 0.0]],
        };
        let b = Bitmap::new(image(), Filter::Nearest, Wrap::Repeat, t);
        assert_eq!(grey(&b, 0.1, 0.1), 1.0);
        assert_eq!(b.eval_1(Vec2::new(0.1, 0.6)), 11.0);
    }

    /// A PNG's 8-bit values are sRGB-decoded unless `raw`, through a scene.
    #[test]
    fn png_texels_are_decoded_from_srgb_unless_raw() {
        let dir = tempfile::tempdir().unwrap();
        let img = image::RgbImage::from_fn(2, 1, |x, _| image::Rgb([128 * x as u8, 64, 255]));
        img.save(dir.path().join("t.png")).unwrap();
        let build = |raw: bool| {
            let text = format!(
                "[textures.t]\ntype = \"bitmap\"\nfilename = \"t.png\"\nraw = {raw}\nfilter_type = \"nearest\"\n"
            );
            let root = crate::description::from_toml(&text, Path::new("s.toml")).unwrap();
            let t = crate::texture::Textures::of_scene(&root, dir.path()).unwrap();
            t.get("t").unwrap().clone()
        };
        let srgb = build(false).eval_uv(Vec2::new(0.75, 0.5));
        let want = Rgb::new(
            srgb_to_linear(128.0 / 255.0),
            srgb_to_linear(64.0 / 255.0),
            1.0,
        );
        assert!((srgb - want).abs().max_element() < 1e-6, "{srgb:?}");
        // The sRGB curve by its formula, independently: ((c + 0.055) / 1.055)^2.4.
        assert!((want.r - ((128.0f32 / 255.0 + 0.055) / 1.055).powf(2.4)).abs() < 1e-6);
        let raw = build(true).eval_uv(Vec2::new(0.75, 0.5));
        assert!(
            (raw - Rgb::new(128.0 / 255.0, 64.0 / 255.0, 1.0))
                .abs()
                .max_element()
                < 1e-6
        );
        assert_eq!(build(true).eval_uv(Vec2::new(0.25, 0.5)).r, 0.0);
    }

    /// Half precision by hand: 10 bits below the leading one, ties to even,
    /// subnormals in steps of 2⁻²⁴, infinite past 65504 (65520 and up).
    #[test]
    fn half_rounding_by_hand() {
        for (x, want) in [
            (1.0f32, 1.0f32),
            (1.0 / 3.0, 0.333_251_95),
            (1.0 + 1.0 / 2048.0, 1.0),
            (1.0 + 3.0 / 2048.0, 1.0 + 2.0 / 1024.0),
            (-2.5e-3, -0.002_500_534),
            (65519.0, 65504.0),
            (1e-8, 0.0),
            (3e-8, 2f32.powi(-24)),
            (1e-6, 17.0 * 2f32.powi(-24)),
            (0.0, 0.0),
        ] {
            assert_eq!(round_to_half(x), want, "{x}");
        }
        assert_eq!(round_to_half(65520.0), f32::INFINITY);
        assert_eq!(round_to_half(-1e6), f32::NEG_INFINITY);
        // The rounding is within half a step: 2⁻¹¹ relative over the
        // normal range.
        let mut rng = crate::sampling::Rng::new(2);
        for _ in 0..1000 {
            let x = rng.range(6.2e-5, 60000.0);
            assert!((round_to_half(x) - x).abs() <= x * 2f32.powi(-11), "{x}");
        }
    }

    /// `format`: `uint8` and `variant` leave an 8-bit file's values as they
    /// are, bit for bit; `float16` rounds each to half precision; `uint8`
    /// of raw values rounds to multiples of 1/255.
    #[test]
    fn format_rounds_the_texels_as_mitsubas_storage() {
        let dir = tempfile::tempdir().unwrap();
        let img = image::RgbImage::from_fn(3, 2, |x, y| {
            image::Rgb([37 * x as u8 + 5, 91 * y as u8 + 1, 200 + x as u8])
        });
        img.save(dir.path().join("t.png")).unwrap();
        let build = |keys: &str| {
            let text = format!(
                "[textures.t]\ntype = \"bitmap\"\nfilename = \"t.png\"\nfilter_type = \"nearest\"\n{keys}"
            );
            let root = crate::description::from_toml(&text, Path::new("s.toml")).unwrap();
            let t = crate::texture::Textures::of_scene(&root, dir.path()).unwrap();
            match t.get("t").unwrap() {
                crate::texture::Texture::Bitmap(b) => b.image.pixels.clone(),
                t => panic!("{t:?}"),
            }
        };
        let bits = |xs: Vec<f32>| xs.into_iter().map(f32::to_bits).collect::<Vec<_>>();
        let auto = build("");
        assert_eq!(bits(build("format = \"uint8\"")), bits(auto.clone()));
        assert_eq!(bits(build("format = \"variant\"")), bits(auto.clone()));
        let half = build("format = \"float16\"");
        assert_eq!(bits(build("format = \"fp16\"")), bits(half.clone()));
        assert_ne!(bits(half.clone()), bits(auto.clone()));
        for (h, a) in half.iter().zip(&auto) {
            assert_eq!(*h, round_to_half(*a));
        }
        let raw = build("raw = true\nformat = \"uint8\"");
        assert_eq!(bits(raw), bits(build("raw = true")));
        assert_eq!(round_to_8_bits(0.5, false), 128.0 / 255.0);
        assert_eq!(round_to_8_bits(1.7, false), 1.0);
        assert_eq!(round_to_8_bits(-0.2, false), 0.0);
        // A 16-bit sRGB value of 0.502 rounds to byte 128 (0.502 · 255 = 128.01).
        assert_eq!(
            round_to_8_bits(srgb_to_linear(0.502), true),
            srgb_to_linear(128.0 / 255.0)
        );
        let text = "[textures.t]\ntype = \"bitmap\"\nfilename = \"t.png\"\nformat = \"int4\"\n";
        let root = crate::description::from_toml(text, Path::new("s.toml")).unwrap();
        let e = crate::texture::Textures::of_scene(&root, dir.path()).unwrap_err().to_string();
        assert!(e.contains("s.toml:4:10: textures.t.format"), "{e}");
    }
}
