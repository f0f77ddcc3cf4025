//! Files in and out: mesh readers (PLY, OBJ) and image writers (PNG, EXR).

pub mod mesh;
pub mod obj;
pub mod output;
pub mod ply;

pub use mesh::{read_mesh, Location, MeshData, MeshError};
