//! Shapes and their intersection routines, and rigid motion over the shutter.

pub mod cube;
pub mod cylinder;
pub mod disk;
pub mod instance;
pub mod interaction;
pub mod mesh;
pub mod mesh_file;
pub mod motion;
pub mod quad;
pub mod shape;
pub mod sphere;
pub mod surface;
pub mod tessellate;
pub mod triangle;

pub use cylinder::Cylinder;
pub use interaction::{shading_frame, LocalGeometry, SurfaceInteraction};
pub use mesh::Mesh;
pub use motion::{Motion, Similarity};
pub use shape::{Shape, ShapeHit};
pub use surface::{Density, Place, ShapeSample, Surface, SurfaceError};
