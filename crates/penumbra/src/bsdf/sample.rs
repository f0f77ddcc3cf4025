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
    /// Scatters into single directions only (`eval` and `pdf` are 0). With
    /// `GLOSSY` too, a delta lobe the thesis blurs: its set of rays is drawn
    /// around the single direction by a distribution of a given radius.
    pub const DELTA: BsdfFlags = BsdfFlags(4);
    pub const REFLECTION: BsdfFlags = BsdfFlags(8);
    pub const TRANSMISSION: BsdfFlags = BsdfFlags(16);
    /// With `DELTA | TRANSMISSION`: passes straight on, unbent and whole
    /// (Mitsuba's `Null`): the `null` material and a mask's pass-through,
    /// which the volumetric path tracer does not count as a scattering.
    pub const NULL: BsdfFlags = BsdfFlags(32);

    pub const fn empty() -> BsdfFlags {
        BsdfFlags(0)
    }

    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Both sets of bits (`|` in constants).
    pub const fn union(self, other: BsdfFlags) -> BsdfFlags {
        BsdfFlags(self.0 | other.0)
    }

    /// True if every bit of `other` is set.
    pub const fn contains(self, other: BsdfFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// True for a lobe with a value for pairs of directions (diffuse or
    /// glossy, not delta): one that direct light is evaluated on.
    pub const fn is_smooth(self) -> bool {
        !self.contains(BsdfFlags::DELTA) && self.0 & (Self::DIFFUSE.0 | Self::GLOSSY.0) != 0
    }

    /// True for a delta lobe.
    pub const fn is_delta(self) -> bool {
        self.contains(BsdfFlags::DELTA)
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
    /// `eval · |cos θ| / pdf` (for a delta lobe, its weight).
    pub weight: Rgb,
    /// Solid-angle density (for a delta lobe, the probability of choosing
    /// the lobe; 1 when the lobe was asked for by itself).
    pub pdf: f32,
    /// The lobe that was sampled.
    pub flags: BsdfFlags,
    /// Its slot (see [`Lobes`]).
    pub lobe: usize,
    /// The relative index of refraction of the interface the sample
    /// crossed, `η_far / η_viewer` (1 for a reflection or a crossing that
    /// does not scale radiance): a path's throughput times its running
    /// product of `eta²` is what Russian roulette reads, free of the `η²`
    /// scaling of radiance between media.
    pub eta: f32,
}

/// The most lobes a model has.
pub const MAX_LOBES: usize = 8;

/// A model's lobes, by slot: the kind of each. Slots with empty flags are
/// absent lobes; a slot keeps its number whether the others are present or
/// not, so that an integrator can name a lobe's random stream, and look up
/// the set of rays it traces for it, by the slot.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lobes {
    pub flags: [BsdfFlags; MAX_LOBES],
}

impl Lobes {
    /// A reflection lobe in slot 0 and a transmission lobe in slot 1, both
    /// of `kind` (delta or glossy): the dielectrics' lobes.
    pub fn reflection_and_transmission(kind: BsdfFlags) -> Lobes {
        let mut l = Lobes::default();
        l.flags[0] = kind | BsdfFlags::REFLECTION;
        l.flags[1] = kind | BsdfFlags::TRANSMISSION;
        l
    }

    /// The slots up to the last present lobe: where lobes placed after
    /// these may start.
    pub fn slots(&self) -> usize {
        (0..MAX_LOBES)
            .rev()
            .find(|&k| !self.flags[k].is_empty())
            .map_or(0, |k| k + 1)
    }

    /// These lobes copied into `into` from slot `at` on (slot `k` to
    /// `at + k`); false, and nothing copied, if they do not fit.
    pub fn place(&self, into: &mut Lobes, at: usize) -> bool {
        let n = self.slots();
        if at + n > MAX_LOBES {
            return false;
        }
        into.flags[at..at + n].copy_from_slice(&self.flags[..n]);
        true
    }

    /// The present lobes: (slot, flags).
    pub fn iter(&self) -> impl Iterator<Item = (usize, BsdfFlags)> + '_ {
        (0..MAX_LOBES)
            .filter(|&k| !self.flags[k].is_empty())
            .map(|k| (k, self.flags[k]))
    }

    /// The union of the lobes' flags.
    pub fn union(&self) -> BsdfFlags {
        self.flags.iter().fold(BsdfFlags::empty(), |a, &f| a | f)
    }

    /// True if some lobe is smooth (direct light is evaluated on it).
    pub fn any_smooth(&self) -> bool {
        self.flags.iter().any(|f| f.is_smooth())
    }

    /// True if some lobe is a delta lobe (rays must be traced to see it).
    pub fn any_delta(&self) -> bool {
        self.flags.iter().any(|f| f.is_delta())
    }
}
