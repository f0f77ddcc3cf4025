//! Reusing built worlds across builds of one scene with other settings.
//!
//! Loading the meshes and building the BVH is nearly all of a scene's build
//! (for the bunny, some 30 ms; for a million triangles, half a second), and
//! none of it depends on the ray budgets, distributions, metrics, image
//! size, camera or material parameters. A sweep over those (the evaluation
//! runner's tables, a Python loop over sample counts) can build the world
//! once: [`WorldCache`] keeps the last few, keyed by everything a world is
//! made from.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

use super::context::{resolve_mesh_path, BuildContext};
use super::desc::{LightDesc, SceneDesc};
use super::error::KeyPath;
use crate::accel::World;

/// Worlds kept by [`WorldCache::default`]: enough for a sweep that
/// alternates between a few scenes (the evaluation's bunny scenes, with and
/// without area lights) without holding meshes forever.
const DEFAULT_CAPACITY: usize = 4;

/// Built worlds, most recently used last, each under a key naming
/// everything it was made from (see `SceneSource::build_reusing`).
pub struct WorldCache {
    entries: Vec<(String, Arc<World>)>,
    capacity: usize,
}

impl Default for WorldCache {
    fn default() -> Self {
        WorldCache::new(DEFAULT_CAPACITY)
    }
}

impl WorldCache {
    /// A cache holding at most `capacity` worlds (at least one).
    pub fn new(capacity: usize) -> WorldCache {
        WorldCache {
            entries: Vec::new(),
            capacity: capacity.max(1),
        }
    }

    /// Worlds held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The world built under `key`, now the most recently used.
    pub(super) fn get(&mut self, key: &str) -> Option<Arc<World>> {
        let i = self.entries.iter().position(|(k, _)| k == key)?;
        let entry = self.entries.remove(i);
        let world = Arc::clone(&entry.1);
        self.entries.push(entry);
        Some(world)
    }

    /// Keeps `world` under `key`, dropping the least recently used if full.
    pub(super) fn insert(&mut self, key: String, world: Arc<World>) {
        self.entries.retain(|(k, _)| *k != key);
        if self.entries.len() >= self.capacity {
            self.entries.remove(0);
        }
        self.entries.push((key, world));
    }
}

/// Everything the world of `desc` is made from, as text: the objects, the
/// material names (objects refer to materials by their index in name order,
/// lights' surfaces to the one after the last) and which of them emit, the
/// lights' shapes, where
/// mesh paths point, and each mesh file's length and modification time (so
/// that a file rewritten between builds is read again). `None` when a mesh
/// path cannot be resolved or a file not examined: such a scene is built
/// afresh, which reports the error.
///
/// Debug formatting keeps every `f32` exactly (and tells NaN from infinity),
/// so equal keys mean equal inputs.
pub(super) fn key(desc: &SceneDesc, ctx: &BuildContext) -> Option<String> {
    let names: Vec<&String> = desc.materials.keys().collect();
    // Objects of an emitting material carry emitters, numbered in the world.
    let emitting: Vec<bool> = desc
        .materials
        .values()
        .map(|m| m.emission != [0.0; 3])
        .collect();
    let lights: Vec<LightDesc> = desc.lights.iter().map(shape_only).collect();
    let files = mesh_stamps(desc, ctx)?;
    Some(format!(
        "{:?}|{names:?}|{emitting:?}|{lights:?}|{:?}|{:?}|{files:?}",
        desc.objects, ctx.base_dir, ctx.bunny
    ))
}

/// A light's description without what does not shape its surface (power,
/// shadow rays), so that sweeps over those share a world.
fn shape_only(l: &LightDesc) -> LightDesc {
    LightDesc {
        intensity: None,
        radiance: None,
        shadow_rays: None,
        shadow_distribution: None,
        ..l.clone()
    }
}

/// Path, length and modification time of every mesh file `desc` names.
fn mesh_stamps(desc: &SceneDesc, ctx: &BuildContext) -> Option<Vec<(PathBuf, u64, SystemTime)>> {
    let path = KeyPath::root();
    desc.objects
        .iter()
        .filter_map(|o| o.path.as_deref())
        .map(|file| {
            let p = resolve_mesh_path(&path, file, ctx).ok()?;
            stamp(&p).map(|(len, modified)| (p, len, modified))
        })
        .collect()
}

fn stamp(path: &Path) -> Option<(u64, SystemTime)> {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.len(), meta.modified().ok()?))
}
