//! The built scene: what a render reads.

use std::sync::Arc;
use std::time::Duration;

use super::ray_sets::{custom_sets, Budgets};
use super::settings::Settings;
use crate::accel::World;
use crate::bsdf::Bsdf;
use crate::camera::Camera;
use crate::description::Node;
use crate::emitter::Emitter;
use crate::medium::Medium;

/// No medium on that side of a shape (see [`Scene::object_media`]).
pub const NO_MEDIUM: u32 = u32::MAX;

/// A validated scene ready to render. Immutable: rendering only reads it.
pub struct Scene {
    pub camera: Camera,
    /// The scattering models, by material index (hits name theirs).
    pub bsdfs: Vec<Bsdf>,
    /// The emitters: the lights in the order of the scene, then the
    /// emitting objects', then those at infinity.
    pub emitters: Vec<Emitter>,
    /// The emitters at infinity (`constant`, `envmap`), which rays that
    /// hit nothing see, by index into `emitters`: the one list every
    /// integrator reads.
    pub far: Vec<u32>,
    /// The sets of rays the description asks of each emitter and material
    /// (the thesis's per-light shadow sets and per-material ray sets), by
    /// index: what the integrators that trace those sets read.
    pub budgets: Budgets,
    /// The geometry and its BVH; shared with other scenes built from the
    /// same geometry through a [`WorldCache`](super::WorldCache).
    pub world: Arc<World>,
    /// The film's and the sampler's settings.
    pub settings: Settings,
    /// The integrator's description (its plugin name and parameters, with
    /// their places), which the integrator reads.
    pub integrator: Node,
    /// Per-material fraction of light a shadow ray keeps crossing it; NaN
    /// where it varies over the surface (read from the material at each
    /// crossing by the integrators' transparent shadows).
    pub transparency: Vec<f32>,
    /// The participating media, by index (the scene's `[media.NAME]`).
    pub media: Vec<Medium>,
    /// The media on either side of each object of the world, by object:
    /// `[interior, exterior]`, [`NO_MEDIUM`] where the shape names none.
    /// Only the volumetric integrators read them.
    pub object_media: Vec<[u32; 2]>,
    /// The medium the camera sits in.
    pub camera_medium: Option<u32>,
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
        let sets = custom_sets(&self.settings, &self.bsdfs, &self.budgets);
        let mut sizes: Vec<u32> = sets.into_iter().map(|(_, n)| n).collect();
        sizes.sort_unstable();
        sizes.dedup();
        sizes
    }
}
