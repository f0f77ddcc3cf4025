//! `depth`, `aov` and `moment` as plugins: their schemas, the settings
//! they are read into (the integrator a holder holds, read through
//! `Nested`), and the renders they make.

use std::marker::PhantomData;

use super::{Aov, AovSpec, Depth, Moment};
use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Kind, Node, Param, Props, Schema, Type};
use crate::integrator::interface::Integrator;
use crate::integrator::metric::Metric;
use crate::integrator::model::{IntegratorModel, Nested, RenderWith};
use crate::scene::Scene;

/// The name Mitsuba gives a held integrator that has none: its first
/// unnamed child's.
pub const UNNAMED: &str = "_arg_0";

/// `depth` has no parameters.
pub const DEPTH: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "depth",
    what: "depth integrator",
    doc: "the distance to the first hit along each camera ray",
    mitsuba: &["depth"],
    params: &[],
};

/// `aov`: the variables, and the integrator it may hold (a child).
pub const AOV: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "aov",
    what: "aov integrator",
    doc: "variables of the first hit (depth, normals, uv, …) as channels beside a held \
          integrator's image",
    mitsuba: &["aov"],
    params: &[Param::new(
        "aovs",
        Type::String,
        "\"\"",
        "the variables, `name:type` pairs separated by commas: types `albedo`, `depth`, \
         `position`, `uv`, `geo_normal`, `sh_normal`, `dp_du`, `dp_dv`, `duv_dx`, `duv_dy`, \
         `prim_index`, `shape_index`",
    )],
};

/// `moment`: only the integrator it holds (a child).
pub const MOMENT: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "moment",
    what: "moment integrator",
    doc: "a held integrator's image with the first and second moments of its samples as \
          channels",
    mitsuba: &["moment"],
    params: &[],
};

/// The three schemas, which the scene-format reference documents one by
/// one (their keys are not render options).
pub const SCHEMAS: [&Schema; 3] = [&DEPTH, &AOV, &MOMENT];

/// How Mitsuba 3's `depth`, `aov` and `moment` map onto Penumbra's: their
/// parameters under the same names; the integrators `aov` and `moment`
/// hold are read as their children (`render.nested`).
pub const PLUGINS: [Plugin; 3] = [
    Plugin::new(&DEPTH, Mitsuba::SAME),
    Plugin::new(
        &AOV,
        Mitsuba::differs(
            "one held integrator (Mitsuba takes several); `prim_index` is 0 on analytic shapes",
        ),
    ),
    Plugin::new(
        &MOMENT,
        Mitsuba::differs("one held integrator (Mitsuba takes several)"),
    ),
];

/// The integrator a holder holds, and its name (its channels' prefix).
#[derive(Clone, Debug, PartialEq)]
pub struct Held<C> {
    pub name: String,
    pub config: Box<C>,
}

impl<C: Nested> Held<C> {
    /// The integrator `node` holds: its one integrator child, named by its
    /// id ([`UNNAMED`] without one); `None` without a child. Two
    /// children are refused, and so is a holder ([`Nested::read`]).
    fn of(node: &Node) -> Result<Option<Held<C>>, Invalid> {
        let mut children = node.children.iter().filter(|c| c.kind == Kind::Integrator);
        let Some(child) = children.next() else {
            return Ok(None);
        };
        if let Some(second) = children.next() {
            return Err(Invalid::at(
                &second.origin,
                format!(
                    "a second integrator inside `{}`: Penumbra's holds one",
                    node.plugin
                ),
            ));
        }
        Ok(Some(Held {
            name: child.id.clone().unwrap_or_else(|| UNNAMED.to_string()),
            config: Box::new(C::read(child)?),
        }))
    }
}

/// The `depth` integrator as a plugin.
pub struct DepthPlugin;

impl IntegratorModel for DepthPlugin {
    const SCHEMA: &'static Schema = &DEPTH;
    type Settings = ();

    fn read(_: &Props) -> Result<(), Invalid> {
        Ok(())
    }

    fn depth(_: &()) -> i64 {
        1
    }

    fn metric(_: &()) -> Option<Metric> {
        None
    }

    fn passes(_: &()) -> u32 {
        1
    }

    fn render_with<R: RenderWith>(scene: &Scene, _: (), run: R) -> R::Output {
        run.render(&Depth::new(scene))
    }
}

/// The settings of `aov`: its variables and the integrator it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct AovSettings<C> {
    pub spec: AovSpec,
    pub held: Option<Held<C>>,
}

/// The `aov` integrator as a plugin, holding any of the plugins `C`.
pub struct AovPlugin<C>(PhantomData<C>);

impl<C: Nested> IntegratorModel for AovPlugin<C> {
    const SCHEMA: &'static Schema = &AOV;
    type Settings = AovSettings<C>;

    fn read(p: &Props) -> Result<AovSettings<C>, Invalid> {
        let spec = match p.string("aovs")? {
            Some(s) => AovSpec::parse(s).map_err(|e| p.error("aovs", e))?,
            None => AovSpec::default(),
        };
        Ok(AovSettings { spec, held: None })
    }

    /// Without variables or a held integrator it renders black and
    /// writes no channel, as Mitsuba's (which warns).
    fn read_node(node: &Node, p: &Props) -> Result<AovSettings<C>, Invalid> {
        let held = Held::of(node)?;
        Ok(AovSettings {
            held,
            ..Self::read(p)?
        })
    }

    fn depth(s: &AovSettings<C>) -> i64 {
        s.held.as_ref().map_or(1, |h| h.config.depth())
    }

    fn metric(s: &AovSettings<C>) -> Option<Metric> {
        s.held.as_ref().and_then(|h| h.config.metric())
    }

    fn passes(s: &AovSettings<C>) -> u32 {
        s.held.as_ref().map_or(1, |h| h.config.passes())
    }

    fn channels(s: &AovSettings<C>) -> Vec<String> {
        super::channel_names(s.held.as_ref().map(|h| h.name.as_str()), &s.spec)
    }

    fn render_with<R: RenderWith>(scene: &Scene, s: AovSettings<C>, run: R) -> R::Output {
        match s.held {
            Some(held) => held.config.render_with(
                scene,
                WithAov {
                    run,
                    scene,
                    spec: s.spec,
                    name: held.name,
                },
            ),
            None => run.render(&Aov::<Depth>::new(scene, None, s.spec)),
        }
    }
}

/// A render of the held integrator wrapped in `aov`.
struct WithAov<'a, R> {
    run: R,
    scene: &'a Scene,
    spec: AovSpec,
    name: String,
}

impl<R: RenderWith> RenderWith for WithAov<'_, R> {
    type Output = R::Output;

    fn render<I: Integrator>(self, inner: &I) -> R::Output {
        let aov = Aov::new(self.scene, Some((inner, &self.name)), self.spec);
        self.run.render(&aov)
    }
}

/// The settings of `moment`: the integrator it holds (without one it
/// renders black and writes no channel, as Mitsuba's).
#[derive(Clone, Debug, PartialEq)]
pub struct MomentSettings<C> {
    pub held: Option<Held<C>>,
}

/// The `moment` integrator as a plugin, holding any of the plugins `C`.
pub struct MomentPlugin<C>(PhantomData<C>);

impl<C: Nested> IntegratorModel for MomentPlugin<C> {
    const SCHEMA: &'static Schema = &MOMENT;
    type Settings = MomentSettings<C>;

    fn read(_: &Props) -> Result<MomentSettings<C>, Invalid> {
        Ok(MomentSettings { held: None })
    }

    fn read_node(node: &Node, _: &Props) -> Result<MomentSettings<C>, Invalid> {
        Ok(MomentSettings {
            held: Held::of(node)?,
        })
    }

    fn depth(s: &MomentSettings<C>) -> i64 {
        s.held.as_ref().map_or(1, |h| h.config.depth())
    }

    fn metric(s: &MomentSettings<C>) -> Option<Metric> {
        s.held.as_ref().and_then(|h| h.config.metric())
    }

    fn passes(s: &MomentSettings<C>) -> u32 {
        s.held.as_ref().map_or(1, |h| h.config.passes())
    }

    fn channels(s: &MomentSettings<C>) -> Vec<String> {
        s.held
            .as_ref()
            .map_or_else(Vec::new, |h| super::moment::channel_names(&h.name))
    }

    fn render_with<R: RenderWith>(scene: &Scene, s: MomentSettings<C>, run: R) -> R::Output {
        match s.held {
            Some(held) => {
                let name = held.name;
                held.config.render_with(scene, WithMoment { run, name })
            }
            None => run.render(&Aov::<Depth>::new(scene, None, AovSpec::default())),
        }
    }
}

/// A render of the held integrator wrapped in `moment`.
struct WithMoment<R> {
    run: R,
    name: String,
}

impl<R: RenderWith> RenderWith for WithMoment<R> {
    type Output = R::Output;

    fn render<I: Integrator>(self, inner: &I) -> R::Output {
        self.run.render(&Moment::new(inner, &self.name))
    }
}
