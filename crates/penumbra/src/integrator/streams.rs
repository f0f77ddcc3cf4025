//! The table of stream keys below a primary sample's path, for every
//! integrator: which branch of a path's stream each use derives. The
//! [module docs](super) give it as a table.
//!
//! `whitted` and `distributed` draw the shadow set toward emitter `j` from
//! the same branch, `SHADOW + j`; the branches of the bounces of `path`
//! (`b`) and of `whitted`'s lobe sets (`2k + 1`, `2k + 2`) lie far below
//! it, and the distributed path tracer's BSDF set and roulette just below.
//! `ptracer`'s light paths take the streams of the camera samples of the
//! same index: their bounces the same branches as `path`'s, the
//! connection of an emitter seen directly one just below those.

/// The first shadow-set branch: the set toward emitter `j` takes
/// `SHADOW + j`.
pub const SHADOW: u64 = 1 << 32;

/// The branch of a vertex's set of BSDF samples (`distributed`).
pub const BSDF_SET: u64 = SHADOW - 1;

/// The branch of a set's path that its Russian roulette reads
/// (`distributed`).
pub const ROULETTE: u64 = SHADOW - 2;

/// The branch of a light path that connects an emitter seen directly to
/// the camera (`ptracer`).
pub const SEEN_EMITTER: u64 = SHADOW - 3;

/// The first path-sampler dimension of a BSDF's third number (the lobe
/// choice of [`SetPoint::third`](crate::sampling::SetPoint::third)): the
/// `k`-th BSDF sample of a bounce, whose point is dimension `d = 2(e + k)`,
/// takes `LOBE_DIMENSION + d`, far above the bounce's other dimensions.
/// `independent` draws it after the sample's roulette number, and only
/// for a model that reads it, so no other number moves.
pub const LOBE_DIMENSION: u64 = 1 << 20;

/// The branch of the shadow set toward emitter `j`.
#[inline]
pub fn shadow(j: u64) -> u64 {
    SHADOW + j
}

/// The branches of a set of lobe `k` of a BSDF (`whitted`): its points
/// from `path.derive(2k + 1)`, the paths of its rays from
/// `path.derive(2k + 2)`.
#[inline]
pub fn lobe(k: usize) -> (u64, u64) {
    (2 * k as u64 + 1, 2 * k as u64 + 2)
}

/// The branch of bounce `b` of a path (`path`, `direct`, `distributed`).
#[inline]
pub fn bounce(b: u32) -> u64 {
    u64::from(b)
}

/// The branch of the shadow rays of step `s` of a volumetric path
/// (`volpath`): their tracking through media (ratio tracking) reads it.
/// Steps (a path's scatterings, null collisions and crossings of `null`
/// surfaces, each one step) stay far below it.
#[inline]
pub fn tracking(s: u32) -> u64 {
    TRACKING + u64::from(s)
}

/// The first branch of [`tracking`].
pub const TRACKING: u64 = 1 << 31;

/// The branch a volumetric path (`volpath`, `volpathmis`) draws its colour channel from:
/// the channel its distances in media are drawn by (Mitsuba's).
pub const CHANNEL: u64 = SHADOW - 3;
