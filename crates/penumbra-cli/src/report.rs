//! What the CLI prints: the scene list, the render summary and the stats JSON.

use std::path::Path;

use penumbra::render::RenderStats;
use penumbra::scene::builtin::SCENES;
use penumbra::scene::{default_bunny_path, Scene};
use serde_json::{json, Value};

pub fn print_scenes() {
    let bunny = default_bunny_path();
    println!("Built-in scenes (use the name wherever a scene file is accepted):");
    for b in SCENES {
        let note = if b.needs_bunny && bunny.is_none() {
            " [needs --bunny PATH]"
        } else {
            ""
        };
        println!("  {:<14} {}{}", b.name, b.description, note);
    }
}

/// The statistics document; its schema is documented in docs/statistics.md.
pub fn stats_json(scene_name: &str, scene: &Scene, stats: &RenderStats) -> Value {
    let s = &scene.settings;
    let r = &stats.rays;
    let render_s = stats.render_time.as_secs_f64();
    let mrays = if render_s > 0.0 {
        r.total() as f64 / render_s / 1e6
    } else {
        0.0
    };
    json!({
        "scene": scene_name,
        "width": s.width,
        "height": s.height,
        "threads": stats.threads,
        "seed": s.seed,
        "spp": s.spp,
        "max_depth": s.max_depth,
        "primitives": scene.world.primitive_count(),
        "rays": {
            "primary": r.primary,
            "shadow": r.shadow,
            "reflection": r.reflection,
            "refraction": r.refraction,
            "total": r.total(),
        },
        "time": {
            "build_s": scene.build_time.as_secs_f64(),
            "render_s": render_s,
        },
        "mrays_per_s": mrays,
        "bad_samples": stats.bad_samples,
    })
}

pub fn print_summary(output: &Path, j: &Value) {
    let rays = &j["rays"];
    let n = |k: &str| rays[k].as_u64().unwrap_or(0);
    println!(
        "wrote {} ({}x{})",
        output.display(),
        j["width"],
        j["height"]
    );
    println!(
        "rays: {} primary, {} shadow, {} reflection, {} refraction, {} total",
        n("primary"),
        n("shadow"),
        n("reflection"),
        n("refraction"),
        n("total")
    );
    println!(
        "time: build {:.3} s, render {:.3} s on {} threads, {:.2} Mrays/s",
        j["time"]["build_s"].as_f64().unwrap_or(0.0),
        j["time"]["render_s"].as_f64().unwrap_or(0.0),
        j["threads"],
        j["mrays_per_s"].as_f64().unwrap_or(0.0)
    );
}
