//! The pass loop: tiles rendered pass after pass over the worker pool,
//! each finished tile merged into the image, and, for a progressive
//! render, the image shown after each pass, the render ended early by a
//! time limit or an interrupt, and its state saved in checkpoints and
//! resumed from them.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use super::checkpoint::{self, CheckpointError, Digest, Saved, SavedTile};
use super::film::{self, Tile, TileSlot};
use super::film::{ExtraChannels, Image};
use super::grid::{aligned, cuts, frame, frame_of, place, pool, tiles};
use super::outcome::{Ended, Progress, RenderError, RenderOptions, RenderStats};
use super::region::Region;
use crate::integrator::splat::{light, resolve, resolve_channels, SplatFilm, Sums};
use crate::integrator::stopping::PixelSamples;
use crate::integrator::{
    pass_samples, BadSample, Channels, Integrator, RayStats, Splatting, StageBatches,
};
use crate::math::Rgb;
use crate::scene::Scene;

/// What a progressive render does besides rendering: when it ends early,
/// what it shows after each pass, and where it keeps its state.
#[derive(Default)]
pub struct Progressive<'a> {
    /// No tile is started after this long; the tiles in flight finish and
    /// the image holds every pixel's samples so far.
    pub time_limit: Option<Duration>,
    /// True to end the render cleanly (a signal, a stop button): the
    /// tiles in flight are abandoned within a row, the checkpoint is saved
    /// and the image of the samples so far returned.
    pub interrupt: Option<&'a (dyn Fn() -> bool + Sync)>,
    /// Called after each pass with the image so far.
    pub on_pass: Option<&'a (dyn Fn(&PassView<'_>) + Sync)>,
    /// Where to save the render's state, and from where to resume it.
    pub checkpoint: Option<Checkpointing>,
}

/// Checkpoints of a render.
#[derive(Clone, Debug)]
pub struct Checkpointing {
    /// The file saved to (none: only resume).
    pub save: Option<PathBuf>,
    /// Saved at least this often while tiles finish, and at the end.
    pub interval: Duration,
    /// The checkpoint resumed, if any.
    pub resume: Option<PathBuf>,
    /// What the render depends on: a checkpoint of another digest is
    /// refused.
    pub digest: Digest,
}

/// The image of a render after a pass, with what it counted so far.
pub struct PassView<'a> {
    /// Passes finished (every tile's), and in all.
    pub pass: u32,
    pub passes: u32,
    pub image: &'a Image,
    pub stats: &'a RenderStats,
}

/// What a tile of the list holds: the passes done, its slot (taken out
/// while a pass renders it unless checkpoints keep it; dropped once the
/// tile is finished unless they keep it), and what it counted once
/// finished and merged into the image.
struct Cell<S> {
    passes_done: u32,
    slot: Option<TileSlot<S>>,
    counted: Option<Counted>,
}

/// What a finished tile counted: its rays, batches, bad samples, and how
/// its pixels ended under adaptive sampling (of its region).
type Counted = (
    RayStats,
    StageBatches,
    Vec<BadSample>,
    Region,
    Vec<PixelSamples>,
);

fn counted(tile: Tile) -> Counted {
    (tile.rays, tile.batches, tile.bad, tile.region, tile.samples)
}

/// The image's share of a render: the pixels of finished tiles (in bands
/// of rows, a band per row of tiles, copied into by the workers while
/// the others go on), or the splatted sums they made, and the light image
/// of a light tracer.
struct Canvas<'i> {
    region: Region,
    /// A light tracer's: its tiles hold nothing of the image.
    anywhere: bool,
    cuts: Vec<u32>,
    bands: Vec<Mutex<(&'i mut [Rgb], &'i mut [f32])>>,
    c: usize,
    splatted: Mutex<(Vec<Sums>, Vec<i128>)>,
    light: Mutex<Vec<Sums>>,
}

impl Canvas<'_> {
    /// Copies a finished tile into the image (or its sums); a light
    /// tracer's tiles hold nothing of the image (its light images do).
    fn merge(&self, tile: &Tile) {
        let region = self.region;
        if self.anywhere {
            return;
        }
        if let Some(splat) = &tile.splat {
            let mut sums = lock(&self.splatted);
            let (xs, ys) = (region.x0..region.x1, region.y0..region.y1);
            splat.merge_into(&mut sums.0, &xs, &ys);
            splat.merge_channels_into(&mut sums.1, &xs, &ys);
        } else {
            let band = self.cuts.partition_point(|&y| y < tile.region.y0);
            let mut rows = lock(&self.bands[band]);
            tile.copy_into(rows.0, region);
            tile.copy_channels_into(rows.1, region, self.c);
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// How a tile's job for a pass ended.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Job {
    Done,
    /// Already past this pass (resumed), or finished.
    Skipped,
    /// Not started: the time limit passed or the render was interrupted.
    Stopped,
    /// Abandoned within the tile: interrupted.
    Abandoned,
    Cancelled,
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
///
/// A progressive render ([`Progressive`]) may end early, at its time limit
/// or interrupted, with the image of the samples added so far (each tile's
/// passes done). With checkpoints, each tile's pass is rendered on a copy
/// of its slot, put back only when the pass is whole, so that a saved
/// state never holds a part of a pass; the state is saved under a lock
/// that every put-back takes, so that it is the state of one moment; a
/// light tracer's job then adds to a light image of its own, added to the
/// render's under that lock.
pub fn render_with<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    opts: &RenderOptions,
    progress: Progress<'_>,
    cancel: Option<&AtomicBool>,
    run: &Progressive<'_>,
) -> Result<(Image, RenderStats), RenderError> {
    let start = Instant::now();
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
    let mut image = Image::new(region.width(), region.height());
    let mut values = vec![0f32; pixels * c];
    let passes = integrator.passes().max(1);
    let whole = integrator.whole_tiles();
    let ckpt = run.checkpoint.as_ref();
    let keep = ckpt.is_some_and(|k| k.save.is_some());
    let mut cells: Vec<Mutex<Cell<I::TileState>>> = tiles
        .iter()
        .map(|_| {
            Mutex::new(Cell {
                passes_done: 0,
                slot: None,
                counted: None,
            })
        })
        .collect();
    let new_slot = |t: &Region| {
        let block = if whole {
            aligned(*t, (s.width, s.height), tile)
        } else {
            *t
        };
        TileSlot::new(*t, block, splatting.as_ref(), channels.as_ref())
    };
    let light_film = |pool: &Mutex<Vec<SplatFilm>>| {
        lock(pool).pop().unwrap_or_else(|| {
            let how = Splatting::new(s.filter.clone(), (0..s.width, 0..s.height), s.filter_steps);
            SplatFilm::exact(how, region.x0..region.x1, region.y0..region.y1)
        })
    };
    // The state resumed.
    let mut light_resumed = Vec::new();
    let mut seconds_before = 0.0;
    if let Some(path) = ckpt.and_then(|k| k.resume.as_ref()) {
        let digest = ckpt.map(|k| k.digest).unwrap_or_default();
        let saved: Saved<I::TileState> = checkpoint::read(path, &digest)?;
        let damaged = |what: &str| CheckpointError::Corrupt {
            path: path.clone(),
            what: what.to_string(),
        };
        if saved.passes != passes
            || saved.region != region
            || saved.tile_regions != tiles
            || saved.tiles.len() != tiles.len()
        {
            return Err(damaged("its tiles or passes are not this render's").into());
        }
        if saved.light.len() != if anywhere { pixels } else { 0 } {
            return Err(damaged("its light image is not this render's").into());
        }
        for ((cell, t), saved) in cells.iter_mut().zip(&tiles).zip(saved.tiles) {
            let Some(saved) = saved else { continue };
            let mut slot = new_slot(t);
            let size = (slot.block.width(), slot.block.height());
            if saved.passes_done > passes
                || !slot.film.restore(saved.film)
                || !integrator.state_fits(&saved.state, size)
            {
                return Err(damaged("a tile's film or state is not this render's").into());
            }
            slot.state = saved.state;
            slot.rays = saved.rays;
            slot.batches = saved.batches;
            slot.bad = saved.bad;
            slot.samples = saved.samples;
            let cell = cell.get_mut().unwrap_or_else(|e| e.into_inner());
            cell.passes_done = saved.passes_done;
            cell.slot = Some(slot);
        }
        light_resumed = saved.light;
        seconds_before = saved.seconds;
    }
    let canvas = {
        // Each finished tile is copied into its band of rows while the
        // other workers go on: copying the whole image after the last tile
        // would take a few percent of a Whitted frame on two threads.
        let cuts = cuts(region.y0, region.y1, tile);
        let mut bands = Vec::new();
        let (mut rest, mut rest_values) = (&mut image.pixels[..], &mut values[..]);
        for rows in cuts.windows(2) {
            let n = (rows[1] - rows[0]) as usize * region.width() as usize;
            let (band, after) = rest.split_at_mut(n);
            let (band_values, after_values) = rest_values.split_at_mut(n * c);
            bands.push(Mutex::new((band, band_values)));
            rest = after;
            rest_values = after_values;
        }
        let splatted = match splatting {
            Some(_) => (
                vec![[0; 4]; pixels],
                vec![0; pixels * (c + 1) * usize::from(c > 0)],
            ),
            None => (Vec::new(), Vec::new()),
        };
        let light = match anywhere {
            true if !light_resumed.is_empty() => light_resumed,
            true => vec![[0; 4]; pixels],
            false => Vec::new(),
        };
        Canvas {
            region,
            anywhere,
            cuts,
            bands,
            c,
            splatted: Mutex::new(splatted),
            light: Mutex::new(light),
        }
    };
    // Resumed tiles already finished are in the image.
    for cell in &mut cells {
        let cell = cell.get_mut().unwrap_or_else(|e| e.into_inner());
        if cell.passes_done == passes {
            if let Some(slot) = &cell.slot {
                let tile = film::finish(slot.clone());
                canvas.merge(&tile);
                cell.counted = Some(counted(tile));
            }
        }
    }
    let lights: Mutex<Vec<SplatFilm>> = Mutex::new(Vec::new());
    // Workers and their buffers, kept across tiles and passes, one per
    // thread of the pool: a job takes its thread's (or makes it) and gives
    // it back, so that its buffers stay in that thread's core's caches.
    let workers: Vec<Mutex<Option<I::Worker<'_>>>> = (0..pool.current_num_threads())
        .map(|_| Mutex::new(None))
        .collect();
    let own_worker = || &workers[rayon::current_thread_index().unwrap_or(0) % workers.len()];
    let jobs_total = tiles.len() * passes as usize;
    let done = AtomicUsize::new(
        cells
            .iter()
            .map(|c| lock(c).passes_done as usize)
            .sum::<usize>(),
    );
    let deadline = run.time_limit.map(|t| start + t);
    let interrupted = || run.interrupt.is_some_and(|i| i());
    let stop = || interrupted() || deadline.is_some_and(|d| Instant::now() >= d);
    let hard = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let cancelled = || hard() || interrupted();
    // Held while a tile's pass is put back and while a state is saved.
    let commit = Mutex::new(());
    let saving = Mutex::new(Instant::now());
    let save_failed: Mutex<Option<CheckpointError>> = Mutex::new(None);
    let save = |now: bool| {
        let (Some(k), Some(path)) = (ckpt, ckpt.and_then(|k| k.save.as_ref())) else {
            return;
        };
        let Ok(mut last) = saving.try_lock() else {
            return;
        };
        if !now && last.elapsed() < k.interval {
            return;
        }
        let state = {
            let _commit = lock(&commit);
            Saved {
                region,
                tile_regions: tiles.clone(),
                passes,
                tiles: cells
                    .iter()
                    .map(|c| {
                        let c = lock(c);
                        c.slot.as_ref().map(|slot| SavedTile {
                            passes_done: c.passes_done,
                            film: slot.film.data(),
                            state: slot.state.clone(),
                            rays: slot.rays,
                            batches: slot.batches,
                            bad: slot.bad.clone(),
                            samples: slot.samples.clone(),
                        })
                    })
                    .collect(),
                light: lock(&canvas.light).clone(),
                seconds: seconds_before + start.elapsed().as_secs_f64(),
            }
        };
        let bytes = checkpoint::encode(&k.digest, &state);
        if let Err(e) = checkpoint::save_atomically(path, &bytes) {
            lock(&save_failed).get_or_insert(e);
        }
        *last = Instant::now();
    };
    let first = cells
        .iter()
        .map(|c| lock(c).passes_done)
        .min()
        .unwrap_or(passes);
    let mut ended = Ended::Complete;
    for pass in first..passes {
        if stop() {
            ended = if interrupted() {
                Ended::Interrupted
            } else {
                Ended::TimeLimit
            };
            break;
        }
        let samples = pass_samples(pass, passes, integrator.samples());
        let last = pass + 1 == passes;
        let jobs: Vec<Job> = pool.install(|| {
            tiles
                .par_iter()
                .zip(&cells)
                .map(|(t, cell)| {
                    let mut work = {
                        let mut cell = lock(cell);
                        if cell.passes_done > pass {
                            return Job::Skipped;
                        }
                        if hard() {
                            return Job::Cancelled;
                        }
                        if stop() {
                            return Job::Stopped;
                        }
                        match (&mut cell.slot, keep) {
                            (Some(slot), true) => slot.clone(),
                            (slot, _) => slot.take().unwrap_or_else(|| new_slot(t)),
                        }
                    };
                    let mut film = None;
                    if anywhere {
                        let mut l = light_film(&lights);
                        if keep {
                            l.sums.fill([0; 4]);
                        }
                        work.film.splat = Some(l);
                    }
                    let mut worker = lock(own_worker())
                        .take()
                        .unwrap_or_else(|| integrator.worker(scene));
                    let rendered = film::render_pass(
                        &mut worker,
                        &mut work,
                        samples.clone(),
                        last,
                        &cancelled,
                    );
                    *lock(own_worker()) = Some(worker);
                    if anywhere {
                        film = work.film.splat.take();
                    }
                    let _commit = keep.then(|| lock(&commit));
                    if let Some(l) = film {
                        if keep && rendered {
                            let (xs, ys) = (region.x0..region.x1, region.y0..region.y1);
                            l.merge_into(&mut lock(&canvas.light), &xs, &ys);
                        }
                        lock(&lights).push(l);
                    }
                    let mut cell = lock(cell);
                    if !rendered {
                        if !keep {
                            cell.slot = Some(work);
                        }
                        return if hard() {
                            Job::Cancelled
                        } else {
                            Job::Abandoned
                        };
                    }
                    cell.passes_done += 1;
                    if last {
                        let (tile, kept) = match keep {
                            true => (film::finish(work.clone()), Some(work)),
                            false => (film::finish(work), None),
                        };
                        canvas.merge(&tile);
                        cell.counted = Some(counted(tile));
                        cell.slot = kept;
                    } else {
                        cell.slot = Some(work);
                    }
                    drop(cell);
                    drop(_commit);
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, jobs_total);
                    save(false);
                    Job::Done
                })
                .collect()
        });
        if jobs.contains(&Job::Cancelled) {
            return Err(RenderError::Cancelled);
        }
        if jobs
            .iter()
            .any(|j| matches!(j, Job::Stopped | Job::Abandoned))
        {
            ended = if interrupted() {
                Ended::Interrupted
            } else {
                Ended::TimeLimit
            };
            break;
        }
        if let (Some(on_pass), false) = (run.on_pass, last) {
            let n = region.width() as usize * region.height() as usize;
            let mut pixels: Vec<Rgb> = Vec::with_capacity(n);
            let mut values: Vec<f32> = Vec::with_capacity(n * c);
            for band in &canvas.bands {
                let band = lock(band);
                pixels.extend_from_slice(band.0);
                values.extend_from_slice(band.1);
            }
            let extra = compose(
                (&lock(&canvas.splatted), &lock(&canvas.light)),
                &cells,
                (region, c, channels.as_ref()),
                &lights,
                (&mut pixels, &mut values),
            );
            let mut stats = tally(&cells, region, whole, threads);
            stats.render_time = Duration::from_secs_f64(seconds_before) + start.elapsed();
            let image = Image {
                width: region.width(),
                height: region.height(),
                pixels,
                extra,
            };
            on_pass(&PassView {
                pass: pass + 1,
                passes,
                image: &image,
                stats: &stats,
            });
        }
    }
    save(true);
    let mut stats = tally(&cells, region, whole, threads);
    stats.checkpoint_error = lock(&save_failed).take().map(|e| e.to_string());
    let Canvas {
        bands,
        splatted,
        light,
        ..
    } = canvas;
    drop(bands);
    let (splatted, light) = (
        splatted.into_inner().unwrap_or_else(|e| e.into_inner()),
        light.into_inner().unwrap_or_else(|e| e.into_inner()),
    );
    let extra = compose(
        (&splatted, &light),
        &cells,
        (region, c, channels.as_ref()),
        &lights,
        (&mut image.pixels, &mut values),
    );
    image.extra = extra;
    stats.render_time = Duration::from_secs_f64(seconds_before) + start.elapsed();
    stats.ended = ended;
    Ok((image, stats))
}

/// Resolves the image whose finished tiles are in `pixels` and `values`
/// (`c` values per pixel of `region`) or in the splatted sums, adding the
/// tiles not finished with the samples they have; a light tracer's
/// pixels are the sum of its light images (the render's and those of the
/// pool). Returns the extra channels.
fn compose<S: Clone>(
    (splatted, lit): (&(Vec<Sums>, Vec<i128>), &[Sums]),
    cells: &[Mutex<Cell<S>>],
    (region, c, channels): (Region, usize, Option<&Arc<Channels>>),
    lights: &Mutex<Vec<SplatFilm>>,
    (pixels, values): (&mut [Rgb], &mut Vec<f32>),
) -> Option<ExtraChannels> {
    let mut splatted = splatted.clone();
    // A light tracer's tiles hold nothing of the image.
    let cells = if lit.is_empty() { cells } else { &[] };
    for cell in cells {
        let cell = lock(cell);
        if let (None, Some(slot)) = (&cell.counted, &cell.slot) {
            slot.resolve_into(region, (pixels, values, c), &mut splatted);
        }
    }
    if !lit.is_empty() {
        let mut sums = lit.to_vec();
        let (xs, ys) = (region.x0..region.x1, region.y0..region.y1);
        for l in lock(lights).iter() {
            l.merge_into(&mut sums, &xs, &ys);
        }
        for (p, s) in pixels.iter_mut().zip(&sums) {
            *p = light(s);
        }
    } else if !splatted.0.is_empty() {
        for (p, s) in pixels.iter_mut().zip(&splatted.0) {
            *p = resolve(s);
        }
        if c > 0 {
            values.clear();
            for s in splatted.1.chunks_exact(c + 1) {
                resolve_channels(s, values);
            }
        }
    }
    let channels = channels?;
    if let Some(at) = channels.image {
        for (p, v) in pixels.iter().zip(values.chunks_exact_mut(c)) {
            v[at..at + 3].copy_from_slice(&p.to_array());
        }
    }
    Some(ExtraChannels {
        names: channels.names.clone(),
        values: std::mem::take(values),
    })
}

/// What the tiles counted: the finished tiles' counts, and the rays of
/// those not finished; with adaptive sampling (`adaptive`), how each pixel
/// of `region` ended.
fn tally<S>(
    cells: &[Mutex<Cell<S>>],
    region: Region,
    adaptive: bool,
    threads: usize,
) -> RenderStats {
    let mut stats = RenderStats {
        threads,
        ..RenderStats::default()
    };
    if adaptive {
        let pixels = region.width() as usize * region.height() as usize;
        stats.pixel_samples = vec![PixelSamples::default(); pixels];
    }
    for cell in cells {
        let cell = lock(cell);
        let (rays, batches, bad) = match (&cell.counted, &cell.slot) {
            (Some((rays, batches, bad, at, samples)), _) => {
                if adaptive {
                    place(&mut stats.pixel_samples, region, *at, samples);
                }
                (rays, batches, bad)
            }
            (None, Some(slot)) => (&slot.rays, &slot.batches, &slot.bad),
            (None, None) => continue,
        };
        stats.rays += *rays;
        stats.batches += *batches;
        stats.bad_samples += bad.len() as u64;
        let room = 16usize.saturating_sub(stats.first_bad_samples.len());
        stats
            .first_bad_samples
            .extend(bad.iter().take(room).cloned());
    }
    stats
}
