//! The thesis's integrator as a plugin: its parameters and its settings.

use crate::description::check::int;
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::integrator::metric::{self, Metric};
use crate::integrator::model::{IntegratorModel, RenderWith};
use crate::integrator::ray_sets::RaySets;
use crate::integrator::stopping::{self, Stopping, STOP_RULES};
use crate::sampling::MAX_RAYS;
use crate::scene::Scene;

/// A parameter documented with the render options.
const fn param(name: &'static str, ty: Type) -> Param {
    Param::new(name, ty, "", "")
}

/// The `whitted` integrator's parameters (documented with the render options).
pub const SCHEMA: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "whitted",
    what: "whitted integrator",
    doc: "the thesis's distributed Whitted ray tracer",
    mitsuba: &[],
    params: &[
        param("max_depth", Type::Int),
        param("passes", Type::Int),
        metric::PARAMS[0],
        metric::PARAMS[1],
        metric::PARAMS[2],
        metric::PARAMS[3],
        metric::PARAMS[4],
        metric::PARAMS[5],
        param("pixel_metric", Type::Bool),
        param("noise_threshold", Type::Number),
        param(
            "stop_rule",
            Type::Choice("adaptive sampling rule", &STOP_RULES),
        ),
        param("confidence", Type::Number),
        param("replicas", Type::Int),
        param("noise_floor", Type::Number),
        param("min_spp", Type::Int),
    ],
};

/// The `whitted` integrator's settings, read from its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WhittedSettings {
    /// Levels of reflection and refraction rays (the thesis's recursion depth).
    pub max_depth: u32,
    /// The acceleration metrics of thesis §3.4, if on.
    pub metric: Option<Metric>,
    /// Adaptive sampling, if on.
    pub stopping: Option<Stopping>,
    /// Passes the samples are cut into.
    pub passes: u32,
}

impl WhittedSettings {
    /// The settings of the parameters `p`.
    pub fn read(p: &Props) -> Result<WhittedSettings, Invalid> {
        Ok(WhittedSettings {
            max_depth: int(p, "max_depth", 3, 0, 64)?,
            passes: int(p, "passes", 1, 1, i64::from(MAX_RAYS))?,
            metric: metric::read(p)?,
            stopping: stopping::read(p)?,
        })
    }
}

/// The `whitted` integrator as a plugin: its parameters read into its
/// settings, rendered by [`Whitted`].
pub struct WhittedPlugin;

impl IntegratorModel for WhittedPlugin {
    const SCHEMA: &'static Schema = &SCHEMA;
    type Settings = WhittedSettings;

    fn read(p: &Props) -> Result<WhittedSettings, Invalid> {
        WhittedSettings::read(p)
    }

    fn depth(s: &WhittedSettings) -> i64 {
        i64::from(s.max_depth)
    }

    fn metric(s: &WhittedSettings) -> Option<Metric> {
        s.metric
    }

    fn passes(s: &WhittedSettings) -> u32 {
        s.passes
    }

    fn render_with<R: RenderWith>(scene: &Scene, s: WhittedSettings, run: R) -> R::Output {
        run.render(&Whitted::new(scene, s))
    }
}

/// The thesis's distributed Whitted integrator, with its settings, ready
/// to render a scene.
#[derive(Clone, Debug, PartialEq)]
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
    /// The shadow set of each emitter and the set of each material's
    /// lobes.
    pub sets: RaySets,
}

impl Whitted {
    /// The integrator of `settings` for `scene`.
    pub fn new(scene: &Scene, settings: WhittedSettings) -> Whitted {
        let s = &scene.settings;
        Whitted {
            max_depth: settings.max_depth,
            metric: settings.metric,
            stopping: settings.stopping,
            spp: s.spp,
            passes: settings.passes,
            image: s.width as usize * s.height as usize,
            sets: RaySets::new(scene),
        }
    }

    /// The integrator of `scene`'s `whitted` description.
    #[cfg(test)]
    pub(crate) fn of(scene: &Scene) -> Whitted {
        let p = Props::new(&scene.integrator);
        let settings = WhittedSettings::read(&p).expect("whitted settings");
        Whitted::new(scene, settings)
    }
}
