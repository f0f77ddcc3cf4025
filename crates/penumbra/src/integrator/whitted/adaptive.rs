//! A tile by adaptive sampling: its pixels take camera rays in passes until
//! the rule ([`Stopper`]) judges them done.

use super::pixel::{camera_samples, guard, pixel_stream, with_scratch};
use super::state::{Schedule, TileState};
use super::tracer::Tracer;
use crate::integrator::film::FilmTile;
use crate::integrator::interface::{BadSample, TileJob};
use crate::integrator::stopping::{Block, StopRule, Stopper};
use crate::sampling::Rng;
use crate::scene::Scene;

/// Adds the samples of `tile.samples` of the rule's schedule to `film`:
/// the rule's passes over the tile's pixels from where `state` left them,
/// up to `tile.samples.end` (the last range, which ends at the budget, runs
/// the rule to its end); `false` if the tile's cancel flag became true
/// (checked before each row of each pass).
///
/// In each pass every active pixel takes its next rays as one batch. Sample
/// `i` of a pixel is sample `j = i / R` of replica `r = i mod R` (`R`: the
/// rule's replicas, 1 but for the calibrated rule), whose film, lens and
/// time sets are that replica's `⌈(spp − r) / R⌉` points in trace order and
/// whose path is the replica's path `j`: so the first `n` samples are the
/// same whenever the pixel stops. A batch's samples are added to the film
/// and the tallies in the order of their index, and the rule judges only
/// at the end of its own passes, so cutting the schedule into ranges
/// anywhere changes no bit.
pub fn render_tile(
    scene: &Scene,
    tracer: &mut Tracer<'_>,
    stopper: &Stopper,
    tile: TileJob<'_>,
    state: &mut TileState,
    film: &mut FilmTile,
    bad: &mut Vec<BadSample>,
) -> bool {
    let (w, h) = (tile.xs.len(), tile.ys.len());
    let samples = tile.samples.clone();
    let replicas = stopper.replicas();
    let spp = stopper.spp;
    if !matches!(state, TileState::Adaptive(_)) {
        let povray = stopper.settings.rule == StopRule::Povray;
        *state = TileState::Adaptive(Box::new(Schedule {
            block: Block::new(w, h, replicas as usize, povray),
            done: 0,
            pass_end: None,
            finished: false,
        }));
    }
    let TileState::Adaptive(sched) = state else {
        return true;
    };
    let last = samples.end >= spp;
    let end = if last { u32::MAX } else { samples.end };
    // Per ray of a pixel's batch: its replica, its sample index and stream.
    let mut rays: Vec<(u32, u32, Rng)> = Vec::new();
    let mut order: Vec<usize> = Vec::new();
    while !sched.finished && sched.done < end {
        let pass_end = match sched.pass_end {
            Some(e) => e,
            None => {
                let size = stopper.pass(sched.done);
                if size == 0 || !sched.block.any_active() {
                    sched.finished = true;
                    break;
                }
                sched.done + size
            }
        };
        let part = pass_end.min(end);
        let size = part - sched.done;
        let whole = tile.rows(1, |ys| {
            let (row, y) = ((ys.start - tile.ys.start) as usize, ys.start);
            for (col, x) in tile.xs.clone().enumerate() {
                let k = row * w + col;
                let t = sched.block.pixels[k];
                if !t.active {
                    continue;
                }
                let range = t.n..(t.n + size).min(spp);
                with_scratch(|buf| {
                    buf.samples.clear();
                    buf.weights.clear();
                    buf.offsets.clear();
                    rays.clear();
                    let pixel = pixel_stream(scene, x, y);
                    // A replica past the last sample (fewer samples than
                    // replicas) has none.
                    for r in 0..replicas.min(spp) {
                        let of = if replicas == 1 {
                            pixel
                        } else {
                            pixel.replica(r, replicas)
                        };
                        // Samples j·R + r within the range.
                        let first = |i: u32| (i.saturating_sub(r)).div_ceil(replicas);
                        let js = first(range.start)..first(range.end);
                        let count = (spp - r).div_ceil(replicas) as usize;
                        let keep = js.start as usize..js.end as usize;
                        camera_samples(scene, (x, y), of, (count, true), keep, buf);
                        rays.extend(js.map(|j| (r, j * replicas + r, of.path(j as usize))));
                    }
                    buf.rays.clear();
                    scene.camera.generate(&buf.samples, &mut buf.rays);
                    buf.radiance.clear();
                    tracer.radiance(&buf.rays, 0, |k| rays[k].2, &mut buf.radiance);
                    order.clear();
                    order.extend(0..rays.len());
                    order.sort_unstable_by_key(|&q| rays[q].1);
                    let f = film.index(x, y);
                    for &q in &order {
                        let (r, i, _) = rays[q];
                        let l = guard(buf.radiance[q], x, y, i as usize, bad);
                        let w = buf.weights[q];
                        // The rule judges the weighted samples, whose mean
                        // tends to the pixel's value.
                        sched.block.add(k, i, r as usize, l * w);
                        film.add(f, l, w, buf.offsets[q]);
                    }
                    tracer.stats.primary += rays.len() as u64;
                });
            }
        });
        if !whole {
            return false;
        }
        sched.done = part;
        if part < pass_end {
            sched.pass_end = Some(pass_end);
            continue;
        }
        sched.pass_end = None;
        let block = &mut sched.block;
        for t in &mut block.pixels {
            t.active &= t.n < spp;
        }
        if block.any_active() {
            stopper.judge(block);
            for t in &mut block.pixels {
                t.active &= t.n < spp;
            }
        }
    }
    if last {
        for t in &sched.block.pixels {
            tracer.stats.saved.primary += u64::from(spp - t.n);
        }
    }
    true
}
