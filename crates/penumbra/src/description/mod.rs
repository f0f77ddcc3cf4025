//! The scene description: a tree of plugins with typed properties, every
//! value carrying the file, line and column it came from (the role of
//! Mitsuba 3's `Properties` and pbrt-v4's `ParameterDictionary`).
//!
//! Every input lowers into it: a TOML scene file ([`from_toml`]), a Python
//! dict through its JSON ([`from_json`]) and a Mitsuba 3 XML file
//! ([`mitsuba`]). One builder turns it into a scene. The description knows
//! the shape of a
//! scene file, not what any plugin means: nothing here depends on the
//! layers that build or render.
//!
//! # The tree
//!
//! A [`Node`] is one plugin: its [`Kind`] (the interface: shape, BSDF,
//! emitter…), its plugin name (`"sphere"`), an optional id (a material's
//! name), its [`Prop`]s and its children. After lowering, a scene is:
//!
//! ```text
//! scene "scene"
//! ├── integrator "whitted" (or render.integrator)
//! ├── sensor "perspective"               [camera]
//! │   ├── film "hdrfilm"
//! │   └── sampler "sets"
//! ├── emitter "constant"                 only if render.background is given
//! ├── texture <type> #NAME               one per [textures.NAME], in name order
//! ├── bsdf <type, else "thesis"> #NAME   one per [materials.NAME], in name order
//! ├── shape <type>                       one per [[objects]], in order
//! │   └── emitter <type, else "area">    its `emitter` table, if any
//! └── emitter <type>                     one per [[lights]], in order
//! ```
//!
//! A property's [`Value`] is what the input wrote: a boolean, an integer, a
//! float, a string, an array, a table (a transform, or a texture with its
//! `type` and parameters), or a TOML datetime
//! (which no reader accepts). Nothing is converted, checked or defaulted
//! in the tree.
//!
//! # Origins
//!
//! Every node, key and value has an [`Origin`]: the key path the user
//! wrote (`objects[1].transform.scale`, `materials.glass.ior`, and
//! `render.width` even though the width is a property of the film) and, for
//! a file, the [`Location`] (line and column, in characters) of its first
//! character: a value's is where the value starts, a key's where the key
//! does, a table's its header (or its first key, for a dotted one). A node
//! takes the origin of its table: the film, sampler and integrator that of
//! `[render]`, the sensor that of `[camera]` (the root's when there is
//! none, line 1 column 1), an object `objects[i]`, the background emitter
//! the key `render.background`. A dict's origins have paths and no
//! location. An [`Invalid`] at an origin becomes a [`SceneError`] printed
//! as `file:line:column: path: message`.
//!
//! # From a scene file to the tree
//!
//! The root's keys are `render`, `camera`, `textures`, `materials`,
//! `objects` and `lights`; any other is an error. A texture's keys are
//! properties of its node but `type`, its plugin, required. `[camera]`'s keys are all properties
//! of the sensor, a material's and an object's or light's of its node (but
//! `type`, the plugin, required for objects and lights). An object's
//! `emitter` table is the area emitter it carries: a child node of the
//! shape (its `type` defaults to `"area"`). [`write`](mod@write) turns a tree back
//! into a scene file. `[render]`'s keys
//! are routed by [`RENDER_KEYS`]:
//!
//! | `[render]` key | goes to |
//! |---|---|
//! | `width`, `height`, `filter` | the film |
//! | `spp`, `seed`, `distribution`, `pixel_distribution`, `lens_distribution`, `time_distribution`, `shadow_distribution`, `reflection_distribution`, `refraction_distribution`, `shadow_rays`, `reflection_rays`, `refraction_rays`, `points` | the sampler |
//! | `max_depth`, `metric`, `reflection_metric`, `shadow_metric`, `metric_threshold`, `metric_min_rays`, `shadow_metric_rays`, `pixel_metric`, `noise_threshold`, `stop_rule`, `confidence`, `replicas`, `noise_floor`, `min_spp`, `passes` | the integrator |
//! | `integrator` | the integrator's plugin name (a string; default `"whitted"`) |
//! | `background` | a `"constant"` emitter's `radiance` |
//!
//! # Reading and checking
//!
//! Two steps divide the work. When a scene is loaded, [`schema::check`]
//! holds each node to its plugin's [`Schema`]: every key known (or said
//! not to apply to this plugin), every value of the right type and shape,
//! tables key by key. Then the builder reads each node through [`Props`],
//! typed readers that give the same messages, leave ranges and defaults to
//! the builder, and remember what was read: [`Props::finish`] reports a
//! property a plugin accepts but never reads, a bug of the plugin rather
//! than the user's.

pub mod check;
mod document;
pub mod error;
pub mod lower;
pub mod mitsuba;
mod nesting;
pub mod placement;
pub mod props;
pub mod schema;
pub mod source;
pub mod tree;
pub mod write;

pub use error::{Invalid, KeyPath, KeySeg, Location, Origin, SceneError};
pub use lower::{from_json, from_toml, toml_to_json, INTEGRATOR_KEYS, RENDER_KEYS};
pub use props::{NumberOr, Props, Scale};
pub use schema::{
    check, checked_table, no_such_name, typed_table, MitsubaKey, Param, Range, Schema, Type,
};
pub use source::Source;
pub use tree::{Kind, Located, Node, Prop, Value};
pub use write::to_toml;
