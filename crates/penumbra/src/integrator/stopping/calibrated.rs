//! The calibrated rule: a confidence interval from independent replicas.
//!
//! The error of a stratified or low-discrepancy set cannot be read from
//! the spread of its own samples: they are not independent, and their
//! spread says how much the integrand varies, not how well the set
//! integrates it (a stratified set's error can be far below what its
//! spread suggests, and a regular one's far above). Randomised
//! quasi-Monte Carlo (Owen 1997; L'Ecuyer and Lemieux 2002) estimates it
//! honestly instead: `R` independent randomisations of the set give `R`
//! independent, unbiased estimates, whose spread is an estimate of their
//! error.
//!
//! So a pixel's samples are split into `R` replicas (`replicas`, default
//! 8): sample `i` belongs to replica `i mod R`, and each replica draws its
//! film, lens and time sets from streams of its own (the sampler's
//! `PixelSampler::replica`), so the replicas are independent scramblings
//! of the chosen distribution. After each pass, with `m_r` the replicas'
//! means and `m` their mean, channel by channel:
//!
//! ```text
//! s² = Σ (m_r − m)² / (R − 1) + (Δ / n)² / 12   (spread of the replica means)
//! h  = t(R − 1, (1 + C) / 2) · s / √R          (half-width of the interval of m)
//! ```
//!
//! with `t` Student's quantile at confidence `C` (`confidence`, default
//! 0.9), `n` the rays of each replica and `Δ` the range of the pixel's
//! samples (largest minus smallest). The second term of `s²` is the
//! variance of rounding to a grid of step `Δ / n`: a stratified set of `n`
//! points sees an edge only to within one point, so its replicas' means
//! take few distinct values and often agree exactly while all being wrong
//! (four 4-point nets over a disk covering 19% of a pixel each give 1/4
//! with probability 0.33). Without the term, sets of the edge test below
//! stopped with the truth inside their 90% interval 55% of the time with 4
//! replicas and 82% with 8; with it, 85% and 89%. A flat pixel (`Δ = 0`)
//! still stops at the first judgement. The pixel stops when the largest
//! channel's `h` is at most `T · max(m_max, F)`: `T` (`noise_threshold`)
//! relative to the pixel's largest channel above the floor `F`
//! (`noise_floor`, default 1, the display's white), and `T · F` absolute
//! below it. The error a render is judged by (RMSE, or what the eye sees
//! on a display) is absolute; a purely relative threshold asks a pixel of
//! value 0.01 for a hundredth of the error of a white one, and spends most
//! rays where they change the image least (docs/distributions.md measures
//! what the floor costs at equal RMSE).
//!
//! **The screen.** A replica needs a few rays before its spread means
//! anything, so a pixel cannot be judged by its replicas before `4R` rays,
//! while most pixels of most frames (sky, floors, blurred backgrounds) are
//! flat and need one. So every pixel first takes one ray (`min_spp` if
//! larger), and stops at once when the samples of its 3×3 neighbourhood
//! (within the tile) span at most `T · max(m_max, F)` in every channel: the
//! pixel's own value is then within that range of its neighbours', and it
//! reports the range as its half-width. This is POV-Ray's idea (judge a
//! pixel's first ray with its neighbours') made stricter: the whole range,
//! not a spread divided by the samples' count, over nine pixels, not five.
//! A feature that falls between all nine samples is missed, as it is by
//! POV-Ray; the study counts those pixels among its false stops. A pixel
//! that fails the screen is judged by its replicas from then on.
//!
//! Passes: every pixel first takes the screen's `max(min_spp, 1)` rays, then
//! up to `max(min_spp, 4R)` (rounded up to a multiple of `R`; no screen when
//! `min_spp` reaches it), then the count doubles each pass, so each
//! replica's set is a power of two long whenever `spp` allows (where
//! `sobol`, `pmj02` and `pmj02bn` are nets). A stopped pixel never resumes.
//!
//! The price of honesty: `R` independent sets of `n / R` points integrate
//! less well than one set of `n` (a low-discrepancy set's error falls
//! faster than `1/√n`, the replicas' mean only as `1/√R`), which is why `R`
//! is small.

use super::tally::Block;
use super::Stopping;
use crate::math::Rgb;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// Rays a replica takes before the first judgement, unless `min_spp` asks
/// for more.
const FIRST_PER_REPLICA: u32 = 4;

/// Student's `t` quantile of `replicas − 1` degrees of freedom at `(1 + C) / 2`.
pub fn quantile(replicas: u32, confidence: f32) -> f32 {
    let df = f64::from(replicas.max(2) - 1);
    let t = StudentsT::new(0.0, 1.0, df).expect("positive degrees of freedom");
    t.inverse_cdf((1.0 + f64::from(confidence)) / 2.0) as f32
}

/// Rays a pixel has when the replicas first judge it: `max(min_spp, 4R)`,
/// rounded up to a multiple of `R`.
pub fn first(s: &Stopping) -> u32 {
    s.min_spp
        .max(FIRST_PER_REPLICA * s.replicas)
        .div_ceil(s.replicas)
        * s.replicas
}

/// Rays per pixel in the pass after `done`: the screening pass of
/// `max(min_spp, 1)` (none if that is already [`first`]), the rest of
/// [`first`], then doubling.
pub fn pass(s: &Stopping, done: u32) -> u32 {
    let first = first(s);
    if done == 0 {
        s.min_spp.max(1).min(first)
    } else if done < first {
        first - done
    } else {
        done
    }
}

/// The half-width of the interval of the mean of `replicas` (sum and count
/// each) at quantile `t`, and that mean, for samples spanning `range` per
/// channel (largest minus smallest); `None` unless every replica has a
/// sample.
pub fn interval(t: f32, replicas: &[(Rgb, u32)], range: Rgb) -> Option<(f32, Rgb)> {
    half_widths(t, replicas, range).map(|(h, mean)| (h.max_element(), mean))
}

/// The half-width of each channel's interval, as [`interval`] computes it
/// before taking the largest, and the mean.
pub fn half_widths(t: f32, replicas: &[(Rgb, u32)], range: Rgb) -> Option<(Rgb, Rgb)> {
    let n = replicas.iter().map(|r| r.1).min()?;
    if replicas.len() < 2 || n == 0 {
        return None;
    }
    let r = replicas.len() as f32;
    let means = replicas.iter().map(|&(sum, n)| sum / n as f32);
    let mean = means.clone().sum::<Rgb>() / r;
    let squares: Rgb = means.map(|m| (m - mean) * (m - mean)).sum();
    let step = range / n as f32;
    let var = squares / (r - 1.0) + step * step / 12.0;
    Some(((var / r).map(f32::sqrt) * t, mean))
}

/// Whether a pixel (or a set) whose replicas hold these sums, of samples
/// spanning `range`, may stop under `threshold`, absolute below `floor`.
pub fn converged(
    (threshold, floor): (f32, f32),
    t: f32,
    replicas: &[(Rgb, u32)],
    range: Rgb,
) -> bool {
    interval(t, replicas, range).is_some_and(|(h, mean)| h <= allowed(threshold, floor, mean))
}

/// The half-width a value `mean` may keep: `threshold` relative to its
/// largest channel, or to `floor` below it.
pub fn allowed(threshold: f32, floor: f32, mean: Rgb) -> f32 {
    threshold * mean.max_element().max(floor)
}

/// Stops the active pixels of `block` that pass the screen (after the
/// screening pass) or whose interval at quantile `t` is narrow enough.
pub fn judge(s: &Stopping, t: f32, block: &mut Block) {
    let first = first(s);
    let screened: Vec<Option<Rgb>> = (0..block.pixels.len())
        .map(|k| {
            let p = &block.pixels[k];
            (p.active && p.n < first)
                .then(|| screen(block, k))
                .filter(|range| range.max_element() <= allowed(s.threshold, s.floor, p.mean()))
        })
        .collect();
    let r = block.replicas;
    for (k, p) in block.pixels.iter_mut().enumerate() {
        if !p.active {
            continue;
        }
        if p.n < first {
            if let Some(range) = screened[k] {
                block.bounds[k] = Some(range);
                p.active = false;
            }
        } else {
            let replicas = &block.replica_sums[k * r..(k + 1) * r];
            if converged((s.threshold, s.floor), t, replicas, p.hi - p.lo) {
                p.active = false;
            }
        }
    }
}

/// The range of the samples of pixel `k` and its eight neighbours within
/// the tile, per channel (largest minus smallest).
fn screen(block: &Block, k: usize) -> Rgb {
    let (w, h) = (block.width, block.height);
    let (x, y) = (k % w, k / w);
    let (mut lo, mut hi) = (block.pixels[k].lo, block.pixels[k].hi);
    for ny in y.saturating_sub(1)..(y + 2).min(h) {
        for nx in x.saturating_sub(1)..(x + 2).min(w) {
            let q = &block.pixels[ny * w + nx];
            if q.n > 0 {
                (lo, hi) = (lo.min(q.lo), hi.max(q.hi));
            }
        }
    }
    hi - lo
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::sobol::Sobol;
    use crate::sampling::Rng;

    #[test]
    fn quantiles_are_students() {
        // Tables of Student's t: t(3, 0.95) = 2.353, t(7, 0.975) = 2.365.
        assert!((quantile(4, 0.9) - 2.353).abs() < 1e-3);
        assert!((quantile(8, 0.95) - 2.365).abs() < 1e-3);
    }

    #[test]
    fn passes_double_from_four_per_replica() {
        let s = Stopping {
            rule: super::super::StopRule::Calibrated,
            threshold: 0.01,
            confidence: 0.9,
            replicas: 4,
            floor: 1.0,
            min_spp: 0,
        };
        let mut done = 0;
        let sizes: Vec<u32> = (0..4)
            .map(|_| {
                let p = pass(&s, done);
                done += p;
                p
            })
            .collect();
        assert_eq!(sizes, [1, 15, 16, 32]);
        let odd = Stopping {
            replicas: 3,
            min_spp: 20,
            ..s
        };
        assert_eq!((pass(&odd, 0), pass(&odd, 20), pass(&odd, 21)), (20, 1, 21));
        // No screen when min_spp reaches the first judgement.
        let full = Stopping { min_spp: 16, ..s };
        assert_eq!((pass(&full, 0), pass(&full, 16)), (16, 16));
    }

    /// The screen stops a pixel after one ray only if the samples of its
    /// whole 3×3 neighbourhood agree within the threshold; a pixel stopped
    /// by it reports that range as its half-width.
    #[test]
    fn the_screen_looks_at_the_neighbours() {
        let s = Stopping {
            rule: super::super::StopRule::Calibrated,
            threshold: 0.05,
            confidence: 0.9,
            replicas: 4,
            floor: 1.0,
            min_spp: 0,
        };
        let t = quantile(s.replicas, s.confidence);
        // A 5×1 strip: 0.5 but for pixels 2 (0.54) and 4 (0.6). Pixels 0–2
        // see a spread of at most 0.04, within 0.05 · 1; pixels 3 and 4
        // see 0.1.
        let mut b = Block::new(5, 1, 4, false);
        for k in 0..5 {
            let l = [0.5, 0.5, 0.54, 0.5, 0.6][k];
            b.add(k, 0, 0, Rgb::splat(l));
        }
        judge(&s, t, &mut b);
        let active: Vec<bool> = b.pixels.iter().map(|p| p.active).collect();
        assert_eq!(active, [false, false, false, true, true]);
        assert!(b.bounds[1].is_some_and(|h| (h.r - 0.04).abs() < 1e-6));
        assert_eq!(b.bounds[3], None);
        // Pixels with the first judgement's rays are judged by their own
        // replicas, not by the screen: a flat pixel beside a different one
        // stops.
        let mut b = Block::new(2, 1, 4, false);
        for i in 0..16 {
            b.add(0, i, (i % 4) as usize, Rgb::splat(0.5));
            b.add(1, i, (i % 4) as usize, Rgb::splat(0.9));
        }
        judge(&s, t, &mut b);
        assert!(b.pixels.iter().all(|p| !p.active));
        assert_eq!(b.bounds, [None, None]);
    }

    /// The rule's promise: at confidence C, the true value lies inside the
    /// interval of the mean it stops with, for at least about C of the
    /// pixels. Checked on the fraction of a pixel covered by a disk (an
    /// edge, the hard case for an estimate of error) with scrambled Sobol'
    /// replicas, over 2000 pixels (random disks), stopped by the rule.
    #[test]
    fn intervals_cover_the_truth() {
        let s = Stopping {
            rule: super::super::StopRule::Calibrated,
            threshold: 0.02,
            confidence: 0.9,
            replicas: 8,
            floor: 1.0,
            min_spp: 0,
        };
        let t = quantile(s.replicas, s.confidence);
        let (mut covered, mut stopped, trials) = (0, 0, 2000);
        for k in 0..trials {
            let mut rng = Rng::new(k);
            // A disk of radius 0.3–0.6 around a point of the pixel; its
            // area within the pixel, exactly, by a fine grid's count.
            let (cx, cy) = (rng.next_f32(), rng.next_f32());
            let radius = 0.3 + 0.3 * rng.next_f32();
            let inside = |x: f32, y: f32| {
                let (dx, dy) = (x - cx, y - cy);
                if dx * dx + dy * dy < radius * radius {
                    Rgb::ONE
                } else {
                    Rgb::ZERO
                }
            };
            let g = 1024;
            let truth = (0..g * g)
                .map(|i| inside((i % g) as f32 / g as f32, (i / g) as f32 / g as f32).r)
                .sum::<f32>()
                / (g * g) as f32;
            let sets: Vec<Sobol> = (0..s.replicas).map(|_| Sobol::new(&mut rng)).collect();
            let mut sums = vec![(Rgb::ZERO, 0u32); s.replicas as usize];
            let (mut lo, mut hi) = (Rgb::ONE, Rgb::ZERO);
            let (mut done, budget) = (0, 4096);
            while done < budget {
                let p = pass(&s, done).min(budget - done);
                for i in done..done + p {
                    let r = (i % s.replicas) as usize;
                    let q = sets[r].point(i / s.replicas);
                    let l = inside(q.x, q.y);
                    (lo, hi) = (lo.min(l), hi.max(l));
                    sums[r].0 += l;
                    sums[r].1 += 1;
                }
                done += p;
                if converged((s.threshold, s.floor), t, &sums, hi - lo) {
                    stopped += 1;
                    break;
                }
            }
            let (h, mean) = interval(t, &sums, hi - lo).expect("every replica sampled");
            covered += usize::from((mean.r - truth).abs() <= h.max(1.0 / (g as f32)));
        }
        // Measured: 0.889 of 2000 (the binomial's deviation is 0.007).
        let coverage = covered as f32 / trials as f32;
        assert!(stopped > trials * 9 / 10, "{stopped} stopped");
        assert!(coverage >= 0.86, "coverage {coverage}");
    }
}
