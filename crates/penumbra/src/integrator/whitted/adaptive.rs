//! A tile by adaptive sampling: its pixels take camera rays in passes until
//! the rule ([`Stopper`]) judges them done.

use super::pixel::{camera_samples, guard, pixel_stream, with_scratch};
use super::tracer::Tracer;
use crate::integrator::interface::{BadSample, TileJob};
use crate::integrator::stopping::{Block, PixelSamples, StopRule, Stopper};
use crate::math::Rgb;
use crate::sampling::Rng;
use crate::scene::Scene;

/// The pixels of `tile`, row by row, appended to `out`, and how each ended
/// to `samples`; `false` if its cancel flag became true (checked before
/// each row of each pass).
///
/// In each pass every active pixel takes its next rays as one batch. Sample
/// `i` of a pixel is sample `j = i / R` of replica `r = i mod R` (`R`: the
/// rule's replicas, 1 but for the calibrated rule), whose film, lens and
/// time sets are that replica's `⌈(spp − r) / R⌉` points in trace order and
/// whose path is the replica's path `j`: so the first `n` samples are the
/// same whenever the pixel stops.
pub fn render_tile(
    scene: &Scene,
    tracer: &mut Tracer<'_>,
    stopper: &Stopper,
    tile: TileJob<'_>,
    bad: &mut Vec<BadSample>,
    out: &mut Vec<Rgb>,
    samples: &mut Vec<PixelSamples>,
) -> bool {
    let TileJob { xs, ys, cancelled } = tile;
    let (w, h) = (xs.len(), ys.len());
    let replicas = stopper.replicas();
    let spp = stopper.spp;
    let povray = stopper.settings.rule == StopRule::Povray;
    let mut block = Block::new(w, h, replicas as usize, povray);
    // Per ray of a pixel's batch: its replica, its sample index and stream.
    let mut rays: Vec<(u32, u32, Rng)> = Vec::new();
    let mut done = 0;
    loop {
        let size = stopper.pass(done);
        if size == 0 || !block.any_active() {
            break;
        }
        for (row, y) in ys.clone().enumerate() {
            if cancelled() {
                return false;
            }
            for (col, x) in xs.clone().enumerate() {
                let k = row * w + col;
                let t = block.pixels[k];
                if !t.active {
                    continue;
                }
                let range = t.n..(t.n + size).min(spp);
                with_scratch(|buf| {
                    buf.samples.clear();
                    rays.clear();
                    let pixel = pixel_stream(scene, x, y);
                    for r in 0..replicas {
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
                    for (&(r, i, _), &l) in rays.iter().zip(&buf.radiance) {
                        let l = guard(l, x, y, i as usize, bad);
                        block.add(k, i, r as usize, l);
                    }
                    tracer.stats.primary += rays.len() as u64;
                });
            }
        }
        done += size;
        for t in &mut block.pixels {
            t.active &= t.n < spp;
        }
        if block.any_active() {
            stopper.judge(&mut block);
            for t in &mut block.pixels {
                t.active &= t.n < spp;
            }
        }
    }
    for t in &block.pixels {
        tracer.stats.saved.primary += u64::from(spp - t.n);
        out.push(t.mean());
    }
    samples.extend(stopper.samples(&block));
    true
}
