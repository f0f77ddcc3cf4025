//! The scene description: a tree of plugins with typed properties, every
//! value carrying the file, line and column it came from.

mod document;
pub mod error;
pub mod lower;
mod nesting;
pub mod props;
pub mod source;
pub mod tree;

pub use error::{Invalid, KeyPath, KeySeg, Location, Origin, SceneError};
pub use lower::{from_json, from_toml, RENDER_KEYS};
pub use props::{Props, Scale};
pub use source::Source;
pub use tree::{Kind, Located, Node, Prop, Value};
