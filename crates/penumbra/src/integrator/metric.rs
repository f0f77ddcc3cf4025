//! The acceleration metrics of thesis §3.4: stop tracing a set of rays once
//! more rays would no longer change the result.
//!
//! * **Reflection / refraction (and, optionally, primary rays):** after at
//!   least α rays, stop as soon as the running average changes by less than a
//!   threshold between n − 1 and n rays.
//! * **Shadows:** after the first k shadow rays toward a light, stop if all of
//!   them reached it or all were blocked.
//!
//! The thesis measures each metric alone (its Tables 4.4 and 4.6) and then
//! both together, so each rule is switched on by itself ([`Metric`]'s
//! `reflections`, `shadows` and `pixels`).
//!
//! The colour difference is the largest per-channel change of the running
//! average *relative to the average's largest channel*: radiance has no
//! natural unit, so a relative measure makes one threshold mean the same in a
//! dim and a bright scene, and taking the largest channel never lets a change
//! of hue hide behind unchanged luminance. Below [`DARK`] the change is
//! measured against `DARK` instead, so that noise around black does not keep a
//! set running forever.

use crate::description::check::{int, range};
use crate::description::{Invalid, Param, Props, Type};
use crate::math::Rgb;
use crate::sampling::MAX_RAYS;

/// Settings of the metrics; `None` in an integrator's configuration means
/// they are all off (`read` never makes one with all three rules off).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metric {
    /// Apply the α/threshold rule to reflection and refraction sets.
    pub reflections: bool,
    /// Apply the k rule to shadow sets.
    pub shadows: bool,
    /// Largest relative change of the running average that stops a set.
    pub threshold: f32,
    /// α: rays always traced before the reflection/refraction metric applies.
    pub min_rays: u32,
    /// k: shadow rays after which an all-lit or all-blocked set stops.
    pub shadow_rays: u32,
    /// Apply the α/threshold rule to the primary rays of a pixel too.
    pub pixels: bool,
}

/// A shadow set under the thesis's shadow metric: after its first `k` of
/// `n` rays, a set whose rays all reached the light, or were all blocked,
/// stops, and their mean stands for the set. Counted by `whitted` ray by
/// ray and by the wavefront set by set, judged the same way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowTally {
    pub n: u32,
    pub k: u32,
    pub reached: u32,
    pub blocked: u32,
}

impl ShadowTally {
    /// The tally of a set of `n` rays under the metric `m`, if the metric
    /// judges it (its shadow rule on, and `k < n`).
    #[inline]
    pub fn of(m: Option<Metric>, n: u32) -> Option<ShadowTally> {
        let k = m.filter(|m| m.shadows).map(|m| m.shadow_rays)?;
        (k < n).then_some(ShadowTally {
            n,
            k,
            reached: 0,
            blocked: 0,
        })
    }

    /// The tally of a set of `n` rays that the metric does not judge: its
    /// `k` is never reached.
    #[inline]
    pub fn unjudged(n: u32) -> ShadowTally {
        ShadowTally {
            n,
            k: u32::MAX,
            reached: 0,
            blocked: 0,
        }
    }

    /// Counts a ray that reached the light (`true`) or was blocked.
    #[inline]
    pub fn count(&mut self, reached: bool) {
        if reached {
            self.reached += 1;
        } else {
            self.blocked += 1;
        }
    }

    /// The metric's verdict after the first `k` members: stop if they all
    /// reached the emitter or were all blocked (and one was a ray).
    #[inline]
    pub fn stops(&self) -> bool {
        (self.reached == 0 || self.blocked == 0) && self.reached + self.blocked > 0
    }
}

/// The keys of the metrics in the schemas of the integrators that have
/// them (documented with the render options).
pub const PARAMS: [Param; 6] = [
    Param::new("metric", Type::Bool, "", ""),
    Param::new("reflection_metric", Type::Bool, "", ""),
    Param::new("shadow_metric", Type::Bool, "", ""),
    Param::new("metric_threshold", Type::Number, "", ""),
    Param::new("metric_min_rays", Type::Int, "", ""),
    Param::new("shadow_metric_rays", Type::Int, "", ""),
];

/// The metrics of an integrator's parameters `i` (`metric` and the keys
/// of each rule); `None` when they are off.
pub fn read(i: &Props) -> Result<Option<Metric>, Invalid> {
    let m = Metric {
        reflections: i.bool("reflection_metric")?.unwrap_or(true),
        shadows: i.bool("shadow_metric")?.unwrap_or(true),
        threshold: range(i, "metric_threshold", 0.01, 0.0, 1e6)?,
        min_rays: int(i, "metric_min_rays", 4, 1, i64::from(MAX_RAYS))?,
        shadow_rays: int(i, "shadow_metric_rays", 4, 1, i64::from(MAX_RAYS))?,
        pixels: i.bool("pixel_metric")?.unwrap_or(false),
    };
    let any = m.reflections || m.shadows || m.pixels;
    Ok((i.bool("metric")?.unwrap_or(false) && any).then_some(m))
}

/// Radiance below which changes are judged in absolute terms.
pub const DARK: f32 = 1e-3;

/// The change between the running averages after n − 1 and n values.
pub fn change(previous: Rgb, current: Rgb) -> f32 {
    let d = (current - previous).abs().max_element();
    d / current.max_element().max(previous.max_element()).max(DARK)
}

/// A running average that knows when the metric says stop.
#[derive(Clone, Copy, Debug, Default)]
pub struct RunningMean {
    sum: Rgb,
    n: u32,
}

impl RunningMean {
    /// The running mean of `n` values summing to `sum`, to be continued.
    pub fn resume(sum: Rgb, n: u32) -> RunningMean {
        RunningMean { sum, n }
    }

    /// Adds a value; returns true if, under `metric`, a set of `budget` rays
    /// may stop after it (at least α values, fewer than the budget, and a
    /// change below the threshold).
    pub fn push(&mut self, x: Rgb, metric: Option<&Metric>, budget: u32) -> bool {
        let previous = self.mean();
        self.sum += x;
        self.n += 1;
        match metric {
            Some(m) if self.n >= m.min_rays.max(2) && self.n < budget => {
                change(previous, self.mean()) < m.threshold
            }
            _ => false,
        }
    }

    pub fn count(&self) -> u32 {
        self.n
    }

    pub fn mean(&self) -> Rgb {
        if self.n == 0 {
            Rgb::ZERO
        } else {
            self.sum / self.n as f32
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_values_stop_at_alpha() {
        let m = Metric {
            reflections: true,
            shadows: true,
            threshold: 0.01,
            min_rays: 4,
            shadow_rays: 4,
            pixels: false,
        };
        let mut r = RunningMean::default();
        let stops: Vec<bool> = (0..8)
            .map(|_| r.push(Rgb::splat(0.5), Some(&m), 16))
            .collect();
        assert_eq!(stops, [false, false, false, true, true, true, true, true]);
    }

    #[test]
    fn never_stops_without_metric_or_at_the_budget() {
        let m = Metric {
            reflections: true,
            shadows: true,
            threshold: 0.5,
            min_rays: 1,
            shadow_rays: 1,
            pixels: false,
        };
        let mut r = RunningMean::default();
        assert!(!r.push(Rgb::ONE, None, 4));
        assert!(!r.push(Rgb::ONE, None, 4));
        let mut r = RunningMean::default();
        r.push(Rgb::ONE, Some(&m), 2);
        assert!(
            !r.push(Rgb::ONE, Some(&m), 2),
            "the last ray of the budget is not a saving"
        );
    }

    #[test]
    fn change_is_relative_and_guarded_near_black() {
        assert!((change(Rgb::splat(1.0), Rgb::splat(1.1)) - 0.1 / 1.1).abs() < 1e-6);
        assert!((change(Rgb::splat(100.0), Rgb::splat(110.0)) - 10.0 / 110.0).abs() < 1e-6);
        assert!((change(Rgb::ZERO, Rgb::splat(1e-5)) - 1e-2).abs() < 1e-6);
        assert_eq!(
            change(Rgb::new(1.0, 0.0, 0.0), Rgb::new(1.0, 0.0, 0.0)),
            0.0
        );
    }
}
