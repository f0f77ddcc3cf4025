//! What a tile's pixels have gathered: the sums every rule reads, and
//! the few definitions those sums are made by.

use serde::{Deserialize, Serialize};

use crate::math::Rgb;

/// What one pixel's samples add up to.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize)]
pub struct Tally {
    /// Sum of the samples' radiance.
    pub sum: Rgb,
    /// Sum over the samples of Cycles' class A (see [`class_a`]).
    pub half: Rgb,
    /// Sum over the samples of odd index (Dammertz's half).
    pub odd: Rgb,
    /// The smallest and largest sample, per channel.
    pub lo: Rgb,
    pub hi: Rgb,
    /// Rays taken.
    pub n: u32,
    /// Whether the pixel takes rays in the next pass.
    pub active: bool,
}

impl Tally {
    /// The pixel's value: the mean of its samples.
    pub fn mean(&self) -> Rgb {
        if self.n == 0 {
            Rgb::ZERO
        } else {
            self.sum / self.n as f32
        }
    }
}

/// The tallies of a tile's pixels, row by row, and what a rule keeps
/// between passes.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Block {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Tally>,
    /// Per pixel, per replica (`pixel * replicas + r`): sum and count.
    pub(super) replicas: usize,
    pub(super) replica_sums: Vec<(Rgb, u32)>,
    /// Per pixel: sum and sum of squares of the gamma-encoded samples
    /// (POV-Ray's statistics); empty unless the rule reads them.
    pub(super) encoded: Vec<(Rgb, Rgb)>,
    /// The blocks of pixels still judged (Dammertz).
    pub(super) regions: Vec<Rect>,
    /// Per pixel stopped by the calibrated rule's screen: the range of
    /// its neighbourhood's samples (the half-width it reports).
    pub(super) bounds: Vec<Option<Rgb>>,
}

impl Block {
    /// A tile of `width × height` pixels, all active, none sampled; with
    /// POV-Ray's gamma-encoded sums if `encoded`.
    pub fn new(width: usize, height: usize, replicas: usize, encoded: bool) -> Block {
        let n = width * height;
        let active = Tally {
            active: true,
            ..Tally::default()
        };
        Block {
            width,
            height,
            pixels: vec![active; n],
            replicas,
            replica_sums: vec![(Rgb::ZERO, 0); n * replicas],
            encoded: vec![(Rgb::ZERO, Rgb::ZERO); if encoded { n } else { 0 }],
            regions: vec![Rect::all(width, height)],
            bounds: vec![None; n],
        }
    }

    /// Whether the block has the shape [`new`](Self::new) gives these
    /// arguments (a block read from a checkpoint): its sizes, and regions
    /// within the tile.
    pub fn fits(&self, width: usize, height: usize, replicas: usize, encoded: bool) -> bool {
        let n = width * height;
        self.width == width
            && self.height == height
            && self.pixels.len() == n
            && self.replicas == replicas
            && self.replica_sums.len() == n * replicas
            && self.encoded.len() == if encoded { n } else { 0 }
            && self.bounds.len() == n
            && self
                .regions
                .iter()
                .all(|r| r.x0 <= r.x1 && r.x1 <= width && r.y0 <= r.y1 && r.y1 <= height)
    }

    /// Adds sample `i` of pixel `k`, of radiance `l`, belonging to `replica`.
    pub fn add(&mut self, k: usize, i: u32, replica: usize, l: Rgb) {
        let t = &mut self.pixels[k];
        (t.lo, t.hi) = if t.n == 0 {
            (l, l)
        } else {
            (t.lo.min(l), t.hi.max(l))
        };
        t.sum += l;
        t.n += 1;
        if class_a(i) {
            t.half += l;
        }
        if i % 2 == 1 {
            t.odd += l;
        }
        let r = &mut self.replica_sums[k * self.replicas + replica];
        r.0 += l;
        r.1 += 1;
        if let Some(e) = self.encoded.get_mut(k) {
            let g = encode(l);
            e.0 += g;
            e.1 += g * g;
        }
    }

    /// Whether any pixel takes rays in the next pass.
    pub fn any_active(&self) -> bool {
        self.pixels.iter().any(|t| t.active)
    }
}

/// Whether sample `i` counts in Cycles' half buffer (see [`cycles`](super::cycles)).
#[inline]
pub fn class_a(i: u32) -> bool {
    (i & 0xAAAA_AAAA).count_ones() & 1 == 1
}

/// POV-Ray's default `Antialias_Gamma`.
const GAMMA: f32 = 2.5;

/// A sample as POV-Ray compares it (see [`povray`](super::povray)): gamma-encoded, negatives as 0.
#[inline]
pub fn encode(l: Rgb) -> Rgb {
    l.map(|c| c.max(0.0).powf(1.0 / GAMMA))
}

/// A rectangle of a tile's pixels, `[x0, x1) × [y0, y1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rect {
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
}

impl Rect {
    pub fn all(width: usize, height: usize) -> Rect {
        Rect {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    pub fn pixels(&self) -> usize {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }
}
