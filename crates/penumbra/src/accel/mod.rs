//! Acceleration structures: a binned-SAH bounding volume hierarchy, generic over
//! the primitive type through closures, and a brute-force oracle with the same
//! interface for tests.

pub mod brute;
mod build;
pub mod bvh;
pub mod bvh4;
pub mod shaft;
#[cfg(test)]
mod testdata;
pub mod tri;
pub mod world;

pub use brute::{brute_any, brute_closest};
pub use bvh::{BuildStats, Bvh};
pub use bvh4::{Bvh4, LeafSet, RayPacket};
pub use shaft::Shaft;
pub use tri::{TriHit, TriStats, TriangleBvh};
pub use world::{Hit, Object, PacketScratch, ShaftSet, World};
