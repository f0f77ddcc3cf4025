//! The parallel render driver: tiles over a rayon pool, deterministic seeding,
//! progress reporting, and the guard that keeps NaN and infinity out of images.

pub mod film;
mod region;
mod report;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use serde::Serialize;

use film::TileSlot;
pub use film::{ExtraChannels, Image};
pub use region::Region;
pub use report::stats_document;

use crate::description::SceneError;
use crate::integrator::aov::Aov;
use crate::integrator::splat::{light, resolve, resolve_channels, SplatFilm, Sums};
use crate::integrator::stopping::PixelSamples;
use crate::integrator::{
    pass_samples, BadSample, Config, Integrator, RayStats, RenderWith, Splatting, StageBatches,
};
use crate::math::Rgb;
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
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("cannot start {threads} worker threads: {message}")]
    Threads { threads: usize, message: String },
    #[error("region [{x0}, {x1}) x [{y0}, {y1}) is empty or outside the {1}x{2} image", x0 = .0.x0, x1 = .0.x1, y0 = .0.y0, y1 = .0.y1)]
    Region(Region, u32, u32),
    #[error("render cancelled")]
    Cancelled,
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
    let config = Config::of(scene).map_err(|e| RenderError::Integrator(e.into()))?;
    config.render_with(
        scene,
        Render {
            scene,
            opts,
            progress,
            cancel,
        },
    )
}

/// A render of a scene with whichever integrator its [`Config`] makes.
struct Render<'a> {
    scene: &'a Scene,
    opts: &'a RenderOptions,
    progress: Progress<'a>,
    cancel: Option<&'a AtomicBool>,
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
            );
        }
        render_with(
            integrator,
            self.scene,
            self.opts,
            self.progress,
            self.cancel,
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

/// Renders the scene (or a region of it) with `integrator`, in its passes:
/// each pass asks a worker per tile to add the pass's range of every
/// pixel's samples to the tile's film, and the last copies each finished
/// tile into the image. The tiles' films and the integrator's state per
/// tile are kept between passes; a render of one pass keeps only the tiles
/// being rendered.
///
/// With a splatting film the samples of the pixels around the region
/// reach it too: the region grown by the filter's reach is rendered, each
/// finished tile's sums are added to the region's (in fixed point, so in
/// any order), and the image is resolved from them at the end. A region
/// thus gets the pixels the whole frame has.
///
/// An integrator whose samples land anywhere ([`Integrator::splats_anywhere`],
/// light tracing) renders the samples of the whole frame whatever the
/// region; each job adds to a light image of the region, taken from a pool
/// (at most one per job running) and given back after the job; the images
/// are summed at the end (in fixed point, so in any order) and each pixel is
/// its sum.
pub fn render_with<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    opts: &RenderOptions,
    progress: Progress<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<(Image, RenderStats), RenderError> {
    let s = &scene.settings;
    let region = opts.region.unwrap_or_else(|| frame(s));
    if region.x0 >= region.x1
        || region.y0 >= region.y1
        || region.x1 > s.width
        || region.y1 > s.height
    {
        return Err(RenderError::Region(region, s.width, s.height));
    }
    let threads = opts
        .threads
        .unwrap_or_else(rayon::current_num_threads)
        .max(1);
    let pool = pool(threads)?;
    let tile = integrator.tile();
    // The pixels sampled: the crop window and its sample border, grown to
    // hold a region beyond them.
    let window = {
        let (f, b) = (frame(s), s.border);
        Region {
            x0: (f.x0 - b).min(region.x0),
            y0: (f.y0 - b).min(region.y0),
            x1: (f.x1 + b).max(region.x1),
            y1: (f.y1 + b).max(region.y1),
        }
    };
    let anywhere = integrator.splats_anywhere();
    let splatting = (s.splat && !anywhere).then(|| {
        Splatting::new(
            s.filter.clone(),
            (window.x0..window.x1, window.y0..window.y1),
            s.filter_steps,
        )
    });
    let lights: Mutex<Vec<SplatFilm>> = Mutex::new(Vec::new());
    let light_film = || {
        let pooled = lights.lock().unwrap_or_else(|e| e.into_inner()).pop();
        pooled.unwrap_or_else(|| {
            let how = Splatting::new(s.filter.clone(), (0..s.width, 0..s.height), s.filter_steps);
            SplatFilm::exact(how, region.x0..region.x1, region.y0..region.y1)
        })
    };
    let sampled = match &splatting {
        _ if anywhere => frame_of(s),
        Some(how) => {
            let (xs, ys) = how.grown(&(region.x0..region.x1), &(region.y0..region.y1));
            Region {
                x0: xs.start,
                y0: ys.start,
                x1: xs.end,
                y1: ys.end,
            }
        }
        None => region,
    };
    let tiles = tiles(sampled, tile);
    let channels = integrator.channels();
    let c = channels.names.len();
    let channels = (c > 0).then(|| Arc::new(channels));
    let pixels = region.width() as usize * region.height() as usize;
    let splatted: Mutex<(Vec<Sums>, Vec<i128>)> = Mutex::new(match splatting {
        Some(_) => (
            vec![[0; 4]; pixels],
            vec![0; pixels * (c + 1) * usize::from(c > 0)],
        ),
        None => (Vec::new(), Vec::new()),
    });
    let done = AtomicUsize::new(0);
    let start = Instant::now();
    let mut image = Image::new(region.width(), region.height());
    // Each finished tile is copied into its band of rows (a band per row of
    // tiles) while the other workers go on: copying the whole image after
    // the last tile would take a few percent of a Whitted frame on two threads.
    let cuts = cuts(region.y0, region.y1, tile);
    let mut values = vec![0f32; pixels * c];
    let mut bands: Vec<Mutex<(&mut [Rgb], &mut [f32])>> = Vec::new();
    let (mut rest, mut rest_values) = (&mut image.pixels[..], &mut values[..]);
    for rows in cuts.windows(2) {
        let n = (rows[1] - rows[0]) as usize * region.width() as usize;
        let (band, after) = rest.split_at_mut(n);
        let (band_values, after_values) = rest_values.split_at_mut(n * c);
        bands.push(Mutex::new((band, band_values)));
        rest = after;
        rest_values = after_values;
    }
    let passes = integrator.passes().max(1);
    let work = tiles.len() * passes as usize;
    let whole = integrator.whole_tiles();
    let slots: Vec<Mutex<Option<TileSlot<I::TileState>>>> =
        tiles.iter().map(|_| Mutex::new(None)).collect();
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    type Counted = (
        RayStats,
        StageBatches,
        Vec<BadSample>,
        Region,
        Vec<PixelSamples>,
    );
    let mut results: Vec<Option<Counted>> = Vec::new();
    for pass in 0..passes {
        let samples = pass_samples(pass, passes, integrator.samples());
        let last = pass + 1 == passes;
        let finished: Vec<Option<Option<Counted>>> = pool.install(|| {
            tiles
                .par_iter()
                .zip(&slots)
                .map(|(t, slot)| {
                    let mut slot = slot.lock().unwrap_or_else(|e| e.into_inner());
                    let block = if whole {
                        aligned(*t, (s.width, s.height), tile)
                    } else {
                        *t
                    };
                    let tile = slot.get_or_insert_with(|| {
                        TileSlot::new(*t, block, splatting.as_ref(), channels.as_ref())
                    });
                    if anywhere {
                        tile.film.splat = Some(light_film());
                    }
                    let rendered = film::render_pass(
                        integrator,
                        scene,
                        tile,
                        samples.clone(),
                        last,
                        &cancelled,
                    );
                    if anywhere {
                        if let Some(l) = tile.film.splat.take() {
                            lights.lock().unwrap_or_else(|e| e.into_inner()).push(l);
                        }
                    }
                    if !rendered {
                        return None;
                    }
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, work);
                    if !last {
                        return Some(None);
                    }
                    let tile = film::finish(slot.take()?);
                    if anywhere {
                        // The light images are summed at the end.
                    } else if let Some(splat) = &tile.splat {
                        let mut sums = splatted.lock().unwrap_or_else(|e| e.into_inner());
                        let (xs, ys) = (region.x0..region.x1, region.y0..region.y1);
                        splat.merge_into(&mut sums.0, &xs, &ys);
                        splat.merge_channels_into(&mut sums.1, &xs, &ys);
                    } else {
                        let band = cuts.partition_point(|&y| y < t.y0);
                        let rows = &bands[band];
                        let mut rows = rows.lock().unwrap_or_else(|e| e.into_inner());
                        tile.copy_into(rows.0, region);
                        tile.copy_channels_into(rows.1, region, c);
                    }
                    Some(Some((
                        tile.rays,
                        tile.batches,
                        tile.bad,
                        tile.region,
                        tile.samples,
                    )))
                })
                .collect()
        });
        if finished.iter().any(Option::is_none) {
            return Err(RenderError::Cancelled);
        }
        if last {
            results = finished.into_iter().flatten().collect();
        }
    }
    drop(bands);
    let (splatted, splatted_channels) = splatted.into_inner().unwrap_or_else(|e| e.into_inner());
    if anywhere {
        let mut sums = vec![[0; 4]; region.width() as usize * region.height() as usize];
        let (xs, ys) = (region.x0..region.x1, region.y0..region.y1);
        for l in lights.into_inner().unwrap_or_else(|e| e.into_inner()) {
            l.merge_into(&mut sums, &xs, &ys);
        }
        for (p, s) in image.pixels.iter_mut().zip(&sums) {
            *p = light(s);
        }
    } else if !splatted.is_empty() {
        for (p, s) in image.pixels.iter_mut().zip(&splatted) {
            *p = resolve(s);
        }
        if c > 0 {
            values.clear();
            for s in splatted_channels.chunks_exact(c + 1) {
                resolve_channels(s, &mut values);
            }
        }
    }
    if let Some(channels) = channels {
        if let Some(at) = channels.image {
            for (p, v) in image.pixels.iter().zip(values.chunks_exact_mut(c)) {
                v[at..at + 3].copy_from_slice(&p.to_array());
            }
        }
        image.extra = Some(ExtraChannels {
            names: channels.names.clone(),
            values,
        });
    }
    let mut stats = RenderStats {
        threads,
        ..RenderStats::default()
    };
    let adaptive = whole;
    if adaptive {
        let pixels = region.width() as usize * region.height() as usize;
        stats.pixel_samples = vec![PixelSamples::default(); pixels];
    }
    for tile in results {
        let (rays, batches, bad, at, samples) = tile.ok_or(RenderError::Cancelled)?;
        if adaptive {
            place(&mut stats.pixel_samples, region, at, &samples);
        }
        stats.rays += rays;
        stats.batches += batches;
        stats.bad_samples += bad.len() as u64;
        let room = 16usize.saturating_sub(stats.first_bad_samples.len());
        stats.first_bad_samples.extend(bad.into_iter().take(room));
    }
    stats.render_time = start.elapsed();
    Ok((image, stats))
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
