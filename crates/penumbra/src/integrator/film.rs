//! The film of a tile: what a pixel's samples add up to.

use std::ops::Range;

use super::splat::{SplatFilm, Splatting};
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
}

impl FilmTile {
    /// A tile of pixels `xs × ys` with nothing added.
    pub fn new(xs: Range<u32>, ys: Range<u32>) -> FilmTile {
        let n = xs.len() * ys.len();
        FilmTile {
            xs,
            ys,
            sum: vec![Rgb::ZERO; n],
            weight: vec![0.0; n],
            splat: None,
        }
    }

    /// A tile of pixels `xs × ys` with nothing added, its samples also
    /// splatted as `how` says where it says so.
    pub fn with(xs: Range<u32>, ys: Range<u32>, how: Option<&Splatting>) -> FilmTile {
        let splat = how.map(|h| SplatFilm::new(h.clone(), &xs, &ys));
        FilmTile {
            splat,
            ..FilmTile::new(xs, ys)
        }
    }

    /// The index of pixel (x, y) (frame coordinates).
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> usize {
        (y - self.ys.start) as usize * self.xs.len() + (x - self.xs.start) as usize
    }

    /// Adds a sample of radiance `l` and weight `w` to pixel `k`, taken at
    /// `offset` from the pixel's centre (where it is splatted from).
    #[inline]
    pub fn add(&mut self, k: usize, l: Rgb, w: f32, offset: Vec2) {
        self.sum[k] += l * w;
        self.weight[k] += w;
        if let Some(splat) = &mut self.splat {
            let width = self.xs.len();
            let (x, y) = (
                self.xs.start as usize + k % width,
                self.ys.start as usize + k / width,
            );
            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            splat.put(centre + offset, l);
        }
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
}
