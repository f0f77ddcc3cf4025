//! Scenes: parse → plain description (with source positions) → validation →
//! immutable [`Scene`].
//!
//! A scene file and a built-in scene go through exactly the same path; see
//! `docs/scene-format.md` for the format.

mod build;
pub mod builtin;
mod check;
pub mod desc;
pub mod error;
mod load;
pub mod options;
mod overrides;
mod reuse;
pub mod source;
pub mod world;

use std::sync::Arc;
use std::time::Duration;

pub use build::BuildContext;
pub use desc::SceneDesc;
pub use error::SceneError;
pub use load::{default_bunny_path, LoadOptions, SceneSource};
pub use options::{Choices, RenderOption, OPTIONS};
pub use overrides::Overrides;
pub use reuse::WorldCache;

use crate::camera::Camera;
use crate::integrator::Metric;
use crate::light::Light;
use crate::material::{Material, Rgb};
use crate::sampling::Distribution;
use world::World;

/// Image-wide settings after validation.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Levels of reflection/refraction rays (the thesis's recursion depth).
    pub max_depth: u32,
    pub seed: u64,
    pub background: Rgb,
    /// Primary rays per pixel.
    pub spp: u32,
    pub pixel: Distribution,
    pub lens: Distribution,
    pub time: Distribution,
    /// The acceleration metrics, if on.
    pub metric: Option<Metric>,
}

/// A validated scene ready to render. Immutable: rendering only reads it.
pub struct Scene {
    pub camera: Camera,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    /// The geometry and its BVH; shared with other scenes built from the
    /// same geometry through a [`WorldCache`].
    pub world: Arc<World>,
    pub settings: Settings,
    /// Per-material transparency, for shadow rays.
    pub transparency: Vec<f32>,
    /// Things worth telling the user once (non-square ray counts).
    pub warnings: Vec<String>,
    /// Time to validate the scene, load meshes and build the BVH.
    pub build_time: Duration,
}
