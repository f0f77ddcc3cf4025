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

/// The mean of the pixels of `img` in `x0..x1 × y0..y1`, and the standard
/// error of that mean from their spread (each pixel an independent
/// estimate of the same value).
pub fn block_mean(
    img: &Image,
    (x0, x1): (u32, u32),
    (y0, y1): (u32, u32),
) -> (penumbra::math::Rgb, penumbra::math::Rgb) {
    use penumbra::math::Rgb;
    let n = ((x1 - x0) * (y1 - y0)) as f32;
    let (mut sum, mut sq) = (Rgb::ZERO, Rgb::ZERO);
    for y in y0..y1 {
        for x in x0..x1 {
            let v = img.get(x, y);
            assert!(v.is_finite(), "pixel ({x}, {y}) is {v:?}");
            sum += v;
            sq += v * v;
        }
    }
    let mean = sum / n;
    let var = (sq / n - mean * mean).map(|v| v.max(0.0)) * (n / (n - 1.0));
    (mean, (var / n).map(f32::sqrt))
}

/// [`block_mean`] over the whole image.
pub fn mean_and_error(img: &Image) -> (penumbra::math::Rgb, penumbra::math::Rgb) {
    block_mean(img, (0, img.width), (0, img.height))
}

/// Holds each channel of `got` (with standard error `err`) to `want`
/// within 3σ (and a relative 1e-4 for rounding).
pub fn assert_within(
    got: penumbra::math::Rgb,
    err: penumbra::math::Rgb,
    want: penumbra::math::Rgb,
    what: &str,
) {
    for c in 0..3 {
        let (g, e, w) = (got.to_array()[c], err.to_array()[c], want.to_array()[c]);
        assert!(
            (g - w).abs() <= 3.0 * e + 1e-4 * w.abs(),
            "{what}, channel {c}: got {g} ± {e}, want {w}"
        );
    }
}

/// Renders the TOML scene `toml` (whose `[render]` holds the line
/// `spp_line`) on 1 and 3 threads and in 3 passes, holds every pixel to
/// the same bits, and returns the ray counts (the same on any threads).
pub fn same_bits_on_threads_and_passes(toml: &str, spp_line: &str) -> RayStats {
    let s = scene(toml);
    let (one, a) = render_scene(&s, 1);
    let (three, b) = render_scene(&s, 3);
    assert_eq!(a, b);
    let passes = scene(&toml.replace(spp_line, &format!("{spp_line}passes = 3\n")));
    let (split, _) = render_scene(&passes, 2);
    for y in 0..one.height {
        for x in 0..one.width {
            let bits = |i: &Image| i.get(x, y).to_array().map(f32::to_bits);
            assert_eq!(bits(&one), bits(&three), "pixel ({x}, {y}), 1 vs 3 threads");
            assert_eq!(bits(&one), bits(&split), "pixel ({x}, {y}), 3 passes");
        }
    }
    a
}
