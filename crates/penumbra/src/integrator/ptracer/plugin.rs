//! The particle tracer as a plugin: its schema and settings
//! ([`config`](super::config)) and the integrator they make.

use crate::description::{Invalid, Props, Schema};
use crate::integrator::metric::Metric;
use crate::integrator::model::{IntegratorModel, RenderWith};
use crate::scene::Scene;

use super::config::{read, PtracerSettings, PTRACER};
use super::Ptracer;

/// The `ptracer` integrator as a plugin.
pub struct PtracerPlugin;

impl IntegratorModel for PtracerPlugin {
    const SCHEMA: &'static Schema = &PTRACER;
    type Settings = PtracerSettings;

    fn read(i: &Props) -> Result<PtracerSettings, Invalid> {
        read(i)
    }

    fn depth(s: &PtracerSettings) -> i64 {
        s.max_depth.map_or(-1, i64::from)
    }

    fn metric(_: &PtracerSettings) -> Option<Metric> {
        None
    }

    fn passes(s: &PtracerSettings) -> u32 {
        s.passes
    }

    fn render_with<R: RenderWith>(scene: &Scene, s: PtracerSettings, run: R) -> R::Output {
        run.render(&Ptracer::new(scene, s))
    }
}
