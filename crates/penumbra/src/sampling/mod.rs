//! Random numbers, the thesis's ray distributions and the warps that map them
//! onto pixels, lenses, lights and directions.

pub mod bilinear2d;
#[cfg(test)]
mod checks;
pub mod custom;
pub mod discrete;
pub mod distribution;
pub mod filter;
pub mod halton;
pub mod linear1d;
mod order;
pub mod path_sampler;
pub mod piecewise2d;
pub mod pmj02;
pub mod pmj02bn;
pub mod points;
pub mod r2;
mod rng;
mod sampler;
pub mod sobol;
pub mod warp;
pub mod zsobol;

pub use bilinear2d::Bilinear2D;
pub use custom::PointTable;
pub use discrete::Discrete;
pub use distribution::{
    poisson_min_distance, poisson_min_distance_1d, shuffle, square_side, Distribution, Domain,
};
pub use filter::{Filter, FilterParams, PixelFilter};
pub use linear1d::Linear1D;
pub use path_sampler::{BounceNumbers, PathSampler};
pub use piecewise2d::Piecewise2D;
pub use points::{EffectSpec, SetPoint, MAX_RAYS};
pub use rng::{index_bits, mix64, BranchKey, Place, Rng};
pub use sampler::{Dimension, PixelSampler, Sampler};
