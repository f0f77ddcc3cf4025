use std::ops::Range;
use std::sync::Arc;

use super::region::Region;
use crate::integrator::splat::Sums;
use crate::integrator::stopping::PixelSamples;
use crate::integrator::{
    BadSample, Channels, FilmTile, PixelWorker, RayStats, SplatFilm, Splatting, StageBatches,
};
use crate::math::Rgb;

/// A linear-RGB float image, row-major, top row first, with the channels
/// an integrator writes beside it (Mitsuba's AOVs), if any.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Rgb>,
    pub extra: Option<ExtraChannels>,
}

/// Channels beside an image's RGB: their names, in Mitsuba's order, and
/// their values, pixel after pixel (every channel of a pixel together),
/// row by row.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtraChannels {
    pub names: Vec<String>,
    pub values: Vec<f32>,
}

impl ExtraChannels {
    /// The values of channel `c`, pixel by pixel.
    pub fn channel(&self, c: usize) -> impl Iterator<Item = f32> + '_ {
        self.values
            .iter()
            .skip(c)
            .step_by(self.names.len().max(1))
            .copied()
    }

    /// The index of the channel named `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        Image {
            width,
            height,
            pixels: vec![Rgb::ZERO; width as usize * height as usize],
            extra: None,
        }
    }

    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Mean of all pixels (handy in tests and reports).
    pub fn mean(&self) -> Rgb {
        self.pixels.iter().copied().sum::<Rgb>() / self.pixels.len().max(1) as f32
    }
}

/// One rendered tile with what it counted.
pub(super) struct Tile {
    pub region: Region,
    /// Its pixels resolved, row by row; empty with a splatting film.
    pub pixels: Vec<Rgb>,
    /// Its extra channels resolved, pixel after pixel, row by row; empty
    /// with a splatting film or none.
    pub channels: Vec<f32>,
    /// With a splatting film, the sums of what its samples splatted (to be
    /// merged with the other tiles').
    pub splat: Option<SplatFilm>,
    pub rays: RayStats,
    pub batches: StageBatches,
    pub bad: Vec<BadSample>,
    /// How each pixel ended under adaptive sampling, row by row; empty
    /// without it.
    pub samples: Vec<PixelSamples>,
}

impl Tile {
    /// Copies the tile into `rows`, the band of the image of `frame` (the
    /// rendered region, in frame coordinates) that holds the tile's rows,
    /// starting with its first.
    pub(super) fn copy_into(&self, rows: &mut [Rgb], frame: Region) {
        copy_rows(&self.pixels, self.region, rows, frame, 1);
    }

    /// Copies the tile's extra channels (`c` per pixel) into `rows`, as
    /// [`copy_into`](Self::copy_into) copies its pixels.
    pub(super) fn copy_channels_into(&self, rows: &mut [f32], frame: Region, c: usize) {
        copy_rows(&self.channels, self.region, rows, frame, c);
    }
}

/// Copies `values` (`c` per pixel of `region`, row by row) into `rows`,
/// the band of the image of `frame` that holds the region's rows,
/// starting with its first.
fn copy_rows<T: Copy>(values: &[T], region: Region, rows: &mut [T], frame: Region, c: usize) {
    if c == 0 {
        return;
    }
    let (w, stride) = (region.width() as usize * c, frame.width() as usize * c);
    let x = (region.x0 - frame.x0) as usize * c;
    for (src, dst) in values.chunks_exact(w).zip(rows.chunks_exact_mut(stride)) {
        dst[x..x + w].copy_from_slice(src);
    }
}

/// What a tile keeps from one pass to the next: its film (of `block`, the
/// tile of the frame's grid that holds it), the integrator's state, and
/// what it counted so far.
#[derive(Clone)]
pub(super) struct TileSlot<S> {
    /// The part of the frame asked for.
    pub region: Region,
    /// How its pixels ended, once its last pass is rendered.
    pub samples: Vec<PixelSamples>,
    /// The tile of the frame's grid rendered for it.
    pub block: Region,
    pub film: FilmTile,
    pub state: S,
    pub rays: RayStats,
    pub batches: StageBatches,
    pub bad: Vec<BadSample>,
}

impl<S: Default> TileSlot<S> {
    /// A tile of `region` rendered as part of `block`, its samples splatted
    /// as `splat` says where it says so.
    pub(super) fn new(
        region: Region,
        block: Region,
        splat: Option<&Splatting>,
        channels: Option<&Arc<Channels>>,
    ) -> Self {
        TileSlot {
            region,
            samples: Vec::new(),
            film: FilmTile::with_channels(block.x0..block.x1, block.y0..block.y1, splat, channels),
            block,
            state: S::default(),
            rays: RayStats::default(),
            batches: StageBatches::default(),
            bad: Vec::new(),
        }
    }
}

impl<S> TileSlot<S> {
    /// Adds what the tile holds so far to the image of `frame` (the
    /// rendered region): its splatted sums to `splatted`, or its pixels
    /// resolved into `pixels` and its `c` channels into `values`, each row
    /// by row from the frame's first; without copying its film.
    pub(super) fn resolve_into(
        &self,
        frame: Region,
        (pixels, values, c): (&mut [Rgb], &mut [f32], usize),
        splatted: &mut (Vec<Sums>, Vec<i128>),
    ) {
        let (xs, ys) = (frame.x0..frame.x1, frame.y0..frame.y1);
        if let Some(splat) = &self.film.splat {
            splat.merge_into(&mut splatted.0, &xs, &ys);
            splat.merge_channels_into(&mut splatted.1, &xs, &ys);
            return;
        }
        let r = self.region;
        let row = (r.y0 - frame.y0) as usize * frame.width() as usize;
        let resolved = self.film.values(r.x0..r.x1, r.y0..r.y1);
        copy_rows(&resolved, r, &mut pixels[row..], frame, 1);
        if c > 0 {
            let channels = self.film.channel_values_of(r.x0..r.x1, r.y0..r.y1);
            copy_rows(&channels, r, &mut values[row * c..], frame, c);
        }
    }
}

/// Adds samples `samples` of the pixels of `slot`'s tile to its film (the
/// `last` range of the render, after which the worker reports how its
/// pixels ended),
/// rendering the whole `block` (the tile of the frame's grid that holds the
/// region asked for: rendered whole when adaptive sampling judges pixels by
/// their neighbours, else the same as the region); `false` if `cancelled`
/// becomes true, which is checked before every row so that a cancel takes
/// effect within a row of pixels, not a whole tile (a tile of a costly
/// scene can take seconds).
pub(super) fn render_pass<W: PixelWorker>(
    worker: &mut W,
    slot: &mut TileSlot<W::State>,
    samples: Range<u32>,
    last: bool,
    cancelled: &dyn Fn() -> bool,
) -> bool {
    worker.clear_counts();
    let block = slot.block;
    let tile = crate::integrator::TileJob {
        xs: block.x0..block.x1,
        ys: block.y0..block.y1,
        samples,
        cancelled,
    };
    let mut bad = Vec::new();
    if !worker.render(tile, &mut slot.state, &mut slot.film, &mut bad) {
        return false;
    }
    let region = slot.region;
    bad.retain(|b| (region.x0..region.x1).contains(&b.x) && (region.y0..region.y1).contains(&b.y));
    slot.bad.extend(bad);
    slot.rays += *worker.stats();
    slot.batches += worker.batches();
    if last {
        slot.samples = worker.pixel_samples(&slot.state);
    }
    true
}

/// The finished tile of `slot`: its pixels resolved (or its splatted
/// sums), and how they ended.
pub(super) fn finish<S>(mut slot: TileSlot<S>) -> Tile {
    let (region, block, samples) = (slot.region, slot.block, slot.samples);
    let samples = if samples.is_empty() || block == region {
        samples
    } else {
        crop(&samples, block, region)
    };
    let splat = slot.film.splat.take();
    let (pixels, channels) = match splat {
        Some(_) => (Vec::new(), Vec::new()),
        None => (
            slot.film.values(region.x0..region.x1, region.y0..region.y1),
            slot.film
                .channel_values_of(region.x0..region.x1, region.y0..region.y1),
        ),
    };
    Tile {
        region,
        splat,
        pixels,
        channels,
        rays: slot.rays,
        batches: slot.batches,
        bad: slot.bad,
        samples,
    }
}

/// The values of `region`'s pixels among `values`, those of `block`'s row
/// by row.
fn crop<T: Copy>(values: &[T], block: Region, region: Region) -> Vec<T> {
    let w = block.width() as usize;
    let x = (region.x0 - block.x0) as usize..(region.x1 - block.x0) as usize;
    let rows = (region.y0 - block.y0) as usize..(region.y1 - block.y0) as usize;
    rows.flat_map(|y| values[y * w + x.start..y * w + x.end].iter().copied())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::{Integrator, Whitted};
    use crate::scene::{LoadOptions, SceneSource};
    use std::cell::Cell;

    /// The cancel flag is read before every row: a tile stops within a row.
    #[test]
    fn a_tile_checks_for_cancel_before_every_row() {
        let src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
        let scene = src.build().expect("showcase builds");
        let region = Region {
            x0: 0,
            y0: 0,
            x1: 8,
            y1: 8,
        };
        let checks = Cell::new(0);
        let after_three_rows = || {
            checks.set(checks.get() + 1);
            checks.get() > 3
        };
        let whitted = Whitted::of(&scene);
        let mut slot = TileSlot::new(region, region, None, None);
        let mut worker = whitted.worker(&scene);
        assert!(!render_pass(
            &mut worker,
            &mut slot,
            0..4,
            true,
            &after_three_rows
        ));
        assert_eq!(checks.get(), 4);
        let never = || false;
        let mut slot = TileSlot::new(region, region, None, None);
        assert!(render_pass(&mut worker, &mut slot, 0..4, true, &never));
        let tile = finish(slot);
        assert_eq!(tile.pixels.len(), 64);
    }
}
