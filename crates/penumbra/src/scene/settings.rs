//! Image-wide settings after validation, and the settings of the thesis's
//! acceleration metrics (whose rules live in the integrator).

use crate::math::Rgb;
use crate::sampling::{Distribution, Filter};

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
    pub pixel: Distribution,
    pub lens: Distribution,
    pub time: Distribution,
    /// The pixel filter the film points are drawn by.
    pub filter: Filter,
    /// The acceleration metrics, if on.
    pub metric: Option<Metric>,
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
