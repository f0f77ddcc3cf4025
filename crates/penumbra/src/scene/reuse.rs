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

use super::context::{mesh_path, BuildContext};
use crate::accel::World;
use crate::description::{Kind, Node, Value};

/// Worlds kept by [`WorldCache::default`]: enough for a sweep that
/// alternates between a few scenes (the evaluation's bunny scenes, with and
/// without area lights) without holding meshes forever.
const DEFAULT_CAPACITY: usize = 4;

/// Built worlds, most recently used last, each under a key naming
/// everything it was made from (see `SceneSource::build_reusing`), with
/// the digests of the files read to build it: a build that reuses a world
/// records them as read again ([`crate::input::recording_reads`]).
pub struct WorldCache {
    entries: Vec<(String, Arc<World>, Vec<[u8; 32]>)>,
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

    /// The world built under `key`, now the most recently used; the files
    /// read to build it are recorded as read.
    pub(super) fn get(&mut self, key: &str) -> Option<Arc<World>> {
        let i = self.entries.iter().position(|(k, ..)| k == key)?;
        let entry = self.entries.remove(i);
        let world = Arc::clone(&entry.1);
        crate::input::note_reads(&entry.2);
        self.entries.push(entry);
        Some(world)
    }

    /// Keeps `world`, built by reading the files of digests `reads`, under
    /// `key`, dropping the least recently used if full.
    pub(super) fn insert(&mut self, key: String, world: Arc<World>, reads: Vec<[u8; 32]>) {
        self.entries.retain(|(k, ..)| *k != key);
        if self.entries.len() >= self.capacity {
            self.entries.remove(0);
        }
        self.entries.push((key, world, reads));
    }
}

/// The keys of an emitter that leave the world as it is.
const UNSHAPED: [&str; 5] = [
    "radiance",
    "intensity",
    "model",
    "shadow_rays",
    "shadow_distribution",
];

/// Everything the world of `root` is made from, as text: the shapes (their
/// whole nodes: materials are named, placements given), the materials'
/// names in order (objects refer to them by index) and what they emit
/// (emitting objects carry emitters, numbered in the world), the lights
/// and the shapes' emitters without what does not shape the world (power,
/// model, shadow rays, so that sweeps over those share a world), where mesh paths point, and each mesh file's length and
/// modification time (so that a file rewritten between builds is read
/// again). `None` when a mesh path cannot be resolved or a file not
/// examined: such a scene is built afresh, which reports the error.
///
/// Fingerprints keep every `f32` exactly (and tell NaN from infinity), so
/// equal keys mean equal inputs.
pub(super) fn key(root: &Node, ctx: &BuildContext) -> Option<String> {
    let mut key = String::new();
    for m in root.children_of(Kind::Bsdf) {
        let emits = m.prop("emission").map(|p| format!("{:?}", p.value.value));
        key += &format!("bsdf {:?} {emits:?}|", m.id);
    }
    // What does not shape the world: the emitters' power, model and
    // shadow sets.
    let unshaped = |node: &mut Node| {
        for name in UNSHAPED {
            node.remove_prop(name);
        }
    };
    for s in root.children_of(Kind::Shape) {
        let mut shape = s.clone();
        shape
            .children
            .iter_mut()
            .filter(|c| c.kind == Kind::Emitter)
            .for_each(unshaped);
        key += &shape.fingerprint();
        key.push('|');
    }
    for l in root
        .children_of(Kind::Emitter)
        .filter(|l| l.plugin != "constant")
    {
        let mut light = l.clone();
        unshaped(&mut light);
        key += &light.fingerprint();
        key.push('|');
    }
    let files = mesh_stamps(root, ctx)?;
    Some(format!("{key}{:?}|{:?}|{files:?}", ctx.base_dir, ctx.bunny))
}

/// Path, length and modification time of every mesh file the shapes name.
fn mesh_stamps(root: &Node, ctx: &BuildContext) -> Option<Vec<(PathBuf, u64, SystemTime)>> {
    root.children_of(Kind::Shape)
        .flat_map(|o| std::iter::once(o).chain(o.children_of(Kind::Shape)))
        .filter_map(|o| match &o.prop("path")?.value.value {
            Value::String(file) => Some(file.as_str()),
            _ => None,
        })
        .map(|file| {
            let p = mesh_path(file, ctx)?;
            stamp(&p).map(|(len, modified)| (p, len, modified))
        })
        .collect()
}

fn stamp(path: &Path) -> Option<(u64, SystemTime)> {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.len(), meta.modified().ok()?))
}
