//! What every scattering model reports: the kind of its lobes and the
//! directions it draws.

use std::ops::BitOr;

use crate::math::{Rgb, Vec3};

/// What kind of lobe a model has (a set of bits).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BsdfFlags(u8);

impl BsdfFlags {
    /// Scatters into the whole hemisphere.
    pub const DIFFUSE: BsdfFlags = BsdfFlags(1);
    /// Scatters around a preferred direction.
    pub const GLOSSY: BsdfFlags = BsdfFlags(2);
    /// Scatters into single directions only (`eval` and `pdf` are 0).
    pub const DELTA: BsdfFlags = BsdfFlags(4);
    pub const REFLECTION: BsdfFlags = BsdfFlags(8);
    pub const TRANSMISSION: BsdfFlags = BsdfFlags(16);

    pub const fn empty() -> BsdfFlags {
        BsdfFlags(0)
    }

    /// True if every bit of `other` is set.
    pub const fn contains(self, other: BsdfFlags) -> bool {
        self.0 & other.0 == other.0
    }
}

impl BitOr for BsdfFlags {
    type Output = BsdfFlags;
    fn bitor(self, o: BsdfFlags) -> BsdfFlags {
        BsdfFlags(self.0 | o.0)
    }
}

/// A direction drawn by `Bsdf::sample`.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Unit direction toward where light comes from.
    pub wi: Vec3,
    /// `eval · cos θ / pdf` (for a delta lobe, its weight).
    pub weight: Rgb,
    /// Solid-angle density (for a delta lobe, the probability of the lobe).
    pub pdf: f32,
    /// The lobe that was sampled.
    pub flags: BsdfFlags,
}
