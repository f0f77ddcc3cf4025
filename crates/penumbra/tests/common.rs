//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use penumbra::integrator::RayStats;
use penumbra::render::{render, Image, Region, RenderOptions};
use penumbra::scene::{LoadOptions, Overrides, Scene, SceneError, SceneSource};

/// Applies `o` to `src` (the render options given in code).
pub fn set(src: &mut SceneSource, o: Overrides) {
    o.apply(src);
}

pub fn scene(toml: &str) -> Scene {
    try_scene(toml).unwrap_or_else(|e| panic!("scene should be valid: {e}"))
}

pub fn try_scene(toml: &str) -> Result<Scene, SceneError> {
    SceneSource::from_toml(
        toml,
        Path::new("test.toml"),
        Path::new("."),
        &LoadOptions::default(),
    )?
    .build()
}

pub fn render_scene(s: &Scene, threads: usize) -> (Image, RayStats) {
    let opts = RenderOptions {
        threads: Some(threads),
        region: None,
    };
    let (img, stats) = render(s, &opts, &|_, _| {}, None).expect("render");
    (img, stats.rays)
}

pub fn render_toml(toml: &str) -> (Image, RayStats) {
    render_scene(&scene(toml), 2)
}

/// The Stanford bunny the test command passes in `$PENUMBRA_BUNNY` (tests
/// that need it skip otherwise; nothing looks for it elsewhere).
pub fn bunny() -> Option<PathBuf> {
    let p = PathBuf::from(std::env::var_os("PENUMBRA_BUNNY").unwrap_or_default());
    if p.is_file() {
        Some(p)
    } else {
        eprintln!(
            "skipping: the Stanford bunny is not at {} (set PENUMBRA_BUNNY)",
            p.display()
        );
        None
    }
}

pub fn builtin(name: &str, bunny: Option<PathBuf>) -> SceneSource {
    SceneSource::open(
        name,
        &LoadOptions {
            bunny,
            ..Default::default()
        },
    )
    .expect("built-in scene")
}

/// Renders `region` of `s` alone (two threads) and checks that its pixels
/// are those of `full`, the whole frame; `what` names the case.
pub fn assert_region_is_the_frames(s: &Scene, full: &Image, region: Region, what: &str) {
    let opts = RenderOptions {
        threads: Some(2),
        region: Some(region),
    };
    let (part, _) = render(s, &opts, &|_, _| {}, None).unwrap();
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            let (a, b) = (part.get(x - region.x0, y - region.y0), full.get(x, y));
            assert_eq!(a, b, "{what} at ({x}, {y})");
        }
    }
}

/// What a docs file's text becomes with its generated parts written afresh
/// (`Err`: the markers it lacks).
pub type Fresh<'a> = &'a dyn Fn(&str) -> Result<String, String>;

/// Checks generated parts of the docs: each file (relative to the
/// repository) against what `fresh` makes of its text (`Err`: markers it
/// lacks). With `PENUMBRA_UPDATE_DOCS` set, stale files are rewritten;
/// otherwise the stale ones are returned.
pub fn stale_docs(files: &[(&str, Fresh)]) -> Vec<String> {
    let update = std::env::var_os("PENUMBRA_UPDATE_DOCS").is_some();
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut stale = Vec::new();
    for (file, fresh) in files {
        let path = repo.join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        let fresh = fresh(&text).unwrap_or_else(|e| panic!("{file}: {e}"));
        if fresh != text {
            if update {
                std::fs::write(&path, fresh).unwrap();
            } else {
                stale.push(file.to_string());
            }
        }
    }
    stale
}
