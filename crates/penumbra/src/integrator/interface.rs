//! What every integrator offers the render driver: workers that add the
//! samples of a tile's pixels to its film, counting their rays, and the
//! samples their guard caught.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use super::film::{Channels, FilmTile};
use super::stats::{RayStats, StageBatches};
use super::stopping::PixelSamples;
use crate::scene::Scene;

/// A non-finite sample: caught where it was made, replaced by black.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BadSample {
    pub x: u32,
    pub y: u32,
    pub sample: u32,
}

/// A light-transport algorithm: how the radiance arriving at the camera
/// through each pixel is estimated. The render driver cuts the image into
/// tiles and asks a [`PixelWorker`] per tile and pass for a range of the
/// pixels' samples; the integrator owns everything from a pixel's samples
/// to what its film adds up.
///
/// A trait, where the scattering models and emitters are closed enums: an
/// integrator is chosen once per render and called once per tile and pass,
/// so its dispatch costs nothing measurable, while new algorithms are added
/// beside the existing one without touching the driver.
pub trait Integrator: Sync {
    /// A worker's state: its buffers and ray statistics.
    type Worker<'s>: PixelWorker<State = Self::TileState> + Send
    where
        Self: 's;

    /// What a tile keeps from one pass to the next besides its film (which
    /// pixels stopped, the tallies of adaptive sampling).
    type TileState: Default + Send + Clone + Serialize + serde::de::DeserializeOwned;

    /// A worker for `scene`: the driver makes one per job running at once
    /// and keeps it, with its buffers, across tiles and passes.
    fn worker<'s>(&'s self, scene: &'s Scene) -> Self::Worker<'s>;

    /// The samples a pixel takes in all (the budget the passes split).
    fn samples(&self) -> u32;

    /// Passes the render is made in: each adds the next range of every
    /// pixel's samples to the film.
    fn passes(&self) -> u32;

    /// True if a tile must be rendered whole, its pixels judged by their
    /// neighbours (adaptive sampling): the driver renders the tile of the
    /// frame's grid that holds a region's part.
    fn whole_tiles(&self) -> bool;

    /// The side of the square tiles of the frame's grid, each a worker's
    /// job. Fixed per integrator, so that the work split never depends on
    /// the thread count (the pixels would not anyway).
    fn tile(&self) -> u32;

    /// True if a pixel's samples land anywhere on the frame (light
    /// tracing): the driver then renders the samples of every pixel of the
    /// frame whatever the region asked for, hands each job a light image
    /// of the region in its film's [`splat`](FilmTile::splat) (a
    /// [`SplatFilm`](super::splat::SplatFilm) of exactly the region's
    /// pixels, added to with
    /// [`put_light`](super::splat::SplatFilm::put_light)), sums the
    /// images (in fixed point: in any order) and resolves each pixel as
    /// its sum ([`light`](super::splat::light)).
    fn splats_anywhere(&self) -> bool {
        false
    }

    /// Whether `state`, read from a checkpoint, is a state this
    /// integrator could have made for a tile of `width × height` pixels
    /// (its sizes, counts and ranges), so that resuming it cannot index
    /// out of its bounds; a state of nothing always fits.
    fn state_fits(&self, _state: &Self::TileState, _size: (u32, u32)) -> bool {
        true
    }

    /// The channels its films hold beside the image (Mitsuba's AOVs):
    /// none unless it writes some.
    fn channels(&self) -> Channels {
        Channels::none()
    }
}

/// One worker of an [`Integrator`].
pub trait PixelWorker {
    /// The integrator's [`TileState`](Integrator::TileState).
    type State;

    /// Adds samples `tile.samples` of each pixel of the tile to `film` (the
    /// tile's), each pixel's in the order of their index; non-finite
    /// samples are replaced by black and reported in `bad`. A pixel's
    /// samples depend only on the scene, the pixel and their index, never on
    /// which worker renders them, in which order, or how the samples are cut
    /// into ranges: adding `[a, b)` then `[b, c)` gives the film the bits
    /// `[a, c)` gives. Returns `false` if the tile's cancel flag became
    /// true, which is checked at least before every row.
    fn render(
        &mut self,
        tile: TileJob<'_>,
        state: &mut Self::State,
        film: &mut FilmTile,
        bad: &mut Vec<BadSample>,
    ) -> bool;

    /// How the pixels of a tile ended, in row order, once its last range
    /// was rendered; empty unless the integrator samples adaptively.
    fn pixel_samples(&self, _state: &Self::State) -> Vec<PixelSamples> {
        Vec::new()
    }

    /// The rays traced so far, by kind.
    fn stats(&self) -> &RayStats;

    /// Sets the ray counts and batches back to zero: a worker kept for
    /// another job counts that job's alone.
    fn clear_counts(&mut self);

    /// The batches its stages took so far; none for an integrator that
    /// traces ray by ray.
    fn batches(&self) -> StageBatches {
        StageBatches::default()
    }
}

/// A tile of the frame's grid to render: pixels `xs × ys`, the range of
/// their samples to add, and the flag that cancels it. Tiles are aligned to
/// the frame, so an adaptive sampling rule may judge a pixel by its
/// neighbours in the tile.
pub struct TileJob<'a> {
    pub xs: Range<u32>,
    pub ys: Range<u32>,
    /// The samples to add: the range of this pass. Under adaptive sampling,
    /// a range of the rule's schedule (see the rule); the last pass ends at
    /// the budget and runs the rule to its end.
    pub samples: Range<u32>,
    pub cancelled: &'a dyn Fn() -> bool,
}

impl TileJob<'_> {
    /// The one tile loop: hands `step` the tile's rows, `rows` at a time
    /// (at least one), the cancel flag checked before each step; `false`
    /// if the tile was cancelled.
    #[inline]
    pub fn rows(&self, rows: u32, mut step: impl FnMut(Range<u32>)) -> bool {
        let mut y0 = self.ys.start;
        while y0 < self.ys.end {
            if (self.cancelled)() {
                return false;
            }
            let y1 = (y0 + rows.max(1)).min(self.ys.end);
            step(y0..y1);
            y0 = y1;
        }
        true
    }
}

/// The range of samples pass `k` of `passes` adds, out of `budget`: the
/// budget cut as evenly as it goes, earlier passes never larger.
pub fn pass_samples(k: u32, passes: u32, budget: u32) -> Range<u32> {
    let at = |k: u32| (u64::from(k) * u64::from(budget) / u64::from(passes.max(1))) as u32;
    at(k)..at(k + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_cut_the_budget_without_gaps() {
        for (passes, budget) in [(1, 16), (3, 16), (16, 16), (5, 3), (7, 1000)] {
            let ranges: Vec<_> = (0..passes)
                .map(|k| pass_samples(k, passes, budget))
                .collect();
            assert_eq!(ranges[0].start, 0);
            assert_eq!(ranges[passes as usize - 1].end, budget);
            for w in ranges.windows(2) {
                assert_eq!(w[0].end, w[1].start);
                assert!(w[0].len() <= w[1].len() + 1);
            }
        }
    }
}
