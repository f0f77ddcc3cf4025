//! The acceleration metrics of thesis §3.4 stop exactly where they should.

mod common;

use common::*;

/// A camera looking straight down at a floor that fills the view.
fn floor_scene(render: &str, floor: &str, extra: &str) -> String {
    format!(
        r#"
[render]
width = 8
height = 8
{render}

[camera]
position = [0.0, 0.5, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 30

[materials.floor]
{floor}

[[objects]]
type = "quad"
material = "floor"
origin = [-50.0, 0.0, -50.0]
edge_u = [0.0, 0.0, 100.0]
edge_v = [100.0, 0.0, 0.0]
{extra}
"#
    )
}

#[test]
fn a_uniform_reflection_stops_at_alpha() {
    let toml = floor_scene(
        "reflection_rays = 16\ndistribution = \"jitter\"\nbackground = [0.2, 0.4, 0.6]\nmetric = true\nmetric_min_rays = 4",
        "albedo = [0.0, 0.0, 0.0]\nreflectivity = 1.0\nglossiness = 0.3",
        "",
    );
    let (img, r) = render_toml(&toml);
    assert_eq!(r.reflection, 64 * 4, "every set stops after alpha = 4 rays");
    assert_eq!(r.saved.reflection, 64 * 12);
    assert!(
        (img.get(3, 3) - penumbra::math::Rgb::new(0.2, 0.4, 0.6))
            .abs()
            .max_element()
            < 1e-6
    );
    let off = toml.replace("metric = true", "metric = false");
    let (_, r) = render_toml(&off);
    assert_eq!((r.reflection, r.saved.reflection), (64 * 16, 0));
}

fn light(extra: &str) -> String {
    format!(
        "[[lights]]\ntype = \"rect\"\norigin = [-0.5, 3.0, -0.5]\nedge_u = [1.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 1.0]\nradiance = [5.0, 5.0, 5.0]\n{extra}"
    )
}

const SHADOW_METRIC: &str =
    "shadow_rays = 32\ndistribution = \"jitter\"\nmetric = true\nshadow_metric_rays = 4";

#[test]
fn fully_lit_and_fully_shadowed_points_stop_at_k_shadow_rays() {
    let lit = floor_scene(SHADOW_METRIC, "albedo = [0.5, 0.5, 0.5]", &light(""));
    let r = render_toml(&lit).1;
    assert_eq!((r.shadow, r.saved.shadow), (64 * 4, 64 * 28));
    // A large occluder at height 1 between the floor and the light (the camera is below it).
    let occluder = "[[objects]]\ntype = \"quad\"\norigin = [-20.0, 1.0, -20.0]\nedge_u = [40.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 40.0]\n";
    let dark = floor_scene(
        SHADOW_METRIC,
        "albedo = [0.5, 0.5, 0.5]",
        &(light("") + occluder),
    );
    let (img, r) = render_toml(&dark);
    assert_eq!((r.shadow, r.saved.shadow), (64 * 4, 64 * 28));
    assert_eq!(img.mean().max_element(), 0.0);
}

#[test]
fn the_penumbra_is_not_cut_short() {
    // An occluder edge through the middle of the view: points near it see part
    // of the light, so their sets run to the full budget.
    let edge = "[[objects]]\ntype = \"quad\"\norigin = [-20.0, 1.0, -20.0]\nedge_u = [20.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 40.0]\n";
    let toml = floor_scene(
        SHADOW_METRIC,
        "albedo = [0.5, 0.5, 0.5]",
        &(light("") + edge),
    );
    let r = render_toml(&toml).1;
    // Every set either stopped at k (saving 28) or ran to all 32 rays.
    assert_eq!(r.shadow + r.saved.shadow, 64 * 32);
    assert_eq!(r.saved.shadow % 28, 0);
    let full_sets = 64 - r.saved.shadow / 28;
    assert!(
        full_sets >= 8,
        "penumbra points trace all 32 rays ({full_sets} sets did)"
    );
}

#[test]
fn the_pixel_metric_stops_primary_rays_on_uniform_pixels() {
    let toml = floor_scene(
        "spp = 16\ndistribution = \"jitter\"\nmetric = true\npixel_metric = true\nmetric_min_rays = 4\nbackground = [1.0, 1.0, 1.0]",
        "albedo = [0.0, 0.0, 0.0]\nreflectivity = 1.0\nglossiness = 0.0",
        "",
    );
    let r = render_toml(&toml).1;
    assert_eq!((r.primary, r.saved.primary), (64 * 4, 64 * 12));
    let without = toml.replace("pixel_metric = true", "pixel_metric = false");
    assert_eq!(render_toml(&without).1.primary, 64 * 16);
}

#[test]
fn each_metric_is_switched_on_alone() {
    // A glossy, partly diffuse floor under a light off to the side: every
    // reflection set sees the black background (uniform, so it stops at α)
    // and every shadow set reaches the light (so it stops at k).
    let render = |switches: &str| {
        let toml = floor_scene(
            &format!(
                "reflection_rays = 16\nshadow_rays = 32\ndistribution = \"jitter\"\n\
                 metric_min_rays = 4\nshadow_metric_rays = 4\n{switches}"
            ),
            "albedo = [0.5, 0.5, 0.5]\nreflectivity = 0.5\nglossiness = 0.3",
            &light("").replace("origin = [-0.5,", "origin = [20.0,"),
        );
        render_toml(&toml)
    };
    let both = render("metric = true").1;
    assert_eq!(
        (both.saved.reflection, both.saved.shadow),
        (64 * 12, 64 * 28)
    );
    let reflections = render("metric = true\nshadow_metric = false").1;
    assert_eq!(
        (reflections.saved.reflection, reflections.saved.shadow),
        (64 * 12, 0)
    );
    assert_eq!(reflections.shadow, 64 * 32);
    let shadows = render("metric = true\nreflection_metric = false").1;
    assert_eq!(
        (shadows.saved.reflection, shadows.saved.shadow),
        (0, 64 * 28)
    );
    assert_eq!(shadows.reflection, 64 * 16);
    // With every rule off the metric is off: the same pixels, bit for bit.
    let (none, _) = render("metric = true\nreflection_metric = false\nshadow_metric = false");
    let (off, _) = render("metric = false");
    let bits = |img: &penumbra::render::Image| -> Vec<u32> {
        img.pixels
            .iter()
            .flat_map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&none), bits(&off));
    assert!(off.mean().max_element() > 0.0, "the floor is lit");
}
