//! The scene description: a tree of plugins with typed properties, every
//! value carrying the file, line and column it came from.

pub mod error;
pub mod source;
pub mod tree;

pub use error::{Invalid, KeyPath, KeySeg, Location, Origin, SceneError};
pub use source::Source;
pub use tree::{Kind, Located, Node, Prop, Value};
