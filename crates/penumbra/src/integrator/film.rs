//! The film of a tile: what a pixel's samples add up to.

use std::ops::Range;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::splat::{SplatFilm, Splatting, Sums};
use crate::math::{Rgb, Vec2};

/// The film of a tile: per pixel, the sum of its samples' weighted
/// radiance and the sum of their weights, row by row. Samples are added one
/// by one in the order the integrator gives them (each pixel's in the order
/// of their sample index), so adding samples `[a, b)` and then `[b, c)` of
/// its pixels gives the very bits adding `[a, c)` gives: passes,
/// checkpoints and previews all read the same sums. A pixel's value is the
/// quotient, resolved when the tile is copied into the image.
///
/// With [`Splatting`], each sample is also splatted into the pixels around
/// it ([`SplatFilm`]): the image is then made of the splatted sums, merged
/// across tiles, and the per-pixel sums above hold each pixel's own
/// samples only, which is what the adaptive rules and the pixel metric
/// judge.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmTile {
    /// The pixels `xs × ys` of the frame.
    pub xs: Range<u32>,
    pub ys: Range<u32>,
    pub sum: Vec<Rgb>,
    pub weight: Vec<f32>,
    /// The splatted sums, with a splatting film.
    pub splat: Option<SplatFilm>,
    /// The extra channels (AOVs, moments) beside the image, if any.
    pub extra: Option<ExtraFilm>,
}

/// The channels an integrator writes beside the image (Mitsuba's AOVs),
/// named as Mitsuba names them, in its order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Channels {
    pub names: Vec<String>,
    /// The channels are the moments of the image's samples: each sample's
    /// CIE XYZ and its square, `[X, Y, Z, X², Y², Z²]`, added with the
    /// sample itself (Mitsuba's `moment`).
    pub moments: bool,
    /// The channels from this index on are the image's R, G and B again
    /// (`aov`'s copy of its held integrator's image): filled from the
    /// image once it is resolved, whatever the samples put there.
    pub image: Option<usize>,
}

impl Channels {
    /// No channel beside the image.
    pub fn none() -> Channels {
        Channels::default()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// The per-pixel sums of a tile's extra channels: per pixel, the sum of
/// its samples' weighted values of each channel and the sum of their
/// weights (their own: a pixel's samples of the image and of the channels
/// need not be the same, under a pixel metric say), and, with a
/// splatting film, their splatted sums.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtraFilm {
    pub channels: Arc<Channels>,
    /// Per pixel, `channels.names.len()` weighted sums, pixel after pixel.
    pub sum: Vec<f32>,
    pub weight: Vec<f32>,
}

/// Linear sRGB to CIE XYZ (D65), Mitsuba's `srgb_to_xyz`.
#[inline]
pub fn srgb_to_xyz(c: Rgb) -> [f32; 3] {
    [
        0.412453 * c.r + 0.357580 * c.g + 0.180423 * c.b,
        0.212671 * c.r + 0.715160 * c.g + 0.072169 * c.b,
        0.019334 * c.r + 0.119193 * c.g + 0.950227 * c.b,
    ]
}

/// What a tile's film has added up, without its layout (which the render
/// makes again from the scene): how a checkpoint keeps it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FilmData {
    sum: Vec<Rgb>,
    weight: Vec<f32>,
    /// The splatted sums and their extra channels.
    splat: Option<(Vec<Sums>, Vec<i128>)>,
    /// The extra channels' sums and weights.
    extra: Option<(Vec<f32>, Vec<f32>)>,
}

impl FilmTile {
    /// What the film has added up.
    pub fn data(&self) -> FilmData {
        FilmData {
            sum: self.sum.clone(),
            weight: self.weight.clone(),
            splat: self
                .splat
                .as_ref()
                .map(|s| (s.sums.clone(), s.extra.clone())),
            extra: self
                .extra
                .as_ref()
                .map(|e| (e.sum.clone(), e.weight.clone())),
        }
    }

    /// Puts back what `data` holds into this film of the same layout;
    /// `false`, the film unchanged, if the layouts differ.
    pub fn restore(&mut self, data: FilmData) -> bool {
        let fits = data.sum.len() == self.sum.len()
            && data.weight.len() == self.weight.len()
            && match (&data.splat, &self.splat) {
                (Some((sums, extra)), Some(s)) => {
                    sums.len() == s.sums.len() && extra.len() == s.extra.len()
                }
                (None, None) => true,
                _ => false,
            }
            && match (&data.extra, &self.extra) {
                (Some((sum, weight)), Some(e)) => {
                    sum.len() == e.sum.len() && weight.len() == e.weight.len()
                }
                (None, None) => true,
                _ => false,
            };
        if !fits {
            return false;
        }
        self.sum = data.sum;
        self.weight = data.weight;
        if let (Some((sums, extra)), Some(s)) = (data.splat, &mut self.splat) {
            s.sums = sums;
            s.extra = extra;
        }
        if let (Some((sum, weight)), Some(e)) = (data.extra, &mut self.extra) {
            e.sum = sum;
            e.weight = weight;
        }
        true
    }

    /// A tile of pixels `xs × ys` with nothing added.
    pub fn new(xs: Range<u32>, ys: Range<u32>) -> FilmTile {
        let n = xs.len() * ys.len();
        FilmTile {
            xs,
            ys,
            sum: vec![Rgb::ZERO; n],
            weight: vec![0.0; n],
            splat: None,
            extra: None,
        }
    }

    /// A tile of pixels `xs × ys` with nothing added, its samples also
    /// splatted as `how` says where it says so.
    pub fn with(xs: Range<u32>, ys: Range<u32>, how: Option<&Splatting>) -> FilmTile {
        FilmTile::with_channels(xs, ys, how, None)
    }

    /// [`with`](Self::with), holding `channels` beside the image (none
    /// when `None` or empty).
    pub fn with_channels(
        xs: Range<u32>,
        ys: Range<u32>,
        how: Option<&Splatting>,
        channels: Option<&Arc<Channels>>,
    ) -> FilmTile {
        let channels = channels.filter(|c| !c.is_empty());
        let n = xs.len() * ys.len();
        let count = channels.map_or(0, |c| c.names.len());
        let splat = how.map(|h| SplatFilm::with_channels(h.clone(), &xs, &ys, count));
        let extra = channels.map(|c| ExtraFilm {
            channels: Arc::clone(c),
            sum: vec![0.0; n * count],
            weight: vec![0.0; n],
        });
        FilmTile {
            splat,
            extra,
            ..FilmTile::new(xs, ys)
        }
    }

    /// The number of extra channels held.
    #[inline]
    pub fn channel_count(&self) -> usize {
        self.extra.as_ref().map_or(0, |e| e.channels.names.len())
    }

    /// The index of pixel (x, y) (frame coordinates).
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> usize {
        (y - self.ys.start) as usize * self.xs.len() + (x - self.xs.start) as usize
    }

    /// Adds a sample of radiance `l` and weight `w` to pixel `k`, taken at
    /// `offset` from the pixel's centre (where it is splatted from).
    /// With a film of the image's moments, the sample's moments are added
    /// to its channels too.
    #[inline(always)]
    pub fn add(&mut self, k: usize, l: Rgb, w: f32, offset: Vec2) {
        self.sum[k] += l * w;
        self.weight[k] += w;
        if self.splat.is_some() || self.extra.is_some() {
            self.add_beside(k, l, w, offset);
        }
    }

    /// What [`add`](Self::add) does beside the sums: the splat and the
    /// moments' channels (out of line: most films have neither).
    #[inline(never)]
    fn add_beside(&mut self, k: usize, l: Rgb, w: f32, offset: Vec2) {
        if self.splat.is_some() {
            let p = self.position(k, offset);
            if let Some(splat) = &mut self.splat {
                splat.put(p, l);
            }
        }
        if self.extra.as_ref().is_some_and(|e| e.channels.moments) {
            let [x, y, z] = srgb_to_xyz(l);
            self.add_channels(k, &[x, y, z, x * x, y * y, z * z], w, offset);
        }
    }

    /// The film position of a sample of pixel `k` at `offset` from its
    /// centre.
    #[inline]
    fn position(&self, k: usize, offset: Vec2) -> Vec2 {
        let width = self.xs.len();
        let (x, y) = (
            self.xs.start as usize + k % width,
            self.ys.start as usize + k / width,
        );
        Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset
    }

    /// Adds a sample of the extra channels, `values` (one per channel) of
    /// weight `w`, to pixel `k`, taken at `offset` from its centre, and
    /// splats it as the image's samples are splatted. Nothing without
    /// extra channels.
    #[inline]
    pub fn add_channels(&mut self, k: usize, values: &[f32], w: f32, offset: Vec2) {
        let p = self.position(k, offset);
        let Some(extra) = &mut self.extra else {
            return;
        };
        let c = extra.channels.names.len();
        debug_assert_eq!(values.len(), c);
        for (s, v) in extra.sum[k * c..(k + 1) * c].iter_mut().zip(values) {
            *s += v * w;
        }
        extra.weight[k] += w;
        if let Some(splat) = &mut self.splat {
            splat.put_channels(p, values);
        }
    }

    /// The extra channels of pixel `k`: the weighted means of its
    /// samples (zeros with none), into `out`.
    pub fn channel_values(&self, k: usize, out: &mut Vec<f32>) {
        let Some(extra) = &self.extra else {
            return;
        };
        let c = extra.channels.names.len();
        let w = extra.weight[k];
        out.extend(
            extra.sum[k * c..(k + 1) * c]
                .iter()
                .map(|s| if w == 0.0 { 0.0 } else { s / w }),
        );
    }

    /// The value of pixel `k`: the weighted mean of its samples (black
    /// with none).
    #[inline]
    pub fn value(&self, k: usize) -> Rgb {
        let w = self.weight[k];
        if w == 0.0 {
            Rgb::ZERO
        } else {
            self.sum[k] / w
        }
    }

    /// The pixels `xs × ys` (within the tile), each resolved, row by row.
    pub fn values(&self, xs: Range<u32>, ys: Range<u32>) -> Vec<Rgb> {
        let mut out = Vec::with_capacity(xs.len() * ys.len());
        for y in ys {
            out.extend(xs.clone().map(|x| self.value(self.index(x, y))));
        }
        out
    }

    /// The extra channels of pixels `xs × ys` (within the tile), each
    /// resolved, pixel after pixel, row by row.
    pub fn channel_values_of(&self, xs: Range<u32>, ys: Range<u32>) -> Vec<f32> {
        let mut out = Vec::with_capacity(xs.len() * ys.len() * self.channel_count());
        for y in ys {
            for x in xs.clone() {
                self.channel_values(self.index(x, y), &mut out);
            }
        }
        out
    }
}
