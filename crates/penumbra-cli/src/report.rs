//! What the CLI prints: the scene list, the render summary and the stats JSON.

use std::path::Path;

use penumbra::scene::builtin::SCENES;
use penumbra::scene::default_bunny_path;
use serde_json::Value;

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
    let b = &j["batches"];
    let mean = |k: &str| b[k]["mean"].as_f64().unwrap_or(0.0);
    if b["closest_hit"]["calls"].as_u64().unwrap_or(0) > 0 {
        println!(
            "mean batch: {:.0} rays per closest-hit call, {:.0} per occlusion call, {:.0} vertices per shading call",
            mean("closest_hit"),
            mean("occlusion"),
            mean("shading")
        );
    }
    println!(
        "time: build {:.3} s, render {:.3} s on {} threads, {:.2} Mrays/s",
        j["time"]["build_s"].as_f64().unwrap_or(0.0),
        j["time"]["render_s"].as_f64().unwrap_or(0.0),
        j["threads"],
        j["mrays_per_s"].as_f64().unwrap_or(0.0)
    );
}
