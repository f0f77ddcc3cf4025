//! Tracking through a heterogeneous density with null collisions: free-flight
//! sampling (delta tracking, Woodcock) and transmittance estimation (ratio
//! tracking), over majorant [`Segment`]s — a [`MajorantGrid`]'s walk, or one
//! stretch with one majorant for the whole medium ([`single_segment`], what
//! Mitsuba's heterogeneous medium does), so that a caller can choose and
//! compare.
//!
//! Pure functions: the density is a closure of the ray's `t` (the caller
//! maps `t` to its point and looks it up, scaled), and the random numbers
//! come from a closure giving uniform numbers in `[0, 1)`, so the caller
//! owns the stream. How many numbers a walk takes depends on the walk; each
//! tentative collision takes 1 (ratio tracking) or 2 (delta tracking: the
//! step, then the choice between a real and a null collision).
//!
//! A density above its segment's majorant breaks the estimators' premise:
//! delta tracking then takes every tentative collision as real, and ratio
//! tracking's weight may turn negative. The majorants of a
//! [`MajorantGrid`] bound the density they were made from. A segment
//! whose majorant is not finite and positive holds nothing and is skipped.
//!
//! [`MajorantGrid`]: super::MajorantGrid

use super::majorant::{clip_to_box, Segment};
use crate::math::{Aabb, Vec3};

/// Where delta tracking ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// The `t` of the real collision; `None` when the ray left the last
    /// segment without one.
    pub collision: Option<f32>,
    /// The null collisions on the way.
    pub nulls: u32,
}

/// Ratio tracking's estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transmittance {
    /// The estimate of `exp(−∫ σ dt)` over the segments.
    pub value: f32,
    /// The tentative collisions (all null ones) it took.
    pub nulls: u32,
}

/// The one segment of a single majorant: the ray's stretch within
/// `[tmin, tmax]` inside `bounds`, with `majorant`; `None` when it misses.
pub fn single_segment(
    bounds: &Aabb,
    origin: Vec3,
    direction: Vec3,
    tmin: f32,
    tmax: f32,
    majorant: f32,
) -> Option<Segment> {
    clip_to_box(bounds, origin, direction, tmin, tmax).map(|(t0, t1)| Segment { t0, t1, majorant })
}

/// Delta tracking: samples the distance to the first real collision with
/// the density `density(t)`, stepping through `segments` by exponential
/// steps of each one's majorant, and counts the null collisions. The
/// probability of no collision is the transmittance `exp(−∫ density)`.
pub fn delta_track(
    segments: impl IntoIterator<Item = Segment>,
    mut density: impl FnMut(f32) -> f32,
    mut uniform: impl FnMut() -> f32,
) -> Flight {
    let mut nulls = 0;
    for s in segments {
        if !s.majorant.is_finite() || s.majorant <= 0.0 {
            continue;
        }
        let mut t = s.t0;
        loop {
            // The exponential step is memoryless: leaving a segment, the
            // walk starts afresh at the next one's start.
            t -= (1.0 - uniform()).ln() / s.majorant;
            if t >= s.t1 {
                break;
            }
            if uniform() * s.majorant < density(t) {
                return Flight {
                    collision: Some(t),
                    nulls,
                };
            }
            nulls += 1;
        }
    }
    Flight {
        collision: None,
        nulls,
    }
}

/// Ratio tracking: an unbiased estimate of the transmittance
/// `exp(−∫ density)` over `segments`, the product of `1 − density/majorant`
/// at each tentative collision.
pub fn ratio_track(
    segments: impl IntoIterator<Item = Segment>,
    mut density: impl FnMut(f32) -> f32,
    mut uniform: impl FnMut() -> f32,
) -> Transmittance {
    let mut value = 1.0f32;
    let mut nulls = 0;
    for s in segments {
        if !s.majorant.is_finite() || s.majorant <= 0.0 {
            continue;
        }
        let mut t = s.t0;
        loop {
            t -= (1.0 - uniform()).ln() / s.majorant;
            if t >= s.t1 {
                break;
            }
            value *= 1.0 - density(t) / s.majorant;
            nulls += 1;
        }
    }
    Transmittance { value, nulls }
}
