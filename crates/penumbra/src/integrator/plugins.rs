//! The integrators as plugins. Each integrator's schema and settings sit
//! beside it (`whitted/config.rs`, `path/config.rs`), each implementing
//! [`IntegratorModel`] (`whitted/config.rs`, `path/plugins.rs`); this
//! file lists them in the `integrators!` list, one line per integrator,
//! which makes [`Config`] and its dispatch (and, for the Mitsuba reader,
//! gives the [`registry`] of every plugin),
//! reads the integrator a scene describes into its settings, and
//! builds scenes so that a bad integrator parameter is refused at its place
//! when the scene is built.
//!
//! The scene keeps its integrator's description ([`Scene::integrator`]),
//! as pbrt-v4's scene keeps its integrator's parameters: the scene sits
//! below the integrators, which read it. [`Config::read`] reads the
//! description into the integrator's own settings, when the scene is built
//! (to check it) and when a render starts.

use super::aov::{self, AovPlugin, DepthPlugin, MomentPlugin};
use super::metric::Metric;
pub use super::model::RenderWith;
use super::model::{IntegratorModel, Nested};
use super::path::{
    self, DirectPlugin, DistributedPlugin, PathPlugin, VolpathPlugin, VolpathmisPlugin,
};
use super::ptracer::{self, PtracerPlugin};
use super::whitted::WhittedPlugin;
use crate::description::mitsuba::Plugin;
use crate::description::{self, Invalid, Kind, Node, Origin, Props, SceneError, Schema};
use crate::scene::{schemas, IntegratorChoice, Scene, SceneSource, WorldCache};

/// The integrators Mitsuba 3 has, as its reader sees them: `path`,
/// `direct` and `ptracer`.
/// Every plugin as the Mitsuba reader sees it: the integrators Mitsuba 3
/// has (`path`, `volpath`, `volpathmis`, `direct`, `ptracer`, `depth`, `aov`, `moment`) and the scene's plugins of every other
/// kind ([`schemas::plugins`]). The scene layer, below the integrators,
/// cannot name them: readers of Mitsuba scenes take this registry.
pub fn registry(kind: Kind) -> &'static [Plugin] {
    match kind {
        Kind::Integrator => &MITSUBA,
        _ => schemas::plugins(kind),
    }
}

/// The integrators Mitsuba 3 has.
const MITSUBA: [Plugin; 8] = {
    let (p, t, a) = (path::PLUGINS, ptracer::PLUGINS, aov::plugins::PLUGINS);
    [p[0], p[1], p[2], p[3], t[0], a[0], a[1], a[2]]
};

/// Makes [`Config`] (an integrator listed, `Variant => Model` with the
/// model implementing [`IntegratorModel`], with its settings), the list
/// of their schemas and the dispatch; and [`HeldConfig`], the integrators
/// listed under `images` (those that make an image of their own),
/// which the `holders` hold.
macro_rules! integrators {
    (images { $($plain:ident => $plain_model:ty,)* } holders { $($holder:ident => $holder_model:ty,)* }) => {
        integrators!(@all $($plain => $plain_model,)* $($holder => $holder_model,)*);

        /// An integrator that makes an image of its own (any but the
        /// holders), held by `aov` or `moment`, with its settings.
        #[derive(Clone, Debug, PartialEq)]
        pub enum HeldConfig {
            $($plain(<$plain_model as IntegratorModel>::Settings),)*
        }

        impl Nested for HeldConfig {
            fn read(node: &Node) -> Result<HeldConfig, Invalid> {
                match Config::read(node)? {
                    $(Config::$plain(s) => Ok(HeldConfig::$plain(s)),)*
                    _ => Err(Invalid::at(
                        &node.plugin_origin,
                        format!(
                            "`{}` cannot be held: `aov` and `moment` hold an integrator that \
                             makes an image ({})",
                            node.plugin,
                            [$(IntegratorChoice::$plain.name(),)*].join(", ")
                        ),
                    )),
                }
            }

            fn plugin(&self) -> &'static str {
                match self {
                    $(HeldConfig::$plain(_) => IntegratorChoice::$plain.name(),)*
                }
            }

            fn depth(&self) -> i64 {
                match self {
                    $(HeldConfig::$plain(s) => <$plain_model as IntegratorModel>::depth(s),)*
                }
            }

            fn metric(&self) -> Option<Metric> {
                match self {
                    $(HeldConfig::$plain(s) => <$plain_model as IntegratorModel>::metric(s),)*
                }
            }

            fn passes(&self) -> u32 {
                match self {
                    $(HeldConfig::$plain(s) => <$plain_model as IntegratorModel>::passes(s),)*
                }
            }

            fn render_with<R: RenderWith>(self, scene: &Scene, run: R) -> R::Output {
                match self {
                    $(HeldConfig::$plain(s) => <$plain_model as IntegratorModel>::render_with(scene, s, run),)*
                }
            }
        }
    };
    (@all $($variant:ident => $model:ty,)*) => {
        /// The schemas of the integrators, in the list's order (that of
        /// [`IntegratorChoice::ALL`]).
        pub const SCHEMAS: [&Schema; [$(IntegratorChoice::$variant,)*].len()] =
            [$(<$model as IntegratorModel>::SCHEMA,)*];

        /// An integrator and its settings, read from its description.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Config {
            $($variant(<$model as IntegratorModel>::Settings),)*
        }

        impl Config {
            /// The integrator `node` describes (checked against its schema:
            /// its name known, each key its own and of its type) with its
            /// settings.
            pub fn read(node: &Node) -> Result<Config, Invalid> {
                let choice = IntegratorChoice::from_name(&node.plugin).ok_or_else(|| {
                    Invalid::at(
                        &node.plugin_origin,
                        format!(
                            "unknown integrator `{}`; valid choices are: {}",
                            node.plugin,
                            IntegratorChoice::NAMES.join(", ")
                        ),
                    )
                })?;
                let schema = match choice {
                    $(IntegratorChoice::$variant => <$model as IntegratorModel>::SCHEMA,)*
                };
                let others: Vec<&Schema> = SCHEMAS
                    .iter()
                    .copied()
                    .filter(|o| o.plugin != schema.plugin)
                    .collect();
                description::check(node, schema, &others)?;
                let p = Props::new(node);
                let config = match choice {
                    $(IntegratorChoice::$variant => Config::$variant(<$model as IntegratorModel>::read_node(node, &p)?),)*
                };
                p.finish("integrator")?;
                Ok(config)
            }

            /// Which integrator it is.
            pub fn choice(&self) -> IntegratorChoice {
                match self {
                    $(Config::$variant(_) => IntegratorChoice::$variant,)*
                }
            }

            /// `max_depth` as the integrator counts it (−1: no bound), as
            /// reports show it.
            pub fn depth(&self) -> i64 {
                match self {
                    $(Config::$variant(s) => <$model as IntegratorModel>::depth(s),)*
                }
            }

            /// The thesis's acceleration metrics, if on.
            pub fn metric(&self) -> Option<Metric> {
                match self {
                    $(Config::$variant(s) => <$model as IntegratorModel>::metric(s),)*
                }
            }

            /// Passes the render is made in.
            pub fn passes(&self) -> u32 {
                match self {
                    $(Config::$variant(s) => <$model as IntegratorModel>::passes(s),)*
                }
            }

            /// The names of the channels it writes beside the image
            /// (Mitsuba's AOVs, in Mitsuba's order; none for most): what a
            /// caller checks its output can hold before it renders.
            pub fn channels(&self) -> Vec<String> {
                match self {
                    $(Config::$variant(s) => <$model as IntegratorModel>::channels(s),)*
                }
            }

            /// Makes the integrator for `scene` and hands it to `run`.
            pub fn render_with<R: RenderWith>(self, scene: &Scene, run: R) -> R::Output {
                match self {
                    $(Config::$variant(s) => <$model as IntegratorModel>::render_with(scene, s, run),)*
                }
            }
        }
    };
}

integrators! {
    images {
        Whitted => WhittedPlugin,
        Path => PathPlugin,
        Direct => DirectPlugin,
        Distributed => DistributedPlugin,
        Volpath => VolpathPlugin,
        Volpathmis => VolpathmisPlugin,
        Ptracer => PtracerPlugin,
        Depth => DepthPlugin,
    }
    holders {
        Aov => AovPlugin<HeldConfig>,
        Moment => MomentPlugin<HeldConfig>,
    }
}

impl Config {
    /// The integrator `scene` describes.
    pub fn of(scene: &Scene) -> Result<Config, Invalid> {
        Config::read(&scene.integrator)
    }
}

/// The integrator node of a scene's tree: its `integrator` child, or
/// `whitted` with its defaults.
pub fn node_of(root: &Node) -> Node {
    root.child(Kind::Integrator).cloned().unwrap_or_else(|| {
        Node::new(
            Kind::Integrator,
            "whitted",
            Origin::unlocated(Default::default()),
        )
    })
}

impl SceneSource {
    /// Validates the description and builds the scene: the integrator it
    /// names reads its parameters first, then the scene is built
    /// ([`SceneSource::build_scene`]).
    pub fn build(&self) -> Result<Scene, SceneError> {
        Config::read(&node_of(&self.root))?;
        self.build_scene(None)
    }

    /// [`build`](Self::build), reusing a world from `worlds` built from the
    /// same geometry (objects, light shapes, material names, mesh files), and
    /// keeping a newly built one there: for many renders of one scene with
    /// other settings. The scene is the same as [`build`](Self::build) gives,
    /// errors included.
    pub fn build_reusing(&self, worlds: &mut WorldCache) -> Result<Scene, SceneError> {
        Config::read(&node_of(&self.root))?;
        self.build_scene(Some(worlds))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scene's choices are the integrators listed, in the list's order,
    /// under their schemas' names.
    #[test]
    fn choices_are_the_integrators_listed() {
        assert_eq!(SCHEMAS.len(), IntegratorChoice::ALL.len());
        for (choice, schema) in IntegratorChoice::ALL.into_iter().zip(SCHEMAS) {
            assert_eq!(choice.name(), schema.plugin);
            assert_eq!(IntegratorChoice::from_name(schema.plugin), Some(choice));
        }
    }
}
