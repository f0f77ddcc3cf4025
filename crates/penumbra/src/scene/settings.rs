//! Image-wide settings after validation, and the settings of the thesis's
//! acceleration metrics and of the adaptive sampling rules (whose rules
//! live in the integrator).

use std::sync::Arc;

use crate::math::Rgb;
use crate::sampling::{Distribution, EffectSpec, Filter, PointTable};

/// Image-wide settings after validation.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Levels of reflection/refraction rays (the thesis's recursion depth).
    pub max_depth: u32,
    pub seed: u64,
    pub background: Rgb,
    /// Primary rays per pixel.
    pub spp: u32,
    /// Passes the render is made in.
    pub passes: u32,
    pub pixel: Distribution,
    pub lens: Distribution,
    pub time: Distribution,
    /// The sets of shadow, reflection and refraction rays of emitters and
    /// lobes that set none of their own.
    pub shadow: EffectSpec,
    pub reflection: EffectSpec,
    pub refraction: EffectSpec,
    /// The `custom` distribution's points ([`PointTable::NONE`] when none
    /// are given, which only a render without `custom` may have).
    pub points: Arc<PointTable>,
    /// The pixel filter the film points are drawn by.
    pub filter: Filter,
    /// The acceleration metrics, if on.
    pub metric: Option<Metric>,
    /// Adaptive sampling: the rule that stops a pixel's camera rays before
    /// `spp`, if on.
    pub stopping: Option<Stopping>,
}

/// Settings of the metrics; `None` in the scene settings means they are all
/// off (the scene builder never makes one with all three rules off).
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

/// An adaptive sampling rule, by the name users write.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum StopRule {
    /// Replicas' spread gives a confidence interval of the pixel's mean.
    #[default]
    Calibrated,
    /// Blender Cycles' adaptive sampling.
    Cycles,
    /// POV-Ray's stochastic anti-aliasing (`Sampling_Method 3`).
    Povray,
    /// Dammertz et al.'s hierarchical stopping condition (2009).
    Dammertz,
}

impl StopRule {
    pub const ALL: [StopRule; 4] = [
        StopRule::Calibrated,
        StopRule::Cycles,
        StopRule::Povray,
        StopRule::Dammertz,
    ];

    /// The name users write (the serde name too).
    pub fn name(self) -> &'static str {
        match self {
            StopRule::Calibrated => "calibrated",
            StopRule::Cycles => "cycles",
            StopRule::Povray => "povray",
            StopRule::Dammertz => "dammertz",
        }
    }

    pub fn from_name(s: &str) -> Option<StopRule> {
        StopRule::ALL.into_iter().find(|r| r.name() == s)
    }
}
