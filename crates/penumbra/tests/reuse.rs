//! A world reused across builds (`SceneSource::build_reusing`) gives the
//! scene a fresh build gives, and is reused exactly when the geometry is the
//! same.

mod common;

use std::path::Path;
use std::sync::Arc;

use penumbra::sampling::Distribution;
use penumbra::scene::{LoadOptions, Overrides, Scene, SceneSource, WorldCache};

use common::render_scene;

/// Two triangles of a tent, as an OBJ file.
const TENT: &str = "v -1 0 -1\nv 1 0 -1\nv 0 1 0\nv -1 0 1\nv 1 0 1\nf 1 2 3\nf 4 3 5\n";

/// A mesh (`tent.obj`) and a sphere on a ground under a rectangle light;
/// `extra_material` adds materials.
fn scene_text(sphere_radius: f32, light_edge: f32, extra_material: &str) -> String {
    format!(
        r#"
[render]
width = 12
height = 9
spp = 4
shadow_rays = 4
distribution = "jitter"

[camera]
position = [0.0, 1.5, 4.0]
look_at = [0.0, 0.3, 0.0]
fov = 50

[materials.floor]
albedo = [0.6, 0.6, 0.6]

[materials.glossy]
albedo = [0.3, 0.2, 0.1]
reflectivity = 0.4
glossiness = 0.2
{extra_material}

[[objects]]
type = "quad"
material = "floor"
origin = [-5.0, 0.0, -5.0]
edge_u = [0.0, 0.0, 10.0]
edge_v = [10.0, 0.0, 0.0]

[[objects]]
type = "mesh"
path = "tent.obj"
material = "glossy"

[[objects]]
type = "sphere"
center = [1.2, 0.4, 0.5]
radius = {sphere_radius}
material = "floor"

[[lights]]
type = "rect"
origin = [-0.5, 3.0, -0.5]
edge_u = [{light_edge}, 0.0, 0.0]
edge_v = [0.0, 0.0, 1.0]
radiance = [5.0, 5.0, 5.0]
"#
    )
}

fn source(dir: &Path, text: &str, overrides: &Overrides) -> SceneSource {
    let opts = LoadOptions::default();
    let mut s = SceneSource::from_toml(text, &dir.join("test.toml"), dir, &opts).expect("parses");
    overrides.apply(&mut s);
    s
}

fn reused(s: &SceneSource, worlds: &mut WorldCache) -> Scene {
    s.build_reusing(worlds).expect("builds")
}

/// The reused scene renders what a fresh build renders, bit for bit.
fn same_pixels(reused: &Scene, s: &SceneSource) {
    let fresh = s.build().expect("builds");
    assert_eq!(render_scene(reused, 2), render_scene(&fresh, 2));
}

fn tent_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("tent.obj"), TENT).expect("writes");
    dir
}

#[test]
fn settings_sweeps_share_one_world() {
    let dir = tent_dir();
    let dir = dir.path();
    let text = scene_text(0.4, 1.0, "");
    let mut worlds = WorldCache::default();
    let first = reused(&source(dir, &text, &Overrides::default()), &mut worlds);
    let sweeps = [
        Overrides {
            spp: Some(9),
            ..Default::default()
        },
        Overrides {
            distribution: Some(Distribution::Poisson),
            shadow_rays: Some(9),
            reflection_rays: Some(4),
            ..Default::default()
        },
        Overrides {
            width: Some(7),
            height: Some(5),
            metric: Some(true),
            aperture: Some(0.1),
            ..Default::default()
        },
    ];
    for o in &sweeps {
        let s = source(dir, &text, o);
        let scene = reused(&s, &mut worlds);
        assert!(Arc::ptr_eq(&first.world, &scene.world), "{o:?}");
        same_pixels(&scene, &s);
    }
    // Material parameters and the light's power are not geometry either.
    let brighter = text
        .replace("glossiness = 0.2", "glossiness = 0.5")
        .replace("radiance = [5.0, 5.0, 5.0]", "radiance = [9.0, 1.0, 5.0]");
    let s = source(dir, &brighter, &Overrides::default());
    let scene = reused(&s, &mut worlds);
    assert!(Arc::ptr_eq(&first.world, &scene.world));
    same_pixels(&scene, &s);
    assert_eq!(worlds.len(), 1);
}

#[test]
fn geometry_changes_build_a_new_world() {
    let dir = tent_dir();
    let dir = dir.path();
    let base = scene_text(0.4, 1.0, "");
    let mut worlds = WorldCache::default();
    let first = reused(&source(dir, &base, &Overrides::default()), &mut worlds);
    let changed = [
        ("an object", scene_text(0.3, 1.0, "")),
        ("a light's shape", scene_text(0.4, 1.5, "")),
        // A material sorted before the others renumbers them.
        (
            "the material names",
            scene_text(0.4, 1.0, "\n[materials.a_first]\nalbedo = [0.1, 0.1, 0.1]"),
        ),
    ];
    for (what, text) in &changed {
        let s = source(dir, text, &Overrides::default());
        let scene = reused(&s, &mut worlds);
        assert!(!Arc::ptr_eq(&first.world, &scene.world), "{what}");
        same_pixels(&scene, &s);
    }
    // The mesh file rewritten with a third triangle is read again.
    let more = format!("{TENT}v 0 2 0\nf 1 2 6\n");
    std::fs::write(dir.join("tent.obj"), more).expect("writes");
    let s = source(dir, &base, &Overrides::default());
    let scene = reused(&s, &mut worlds);
    assert!(!Arc::ptr_eq(&first.world, &scene.world));
    assert_eq!(
        scene.world.primitive_count(),
        first.world.primitive_count() + 1
    );
    same_pixels(&scene, &s);
}

#[test]
fn the_least_recently_used_world_is_dropped() {
    let dir = tent_dir();
    let dir = dir.path();
    let mut worlds = WorldCache::new(2);
    let build = |r: f32, worlds: &mut WorldCache| {
        let s = source(dir, &scene_text(r, 1.0, ""), &Overrides::default());
        reused(&s, worlds).world
    };
    let a = build(0.1, &mut worlds);
    let b = build(0.2, &mut worlds);
    assert!(Arc::ptr_eq(&a, &build(0.1, &mut worlds)), "a is kept");
    let _c = build(0.3, &mut worlds);
    assert_eq!(worlds.len(), 2);
    assert!(Arc::ptr_eq(&a, &build(0.1, &mut worlds)), "a was used last");
    assert!(!Arc::ptr_eq(&b, &build(0.2, &mut worlds)), "b was dropped");
}

#[test]
fn errors_are_those_of_a_fresh_build() {
    let dir = tent_dir();
    let dir = dir.path();
    let base = scene_text(0.4, 1.0, "");
    let mut worlds = WorldCache::default();
    reused(&source(dir, &base, &Overrides::default()), &mut worlds);
    let bad = [
        // The cached world's geometry, with a setting out of range.
        base.replace("spp = 4", "spp = 0"),
        base.replace(
            "radiance = [5.0, 5.0, 5.0]",
            "radiance = [5.0, 5.0, 5.0]\nshadow_rays = 0",
        ),
        // Other geometry: no world to reuse.
        base.replace("path = \"tent.obj\"", "path = \"missing.obj\""),
        base.replace("radius = 0.4", "radius = -1.0"),
    ];
    for text in &bad {
        let s = source(dir, text, &Overrides::default());
        let fresh = s.build().err().expect("invalid").to_string();
        let again = s.build_reusing(&mut worlds).err().expect("invalid");
        assert_eq!(again.to_string(), fresh);
    }
    assert_eq!(worlds.len(), 1, "a failed build keeps nothing");
}

/// A build that reuses a world records the files read to build it, as a
/// fresh build does: a checkpoint's digest is the same with or without
/// the cache, and changes with a mesh file rewritten.
#[test]
fn reused_worlds_record_the_files_they_were_read_from() {
    let dir = tent_dir();
    let dir = dir.path();
    let text = scene_text(0.4, 1.0, "");
    let s = source(dir, &text, &Overrides::default());
    let (_, fresh) = penumbra::input::recording_reads(|| s.build().expect("builds"));
    use sha2::Digest as _;
    let tent: [u8; 32] = sha2::Sha256::digest(TENT.as_bytes()).into();
    assert_eq!(fresh, vec![tent]);
    let mut worlds = WorldCache::default();
    let (first, built) = penumbra::input::recording_reads(|| reused(&s, &mut worlds));
    let (second, again) = penumbra::input::recording_reads(|| reused(&s, &mut worlds));
    assert!(Arc::ptr_eq(&first.world, &second.world));
    assert_eq!(built, fresh);
    assert_eq!(again, fresh);
    // Rewritten (another length): read again, and recorded as it is now.
    let bigger = format!("{TENT}f 1 2 5\n");
    std::fs::write(dir.join("tent.obj"), &bigger).expect("writes");
    let (third, changed) = penumbra::input::recording_reads(|| reused(&s, &mut worlds));
    assert!(!Arc::ptr_eq(&first.world, &third.world));
    let bigger: [u8; 32] = sha2::Sha256::digest(bigger.as_bytes()).into();
    assert_eq!(changed, vec![bigger]);
}
