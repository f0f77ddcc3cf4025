//! Acceleration: the four-wide bounding volume hierarchy ([`Bvh4`]) with its
//! one traversal kernel, the triangle packets of meshes ([`TriangleBvh`]),
//! the scene's two levels of it ([`World`]), and shafts around shadow sets.
//! Each query of the world (and each batch call of a mesh) enters the code
//! of the kernel set in use once ([`crate::simd`]): everything it runs is
//! inlined below that entry point, so that it compiles for the set's
//! instructions.

#[cfg(test)]
mod brute;
mod build;
pub mod bvh4;
pub mod shaft;
#[cfg(test)]
mod testdata;
pub mod tri;
pub mod world;

pub use bvh4::{Bvh4, LeafSet, RayPacket};
pub use shaft::Shaft;
pub use tri::{TriHit, TriStats, TriangleBvh};
pub use world::{Crossing, Hit, HitRef, Hits, Object, PacketScratch, ShaftSet, World};
