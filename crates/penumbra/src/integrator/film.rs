//! The film of a tile: what a pixel's samples add up to.

use std::ops::Range;

use crate::math::Rgb;

/// The film of a tile: per pixel, the sum of its samples' weighted
/// radiance and the sum of their weights, row by row. Samples are added one
/// by one in the order the integrator gives them (each pixel's in the order
/// of their sample index), so adding samples `[a, b)` and then `[b, c)` of
/// its pixels gives the very bits adding `[a, c)` gives: passes,
/// checkpoints and previews all read the same sums. A pixel's value is the
/// quotient, resolved when the tile is copied into the image.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmTile {
    /// The pixels `xs × ys` of the frame.
    pub xs: Range<u32>,
    pub ys: Range<u32>,
    pub sum: Vec<Rgb>,
    pub weight: Vec<f32>,
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
        }
    }

    /// The index of pixel (x, y) (frame coordinates).
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> usize {
        (y - self.ys.start) as usize * self.xs.len() + (x - self.xs.start) as usize
    }

    /// Adds a sample of radiance `l` and weight `w` to pixel `k`.
    #[inline]
    pub fn add(&mut self, k: usize, l: Rgb, w: f32) {
        self.sum[k] += l * w;
        self.weight[k] += w;
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
