//! The settings of the thesis's integrator.

use crate::scene::{Metric, Scene, Stopping};

/// The thesis's distributed Whitted integrator, with its settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Whitted {
    /// Levels of reflection and refraction rays (the thesis's recursion depth).
    pub max_depth: u32,
    /// The acceleration metrics of thesis §3.4, if on.
    pub metric: Option<Metric>,
    /// Adaptive sampling, if on.
    pub stopping: Option<Stopping>,
    /// Camera rays per pixel (the budget, under adaptive sampling).
    pub spp: u32,
    /// Passes the samples are cut into.
    pub passes: u32,
    /// Pixels of the whole image (adaptive rules judge blocks against it).
    pub image: usize,
}

impl Whitted {
    /// The integrator with the scene's settings.
    pub fn new(scene: &Scene) -> Whitted {
        let s = &scene.settings;
        Whitted {
            max_depth: s.max_depth,
            metric: s.metric,
            stopping: s.stopping,
            spp: s.spp,
            passes: s.passes,
            image: s.width as usize * s.height as usize,
        }
    }
}
