//! Renders a scene several times in one process and prints, as JSON, the
//! median render time measured around the library's render call (no process
//! start, no scene loading or BVH build in it), wall clock and on-CPU time
//! of all threads, and the rays traced.
//!
//! ```text
//! scenebench SCENE [--bunny PATH] [--width W] [--height H] [--spp N]
//!            [--shadow-rays N] [--distribution D] [--threads T] [--repeat N]
//! ```
//!
//! SCENE is a scene file or a built-in name, as for `penumbra render`.

use penumbra::render::{render, RenderOptions};
use penumbra::scene::{default_bunny_path, LoadOptions, Overrides, SceneSource};
use penumbra_bench::{median, process_time};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

fn run() -> Result<serde_json::Value, String> {
    let mut it = std::env::args().skip(1);
    let mut scene = None;
    let mut load = LoadOptions {
        bunny: default_bunny_path(),
    };
    let mut ov = Overrides::default();
    let (mut threads, mut repeat) = (None, 5usize);
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        let num = |v: String| v.parse::<u32>().map_err(|e| format!("{a}: {e}"));
        match a.as_str() {
            "--bunny" => load.bunny = Some(PathBuf::from(value()?)),
            "--width" => ov.width = Some(num(value()?)?),
            "--height" => ov.height = Some(num(value()?)?),
            "--spp" => ov.spp = Some(num(value()?)?),
            "--shadow-rays" => ov.shadow_rays = Some(num(value()?)?),
            "--distribution" => {
                ov.distribution = Some(value()?.parse().map_err(|e| format!("{a}: {e}"))?)
            }
            "--threads" => threads = Some(num(value()?)? as usize),
            "--repeat" => repeat = num(value()?)?.max(1) as usize,
            _ if scene.is_none() && !a.starts_with('-') => scene = Some(a),
            _ => return Err(format!("unknown argument {a}")),
        }
    }
    let scene = scene.ok_or("usage: scenebench SCENE [options]")?;
    let mut src = SceneSource::open(&scene, &load).map_err(|e| e.to_string())?;
    ov.apply(&mut src.desc);
    let start = Instant::now();
    let scene_built = src.build().map_err(|e| e.to_string())?;
    let load_s = start.elapsed().as_secs_f64();
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
    match run() {
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
