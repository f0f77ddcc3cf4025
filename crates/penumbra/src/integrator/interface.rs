//! What every integrator offers the render driver: workers that estimate
//! the radiance of a row of pixels, counting their rays, and the samples
//! their guard caught.

use std::ops::Range;

use serde::Serialize;

use super::stats::RayStats;
use super::stopping::PixelSamples;
use crate::math::Rgb;
use crate::scene::Scene;

/// A non-finite sample: caught where it was made, replaced by black.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BadSample {
    pub x: u32,
    pub y: u32,
    pub sample: u32,
}

/// A light-transport algorithm: how the radiance arriving at the camera
/// through each pixel is estimated. The render driver cuts the image into
/// tiles and gives each worker thread one [`PixelWorker`] per tile; the
/// integrator owns everything from a pixel's samples to its value.
///
/// A trait, where the scattering models and lights are closed enums: an
/// integrator is chosen once per render and called once per row of a tile,
/// so its dispatch costs nothing measurable, while new algorithms (direct
/// lighting, path tracing) are added beside the existing one without
/// touching the driver.
pub trait Integrator: Sync {
    /// A worker's state: its buffers and ray statistics.
    type Worker<'s>: PixelWorker
    where
        Self: 's;

    /// A worker for `scene`, made once per tile.
    fn worker<'s>(&'s self, scene: &'s Scene) -> Self::Worker<'s>;
}

/// One worker of an [`Integrator`].
pub trait PixelWorker {
    /// Appends the values of pixels `xs` of row `y` to `out`, each the
    /// estimate of its radiance; non-finite samples are replaced by black
    /// and reported in `bad`. A pixel's value depends only on the scene and
    /// the pixel, never on which worker renders it or in which order.
    fn row(&mut self, y: u32, xs: Range<u32>, out: &mut Vec<Rgb>, bad: &mut Vec<BadSample>);

    /// Appends the values of the pixels of `tile` to `out`, row by row, as
    /// [`row`](Self::row) does; `false` if its cancel flag became true,
    /// which is checked at least before every row. By default, row after
    /// row.
    fn tile(&mut self, tile: TileJob<'_>, out: &mut Vec<Rgb>, bad: &mut Vec<BadSample>) -> bool {
        by_rows(self, tile, out, bad)
    }

    /// How the pixels rendered by [`tile`](Self::tile) with adaptive
    /// sampling ended, in the order of their values, taken out of the
    /// worker; empty without adaptive sampling.
    fn take_samples(&mut self) -> Vec<PixelSamples> {
        Vec::new()
    }

    /// The rays traced so far, by kind.
    fn stats(&self) -> &RayStats;
}

/// A tile of the frame's grid to render: pixels `xs × ys`, and the flag
/// that cancels it. Tiles are aligned to the frame, so an adaptive sampling
/// rule may judge a pixel by its neighbours in the tile.
pub struct TileJob<'a> {
    pub xs: Range<u32>,
    pub ys: Range<u32>,
    pub cancelled: &'a dyn Fn() -> bool,
}

/// [`PixelWorker::tile`] row after row, checking the cancel flag before each.
pub fn by_rows<W: PixelWorker + ?Sized>(
    worker: &mut W,
    tile: TileJob<'_>,
    out: &mut Vec<Rgb>,
    bad: &mut Vec<BadSample>,
) -> bool {
    for y in tile.ys {
        if (tile.cancelled)() {
            return false;
        }
        worker.row(y, tile.xs.clone(), out, bad);
    }
    true
}
