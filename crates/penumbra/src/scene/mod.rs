//! Scenes: parse → plain description (with source positions) → validation →
//! immutable [`Scene`].
//!
//! A scene file and a built-in scene go through exactly the same path; see
//! `docs/scene-format.md` for the format.

mod build;
mod built;
pub mod builtin;
mod camera;
mod context;
pub mod convert;
mod error;
mod filters;
mod lights;
mod load;
pub mod options;
mod overrides;
pub mod points;
mod ray_sets;
pub mod reference;
mod reuse;
pub mod schemas;
mod settings;
mod shapes;
mod transform;

pub use crate::description::SceneError;
pub use build::{BuildError, INSTANCED_TRIANGLES, INSTANCING_FACTOR, MAX_PIXELS};
pub use built::{Scene, NO_MEDIUM};
pub use context::BuildContext;
pub use load::{default_bunny_path, LoadOptions, SceneSource, MAX_SCENE_FILE_SIZE};
pub(crate) use load::{is_xml, read_text};
pub use options::{Choices, RenderOption, OPTIONS};
pub use overrides::Overrides;
pub use points::{read_points, Points, PointsFileError};
pub use ray_sets::Budgets;
pub use reuse::WorldCache;
pub use settings::{Crop, IntegratorChoice, Sets, Settings, StopRule};

pub use crate::sampling::EffectSpec;
