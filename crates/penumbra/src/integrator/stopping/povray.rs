//! POV-Ray's stochastic anti-aliasing (`Sampling_Method 3`, POV-Ray 3.8:
//! `StochasticSupersamplingM3` in `source/backend/render/tracetask.cpp`).
//!
//! * **Statistics.** Samples are compared after gamma encoding,
//!   `c^(1/2.5)` per channel (`Antialias_Gamma` 2.5), while the pixel's value
//!   stays the mean of the linear samples. A pixel is judged on the samples
//!   of itself and of its four neighbours within the tile, pooled: with `N`
//!   samples, sums `S1` and `S2` of the encoded values and their squares,
//!   per channel
//!
//!   ```text
//!   var = (S2 − S1² / N) / (N − 1),    δ = z · √(var / N)
//!   ```
//!
//!   with `z` the normal quantile at `(1 + C) / 2` (`Antialias_Confidence`,
//!   default 0.9). The pixel stops when `δ_r + δ_g + δ_b ≤ T`
//!   (`Antialias_Threshold`, default 0.3; POV-Ray adds the alpha channel's
//!   δ, which is 0 here).
//! * **Passes.** Each pass gives one ray to every pixel not yet judged done,
//!   and every pixel is judged again after each pass (its neighbours'
//!   samples may widen its interval again), until none takes a ray or a
//!   pixel has `spp` (POV-Ray's `4^Antialias_Depth`, 64 by default). A
//!   pixel takes at least `min_spp` rays (POV-Ray: 1).
//!
//! POV-Ray judges the pixels of a pass in raster order, so a pixel's left
//! and upper neighbours already hold that pass's ray; here every pixel is
//! judged after the pass, which treats the four neighbours alike and keeps
//! the result independent of the order. Its own samples are uniform over
//! the pixel; here they come from the pixel's distribution, in trace order.

use super::tally::Block;
use super::Stopping;
use crate::math::Rgb;
use statrs::distribution::{ContinuousCDF, Normal};

/// The normal quantile at `(1 + C) / 2`.
pub fn quantile(confidence: f32) -> f32 {
    let n = Normal::new(0.0, 1.0).expect("the standard normal");
    n.inverse_cdf((1.0 + f64::from(confidence)) / 2.0) as f32
}

/// The sum of the channels' half-widths for pooled sums `s1`, `s2` of `n`
/// samples; infinite below two samples.
pub fn spread(z: f32, s1: Rgb, s2: Rgb, n: u32) -> f32 {
    if n < 2 {
        return f32::INFINITY;
    }
    let n = n as f32;
    let var = ((s2 - s1 * s1 / n) / (n - 1.0)).map(|v| v.max(0.0));
    (var / n).map(f32::sqrt).to_array().iter().sum::<f32>() * z
}

/// Judges every pixel on its pooled statistics.
pub fn judge(s: &Stopping, z: f32, spp: u32, block: &mut Block) {
    let (w, h) = (block.width, block.height);
    let min = s.min_spp.max(1);
    let done: Vec<bool> = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            let near = [
                Some(k),
                (x > 0).then(|| k - 1),
                (x + 1 < w).then_some(k + 1),
                (y > 0).then(|| k - w),
                (y + 1 < h).then_some(k + w),
            ];
            let (mut s1, mut s2, mut n) = (Rgb::ZERO, Rgb::ZERO, 0);
            for j in near.into_iter().flatten() {
                s1 += block.encoded[j].0;
                s2 += block.encoded[j].1;
                n += block.pixels[j].n;
            }
            let own = block.pixels[k].n;
            own >= spp || (own >= min && spread(z, s1, s2, n) <= s.threshold)
        })
        .collect();
    for (t, done) in block.pixels.iter_mut().zip(done) {
        t.active = !done;
    }
}

#[cfg(test)]
mod tests {
    use super::super::StopRule;
    use super::*;

    #[test]
    fn the_quantile_is_the_normal() {
        assert!((quantile(0.9) - 1.6449).abs() < 1e-4);
    }

    #[test]
    fn pixels_pool_their_neighbours() {
        let s = Stopping {
            rule: StopRule::Povray,
            threshold: 0.3,
            confidence: 0.9,
            replicas: 4,
            floor: 1.0,
            min_spp: 0,
        };
        let z = quantile(0.9);
        // A 3×1 strip: a flat pixel between two noisy ones is judged on all
        // three, the same flat pixel alone is done.
        let mut b = Block::new(3, 1, 1, true);
        for (k, i) in [0usize, 1, 2].into_iter().zip(0..) {
            for j in 0..4 {
                let l = if k == 1 || j % 2 == 0 { 0.5 } else { 4.0 };
                b.add(k, i * 4 + j, 0, Rgb::splat(l));
            }
        }
        judge(&s, z, 64, &mut b);
        assert!(b.pixels.iter().all(|t| t.active));
        let mut alone = Block::new(1, 1, 1, true);
        for i in 0..4 {
            alone.add(0, i, 0, Rgb::splat(0.5));
        }
        judge(&s, z, 64, &mut alone);
        assert!(!alone.pixels[0].active);
        // The budget ends a pixel whatever its spread.
        judge(&s, z, 4, &mut b);
        assert!(!b.any_active());
    }
}
