//! What every integrator offers the render driver: workers that estimate
//! the radiance of a row of pixels, counting their rays, and the samples
//! their guard caught.

use std::ops::Range;

use serde::Serialize;

use super::stats::RayStats;
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

    /// Appends the values of the pixels of the tile `xs × ys` to `out`, row
    /// by row, as [`row`](Self::row) does; `false` if `cancelled` became
    /// true, which is checked at least before every row. Tiles are aligned
    /// to the frame (an adaptive sampling rule may judge a pixel by its
    /// neighbours in the tile). By default, row after row.
    fn tile(
        &mut self,
        xs: Range<u32>,
        ys: Range<u32>,
        cancelled: &dyn Fn() -> bool,
        out: &mut Vec<Rgb>,
        bad: &mut Vec<BadSample>,
    ) -> bool {
        by_rows(self, xs, ys, cancelled, out, bad)
    }

    /// The rays traced so far, by kind.
    fn stats(&self) -> &RayStats;
}

/// [`PixelWorker::tile`] row after row, checking `cancelled` before each.
pub fn by_rows<W: PixelWorker + ?Sized>(
    worker: &mut W,
    xs: Range<u32>,
    ys: Range<u32>,
    cancelled: &dyn Fn() -> bool,
    out: &mut Vec<Rgb>,
    bad: &mut Vec<BadSample>,
) -> bool {
    for y in ys {
        if cancelled() {
            return false;
        }
        worker.row(y, xs.clone(), out, bad);
    }
    true
}
