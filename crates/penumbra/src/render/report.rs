use serde_json::{json, Value};

use super::RenderStats;
use crate::integrator::{Batches, Config};
use crate::scene::Scene;

/// The statistics document written by `--stats` and returned by the Python
/// API; its schema is documented in `docs/statistics.md`.
pub fn stats_document(scene_name: &str, scene: &Scene, stats: &RenderStats) -> Value {
    let s = &scene.settings;
    // A built scene's integrator reads (it was read when it was built).
    let config = Config::of(scene).ok();
    let r = &stats.rays;
    let render_s = stats.render_time.as_secs_f64();
    let mrays = if render_s > 0.0 {
        r.total() as f64 / render_s / 1e6
    } else {
        0.0
    };
    json!({
        "scene": scene_name,
        // The film's size, without the border sampled beyond it.
        "width": s.width - 2 * s.border,
        "height": s.height - 2 * s.border,
        "threads": stats.threads,
        "seed": s.seed,
        "spp": s.spp,
        "max_depth": config.as_ref().map(|c| c.depth()),
        "integrator": config.as_ref().map(|c| c.choice().name()),
        "passes": config.as_ref().map(|c| c.passes()),
        "primitives": scene.world.primitive_count(),
        "kernels": scene.world.kernels().name(),
        "rays": {
            "primary": r.primary,
            "shadow": r.shadow,
            "reflection": r.reflection,
            "refraction": r.refraction,
            "total": r.total(),
        },
        "saved": {
            "primary": r.saved.primary,
            "shadow": r.saved.shadow,
            "reflection": r.saved.reflection,
            "refraction": r.saved.refraction,
            "total": r.saved.total(),
        },
        "media": {
            "scatterings": r.media.scatterings,
            "null_collisions": r.media.null_collisions,
            "scattered": r.media.scattered,
            "saved": r.media.saved,
        },
        "batches": {
            "closest_hit": batches(&stats.batches.closest_hit),
            "occlusion": batches(&stats.batches.occlusion),
            "shading": batches(&stats.batches.shading),
        },
        "metric": config.and_then(|c| c.metric()).map(|m| json!({
            "reflections": m.reflections,
            "shadows": m.shadows,
            "threshold": m.threshold,
            "min_rays": m.min_rays,
            "shadow_rays": m.shadow_rays,
            "pixels": m.pixels,
        })),
        "time": {
            "build_s": scene.build_time.as_secs_f64(),
            "render_s": render_s,
        },
        "mrays_per_s": mrays,
        "bad_samples": stats.bad_samples,
        "ended": stats.ended,
    })
}

/// A stage's calls, the items they took and their mean.
fn batches(b: &Batches) -> Value {
    json!({ "calls": b.calls, "items": b.items, "mean": b.mean() })
}
