//! Blender Cycles' adaptive sampling, as Cycles X does it (the kernel's
//! `film/adaptive_sampling.h`, `film/light_passes.h`, `sample/pattern.h`;
//! the schedule in `integrator/adaptive_sampling.cpp` and
//! `scene/integrator.cpp`).
//!
//! * **Two estimates.** Besides the sum `I` of a pixel's samples, Cycles
//!   keeps the sum of half of them, `A = 2 Σ_{class A} L`, where sample `i`
//!   is of class A ([`class_a`](super::class_a)) when the bits of `i` at odd positions have odd parity
//!   (`popcount(i & 0xAAAAAAAA)` odd: two of every four consecutive
//!   indices, as in Christensen et al. 2018 §10.2.1). `I − A` is the
//!   difference between the two halves' estimates.
//! * **The test**, with `N` the pixel's own count:
//!
//!   ```text
//!   e = Σ_c |I_c − A_c| / N  /  (0.0001 + n(Σ_c I_c / N)),   n(m) = √m if m < 1, else m
//!   ```
//!
//!   and the pixel has converged when `e < 5 T` (Cycles multiplies the
//!   user's threshold by 5 before comparing). A converged pixel is not
//!   tested again.
//! * **Dilation.** After each test, if any pixel is still active, every
//!   active pixel makes its eight neighbours active again (a 3×3 box, in a
//!   pass along rows then one along columns), so that noise is not left at
//!   the rim of a noisy region.
//! * **Schedule.** Every pixel first takes `min_spp` rays, Cycles' automatic
//!   `max(4, ⌈16 / T^0.3⌉)` when it is 0 (64 at `T = 0.01`); the first test
//!   comes at the next multiple of 16 beyond it, then one every 16 rays.
//!   An active pixel takes 16 rays per pass, so a pixel made active again
//!   ends with fewer than the others.
//!
//! Cycles' defaults are `T = 0.01` and 4096 samples.

use super::tally::{Block, Tally};
use super::Stopping;

/// Rays between two tests (Cycles' `adaptive_step`).
const STEP: u32 = 16;

/// The automatic minimum for threshold `t`.
pub fn min_samples(s: &Stopping) -> u32 {
    if s.min_spp > 0 {
        return s.min_spp.max(4);
    }
    let t = f64::from(s.threshold);
    (16.0 / t.powf(0.3)).ceil().max(4.0) as u32
}

/// Rays per pixel in the pass after `done`.
pub fn pass(s: &Stopping, done: u32) -> u32 {
    if done == 0 {
        // The first test follows sample index `(min + 1) | 15`.
        ((min_samples(s) + 1) | (STEP - 1)) + 1
    } else {
        STEP
    }
}

/// Cycles' error of a pixel.
pub fn error(t: &Tally) -> f32 {
    let n = t.n.max(1) as f32;
    let (i, a) = (t.sum / n, t.half * 2.0 / n);
    let difference = (i - a).abs().to_array().iter().sum::<f32>();
    let m: f32 = i.to_array().iter().sum();
    let normalize = if m < 1.0 { m.max(0.0).sqrt() } else { m };
    difference / (0.0001 + normalize)
}

/// Tests the active pixels, then dilates the active set.
pub fn judge(s: &Stopping, block: &mut Block) {
    for t in &mut block.pixels {
        if t.active && error(t) < 5.0 * s.threshold {
            t.active = false;
        }
    }
    if !block.any_active() {
        return;
    }
    let (w, h) = (block.width, block.height);
    let was: Vec<bool> = block.pixels.iter().map(|t| t.active).collect();
    let mut rows = was.clone();
    for y in 0..h {
        for x in 0..w {
            let near = |x: usize| was[y * w + x];
            if (x > 0 && near(x - 1)) || (x + 1 < w && near(x + 1)) {
                rows[y * w + x] = true;
            }
        }
    }
    for y in 0..h {
        for x in 0..w {
            let near = |y: usize| rows[y * w + x];
            let on = near(y) || (y > 0 && near(y - 1)) || (y + 1 < h && near(y + 1));
            block.pixels[y * w + x].active = on;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{class_a, StopRule};
    use super::*;
    use crate::math::Rgb;

    fn cycles(threshold: f32) -> Stopping {
        Stopping {
            rule: StopRule::Cycles,
            threshold,
            confidence: 0.9,
            replicas: 4,
            floor: 1.0,
            min_spp: 0,
        }
    }

    #[test]
    fn class_a_is_half_of_every_four() {
        for k in 0..64 {
            let a = (4 * k..4 * k + 4).filter(|&i| class_a(i)).count();
            assert_eq!(a, 2, "block {k}");
        }
        assert!(!class_a(0) && !class_a(1) && class_a(2) && class_a(3));
    }

    #[test]
    fn the_schedule_is_cycles() {
        // Blender's default 0.01: 64 samples, first test after 80, then every 16.
        assert_eq!(min_samples(&cycles(0.01)), 64);
        assert_eq!(min_samples(&cycles(0.1)), 32);
        assert_eq!(min_samples(&cycles(0.001)), 128);
        assert_eq!(pass(&cycles(0.01), 0), 80);
        assert_eq!(pass(&cycles(0.01), 80), 16);
    }

    #[test]
    fn the_error_compares_the_halves() {
        let t = Tally {
            sum: Rgb::splat(8.0),
            half: Rgb::splat(4.0),
            n: 16,
            active: true,
            ..Tally::default()
        };
        assert_eq!(error(&t), 0.0);
        // I = 0.5 and A = 0.25 in every channel: Σ|I − A| = 0.75 over
        // 1e-4 + ΣI, as ΣI = 1.5 is not below 1; at a tenth of the
        // radiance, over 1e-4 + √0.15.
        let t = Tally {
            half: Rgb::splat(2.0),
            ..t
        };
        assert!((error(&t) - 0.75 / (1e-4 + 1.5)).abs() < 1e-6);
        let dim = Tally {
            sum: t.sum * 0.1,
            half: t.half * 0.1,
            ..t
        };
        assert!((error(&dim) - 0.075 / (1e-4 + 0.15f32.sqrt())).abs() < 1e-6);
    }

    #[test]
    fn active_pixels_wake_their_eight_neighbours() {
        let mut b = Block::new(5, 4, 1, false);
        for (k, t) in b.pixels.iter_mut().enumerate() {
            // Converged but for pixel (1, 1), which stays noisy.
            t.n = 16;
            t.sum = Rgb::splat(8.0);
            t.half = if k == 6 { Rgb::ZERO } else { Rgb::splat(4.0) };
        }
        judge(&cycles(0.01), &mut b);
        let active: Vec<usize> = (0..20).filter(|&k| b.pixels[k].active).collect();
        assert_eq!(active, [0, 1, 2, 5, 6, 7, 10, 11, 12]);
        // Once none is active, none wakes.
        let mut b = Block::new(3, 3, 1, false);
        for t in &mut b.pixels {
            t.n = 16;
        }
        judge(&cycles(0.01), &mut b);
        assert!(!b.any_active());
    }
}
