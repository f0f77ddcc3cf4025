//! What every integrator implements as a plugin ([`IntegratorModel`]):
//! its name and schema, the settings its parameters are read into, what
//! reports show of them, and the integrator that renders with them.

use std::fmt::Debug;

use crate::description::{Invalid, Props, Schema};
use crate::scene::Scene;

use super::interface::Integrator;
use super::metric::Metric;

/// An integrator as a plugin (see the [`plugins`](super::plugins) list).
pub trait IntegratorModel {
    /// Its parameters (its name, scenes select it by, among them).
    const SCHEMA: &'static Schema;

    /// The settings its parameters are read into.
    type Settings: Clone + Copy + Debug + PartialEq;

    /// The integrator that renders with them.
    type Integrator: Integrator;

    /// The settings of the parameters `p` (checked against the schema
    /// already).
    fn read(p: &Props) -> Result<Self::Settings, Invalid>;

    /// `max_depth` as the integrator counts it (−1: no bound), as reports
    /// show it.
    fn depth(s: &Self::Settings) -> i64;

    /// The thesis's acceleration metrics, if on.
    fn metric(s: &Self::Settings) -> Option<Metric>;

    /// Passes the render is made in.
    fn passes(s: &Self::Settings) -> u32;

    /// The integrator of settings `s` for `scene`.
    fn integrator(scene: &Scene, s: Self::Settings) -> Self::Integrator;
}
