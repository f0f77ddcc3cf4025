//! Dammertz, Hanika, Keller and Lensch's hierarchical stopping condition
//! ("A Hierarchical Automatic Stopping Condition for Monte Carlo Global
//! Illumination", WSCG 2009), in the form the renderers that implement it
//! agree on (Cycles' per-pixel error cites it; appleseed, Photon-v2 and
//! MoonRay implement the blocks).
//!
//! * **Pixel error.** With `I` the mean of all of a pixel's samples and `A`
//!   the mean of every second one (the odd sample indices),
//!   `e_p = Σ_c |I_c − A_c| / √(Σ_c I_c)` (guarded by `10⁻⁴` against black).
//! * **Block error.** A block of `N` pixels in an image of `N_img` has
//!   `e_b = Σ_p e_p / √(N · N_img)`: the mean pixel error for the whole
//!   image, and a larger allowance per pixel for smaller blocks.
//! * **Blocks.** After each pass every active block is judged against
//!   the threshold `e_t` (`noise_threshold`): below `e_t` it is done and
//!   takes no more rays; below `256 e_t` it is split in two across its
//!   longer side, where the error on either side is as equal as the pixel
//!   columns (or rows) allow, and both halves stay active; otherwise it
//!   stays whole and active. A block of one pixel is never split.
//! * **Passes.** Every pixel first takes `max(min_spp, 16)` rays, then an
//!   active block's pixels take 16 per pass.
//!
//! The paper starts from the whole image as one block; here the hierarchy
//! starts from each tile, which is where the renderers above start too
//! (their render tiles), and keeps a pixel independent of the tiles
//! rendered beside it.

use super::tally::{Block, Rect, Tally};
use super::Stopping;

/// Rays per pass, and the least before the first judgement.
const STEP: u32 = 16;

/// How much above the threshold a block may be and still split.
const SPLIT: f32 = 256.0;

/// Rays per pixel in the pass after `done`.
pub fn pass(s: &Stopping, done: u32) -> u32 {
    if done == 0 {
        s.min_spp.max(STEP)
    } else {
        STEP
    }
}

/// A pixel's error.
pub fn pixel_error(t: &Tally) -> f32 {
    let odd = t.n / 2;
    if odd == 0 {
        return f32::INFINITY;
    }
    let i = t.sum / t.n as f32;
    let a = t.odd / odd as f32;
    let difference: f32 = (i - a).abs().to_array().iter().sum();
    let m: f32 = i.to_array().iter().sum();
    difference / m.max(0.0).sqrt().max(1e-4)
}

/// Judges the active blocks of `block`, in an image of `image` pixels.
pub fn judge(s: &Stopping, image: usize, block: &mut Block) {
    let w = block.width;
    let errors: Vec<f32> = block.pixels.iter().map(pixel_error).collect();
    let sum = |r: &Rect| -> f32 {
        (r.y0..r.y1)
            .flat_map(|y| (r.x0..r.x1).map(move |x| y * w + x))
            .map(|k| errors[k])
            .sum()
    };
    let mut next = Vec::new();
    for r in std::mem::take(&mut block.regions) {
        let e = sum(&r) / ((r.pixels() * image) as f32).sqrt();
        if e < s.threshold {
            for y in r.y0..r.y1 {
                for t in &mut block.pixels[y * w + r.x0..y * w + r.x1] {
                    t.active = false;
                }
            }
        } else if e < SPLIT * s.threshold && r.pixels() > 1 {
            let (a, b) = split(&r, &sum);
            next.extend([a, b]);
        } else {
            next.push(r);
        }
    }
    block.regions = next;
}

/// `r` cut across its longer side where the two halves' errors (by `sum`)
/// differ least.
fn split(r: &Rect, sum: &impl Fn(&Rect) -> f32) -> (Rect, Rect) {
    let wide = r.x1 - r.x0 >= r.y1 - r.y0;
    let (lo, hi) = if wide { (r.x0, r.x1) } else { (r.y0, r.y1) };
    let cut = |c: usize| {
        if wide {
            (Rect { x1: c, ..*r }, Rect { x0: c, ..*r })
        } else {
            (Rect { y1: c, ..*r }, Rect { y0: c, ..*r })
        }
    };
    let best = (lo + 1..hi)
        .min_by(|&a, &b| {
            let d = |c| {
                let (p, q) = cut(c);
                (sum(&p) - sum(&q)).abs()
            };
            d(a).total_cmp(&d(b))
        })
        .expect("a block of two or more pixels across");
    cut(best)
}

#[cfg(test)]
mod tests {
    use super::super::StopRule;
    use super::*;
    use crate::math::Rgb;

    fn rule(threshold: f32) -> Stopping {
        Stopping {
            rule: StopRule::Dammertz,
            threshold,
            confidence: 0.9,
            replicas: 4,
            floor: 1.0,
            min_spp: 0,
        }
    }

    /// A tile whose left half is flat and right half noisy: the block is
    /// split between them, the flat half stops, the noisy one goes on.
    #[test]
    fn blocks_split_where_the_error_is() {
        let mut b = Block::new(8, 4, 1, false);
        for k in 0..32 {
            for i in 0..16 {
                let noisy = k % 8 >= 4;
                let l = if noisy && i % 2 == 1 { 0.2 } else { 1.0 };
                b.add(k, i, 0, Rgb::splat(l));
            }
        }
        let image = 64 * 64;
        for _ in 0..8 {
            judge(&rule(0.01), image, &mut b);
        }
        for (k, t) in b.pixels.iter().enumerate() {
            assert_eq!(t.active, k % 8 >= 4, "pixel {k}");
        }
        assert!(b.regions.iter().all(|r| r.x0 >= 4), "{:?}", b.regions);
    }

    #[test]
    fn the_pixel_error_compares_all_with_every_second() {
        let mut t = Tally::default();
        for i in 0..8 {
            let l = Rgb::splat(if i % 2 == 1 { 1.0 } else { 0.0 });
            t.sum += l;
            if i % 2 == 1 {
                t.odd += l;
            }
            t.n += 1;
        }
        // I = 0.5, A = 1: 3 · 0.5 / √1.5.
        assert!((pixel_error(&t) - 1.5 / 1.5f32.sqrt()).abs() < 1e-6);
    }
}
