//! Files in and out: mesh readers (PLY, OBJ) and image writers (PNG, EXR).

pub mod mesh;
pub mod output;
