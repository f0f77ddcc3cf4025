//! The settings of adaptive sampling, read from an integrator's parameters.

use super::StopRule;
use crate::description::check::{int, range};
use crate::description::{Invalid, Props};
use crate::sampling::MAX_RAYS;
use crate::scene::options::MAX_REPLICAS;

/// Settings of adaptive sampling: a pixel takes camera rays in passes until
/// its rule judges its noise below `threshold`, or it reaches the budget
/// (`spp`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stopping {
    pub rule: StopRule,
    /// The noise a pixel may keep, in the rule's own measure (> 0).
    pub threshold: f32,
    /// The confidence of the rules that bound the error by an interval
    /// (`calibrated`, `povray`), from 0.5 to 0.999.
    pub confidence: f32,
    /// Independently scrambled replicas of a pixel's sets (`calibrated`), ≥ 2.
    pub replicas: u32,
    /// The value below which the calibrated rule's threshold is absolute:
    /// a half-width of `threshold · max(value, floor)` is allowed (> 0).
    pub floor: f32,
    /// Camera rays a pixel takes before the rule may stop it; 0: the rule's own.
    pub min_spp: u32,
}

/// The names of the rules, as `stop_rule` takes them.
pub const STOP_RULES: [&str; 4] = ["calibrated", "cycles", "povray", "dammertz"];

/// Adaptive sampling's settings of an integrator's parameters `i`; `None`
/// when `noise_threshold` is 0.
pub fn read(i: &Props) -> Result<Option<Stopping>, Invalid> {
    let threshold = range(i, "noise_threshold", 0.0, 0.0, 1e6)?;
    let rule = match i.choice("stop_rule", "adaptive sampling rule", &STOP_RULES)? {
        Some(r) => StopRule::from_name(r).unwrap_or_default(),
        None => StopRule::default(),
    };
    let s = Stopping {
        rule,
        threshold,
        confidence: range(i, "confidence", 0.9, 0.5, 0.999)?,
        replicas: int(i, "replicas", 8, 2, i64::from(MAX_REPLICAS))?,
        floor: range(i, "noise_floor", 1.0, 1e-6, 1e6)?,
        min_spp: int(i, "min_spp", 0, 0, i64::from(MAX_RAYS))?,
    };
    let metric = i.bool("metric")?.unwrap_or(false);
    if threshold > 0.0 && metric && i.bool("pixel_metric")?.unwrap_or(false) {
        return Err(i.error(
            "noise_threshold",
            "adaptive sampling and `pixel_metric` both stop a pixel's camera rays: \
             turn one of them off",
        ));
    }
    Ok((threshold > 0.0).then_some(s))
}
