//! What the Mitsuba reader knows of Penumbra's plugins: for each kind, every
//! plugin's [`Schema`] and how Mitsuba's plugin of that name maps onto it.
//!
//! The reader sits below the layers that define the plugins, so they hand
//! it a [`Registry`]: the integrator layer's (`integrator::plugins::registry`,
//! its integrators and the scene layer's `scene::schemas::plugins` for every
//! other kind). A plugin
//! whose Mitsuba counterpart means the same thing maps through its schema
//! alone: each parameter under Mitsuba's name for it
//! ([`Param::mitsuba_name`](crate::description::Param::mitsuba_name)), read
//! as its type says, a nested `<texture>` as the texturable parameter of
//! its name, nested `<bsdf>`s as the parameters naming materials, in
//! order. What Mitsuba means otherwise is said in the plugin's own file: a
//! line for the reference ([`Mitsuba::differences`]) and, where the
//! mapping is not the schema's, an [`Adapt`] that does it.

use std::rc::Rc;

use super::objects::{Object, Place};
use crate::description::error::{KeyPath, SceneError};
use crate::description::schema::Schema;
use crate::description::tree::{Kind, Node};

/// How Mitsuba's plugins of a Penumbra plugin's names map onto it.
#[derive(Clone, Copy, Debug)]
pub struct Mitsuba {
    /// What differs from Mitsuba's plugin, for the reference (empty where
    /// nothing does).
    pub differences: &'static str,
    /// The Mitsuba parameters [`adapt`](Self::adapt) reads beside the
    /// schema's.
    pub reads: &'static [&'static str],
    /// The mapping where it is not the schema's alone.
    pub adapt: Option<Adapt>,
}

impl Mitsuba {
    /// Mapped through the schema alone, the same as Mitsuba's.
    pub const SAME: Mitsuba = Mitsuba {
        differences: "",
        reads: &[],
        adapt: None,
    };

    /// Mapped through the schema alone; `differences` for the reference.
    pub const fn differs(differences: &'static str) -> Mitsuba {
        Mitsuba {
            differences,
            reads: &[],
            adapt: None,
        }
    }
}

/// A plugin's own part of the mapping.
#[derive(Clone, Copy, Debug)]
pub enum Adapt {
    /// Maps a Mitsuba object itself: `Some` with the name of what it made,
    /// `None` where the object maps through the schema after all.
    Object(fn(&mut dyn Mapper, &Object) -> Option<Result<String, SceneError>>),
    /// Completes the node the schema made of a Mitsuba object (at the key
    /// path `base`): the parameters whose meaning differs.
    Node(fn(&Object, &mut Node, &KeyPath) -> Result<(), SceneError>),
    /// Completes the node as [`Node`](Self::Node) does, asking the reader
    /// for what the object holds and telling it what the user should know.
    Held(fn(&mut dyn Mapper, &Object, &mut Node, &KeyPath) -> Result<(), SceneError>),
}

/// One plugin of a kind, as the reader sees it.
#[derive(Clone, Copy, Debug)]
pub struct Plugin {
    pub schema: &'static Schema,
    /// The Mitsuba plugins mapped so: the schema's, or some of them where
    /// they map each in its own way.
    pub names: &'static [&'static str],
    pub mitsuba: Mitsuba,
}

impl Plugin {
    /// The plugin of `schema`, each of the schema's Mitsuba names mapped
    /// as `mitsuba` says.
    pub const fn new(schema: &'static Schema, mitsuba: Mitsuba) -> Plugin {
        Plugin {
            schema,
            names: schema.mitsuba,
            mitsuba,
        }
    }

    /// The plugin of `schema` for Mitsuba's plugins `names` (some of the
    /// schema's), mapped as `mitsuba` says.
    pub const fn named(
        schema: &'static Schema,
        names: &'static [&'static str],
        mitsuba: Mitsuba,
    ) -> Plugin {
        Plugin {
            schema,
            names,
            mitsuba,
        }
    }

    /// True if Mitsuba's plugin `name` maps onto this one.
    pub fn reads(&self, name: &str) -> bool {
        self.names.contains(&name)
    }
}

/// Every plugin of a kind (none for a kind the reader maps by hand).
pub type Registry = fn(Kind) -> &'static [Plugin];

/// What an [`Adapt`] may ask of the reader.
pub trait Mapper {
    /// The objects `obj` holds, references resolved.
    fn held(&self, obj: &Object) -> Result<Vec<Rc<Object>>, SceneError>;

    /// Maps `inner`, a BSDF, through its schema as the material of `outer`
    /// (its id, name and place), with the Penumbra flag `flag` set true
    /// at `outer`'s type: the material's name.
    fn bsdf_as(
        &mut self,
        inner: &Object,
        outer: &Object,
        flag: &'static str,
    ) -> Result<String, SceneError>;

    /// The node of `obj`, an object of `kind` that another holds, through
    /// the plugin of that kind that reads it, at the key path `base`.
    fn node(&mut self, kind: Kind, obj: &Object, base: KeyPath) -> Result<Node, SceneError>;

    /// Maps `obj`, a medium (nested or declared with an id), into the
    /// scene's media once: its name there.
    fn medium(&mut self, obj: &Object) -> Result<String, SceneError>;

    /// Refuses a child of `obj`, which holds none.
    fn no_children(&self, obj: &Object) -> Result<(), SceneError>;

    /// Tells the user `message` once the scene is read.
    fn warn(&mut self, message: String);

    /// Sets the integrator's `path_sampler` to `name`, from the sampler
    /// written at `at`.
    fn path_sampler(&mut self, name: &'static str, at: &Place);
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::description::schema::{Param, Range, Type};

    const DIFFUSE: Schema = Schema {
        kind: Kind::Bsdf,
        plugin: "diffuse",
        what: "diffuse material",
        doc: "",
        mitsuba: &["diffuse"],
        params: &[Param::new("reflectance", Type::ColourTexture, "", "").range(Range::Unit)],
    };

    /// A plugin read by name only.
    const fn named(kind: Kind, names: &'static [&'static str]) -> Schema {
        Schema {
            kind,
            plugin: names[0],
            what: "",
            doc: "",
            mitsuba: names,
            params: &[],
        }
    }

    const SHAPES: Schema = named(Kind::Shape, &["sphere", "rectangle", "disk"]);
    const POINT: Schema = named(Kind::Emitter, &["point"]);
    const INTEGRATOR: Schema = named(Kind::Integrator, &["path", "direct"]);

    const BSDFS: &[Plugin] = &[Plugin::new(&DIFFUSE, Mitsuba::SAME)];
    const SHAPE_PLUGINS: &[Plugin] = &[Plugin::new(&SHAPES, Mitsuba::SAME)];
    const EMITTERS: &[Plugin] = &[Plugin::new(&POINT, Mitsuba::SAME)];
    const INTEGRATORS: &[Plugin] = &[Plugin::new(&INTEGRATOR, Mitsuba::SAME)];

    /// A registry of a few plugins (`diffuse`, shapes, a point light and
    /// the integrators known by name), for the reader's own tests.
    pub(crate) fn registry(kind: Kind) -> &'static [Plugin] {
        match kind {
            Kind::Bsdf => BSDFS,
            Kind::Shape => SHAPE_PLUGINS,
            Kind::Emitter => EMITTERS,
            Kind::Integrator => INTEGRATORS,
            _ => &[],
        }
    }
}
