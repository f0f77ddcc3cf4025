//! Scenes: parse → plain description (with source positions) → validation →
//! immutable [`Scene`].
//!
//! A scene file and a built-in scene go through exactly the same path; see
//! `docs/scene-format.md` for the format.

mod arity;
mod build;
pub mod builtin;
mod check;
mod context;
pub mod desc;
pub mod error;
mod load;
mod nesting;
pub mod options;
mod overrides;
pub mod points;
mod ray_sets;
mod reuse;
mod settings;
pub mod source;

use std::sync::Arc;
use std::time::Duration;

pub use build::BuildContext;
pub use desc::SceneDesc;
pub use error::SceneError;
pub use load::{default_bunny_path, LoadOptions, SceneSource, MAX_SCENE_FILE_SIZE};
pub use options::{Choices, RenderOption, OPTIONS};
pub use overrides::Overrides;
pub use points::{read_points, Points, PointsFileError};
pub use reuse::WorldCache;
pub use settings::{Metric, Settings, StopRule, Stopping};

use crate::accel::World;
use crate::bsdf::Bsdf;
use crate::camera::Camera;
use crate::emitter::Emitter;
pub use crate::sampling::EffectSpec;

/// A validated scene ready to render. Immutable: rendering only reads it.
pub struct Scene {
    pub camera: Camera,
    /// The scattering models, by material index (hits name theirs).
    pub bsdfs: Vec<Bsdf>,
    /// The emitters: the lights in the order of the scene, then the
    /// emitting objects', then those at infinity.
    pub emitters: Vec<Emitter>,
    /// The geometry and its BVH; shared with other scenes built from the
    /// same geometry through a [`WorldCache`].
    pub world: Arc<World>,
    pub settings: Settings,
    /// Per-material fraction of light a shadow ray keeps crossing it.
    pub transparency: Vec<f32>,
    /// Things worth telling the user once (non-square ray counts).
    pub warnings: Vec<String>,
    /// Time to validate the scene, load meshes and build the BVH.
    pub build_time: Duration,
}

impl Scene {
    /// The sizes of the sets the render draws from the `custom`
    /// distribution, smallest first, each once: what a table made by a
    /// function (Python's `points=`) is asked for.
    pub fn custom_set_sizes(&self) -> Vec<u32> {
        let sets = ray_sets::custom_sets(&self.settings, &self.bsdfs, &self.emitters);
        let mut sizes: Vec<u32> = sets.into_iter().map(|(_, n)| n).collect();
        sizes.sort_unstable();
        sizes.dedup();
        sizes
    }
}
