//! Adaptive sampling: when a pixel has taken enough camera rays.
//!
//! A pixel's budget is `spp` camera rays; with adaptive sampling on
//! (`noise_threshold` > 0) the pixels of a tile take them in passes, and
//! after each pass a rule judges which pixels are done. Four rules are
//! offered ([`StopRule`]), each in its own file with its sources:
//!
//! | rule | judges a pixel by | passes |
//! |---|---|---|
//! | [`calibrated`] | after one ray, the range of its 3×3 neighbourhood's samples; then a confidence interval of its mean from `R` independently scrambled replicas | the screen at `max(min_spp, 1)` rays, the replicas' first at `max(min_spp, 4R)`, then doubling |
//! | [`cycles`] | Blender Cycles' half-buffer error, then a 3×3 dilation of the pixels still active | after Cycles' automatic minimum, every 16 rays |
//! | [`povray`] | POV-Ray 3.8's stochastic anti-aliasing: a normal interval of the pooled spread of the pixel and its four neighbours | one ray per pixel per pass |
//! | [`dammertz`] | Dammertz et al.'s error of blocks of pixels, split while they converge | the first at `max(min_spp, 16)` rays, then every 16 |
//!
//! The threshold is in each rule's own measure (its file says which), so
//! one value does not mean the same noise under two rules. A tile is the
//! unit of the rules that look beyond one pixel (Cycles' dilation,
//! POV-Ray's neighbours, Dammertz's blocks): Cycles and POV-Ray do the same
//! within their render tiles. Tiles are aligned to the frame, so a pixel's
//! value does not depend on the threads, the tile order or the part of the
//! frame rendered.
//!
//! Every sample of a pixel is a pure function of (seed, pixel, sample
//! index): a pixel that stops after `n` rays has exactly the first `n` of
//! the samples a full render would trace (with the calibrated rule, the
//! first of each replica's), and its value is their mean.
//!
//! The calibrated rule judges the sets of shadow, reflection and
//! refraction rays below a camera ray too, each by its own replicas
//! ([`sets`]).

pub mod calibrated;
pub mod cycles;
pub mod dammertz;
pub mod povray;
pub mod sets;
mod settings;
mod tally;

pub use crate::scene::StopRule;
pub use settings::{read, Stopping, STOP_RULES};
pub use tally::{class_a, encode, Block, Rect, Tally};

use serde::{Deserialize, Serialize};

use crate::math::Rgb;

/// How one pixel of an adaptive render ended: the camera rays it took and,
/// under the calibrated rule, the half-width of the interval of its value
/// it was last judged by (per channel; the rule compares the largest).
/// Reported so that a rule's promises can be checked against a reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PixelSamples {
    pub count: u32,
    pub half_width: Option<Rgb>,
}

/// A rule with its settings, ready for a render of `spp` rays per pixel.
#[derive(Clone, Copy, Debug)]
pub struct Stopper {
    pub settings: Stopping,
    /// The rays a pixel may take.
    pub spp: u32,
    /// The pixels of the whole image (Dammertz's blocks are judged against it).
    pub image: usize,
    /// The rule's quantile: Student's t for `calibrated`, the normal for
    /// `povray`.
    quantile: f32,
}

impl Stopper {
    pub fn new(settings: Stopping, spp: u32, image: usize) -> Stopper {
        let quantile = match settings.rule {
            StopRule::Calibrated => calibrated::quantile(settings.replicas, settings.confidence),
            StopRule::Povray => povray::quantile(settings.confidence),
            StopRule::Cycles | StopRule::Dammertz => 0.0,
        };
        Stopper {
            settings,
            spp,
            image,
            quantile,
        }
    }

    /// Replicas a pixel's sets are split into (1 but for `calibrated`).
    pub fn replicas(&self) -> u32 {
        match self.settings.rule {
            StopRule::Calibrated => self.settings.replicas,
            _ => 1,
        }
    }

    /// The rays each active pixel takes in the pass after `done` rays,
    /// counted over the passes, not per pixel (a pixel made active again by
    /// Cycles' dilation or POV-Ray's neighbours has fewer); 0 when the rule
    /// has no more passes. The rules with a fixed schedule end when it
    /// reaches `spp`; POV-Ray's goes on while a pixel below `spp` is active.
    /// A pixel never takes more than `spp` rays in all.
    pub fn pass(&self, done: u32) -> u32 {
        let s = &self.settings;
        let left = self.spp.saturating_sub(done);
        match s.rule {
            StopRule::Calibrated => calibrated::pass(s, done).min(left),
            StopRule::Cycles => cycles::pass(s, done).min(left),
            StopRule::Povray => 1,
            StopRule::Dammertz => dammertz::pass(s, done).min(left),
        }
    }

    /// How each pixel of `block` ended, row by row.
    pub fn samples(&self, block: &Block) -> Vec<PixelSamples> {
        let r = block.replicas;
        block
            .pixels
            .iter()
            .enumerate()
            .map(|(k, p)| PixelSamples {
                count: p.n,
                half_width: match self.settings.rule {
                    StopRule::Calibrated => {
                        let replicas = &block.replica_sums[k * r..(k + 1) * r];
                        calibrated::half_widths(self.quantile, replicas, p.hi - p.lo)
                            .map(|(h, _)| h)
                            .or(block.bounds[k])
                    }
                    _ => None,
                },
            })
            .collect()
    }

    /// Marks which pixels of `block` take rays in the next pass.
    pub fn judge(&self, block: &mut Block) {
        let s = &self.settings;
        match s.rule {
            StopRule::Calibrated => calibrated::judge(s, self.quantile, block),
            StopRule::Cycles => cycles::judge(s, block),
            StopRule::Povray => povray::judge(s, self.quantile, self.spp, block),
            StopRule::Dammertz => dammertz::judge(s, self.image, block),
        }
    }
}
