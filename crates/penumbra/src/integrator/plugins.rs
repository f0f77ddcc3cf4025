//! The integrators as plugins. Each integrator's schema and settings sit
//! beside it (`whitted/config.rs`, `path/config.rs`); this file lists
//! them (and, for the Mitsuba reader, the [`registry`] of every plugin),
//! reads the integrator a scene describes into its settings, and
//! builds scenes so that a bad integrator parameter is refused at its place
//! when the scene is built.
//!
//! The scene keeps its integrator's description ([`Scene::integrator`]),
//! as pbrt-v4's scene keeps its integrator's parameters: the scene sits
//! below the integrators, which read it. [`Config::read`] reads the
//! description into the integrator's own settings, when the scene is built
//! (to check it) and when a render starts.

use super::metric::Metric;
use super::path::{self, PathSettings, Variant};
use super::whitted::{self, WhittedSettings};
use crate::description::mitsuba::Plugin;
use crate::description::{self, Invalid, Kind, Node, Origin, Props, SceneError, Schema};
use crate::scene::{schemas, IntegratorChoice, Scene, SceneSource, WorldCache};

/// The schemas of the integrators, in the order of [`IntegratorChoice::ALL`].
pub const SCHEMAS: [&Schema; 4] = [
    &whitted::SCHEMA,
    &path::PATH,
    &path::DIRECT,
    &path::DISTRIBUTED,
];

/// Every plugin as the Mitsuba reader sees it: the integrators Mitsuba 3
/// has (`path`, `direct`) and the scene's plugins of every other kind
/// ([`schemas::plugins`]). The scene layer, below the integrators, cannot
/// name them: readers of Mitsuba scenes take this registry.
pub fn registry(kind: Kind) -> &'static [Plugin] {
    match kind {
        Kind::Integrator => &path::PLUGINS,
        _ => schemas::plugins(kind),
    }
}

/// An integrator and its settings, read from its description.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Config {
    Whitted(WhittedSettings),
    /// `path`, `direct` or `distributed`: the path tracer's wavefront.
    Path(Variant, PathSettings),
}

impl Config {
    /// The integrator `node` describes (checked against its schema: its
    /// name known, each key its own and of its type) with its settings.
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
        let schema = SCHEMAS[choice as usize];
        let others: Vec<&Schema> = SCHEMAS
            .iter()
            .copied()
            .filter(|o| o.plugin != schema.plugin)
            .collect();
        description::check(node, schema, &others)?;
        let p = Props::new(node);
        let config = match choice {
            IntegratorChoice::Whitted => Config::Whitted(WhittedSettings::read(&p)?),
            IntegratorChoice::Path => {
                Config::Path(Variant::Path, PathSettings::read(Variant::Path, &p)?)
            }
            IntegratorChoice::Direct => {
                Config::Path(Variant::Direct, PathSettings::read(Variant::Direct, &p)?)
            }
            IntegratorChoice::Distributed => Config::Path(
                Variant::Distributed,
                PathSettings::read(Variant::Distributed, &p)?,
            ),
        };
        p.finish("integrator")?;
        Ok(config)
    }

    /// The integrator `scene` describes.
    pub fn of(scene: &Scene) -> Result<Config, Invalid> {
        Config::read(&scene.integrator)
    }

    /// Which integrator it is.
    pub fn choice(&self) -> IntegratorChoice {
        match self {
            Config::Whitted(_) => IntegratorChoice::Whitted,
            Config::Path(Variant::Path, _) => IntegratorChoice::Path,
            Config::Path(Variant::Direct, _) => IntegratorChoice::Direct,
            Config::Path(Variant::Distributed, _) => IntegratorChoice::Distributed,
        }
    }

    /// `max_depth` as the integrator counts it (−1: no bound), as reports
    /// show it.
    pub fn depth(&self) -> i64 {
        match self {
            Config::Whitted(w) => i64::from(w.max_depth),
            Config::Path(_, p) => p.max_depth.map_or(-1, i64::from),
        }
    }

    /// The thesis's acceleration metrics, if on.
    pub fn metric(&self) -> Option<Metric> {
        match self {
            Config::Whitted(w) => w.metric,
            Config::Path(_, p) => p.metric,
        }
    }

    /// Passes the render is made in.
    pub fn passes(&self) -> u32 {
        match self {
            Config::Whitted(w) => w.passes,
            Config::Path(_, p) => p.passes,
        }
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
