//! Renders a scene several times in one process and prints, as JSON, the
//! median render time measured around the library's render call (no process
//! start, no scene loading or BVH build in it), wall clock and on-CPU time
//! of all threads, and the rays traced; and the time from opening the scene
//! file to the built scene (`read_and_build_s`: reading and parsing the
//! file, meshes and BVH) and of the build alone (`load_and_build_s`).
//!
//! ```text
//! scenebench SCENE [--bunny PATH] [--width W] [--height H] [--spp N]
//!            [--shadow-rays N] [--distribution D] [--threads T] [--repeat N]
//! ```
//!
//! SCENE is a scene file or a built-in name, as for `penumbra render`.

use clap::Parser;
use penumbra::render::{render, RenderOptions};
use penumbra::sampling::Distribution;
use penumbra::scene::{default_bunny_path, LoadOptions, Overrides, SceneSource};
use penumbra_bench::{median, process_time};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Renders a scene several times in one process and prints JSON: the median
/// render time (wall clock and CPU time of all threads) and the rays traced.
#[derive(Parser)]
#[command(name = "scenebench")]
struct Args {
    /// A scene file or a built-in scene's name, as for `penumbra render`.
    scene: String,
    /// The Stanford bunny PLY (else $PENUMBRA_BUNNY).
    #[arg(long)]
    bunny: Option<PathBuf>,
    /// Image width in pixels.
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    height: Option<u32>,
    /// Camera rays per pixel.
    #[arg(long)]
    spp: Option<u32>,
    /// Shadow rays per light.
    #[arg(long)]
    shadow_rays: Option<u32>,
    /// The distribution of every effect.
    #[arg(long, value_parser = |s: &str| s.parse::<Distribution>().map_err(|e| e.to_string()))]
    distribution: Option<Distribution>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Renders whose median is reported.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    repeat: u32,
}

fn run(args: Args) -> Result<serde_json::Value, String> {
    let scene = args.scene;
    let load = LoadOptions {
        bunny: args.bunny.or_else(default_bunny_path),
        ..Default::default()
    };
    let ov = Overrides {
        width: args.width,
        height: args.height,
        spp: args.spp,
        shadow_rays: args.shadow_rays,
        distribution: args.distribution,
        ..Overrides::default()
    };
    let (threads, repeat) = (args.threads, args.repeat as usize);
    let read_start = Instant::now();
    let mut src = SceneSource::open(&scene, &load).map_err(|e| e.to_string())?;
    ov.apply(&mut src);
    let start = Instant::now();
    let scene_built = src.build().map_err(|e| e.to_string())?;
    let load_s = start.elapsed().as_secs_f64();
    let read_s = read_start.elapsed().as_secs_f64();
    let opts = RenderOptions {
        threads,
        region: None,
    };
    let (mut wall, mut cpu) = (Vec::new(), Vec::new());
    let mut stats = None;
    for _ in 0..repeat {
        let c0 = process_time();
        let t0 = Instant::now();
        let (_, s) = render(&scene_built, &opts, &|_, _| {}, None).map_err(|e| e.to_string())?;
        wall.push(t0.elapsed().as_secs_f64());
        if let (Some(a), Some(b)) = (c0, process_time()) {
            cpu.push(b - a);
        }
        stats = Some(s);
    }
    let s = stats.expect("repeat >= 1");
    let w = median(wall.clone());
    Ok(json!({
        "scene": scene,
        "width": scene_built.settings.width,
        "height": scene_built.settings.height,
        "spp": scene_built.settings.spp,
        "threads": s.threads,
        "primitives": scene_built.world.primitive_count(),
        "load_and_build_s": load_s,
        "read_and_build_s": read_s,
        "render_s": w,
        "render_s_all": wall,
        "render_cpu_s": (!cpu.is_empty()).then(|| median(cpu)),
        "rays": s.rays.total(),
        "shadow_rays": s.rays.shadow,
        "primary_rays": s.rays.primary,
        "mrays_per_s": s.rays.total() as f64 / w / 1e6,
    }))
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(doc) => {
            println!("{doc}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("scenebench: {e}");
            ExitCode::from(2)
        }
    }
}
