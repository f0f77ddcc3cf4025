//! The parallel render driver: tiles over a rayon pool, deterministic seeding,
//! progress reporting, and the guard that keeps NaN and infinity out of images.

pub mod checkpoint;
mod driver;
pub mod film;
mod region;
mod report;

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde::Serialize;

pub use checkpoint::{render_digest, CheckpointError, Digest, DigestInput};
pub use driver::{render_with, Checkpointing, Ended, PassView, Progressive};
pub use film::{ExtraChannels, Image};
pub use region::Region;
pub use report::stats_document;

use crate::description::SceneError;
use crate::integrator::aov::Aov;
use crate::integrator::stopping::PixelSamples;
use crate::integrator::{BadSample, Config, Integrator, RayStats, RenderWith, StageBatches};
use crate::scene::Scene;

/// How to run a render (what to render is the scene's business).
#[derive(Clone, Debug, Default)]
pub struct RenderOptions {
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Render only this part of the frame (pixels keep their full-frame
    /// values); `None` renders the scene's crop window, the whole frame
    /// when it has none.
    pub region: Option<Region>,
}

/// What a render measured.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RenderStats {
    pub rays: RayStats,
    /// The mean batches of the wavefront's stages (see [`StageBatches`]).
    pub batches: StageBatches,
    pub render_time: Duration,
    pub threads: usize,
    /// Number of non-finite samples discarded, and the first few of them.
    pub bad_samples: u64,
    pub first_bad_samples: Vec<BadSample>,
    /// With adaptive sampling, how each pixel of the rendered region ended
    /// (its camera rays, the calibrated rule's interval), row by row; empty
    /// without it.
    #[serde(skip)]
    pub pixel_samples: Vec<PixelSamples>,
    /// How the render ended: every pass done, or early.
    pub ended: Ended,
    /// Why a checkpoint could not be saved (the first failure), if one
    /// could not: the render goes on and its image is made all the same.
    #[serde(skip)]
    pub checkpoint_error: Option<String>,
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("cannot start {threads} worker threads: {message}")]
    Threads { threads: usize, message: String },
    #[error("region [{x0}, {x1}) x [{y0}, {y1}) is empty or outside the {1}x{2} image", x0 = .0.x0, x1 = .0.x1, y0 = .0.y0, y1 = .0.y1)]
    Region(Region, u32, u32),
    #[error("render cancelled")]
    Cancelled,
    /// A checkpoint could not be resumed or saved.
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    /// The scene's integrator does not read (a description changed after
    /// the scene was built).
    #[error("{0}")]
    Integrator(SceneError),
    /// The film asks for an alpha channel the integrator cannot give.
    #[error("the film's `alpha` (Mitsuba's `pixel_format` `rgba`) is not supported with this integrator: {0}")]
    Alpha(&'static str),
}

/// The whole frame of `s`, crop window or not.
fn frame_of(s: &crate::scene::Settings) -> Region {
    Region {
        x0: 0,
        y0: 0,
        x1: s.width,
        y1: s.height,
    }
}

/// The part of the frame a render makes unless told otherwise: the
/// film's crop window, or the whole frame.
pub fn frame(s: &crate::scene::Settings) -> Region {
    match s.crop {
        Some(c) => Region {
            x0: c.x,
            y0: c.y,
            x1: c.x + c.width,
            y1: c.y + c.height,
        },
        None => Region {
            x0: 0,
            y0: 0,
            x1: s.width,
            y1: s.height,
        },
    }
}

/// Progress callback: (tiles done, tiles in all).
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// Renders the scene (or a region of it) with the integrator it chose and
/// returns the image with its statistics.
pub fn render(
    scene: &Scene,
    opts: &RenderOptions,
    progress: Progress<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<(Image, RenderStats), RenderError> {
    render_progressive(scene, opts, progress, cancel, &Progressive::default())
}

/// [`render`], progressively: ended early by a time limit or an
/// interrupt, the image shown after each pass, its state saved in
/// checkpoints and resumed from one, as `run` says.
pub fn render_progressive(
    scene: &Scene,
    opts: &RenderOptions,
    progress: Progress<'_>,
    cancel: Option<&AtomicBool>,
    run: &Progressive<'_>,
) -> Result<(Image, RenderStats), RenderError> {
    let config = Config::of(scene).map_err(|e| RenderError::Integrator(e.into()))?;
    config.render_with(
        scene,
        Render {
            scene,
            opts,
            progress,
            cancel,
            run,
        },
    )
}

/// A render of a scene with whichever integrator its [`Config`] makes.
struct Render<'a> {
    scene: &'a Scene,
    opts: &'a RenderOptions,
    progress: Progress<'a>,
    cancel: Option<&'a AtomicBool>,
    run: &'a Progressive<'a>,
}

impl RenderWith for Render<'_> {
    type Output = Result<(Image, RenderStats), RenderError>;

    fn render<I: Integrator>(self, integrator: &I) -> Self::Output {
        // An integrator writing channels of its own (`aov`, whose `N.A` is
        // the alpha, `moment`) writes them without the film's alpha.
        if self.scene.settings.alpha && integrator.channels().is_empty() {
            alpha_refused(integrator)?;
            return render_with(
                &Aov::alpha(self.scene, integrator),
                self.scene,
                self.opts,
                self.progress,
                self.cancel,
                self.run,
            );
        }
        render_with(
            integrator,
            self.scene,
            self.opts,
            self.progress,
            self.cancel,
            self.run,
        )
    }
}

/// Refuses the film's alpha channel with an integrator that cannot carry
/// it: one whose samples land anywhere (`ptracer`).
fn alpha_refused<I: Integrator>(integrator: &I) -> Result<(), RenderError> {
    if integrator.splats_anywhere() {
        return Err(RenderError::Alpha(
            "its samples land anywhere on the film, not in the pixel of a camera ray",
        ));
    }
    Ok(())
}

/// Copies the values of tile `at` (row by row) within `region` into `out`,
/// the values of `region` row by row (a tile of the grown region of a
/// splatting film may reach beyond it).
fn place<T: Copy>(out: &mut [T], region: Region, at: Region, values: &[T]) {
    let (w, stride) = (at.width() as usize, region.width() as usize);
    let (x0, x1) = (at.x0.max(region.x0), at.x1.min(region.x1));
    if x0 >= x1 {
        return;
    }
    let n = (x1 - x0) as usize;
    for y in at.y0.max(region.y0)..at.y1.min(region.y1) {
        let src = (y - at.y0) as usize * w + (x0 - at.x0) as usize;
        let dst = (y - region.y0) as usize * stride + (x0 - region.x0) as usize;
        out[dst..dst + n].copy_from_slice(&values[src..src + n]);
    }
}

/// The worker pool of `threads` threads, made on first use and kept: starting
/// threads costs about half a millisecond per render, which small renders
/// (a distributed tile, an interactive preview) and the first tiles of every
/// render would otherwise pay, and kept workers keep their warm buffers.
fn pool(threads: usize) -> Result<Arc<rayon::ThreadPool>, RenderError> {
    static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());
    let mut pools = POOLS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(n, _)| *n == threads) {
        return Ok(Arc::clone(p));
    }
    let p = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("penumbra-worker-{i}"))
        .build()
        .map_err(|e| RenderError::Threads {
            threads,
            message: e.to_string(),
        })?;
    let p = Arc::new(p);
    pools.push((threads, Arc::clone(&p)));
    Ok(p)
}

/// The region cut into tiles, row by row: its parts in each tile of the
/// frame's grid of `tile × tile` tiles.
fn tiles(r: Region, tile: u32) -> Vec<Region> {
    let (xs, ys) = (cuts(r.x0, r.x1, tile), cuts(r.y0, r.y1, tile));
    let mut out = Vec::new();
    for y in ys.windows(2) {
        for x in xs.windows(2) {
            out.push(Region {
                x0: x[0],
                y0: y[0],
                x1: x[1],
                y1: y[1],
            });
        }
    }
    out
}

/// `lo`, the multiples of `tile` between, and `hi`: where `[lo, hi)` is cut.
fn cuts(lo: u32, hi: u32, tile: u32) -> Vec<u32> {
    let mut at = vec![lo];
    at.extend((lo / tile + 1..).map(|k| k * tile).take_while(|&c| c < hi));
    at.push(hi);
    at
}

/// The tile of the frame's grid (a `width × height` frame cut into tiles
/// of side `tile`) that holds `t`.
fn aligned(t: Region, (width, height): (u32, u32), tile: u32) -> Region {
    let (x0, y0) = (t.x0 / tile * tile, t.y0 / tile * tile);
    Region {
        x0,
        y0,
        x1: (x0 + tile).min(width),
        y1: (y0 + tile).min(height),
    }
}
