//! What every integrator implements as a plugin ([`IntegratorModel`]):
//! its name and schema, the settings its parameters are read into, what
//! reports show of them, and the render it makes with them; and what an
//! integrator holding another reads it as ([`Nested`]).

use std::fmt::Debug;

use crate::description::{Invalid, Kind, Node, Props, Schema};
use crate::scene::Scene;

use super::interface::Integrator;
use super::metric::Metric;

/// What a caller does with the integrator a plugin's settings make
/// ([`IntegratorModel::render_with`]): a render, generic over the
/// integrator.
pub trait RenderWith {
    type Output;

    fn render<I: Integrator>(self, integrator: &I) -> Self::Output;
}

/// An integrator as a plugin (see the [`plugins`](super::plugins) list).
pub trait IntegratorModel {
    /// Its parameters (its name, scenes select it by, among them).
    const SCHEMA: &'static Schema;

    /// The settings its parameters are read into.
    type Settings: Clone + Debug + PartialEq;

    /// The settings of the parameters `p` (checked against the schema
    /// already).
    fn read(p: &Props) -> Result<Self::Settings, Invalid>;

    /// The settings of `node`, its parameters `p`: [`read`](Self::read),
    /// unless the plugin also reads the node's children (an integrator it
    /// holds).
    fn read_node(node: &Node, p: &Props) -> Result<Self::Settings, Invalid> {
        holds_none(node)?;
        Self::read(p)
    }

    /// `max_depth` as the integrator counts it (−1: no bound), as reports
    /// show it.
    fn depth(s: &Self::Settings) -> i64;

    /// The thesis's acceleration metrics, if on.
    fn metric(s: &Self::Settings) -> Option<Metric>;

    /// Passes the render is made in.
    fn passes(s: &Self::Settings) -> u32;

    /// The names of the channels it writes beside the image (Mitsuba's
    /// AOVs, in Mitsuba's order): none unless it writes some.
    fn channels(_s: &Self::Settings) -> Vec<String> {
        Vec::new()
    }

    /// Makes the integrator of settings `s` for `scene` and hands it to
    /// `run`.
    fn render_with<R: RenderWith>(scene: &Scene, s: Self::Settings, run: R) -> R::Output;
}

/// An integrator held by another (`aov`, `moment`): any of the plugins,
/// read from its node and rendered through. The list of plugins
/// ([`Config`](super::Config)) is one; the holders are generic over it, so
/// that they need not name the list that names them.
pub trait Nested: Clone + Debug + PartialEq {
    /// The integrator `node` describes, with its settings.
    fn read(node: &Node) -> Result<Self, Invalid>;

    /// Its name, as scenes select it.
    fn plugin(&self) -> &'static str;

    fn depth(&self) -> i64;

    fn metric(&self) -> Option<Metric>;

    fn passes(&self) -> u32;

    /// Makes the integrator for `scene` and hands it to `run`.
    fn render_with<R: RenderWith>(self, scene: &Scene, run: R) -> R::Output;
}

/// The error for an integrator child of a plugin that holds none.
pub fn holds_none(node: &Node) -> Result<(), Invalid> {
    match node.children.iter().find(|c| c.kind == Kind::Integrator) {
        Some(child) => Err(Invalid::at(
            &child.origin,
            format!(
                "the `{}` integrator holds no integrator (`aov` and `moment` do)",
                node.plugin
            ),
        )),
        None => Ok(()),
    }
}
