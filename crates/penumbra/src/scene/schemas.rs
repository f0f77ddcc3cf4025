//! Every plugin a scene may name, by kind, and the check of a scene's tree
//! against their schemas when it is loaded: each plugin's name known, each
//! key its plugin's, each value of its type (see
//! [`description::check`](crate::description::check())). Integrators sit
//! above the scene and check their own node (`integrator::plugins`) when
//! the scene is built.

use super::{camera, filters, lights, settings, shapes};
use crate::bsdf::Bsdf;
use crate::description::mitsuba::Plugin;
use crate::description::{self, Invalid, Kind, Node, Schema};
use crate::emitter::{self, area};
use crate::medium::{Medium, Phase};
use crate::texture::Texture;
use crate::volume::Volume;

/// The plugins of a kind a scene names by itself.
pub fn of(kind: Kind) -> &'static [&'static Schema] {
    match kind {
        Kind::Scene => &[],
        Kind::Texture => Texture::SCHEMAS,
        Kind::Volume => Volume::SCHEMAS,
        Kind::Integrator => &[],
        Kind::Sensor => &[&camera::PERSPECTIVE],
        Kind::Film => &[&settings::FILM],
        // A film's filter is its keys.
        Kind::Filter => &[],
        Kind::Sampler => &[&settings::SAMPLER],
        Kind::Bsdf => Bsdf::SCHEMAS,
        Kind::Shape => shapes::SCHEMAS,
        Kind::Emitter => emitter::SCHEMAS,
        Kind::Medium => Medium::SCHEMAS,
        // A medium's.
        Kind::Phase => &[],
    }
}

/// The `area` emitter a shape carries.
pub fn area_schema() -> &'static Schema {
    &area::SCHEMA
}

/// The plugins of a kind as the Mitsuba reader sees them: the kinds it maps
/// through their schemas but the integrators, which sit above the scene
/// (`integrator::plugins::registry` adds them).
pub fn plugins(kind: Kind) -> &'static [Plugin] {
    match kind {
        Kind::Sensor => &camera::PLUGINS,
        Kind::Film => &settings::FILM_PLUGINS,
        Kind::Filter => &filters::PLUGINS,
        Kind::Sampler => &settings::SAMPLER_PLUGINS,
        Kind::Bsdf => Bsdf::PLUGINS,
        Kind::Texture => Texture::PLUGINS,
        Kind::Volume => Volume::PLUGINS,
        Kind::Shape => shapes::PLUGINS,
        Kind::Emitter => emitter::PLUGINS,
        Kind::Medium => Medium::PLUGINS,
        Kind::Phase => Phase::PLUGINS,
        Kind::Scene | Kind::Integrator => &[],
    }
}

/// The plugins a node of `kind` may hold as its children, of kind `child`:
/// the scene's are [`of`] their kind, the sensor's its film and sampler,
/// a shape's the `area` emitter it carries, a medium's its phase function.
fn children(parent: Kind, child: Kind) -> &'static [&'static Schema] {
    match (parent, child) {
        (Kind::Scene, kind) => of(kind),
        (Kind::Sensor, Kind::Film | Kind::Sampler) => of(child),
        (Kind::Shape, Kind::Emitter) => &[&area::SCHEMA],
        // The shapes of a group.
        (Kind::Shape, Kind::Shape) => of(Kind::Shape),
        (Kind::Medium, Kind::Phase) => Phase::SCHEMAS,
        _ => &[],
    }
}

/// What messages call a plugin of a kind when its name is not known.
fn what(kind: Kind) -> &'static str {
    match kind {
        Kind::Shape => "object type",
        Kind::Emitter => "light type",
        Kind::Bsdf => "material type",
        Kind::Integrator => "integrator",
        Kind::Sensor => "sensor",
        Kind::Film => "film",
        Kind::Filter => "pixel filter",
        Kind::Sampler => "sampler",
        Kind::Texture => "texture",
        Kind::Volume => "volume",
        Kind::Medium => "medium type",
        Kind::Phase => "phase function",
        Kind::Scene => "scene",
    }
}

/// The schema of a node's plugin (a child of the scene), or the error that
/// names the plugins of its kind.
pub fn schema(node: &Node) -> Result<&'static Schema, Invalid> {
    schema_in(Kind::Scene, node)
}

/// [`schema`] for a child of a node of kind `parent`.
pub(crate) fn schema_in(parent: Kind, node: &Node) -> Result<&'static Schema, Invalid> {
    let all = children(parent, node.kind);
    all.iter()
        .find(|s| s.plugin == node.plugin)
        .copied()
        .ok_or_else(|| {
            let mut names: Vec<&str> = all.iter().map(|s| s.plugin).collect();
            if (parent, node.kind) == (Kind::Scene, Kind::Emitter) {
                // A light of a shape's type is lowered to that shape.
                names.extend(lights::shape_types());
            }
            Invalid::at(
                &node.plugin_origin,
                format!(
                    "unknown {} `{}`; valid choices are: {}",
                    what(node.kind),
                    node.plugin,
                    names.join(", ")
                ),
            )
        })
}

/// Checks every node of the tree below `root` against its plugin's schema,
/// but for the integrator's.
pub fn check(root: &Node) -> Result<(), Invalid> {
    for node in root.children.iter().filter(|c| c.kind != Kind::Integrator) {
        let s = schema_in(root.kind, node)?;
        let others: Vec<&Schema> = children(root.kind, node.kind)
            .iter()
            .copied()
            .filter(|o| o.plugin != s.plugin)
            .collect();
        description::check(node, s, &others)?;
        check(node)?;
    }
    Ok(())
}
