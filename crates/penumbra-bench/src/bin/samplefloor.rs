//! How far scene (a)'s per-sample work is from its floor: the bunny scene
//! without the bunny (the ground quad under the rectangle light, 16 jittered
//! camera rays and one shadow ray each) rendered twice on one thread, by
//! the renderer and by a kernel that does only that scene's arithmetic,
//! four samples at a time in lanes, with the library's own routines: its
//! random streams (the same ones, so the same samples), film points,
//! four-wide camera rays, quad test, light samples (four-wide) and BRDF.
//!
//! The kernel knows the scene in advance: one quad, one light, nothing that
//! can cast a shadow (so no shadow ray is traced), no metric, no lens, no
//! motion. What the renderer spends beyond it is what its generality costs
//! per sample (hit records, per-hit dispatch, the integrator's batches, the
//! shaft that finds the shadow rays unblocked): the part of scene (a) that
//! a wavefront integrator, which runs each stage over many samples at once,
//! could save. The bunny's traversal is not in either.
//!
//! The two images are compared before any time is reported: the kernel must
//! give every pixel the renderer gives, bit for bit, or the run fails.
//!
//! ```text
//! samplefloor [--width W] [--height H] [--spp N] [--rounds R]
//! ```
//!
//! Prints JSON: the median seconds of each, one thread, in alternating
//! rounds, and the median ratio of adjacent pairs.

use penumbra::accel::Hit;
use penumbra::bsdf::Bsdf;
use penumbra::camera::CameraSample;
use penumbra::emitter::{Emitter, LightSample, Reference};
use penumbra::geometry::quad::Quad;
use penumbra::integrator::RaySets;
use penumbra::math::Rgb;
use penumbra::math::{Ray, Vec2, Vec3};
use penumbra::render::{render, Image, RenderOptions};
use penumbra::sampling::{BranchKey, Distribution, Rng};
use penumbra::scene::{LoadOptions, Scene, SceneSource};
use penumbra_bench::median;
use serde_json::json;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

/// The built-in bunny scene without its mesh.
const SCENE: &str = r#"
[render]
width = 800
height = 600
spp = 16
distribution = "jitter"

[camera]
position = [0.0, 1.3, 4.2]
look_at = [-0.15, 0.65, 0.0]
fov = 40

[materials.ground]
albedo = [0.7, 0.7, 0.7]

[[objects]]
type = "quad"
material = "ground"
origin = [-5.0, 0.0, -5.0]
edge_u = [0.0, 0.0, 10.0]
edge_v = [10.0, 0.0, 0.0]

[[lights]]
type = "rect"
origin = [-0.5, 4.0, -0.5]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 1.0]
radiance = [40.0, 40.0, 40.0]
"#;

/// The branch labels the integrator uses: sample `i`'s path is `3 + i`,
/// the first light's shadow sets `1 << 32` (see `integrator::tracer`).
const PATH: u64 = 3;
const SHADOW: u64 = 1 << 32;

/// What the kernel reads of the scene, checked to be what it assumes.
struct Floor<'a> {
    scene: &'a Scene,
    ground: Quad,
    light: &'a Emitter,
    shading: &'a Bsdf,
    /// The ground's interaction record at one point: all the BSDF reads
    /// of it (its normals) is the same everywhere on the flat ground.
    at: Hit,
    /// What rays that miss the ground see.
    background: Rgb,
    paths: Vec<BranchKey>,
    shadow: BranchKey,
}

impl<'a> Floor<'a> {
    fn new(scene: &'a Scene) -> Result<Floor<'a>, String> {
        let s = &scene.settings;
        let square = (s.spp as f32).sqrt() as u32;
        if square * square != s.spp || s.spp & 3 != 0 {
            return Err(format!(
                "--spp {}: the kernel needs a square multiple of 4",
                s.spp
            ));
        }
        let [light] = scene.emitters.as_slice() else {
            return Err("the kernel needs exactly one light".into());
        };
        let rect = match light {
            Emitter::Area(a) => a.surface.shape().as_quad().is_some(),
            _ => false,
        };
        if !rect || RaySets::new(scene).shadow[0].rays != 1 {
            return Err("the kernel needs a rectangle light with one shadow ray".into());
        }
        // The ground's material, as the renderer finds it: what a ray
        // straight down hits.
        let down = Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::NEG_Y, 0.0);
        let hit = scene.world.intersect(&down, 0.0, f32::INFINITY);
        let at = hit.ok_or("the ground is not below the origin")?;
        Ok(Floor {
            scene,
            ground: ground(),
            light,
            shading: &scene.bsdfs[at.material as usize],
            at,
            background: Rgb::ZERO,
            paths: (0..u64::from(s.spp))
                .map(|i| BranchKey::new(PATH + i))
                .collect(),
            shadow: BranchKey::new(SHADOW),
        })
    }

    /// The whole frame, row by row, into `out`.
    fn render(&self, out: &mut Vec<Rgb>) {
        let s = &self.scene.settings;
        out.clear();
        let (mut film, mut lights) = (Vec::new(), Vec::new());
        for y in 0..s.height {
            for x in 0..s.width {
                out.push(self.pixel(x, y, &mut film, &mut lights));
            }
        }
    }

    /// Pixel (x, y): its samples four at a time.
    fn pixel(
        &self,
        x: u32,
        y: u32,
        film: &mut Vec<Vec3>,
        lights: &mut Vec<Option<LightSample>>,
    ) -> Rgb {
        let s = &self.scene.settings;
        let cam = &self.scene.camera;
        let pixel = Rng::new(s.seed).derive(u64::from(y) * u64::from(s.width) + u64::from(x));
        Distribution::Jitter.generate_unordered(s.spp as usize, 0.5, &mut pixel.derive(0), film);
        let time = [cam.time(0.0); 4];
        let mut sum = Rgb::ZERO;
        for (c, four) in film.chunks_exact(4).enumerate() {
            let f: [Vec2; 4] = std::array::from_fn(|k| {
                Vec2::new(x as f32 + 0.5 + four[k].x, y as f32 + 0.5 + four[k].y)
            });
            let samples: [CameraSample; 4] = std::array::from_fn(|k| CameraSample {
                film: f[k],
                lens: Vec2::ZERO,
                time: time[k],
            });
            let mut made = Vec::with_capacity(4);
            cam.generate(&samples, &mut made);
            // Four samples make four rays; anything else would be a NaN
            // pixel, which fails the comparison with the renderer.
            let Ok(rays) = <[Ray; 4]>::try_from(made) else {
                return Rgb::splat(f32::NAN);
            };
            let t = rays.map(|r| self.ground.intersect(&r, 0.0, f32::INFINITY));
            let p: [Vec3; 4] = std::array::from_fn(|k| rays[k].at(t[k].map_or(0.0, |h| h.0)));
            let points: [Vec3; 4] = std::array::from_fn(|k| {
                let mut rng = pixel
                    .derive_key(self.paths[4 * c + k])
                    .derive_key(self.shadow);
                Distribution::Jitter.one(1.0, &mut rng)
            });
            lights.clear();
            self.light.sample(
                |k| Reference::new(p[k], 0.0),
                &points,
                Distribution::Jitter,
                lights,
            );
            for k in 0..4 {
                if t[k].is_none() {
                    sum += self.background;
                    continue;
                }
                // The viewer is above the ground: its normal needs no flip.
                let (n, wo) = (self.ground.normal, -rays[k].dir.normalize());
                let Some(ls) = lights[k] else { continue };
                let cos = n.dot(ls.dir);
                if cos > 0.0 {
                    sum += self.shading.eval(&self.at, wo, ls.dir) * ls.weight * cos;
                }
            }
        }
        sum / s.spp as f32
    }
}

/// How many pixels of `a` differ from `b`'s, bit for bit.
fn differing(a: &[Rgb], b: &Image) -> usize {
    let bits = |c: &Rgb| c.to_array().map(f32::to_bits);
    a.iter()
        .zip(&b.pixels)
        .filter(|(x, y)| bits(x) != bits(y))
        .count()
}

/// The scene at `size` with `spp` camera rays per pixel.
fn build(size: (u32, u32), spp: u32) -> Result<Scene, String> {
    let here = Path::new(".");
    let mut src = SceneSource::from_toml(
        SCENE,
        Path::new("samplefloor.toml"),
        here,
        &LoadOptions::default(),
    )
    .map_err(|e| e.to_string())?;
    penumbra::scene::Overrides {
        width: Some(size.0),
        height: Some(size.1),
        spp: Some(spp),
        ..Default::default()
    }
    .apply(&mut src);
    src.build().map_err(|e| e.to_string())
}

/// The scene's ground, as its description gives it.
fn ground() -> Quad {
    let (origin, u, v) = (
        Vec3::new(-5.0, 0.0, -5.0),
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::new(10.0, 0.0, 0.0),
    );
    Quad::new(origin, u, v)
}

fn run() -> Result<serde_json::Value, String> {
    let mut it = std::env::args().skip(1);
    let (mut size, mut spp, mut rounds) = ((800u32, 600u32), 16u32, 5usize);
    while let Some(a) = it.next() {
        let mut num = || {
            let v = it.next().ok_or(format!("{a} needs a value"))?;
            v.parse::<u32>().map_err(|e| format!("{a}: {e}"))
        };
        match a.as_str() {
            "--width" => size.0 = num()?,
            "--height" => size.1 = num()?,
            "--spp" => spp = num()?,
            "--rounds" => rounds = num()?.max(1) as usize,
            _ => return Err(format!("unknown argument {a}")),
        }
    }
    let scene = build(size, spp)?;
    let floor = Floor::new(&scene)?;
    let opts = RenderOptions {
        threads: Some(1),
        region: None,
    };
    let mut pixels = Vec::new();
    let (mut full, mut kernel) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        let t0 = Instant::now();
        let (image, _) = render(&scene, &opts, &|_, _| {}, None).map_err(|e| e.to_string())?;
        full.push(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        floor.render(&mut pixels);
        kernel.push(t0.elapsed().as_secs_f64());
        let bad = differing(&pixels, &image);
        if bad > 0 || pixels.len() != image.pixels.len() {
            return Err(format!(
                "{bad} pixels of the kernel's image differ from the renderer's"
            ));
        }
    }
    let samples = f64::from(size.0) * f64::from(size.1) * f64::from(spp);
    let ratios: Vec<f64> = full.iter().zip(&kernel).map(|(f, k)| f / k).collect();
    let ns = |s: &[f64]| median(s.to_vec()) * 1e9 / samples;
    Ok(json!({
        "width": size.0, "height": size.1, "spp": spp, "rounds": rounds,
        "renderer_s": median(full.clone()), "kernel_s": median(kernel.clone()),
        "renderer_ns_per_sample": ns(&full), "kernel_ns_per_sample": ns(&kernel),
        "renderer_over_kernel": median(ratios),
    }))
}

const USAGE: &str = "usage: samplefloor [--width W] [--height H] [--spp N] [--rounds R]\n\
    Renders the bunny scene without the bunny on one thread, by the renderer and by a\n\
    kernel that knows the scene, checks that the images agree bit for bit, and prints\n\
    the median times and their ratio as JSON (defaults: 800x600, 16 spp, 5 rounds).";

fn main() -> ExitCode {
    if std::env::args().any(|a| a == "-h" || a == "--help") {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    match run() {
        Ok(v) => {
            println!("{v}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("samplefloor: {e}");
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kernel gives the renderer's pixels bit for bit, at the
    /// benchmark's size and at a small one with 4 samples: a change to
    /// either that alters the arithmetic of a sample shows here. An
    /// origin offset that leaves points near the world's origin shadowed by
    /// their own surface makes 4 pixels of the first differ.
    #[test]
    fn kernel_renders_what_the_renderer_renders() {
        for (size, spp) in [((800, 600), 16), ((64, 48), 4)] {
            let scene = build(size, spp).expect("the built-in scene");
            let floor = Floor::new(&scene).expect("a scene the kernel knows");
            let mut pixels = Vec::new();
            floor.render(&mut pixels);
            let opts = RenderOptions {
                threads: Some(1),
                region: None,
            };
            let (image, _) = render(&scene, &opts, &|_, _| {}, None).expect("renders");
            assert_eq!(pixels.len(), image.pixels.len());
            assert_eq!(differing(&pixels, &image), 0, "{size:?} at {spp} spp");
            assert!(image.mean().r > 0.05, "the ground is lit");
        }
    }
}
