//! The path tracers as plugins: `path`, `direct`, `distributed`, `volpath` and
//! `volpathmis`, one
//! integrator ([`Path`]) and one kind of settings ([`PathSettings`]), each
//! its own schema and reading.

use crate::description::{Invalid, Props, Schema};
use crate::integrator::metric::Metric;
use crate::integrator::model::{IntegratorModel, RenderWith};
use crate::scene::Scene;

use super::config::{
    direct, distributed, path, volpath, volpathmis, PathSettings, DIRECT, DISTRIBUTED, PATH,
    VOLPATH, VOLPATHMIS,
};
use super::Path;

/// The `path` integrator as a plugin: its parameters read into its settings.
pub struct PathPlugin;

/// The `direct` integrator as a plugin: its parameters read into its settings.
pub struct DirectPlugin;

/// The `distributed` integrator as a plugin: its parameters read into its
/// settings.
pub struct DistributedPlugin;

/// The `volpath` integrator as a plugin: its parameters read into its
/// settings.
pub struct VolpathPlugin;

/// The `volpathmis` integrator as a plugin: its parameters read into its
/// settings.
pub struct VolpathmisPlugin;

/// The five as plugins: the same settings and integrator, each its own
/// schema and reading.
macro_rules! path_plugins {
    ($($plugin:ident: $schema:ident, $read:expr;)*) => {$(
        impl IntegratorModel for $plugin {
            const SCHEMA: &'static Schema = &$schema;
            type Settings = PathSettings;

            fn read(i: &Props) -> Result<PathSettings, Invalid> {
                let read: fn(&Props) -> Result<PathSettings, Invalid> = $read;
                PathSettings::read_shared(read(i)?, i)
            }

            fn depth(s: &PathSettings) -> i64 {
                s.depth()
            }

            fn metric(s: &PathSettings) -> Option<Metric> {
                s.metric
            }

            fn passes(s: &PathSettings) -> u32 {
                s.passes
            }

            fn render_with<R: RenderWith>(scene: &Scene, s: PathSettings, run: R) -> R::Output {
                run.render(&Path::new(scene, s))
            }
        }
    )*};
}

path_plugins! {
    PathPlugin: PATH, path;
    DirectPlugin: DIRECT, direct;
    DistributedPlugin: DISTRIBUTED, distributed;
    VolpathPlugin: VOLPATH, volpath;
    VolpathmisPlugin: VOLPATHMIS, volpathmis;
}
