//! Shapes (one file each, dispatched by [`Shape`]) and their intersection
//! routines, and rigid motion over the shutter.

pub mod cube;
pub mod cylinder;
pub mod disk;
pub mod instance;
pub mod interaction;
pub mod mesh;
pub mod mesh_file;
pub mod mesh_shape;
pub mod model;
pub mod motion;
pub mod quad;
pub mod shape;
pub mod sphere;
pub mod surface;
pub mod tessellate;
pub mod triangle;

pub use cylinder::Cylinder;
pub use disk::Disk;
pub use interaction::{shading_frame, LocalGeometry, SurfaceInteraction};
pub use mesh::Mesh;
pub use mesh_shape::MeshShape;
pub use model::{ShapeHit, ShapeModel};
pub use motion::{Motion, Similarity};
pub use quad::Quad;
pub use shape::Shape;
pub use sphere::Sphere;
pub use surface::{Density, Place, ShapeSample, Surface, SurfaceError};
