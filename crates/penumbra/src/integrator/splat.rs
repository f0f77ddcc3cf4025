//! The splatting film: Mitsuba's `hdrfilm` development, each camera
//! sample added to every pixel its reconstruction filter covers.
//!
//! A sample at film position `p` (continuous pixel coordinates) adds
//! `f(q − p) · L` and `f(q − p)` to each pixel whose centre `q` lies within
//! the filter's radius on both axes, `f` the filter's profile along x times
//! its profile along y; a pixel's value is the quotient of its two sums.
//! This is what Mitsuba does by default (a Gaussian of σ = 0.5, radius 2),
//! and what its references are made with: each sample informs up to 25
//! pixels, where drawing film points from the filter (Penumbra's other
//! method, `filter_method = "importance"`) lets it inform one.
//!
//! # Order-free sums
//!
//! A pixel near a tile's border receives samples of the neighbouring
//! tiles' pixels, and floating-point sums depend on their order: threads,
//! tile sizes, passes or Dask workers would change the bits. The sums are
//! therefore kept in fixed point, as 128-bit integers in units of 2⁻⁶⁴.
//! The product of a sample's value and its filter weight is exact in
//! `f64` (two `f32`s), scaling it by 2⁶⁴ is exact, and the conversion
//! truncates toward zero: the same integer whoever computes it. Integer
//! addition is associative, so the tiles' bordered films merge in any
//! order into the same sums, and a pixel's value is the same on any number
//! of threads, with any tile size, in any number of passes, and in a
//! region or a Dask tile as in the whole frame. The range (±2⁶³ per sum)
//! and resolution (2⁻⁶⁴ per product) are far beyond what an `f32` image
//! can hold or show.

use std::ops::Range;

use crate::math::{Rgb, Vec2};
use crate::sampling::filter::PixelFilter;

/// 2⁶⁴: one unit of the fixed-point sums is its inverse.
const SCALE: f64 = 18_446_744_073_709_551_616.0;

/// A product in fixed point (exact but for the truncation below 2⁻⁶⁴;
/// saturating far beyond any radiance).
#[inline]
fn fixed(v: f64) -> i128 {
    (v * SCALE) as i128
}

/// One pixel's fixed-point sums: red, green, blue (weighted) and the weight.
pub type Sums = [i128; 4];

/// How samples are splatted: the filter, and how many pixels beyond its
/// own a sample of a pixel can reach.
#[derive(Clone, Debug, PartialEq)]
pub struct Splatting {
    pub filter: PixelFilter,
    /// The pixels sampled, columns and rows: the film's crop window (the
    /// whole film without one) and its sample border. Pixels beyond it are
    /// neither sampled nor written, as Mitsuba's film, whose image block is
    /// the crop window.
    pub window: (Range<u32>, Range<u32>),
    /// The filter tabulated, `filter_steps` values over its radius and a
    /// 0 (Mitsuba's `eval_discretized`); empty where it is evaluated
    /// exactly.
    table: Vec<f32>,
}

impl Splatting {
    /// Splatting by `filter` the samples of the pixels in `window`,
    /// weighted by the filter tabulated at `steps` steps over its radius
    /// (0: evaluated exactly).
    pub fn new(filter: PixelFilter, window: (Range<u32>, Range<u32>), steps: u32) -> Splatting {
        let r = filter.radius();
        let table = match steps {
            0 => Vec::new(),
            n => (0..n)
                .map(|i| filter.eval(r * i as f32 / n as f32))
                .chain([0.0])
                .collect(),
        };
        Splatting {
            filter,
            window,
            table,
        }
    }

    /// The filter's weight at offset `x` from a pixel's centre along one
    /// axis: its value, or that of the step of the table `x` falls in
    /// (the last, 0, from the radius on).
    #[inline]
    pub fn weight(&self, x: f32) -> f32 {
        if self.table.is_empty() {
            return self.filter.eval(x);
        }
        let steps = self.table.len() - 1;
        let scale = steps as f32 / self.filter.radius();
        self.table[((x.abs() * scale) as usize).min(steps)]
    }

    /// How many pixels beyond its own a sample can reach, on each side: a
    /// sample of pixel `x` lies in `[x, x + 1)`, and reaches the pixels
    /// whose centre `q + 1/2` is within the radius `r` of it, so `|q − x| ≤
    /// ⌊r + 1/2⌋`.
    pub fn border(&self) -> u32 {
        (self.filter.radius() + 0.5).floor() as u32
    }

    /// `xs × ys` grown by the border on every side, within the window
    /// (empty where it lies outside it).
    pub fn grown(&self, xs: &Range<u32>, ys: &Range<u32>) -> (Range<u32>, Range<u32>) {
        let b = self.border();
        let grow = |r: &Range<u32>, w: &Range<u32>| {
            let start = r.start.saturating_sub(b).max(w.start);
            start..(r.end + b).min(w.end).max(start)
        };
        (grow(xs, &self.window.0), grow(ys, &self.window.1))
    }
}

/// The splatted sums of the pixels a tile's samples reach: the tile's
/// pixels and a border around them, within the frame.
#[derive(Clone, Debug, PartialEq)]
pub struct SplatFilm {
    pub how: Splatting,
    /// The pixels held, `xs × ys` of the frame.
    pub xs: Range<u32>,
    pub ys: Range<u32>,
    /// Their sums, row by row.
    pub sums: Vec<Sums>,
    /// The extra channels splatted (AOVs, moments): per pixel, row by
    /// row, `channels` weighted sums and the sum of their weights, in the
    /// same fixed point.
    pub channels: usize,
    pub extra: Vec<i128>,
}

impl SplatFilm {
    /// The film of the samples of pixels `xs × ys`.
    pub fn new(how: Splatting, xs: &Range<u32>, ys: &Range<u32>) -> SplatFilm {
        SplatFilm::with_channels(how, xs, ys, 0)
    }

    /// [`new`](Self::new), with `channels` extra channels.
    pub fn with_channels(
        how: Splatting,
        xs: &Range<u32>,
        ys: &Range<u32>,
        channels: usize,
    ) -> SplatFilm {
        let (xs, ys) = how.grown(xs, ys);
        let n = xs.len() * ys.len();
        SplatFilm {
            how,
            sums: vec![[0; 4]; n],
            channels,
            extra: if channels == 0 {
                Vec::new()
            } else {
                vec![0; n * (channels + 1)]
            },
            xs,
            ys,
        }
    }

    /// Adds a sample of radiance `l` at film position `p` to every pixel
    /// held whose centre is within the filter's radius of `p` on both
    /// axes, weighted by the filter: Mitsuba's splat. The pixels range
    /// from `⌈p − 1/2 − r⌉` to `⌊p − 1/2 + r⌋` on each axis.
    pub fn put(&mut self, p: Vec2, l: Rgb) {
        let l = l.to_array().map(f64::from);
        let sums = &mut self.sums;
        reach(&self.how, &self.xs, &self.ys, p, |k, w64| {
            let s = &mut sums[k];
            s[0] += fixed(l[0] * w64);
            s[1] += fixed(l[1] * w64);
            s[2] += fixed(l[2] * w64);
            s[3] += fixed(w64);
        });
    }

    /// Adds a sample of the extra channels, `values`, at film position
    /// `p`, as [`put`](Self::put) adds the image's: to the same pixels by
    /// the same weights, in the same fixed point.
    pub fn put_channels(&mut self, p: Vec2, values: &[f32]) {
        let c = self.channels;
        if c == 0 {
            return;
        }
        let extra = &mut self.extra;
        reach(&self.how, &self.xs, &self.ys, p, |k, w64| {
            let s = &mut extra[k * (c + 1)..(k + 1) * (c + 1)];
            for (s, v) in s.iter_mut().zip(values) {
                *s += fixed(f64::from(*v) * w64);
            }
            s[c] += fixed(w64);
        });
    }

    /// Adds the sums of the extra channels held for the pixels `xs × ys`
    /// of the frame to `sums` (theirs, row by row, as [`extra`](Self::extra)
    /// holds them).
    pub fn merge_channels_into(&self, sums: &mut [i128], xs: &Range<u32>, ys: &Range<u32>) {
        let c = self.channels + 1;
        if self.channels == 0 {
            return;
        }
        let (x0, x1) = (self.xs.start.max(xs.start), self.xs.end.min(xs.end));
        let (y0, y1) = (self.ys.start.max(ys.start), self.ys.end.min(ys.end));
        for y in y0..y1 {
            let from = (y - self.ys.start) as usize * self.xs.len();
            let to = (y - ys.start) as usize * xs.len();
            for x in x0..x1 {
                let a = (from + (x - self.xs.start) as usize) * c;
                let b = (to + (x - xs.start) as usize) * c;
                for (t, f) in sums[b..b + c].iter_mut().zip(&self.extra[a..a + c]) {
                    *t += f;
                }
            }
        }
    }

    /// A film of exactly the pixels `xs × ys`, with no border: the light
    /// image of a region, which light paths reach from anywhere.
    pub fn exact(how: Splatting, xs: Range<u32>, ys: Range<u32>) -> SplatFilm {
        SplatFilm {
            how,
            sums: vec![[0; 4]; xs.len() * ys.len()],
            xs,
            ys,
            channels: 0,
            extra: Vec::new(),
        }
    }

    /// Adds the value `v` a light path brings to film position `p`, shared
    /// among the pixels whose centres are within the filter's radius by
    /// their weights over the sum of the weights of the whole footprint
    /// (pixels beyond the frame included, which keep their share): Mitsuba's
    /// normalised splat of a particle tracer. Only the colour sums grow; a
    /// pixel's value is its sum ([`light`]), not a weighted mean.
    pub fn put_light(&mut self, p: Vec2, v: Rgb) {
        let f = &self.how;
        let r = f.filter.radius();
        let (cx, cy) = (p.x - 0.5, p.y - 0.5);
        // The footprint, unclamped, in pixel indices.
        let span = |c: f32| ((c - r).ceil() as i64, (c + r).floor() as i64 + 1);
        let ((x0, x1), (y0, y1)) = (span(cx), span(cy));
        if x1 <= x0 || y1 <= y0 {
            return;
        }
        let weights = |lo: i64, hi: i64, c: f32, out: &mut [f32; 16]| {
            let mut sum = 0.0f32;
            for i in lo..hi {
                let w = f.weight(i as f32 - c);
                if let Some(o) = out.get_mut((i - lo) as usize) {
                    *o = w;
                }
                sum += w;
            }
            sum
        };
        let (mut wx, mut wy) = ([0f32; 16], [0f32; 16]);
        let norm = weights(x0, x1, cx, &mut wx) * weights(y0, y1, cy, &mut wy);
        if norm == 0.0 || !norm.is_finite() {
            return;
        }
        let held =
            |lo: i64, hi: i64, h: &Range<u32>| lo.max(i64::from(h.start))..hi.min(i64::from(h.end));
        let (xs, ys) = (held(x0, x1, &self.xs), held(y0, y1, &self.ys));
        let v = v.to_array().map(f64::from);
        let stride = self.xs.len();
        for y in ys {
            let wy = wy
                .get((y - y0) as usize)
                .copied()
                .unwrap_or_else(|| f.weight(y as f32 - cy));
            for x in xs.clone() {
                let wx = wx
                    .get((x - x0) as usize)
                    .copied()
                    .unwrap_or_else(|| f.weight(x as f32 - cx));
                let w = wx * wy / norm;
                if w == 0.0 {
                    continue;
                }
                let k = (y as usize - self.ys.start as usize) * stride
                    + (x as usize - self.xs.start as usize);
                let s = &mut self.sums[k];
                let w64 = f64::from(w);
                s[0] += fixed(v[0] * w64);
                s[1] += fixed(v[1] * w64);
                s[2] += fixed(v[2] * w64);
            }
        }
    }

    /// Adds the sums held for the pixels of `into` (`xs × ys` of the frame,
    /// row by row) to `sums`.
    pub fn merge_into(&self, sums: &mut [Sums], xs: &Range<u32>, ys: &Range<u32>) {
        let (x0, x1) = (self.xs.start.max(xs.start), self.xs.end.min(xs.end));
        let (y0, y1) = (self.ys.start.max(ys.start), self.ys.end.min(ys.end));
        for y in y0..y1 {
            let from = (y - self.ys.start) as usize * self.xs.len();
            let to = (y - ys.start) as usize * xs.len();
            for x in x0..x1 {
                let (a, b) = (
                    &self.sums[from + (x - self.xs.start) as usize],
                    &mut sums[to + (x - xs.start) as usize],
                );
                for c in 0..4 {
                    b[c] += a[c];
                }
            }
        }
    }
}

/// Calls `add` with the index (among the pixels `xs × ys`, row by row)
/// and the filter weight of every pixel held whose centre is within the
/// filter's radius of `p` on both axes, the weight nonzero: where a
/// sample at `p` is splatted. The pixels range from `⌈p − 1/2 − r⌉` to
/// `⌊p − 1/2 + r⌋` on each axis.
#[inline]
fn reach(
    how: &Splatting,
    held_xs: &Range<u32>,
    held_ys: &Range<u32>,
    p: Vec2,
    mut add: impl FnMut(usize, f64),
) {
    let r = how.filter.radius();
    // Pixel centres are at integer + 1/2: in index units the sample is
    // at `p − 1/2`.
    let (cx, cy) = (p.x - 0.5, p.y - 0.5);
    let span = |c: f32, held: &Range<u32>| {
        let lo = (c - r).ceil().max(held.start as f32) as u32;
        let hi = ((c + r).floor() + 1.0).clamp(0.0, held.end as f32) as u32;
        lo..hi.max(lo)
    };
    let (xs, ys) = (span(cx, held_xs), span(cy, held_ys));
    if xs.is_empty() || ys.is_empty() {
        return;
    }
    // The weights along x, each evaluated once (a wide filter's past
    // 16 pixels are evaluated where used).
    let mut wx = [0f32; 16];
    for (i, w) in wx.iter_mut().take(xs.len()).enumerate() {
        *w = how.weight((xs.start + i as u32) as f32 - cx);
    }
    let stride = held_xs.len();
    for y in ys {
        let wy = how.weight(y as f32 - cy);
        if wy == 0.0 {
            continue;
        }
        let row = (y - held_ys.start) as usize * stride;
        for (i, x) in xs.clone().enumerate() {
            let wx = wx
                .get(i)
                .copied()
                .unwrap_or_else(|| how.weight(x as f32 - cx));
            let w = wx * wy;
            if w == 0.0 {
                continue;
            }
            add(row + (x - held_xs.start) as usize, f64::from(w));
        }
    }
}

/// The extra channels of a pixel from their sums (`channels` of them and
/// the weight), into `out`: zeros where nothing reached it.
pub fn resolve_channels(s: &[i128], out: &mut Vec<f32>) {
    let (values, w) = s.split_at(s.len() - 1);
    let w = w[0];
    out.extend(values.iter().map(|v| {
        if w == 0 {
            0.0
        } else {
            (*v as f64 / w as f64) as f32
        }
    }));
}

/// A pixel's value from its sums: the weighted mean of what reached it
/// (black where nothing did, or where the weights cancel).
pub fn resolve(s: &Sums) -> Rgb {
    if s[3] == 0 {
        return Rgb::ZERO;
    }
    let w = s[3] as f64;
    Rgb::new(
        (s[0] as f64 / w) as f32,
        (s[1] as f64 / w) as f32,
        (s[2] as f64 / w) as f32,
    )
}

/// A pixel's value in a light image ([`SplatFilm::put_light`]): the sum
/// of what light paths brought it.
pub fn light(s: &Sums) -> Rgb {
    let v = |c: i128| (c as f64 / SCALE) as f32;
    Rgb::new(v(s[0]), v(s[1]), v(s[2]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::filter::{Filter, PixelFilter};

    fn gaussian(frame: (u32, u32)) -> Splatting {
        Splatting::new(
            PixelFilter::of(Filter::Gaussian),
            (0..frame.0, 0..frame.1),
            0,
        )
    }

    /// Mitsuba's default Gaussian (σ = 0.5, radius 2) reaches two pixels
    /// beyond a sample's own, and a film holds them within the frame.
    #[test]
    fn the_border_is_what_the_radius_reaches() {
        let how = gaussian((10, 8));
        assert_eq!(how.border(), 2);
        assert_eq!(how.grown(&(0..4), &(3..5)), (0..6, 1..7));
        assert_eq!(how.grown(&(8..10), &(6..8)), (6..10, 4..8));
        let tent = Splatting::new(PixelFilter::of(Filter::Tent), (0..10, 0..8), 0);
        assert_eq!(tent.border(), 1);
        // A crop window: nothing beyond it, nothing of a part outside it.
        let crop = Splatting::new(PixelFilter::of(Filter::Gaussian), (3..9, 2..5), 0);
        assert_eq!(crop.grown(&(4..6), &(2..3)), (3..8, 2..5));
        assert_eq!(crop.grown(&(0..1), &(7..8)).0, 3..3);
        assert!(crop.grown(&(0..1), &(7..8)).1.is_empty());
    }

    /// Tabulated as Mitsuba's CPU variants do (31 steps over the radius),
    /// a weight is the filter's value at the start of the step its offset
    /// falls in, on either side, and 0 from the radius on; without steps it
    /// is the filter's own value.
    #[test]
    fn a_tabulated_filter_weighs_by_its_steps() {
        let filter = PixelFilter::of(Filter::Gaussian);
        let r = filter.radius();
        let table = Splatting::new(filter.clone(), (0..4, 0..4), 31);
        let exact = Splatting::new(filter.clone(), (0..4, 0..4), 0);
        for k in 0..=400 {
            let x = r * 1.1 * k as f32 / 400.0;
            let step = (x * 31.0 / r) as u32;
            let want = if step >= 31 {
                0.0
            } else {
                filter.eval(r * step as f32 / 31.0)
            };
            assert_eq!(table.weight(x), want, "{x}");
            assert_eq!(table.weight(-x), want, "{x}");
            assert_eq!(exact.weight(x), filter.eval(x), "{x}");
        }
        assert_eq!(table.weight(0.0), filter.eval(0.0));
        assert!(table.weight(0.5 * r) > exact.weight(0.5 * r));
    }

    /// A sample reaches exactly the pixels whose centres are within the
    /// radius, each weighted by the filter's profiles at its offsets.
    #[test]
    fn a_sample_reaches_the_pixels_within_the_radius_by_their_weights() {
        let how = gaussian((16, 16));
        let mut film = SplatFilm::new(how.clone(), &(6..7), &(6..7));
        let p = Vec2::new(6.3, 6.8);
        film.put(p, Rgb::new(1.0, 2.0, 4.0));
        let f = &how.filter;
        for y in film.ys.clone() {
            for x in film.xs.clone() {
                let k = (y - film.ys.start) as usize * film.xs.len() + (x - film.xs.start) as usize;
                let (dx, dy) = (x as f32 + 0.5 - p.x, y as f32 + 0.5 - p.y);
                let w = f.eval(dx) * f.eval(dy);
                let s = film.sums[k];
                if dx.abs() > 2.0 || dy.abs() > 2.0 || w == 0.0 {
                    assert_eq!(s, [0; 4], "pixel ({x}, {y})");
                    continue;
                }
                assert_eq!(s[3], fixed(f64::from(w)), "pixel ({x}, {y})");
                let v = resolve(&s);
                assert!((v - Rgb::new(1.0, 2.0, 4.0)).abs().max_element() < 1e-6);
            }
        }
    }

    /// Splitting a frame's samples among tiles of any size, merged in any
    /// order, gives the sums of one film holding every sample: bit for bit.
    #[test]
    fn tiles_merge_in_any_order_to_the_same_sums() {
        let frame = (13, 11);
        let how = gaussian(frame);
        let all = (0..frame.0, 0..frame.1);
        let sample = |x: u32, y: u32, i: u32| {
            let h = (x * 73 + y * 151 + i * 31) as f32;
            let p = Vec2::new(
                x as f32 + (h * 0.618).fract(),
                y as f32 + (h * 0.414).fract(),
            );
            (p, Rgb::new(h.sin().abs() * 3.0, 0.1 * i as f32, 1e-3 * h))
        };
        let mut whole = SplatFilm::new(how.clone(), &all.0, &all.1);
        for y in all.1.clone() {
            for x in all.0.clone() {
                for i in 0..5 {
                    let (p, l) = sample(x, y, i);
                    whole.put(p, l);
                }
            }
        }
        for tile in [1u32, 3, 4, 7, 16] {
            let mut sums = vec![[0; 4]; (frame.0 * frame.1) as usize];
            let mut films = Vec::new();
            for ty in (0..frame.1).step_by(tile as usize) {
                for tx in (0..frame.0).step_by(tile as usize) {
                    let (xs, ys) = (tx..(tx + tile).min(frame.0), ty..(ty + tile).min(frame.1));
                    let mut film = SplatFilm::new(how.clone(), &xs, &ys);
                    // Samples in the other order within the tile.
                    for y in ys.clone().rev() {
                        for x in xs.clone() {
                            for i in (0..5).rev() {
                                let (p, l) = sample(x, y, i);
                                film.put(p, l);
                            }
                        }
                    }
                    films.push(film);
                }
            }
            for film in films.iter().rev() {
                film.merge_into(&mut sums, &all.0, &all.1);
            }
            assert_eq!(sums, whole.sums, "tiles of {tile}");
        }
    }

    /// A light path's value is shared among the pixels its footprint
    /// reaches by their normalised weights: they add up to the value (within
    /// the truncation of the fixed point) where the whole footprint is in the
    /// frame, and to less at the frame's edge; the box gives it to one pixel.
    #[test]
    fn light_splats_share_the_value_by_normalised_weights() {
        let how = gaussian((16, 16));
        let all = (0..16, 0..16);
        let mut film = SplatFilm::exact(how.clone(), all.0.clone(), all.1.clone());
        film.put_light(Vec2::new(7.3, 8.9), Rgb::new(2.0, 1.0, 0.5));
        let total = film.sums.iter().map(light).sum::<Rgb>();
        assert!((total - Rgb::new(2.0, 1.0, 0.5)).abs().max_element() < 1e-5);
        assert!(film.sums.iter().all(|s| s[3] == 0));
        let mut edge = SplatFilm::exact(how, all.0.clone(), all.1.clone());
        edge.put_light(Vec2::new(0.2, 8.0), Rgb::ONE);
        let total = edge.sums.iter().map(light).sum::<Rgb>();
        assert!(total.r < 0.95 && total.r > 0.3, "{total:?}");
        let boxed = Splatting::new(PixelFilter::of(Filter::Box), (0..16, 0..16), 0);
        let mut film = SplatFilm::exact(boxed, all.0, all.1);
        film.put_light(Vec2::new(3.3, 4.6), Rgb::ONE);
        let hit: Vec<usize> = (0..256).filter(|&k| film.sums[k] != [0; 4]).collect();
        assert_eq!(hit, vec![4 * 16 + 3]);
        assert_eq!(light(&film.sums[4 * 16 + 3]), Rgb::ONE);
    }

    #[test]
    fn a_pixel_nothing_reached_is_black() {
        assert_eq!(resolve(&[0; 4]), Rgb::ZERO);
        let s = [fixed(0.5), fixed(0.25), 0, fixed(0.5)];
        assert_eq!(resolve(&s), Rgb::new(1.0, 0.5, 0.0));
    }
}
