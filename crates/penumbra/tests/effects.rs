//! The stochastic effects behave as the thesis says they should.

mod common;

use common::*;

/// Vertical field of view (degrees) of a `width`×`height` image whose rows
/// span `span` units at `distance` (the tests use one-row-like strips).
fn fov_for(span: f32, distance: f32, width: u32, height: u32) -> f32 {
    let aspect = width as f32 / height as f32;
    2.0 * (0.5 * span / distance / aspect).atan().to_degrees()
}

/// A floor seen from above with a thin bar casting a shadow from `light`;
/// `occluder = false` leaves the bar out.
fn shadow_scene(light: &str, occluder: bool) -> String {
    // The camera sits below the light (which would hide the view) and above
    // the occluder's edge, so it sees the floor for x > 0 only: the half of
    // the penumbra outside the occluder's footprint.
    let fov = fov_for(SPAN, 2.5, 200, 5);
    let bar = if occluder {
        "[[objects]]\ntype = \"quad\"\norigin = [-20.0, 1.0, -20.0]\nedge_u = [20.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 40.0]\n"
    } else {
        ""
    };
    format!(
        r#"
[render]
width = 200
height = 5
shadow_rays = 64
distribution = "jitter"

[camera]
position = [0.0, 2.5, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = {fov}

[[objects]]
type = "quad"
origin = [-50.0, 0.0, -50.0]
edge_u = [0.0, 0.0, 100.0]
edge_v = [100.0, 0.0, 0.0]

# An occluder covering x < 0 at height 1.
{bar}
{light}
"#
    )
}

/// Width in units of the strip of floor the shadow tests look at.
const SPAN: f32 = 3.5;

/// Pixels of the middle row that are neither fully lit nor fully shadowed:
/// the ratio to the same scene without the occluder is the visible fraction.
fn penumbra_pixels(light: &str) -> usize {
    let (with, _) = render_toml(&shadow_scene(light, true));
    let (without, _) = render_toml(&shadow_scene(light, false));
    (0..with.width)
        .map(|x| with.get(x, 2).r / without.get(x, 2).r.max(1e-12))
        .filter(|&v| v > 0.02 && v < 0.98)
        .count()
}

fn rect_light(size: f32) -> String {
    format!(
        "[[lights]]\ntype = \"rect\"\norigin = [{o}, 3.0, {o}]\nedge_u = [{size}, 0.0, 0.0]\nedge_v = [0.0, 0.0, {size}]\nradiance = [5.0, 5.0, 5.0]\n",
        o = -size / 2.0
    )
}

#[test]
fn penumbra_grows_with_light_size_and_vanishes_for_a_point_light() {
    let point = penumbra_pixels(
        "[[lights]]\ntype = \"point\"\nposition = [0.0, 3.0, 0.0]\nintensity = [5.0, 5.0, 5.0]\n",
    );
    let small = penumbra_pixels(&rect_light(0.5));
    let large = penumbra_pixels(&rect_light(2.0));
    assert!(
        point <= 1,
        "a point light casts a hard shadow, got {point} partial pixels"
    );
    assert!(
        small >= 4,
        "a small area light casts a penumbra, got {small}"
    );
    assert!(
        large > 2 * small,
        "a 4x larger light casts a wider penumbra: {small} vs {large}"
    );
    // Similar triangles: penumbra width = size · occluder height / (light − occluder height)
    // = 2 · 1 / 2 = 1 unit, centred on x = 0; the visible half is 0.5 of the
    // SPAN units the 200 pixels cover.
    let expected = 0.5 / SPAN * 200.0;
    assert!(
        (large as f32 - expected).abs() < 0.25 * expected,
        "{large} vs ~{expected}"
    );
}

#[test]
fn thesis_model_also_softens_shadows() {
    let light = rect_light(2.0).replace("radiance", "model = \"thesis\"\nradiance");
    assert!(penumbra_pixels(&light) > 10);
}

/// Two bars, one on the focal plane and one far behind, seen through a lens.
fn edge_widths(aperture: f32) -> (usize, usize) {
    // The row spans tan ±0.4 around the view axis: the near edge (x = -0.5 at
    // distance 5) lands at pixel 45, the far one (x = 3 at distance 15) at 90.
    let fov = fov_for(0.8, 1.0, 120, 3);
    let toml = format!(
        r#"
[render]
width = 120
height = 3
spp = 64
distribution = "jitter"
background = [1.0, 1.0, 1.0]

[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = {fov}
aperture = {aperture}
focal_distance = 5.0

[materials.black]
albedo = [0.0, 0.0, 0.0]

# In focus: a black half-plane x < -0.5 at z = 0.
[[objects]]
type = "quad"
material = "black"
origin = [-10.0, -5.0, 0.0]
edge_u = [9.5, 0.0, 0.0]
edge_v = [0.0, 10.0, 0.0]

# Far behind: a black half-plane x > 3 at z = -10 (seen through the gap).
[[objects]]
type = "quad"
material = "black"
origin = [3.0, -50.0, -10.0]
edge_u = [50.0, 0.0, 0.0]
edge_v = [0.0, 100.0, 0.0]
"#
    );
    let (img, _) = render_toml(&toml);
    let row: Vec<f32> = (0..img.width).map(|x| img.get(x, 1).r).collect();
    let partial = |range: std::ops::Range<usize>| {
        row[range].iter().filter(|&&v| v > 0.02 && v < 0.98).count()
    };
    // The near edge projects left of centre, the far edge right of centre.
    (partial(0..60), partial(60..120))
}

#[test]
fn focal_plane_stays_sharp_while_far_objects_blur() {
    let (near_pin, far_pin) = edge_widths(0.0);
    let (near_lens, far_lens) = edge_widths(0.25);
    assert!(
        near_pin <= 1 && far_pin <= 1,
        "pinhole: every edge is sharp ({near_pin}, {far_pin})"
    );
    assert!(
        near_lens <= 1,
        "the focal plane stays sharp through the lens ({near_lens})"
    );
    assert!(
        far_lens >= 6,
        "a far edge blurs through the lens ({far_lens})"
    );
}

#[test]
fn moving_sphere_smear_matches_velocity_times_shutter() {
    // A sphere of radius 0.5 moving by 2 units along x over the frame, seen
    // from far away (nearly orthographic); the shutter is open for [0, 0.5].
    let fov = fov_for(5.0, 100.0, 400, 3);
    let toml = format!(
        r#"
[render]
width = 400
height = 3
spp = 64
distribution = "jitter"
background = [1.0, 1.0, 1.0]

[camera]
position = [0.0, 0.0, 100.0]
look_at = [0.0, 0.0, 0.0]
fov = {fov}
shutter = [0.0, 0.5]

[materials.black]
albedo = [0.0, 0.0, 0.0]

[[objects]]
type = "sphere"
material = "black"
center = [0.0, 0.0, 0.0]
radius = 0.5
transform = {{ translate = [-1.0, 0.0, 0.0] }}
transform_end = {{ translate = [1.0, 0.0, 0.0] }}
"#
    );
    let (img, _) = render_toml(&toml);
    // The view is 5 units wide (400 px): 80 px per unit.
    let covered: f32 = (0..img.width).map(|x| 1.0 - img.get(x, 1).r).sum();
    // Integrated darkness along the row = diameter × 80 px, whatever the motion;
    // the extent of the smear is diameter + velocity × shutter = 1 + 2 · 0.5 = 2 units.
    let extent = (0..img.width).filter(|&x| img.get(x, 1).r < 0.99).count() as f32;
    assert!((covered - 80.0).abs() < 4.0, "covered {covered}");
    assert!(
        (extent - 160.0).abs() < 6.0,
        "smear extent {extent} px, expected 160"
    );
}

fn mirror_scene(rays: u32, glossiness: f32) -> String {
    format!(
        r#"
[render]
width = 40
height = 30
reflection_rays = {rays}

[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]

[materials.floor]
albedo = [0.4, 0.4, 0.4]
reflectivity = 0.5
glossiness = {glossiness}

[materials.red]
albedo = [0.8, 0.1, 0.1]

[[objects]]
type = "quad"
material = "floor"
origin = [-5.0, 0.0, -5.0]
edge_u = [0.0, 0.0, 10.0]
edge_v = [10.0, 0.0, 0.0]

[[objects]]
type = "sphere"
material = "red"
center = [0.0, 0.6, 0.0]
radius = 0.6

[[lights]]
type = "point"
position = [2.0, 4.0, 2.0]
intensity = [20.0, 20.0, 20.0]
"#
    )
}

#[test]
fn glossiness_zero_reproduces_the_mirror_exactly() {
    let (mirror, _) = render_toml(&mirror_scene(1, 0.0));
    let (many, _) = render_toml(&mirror_scene(16, 0.0));
    assert!(mirror == many, "16 rays of radius 0 differ from the mirror");
    let (glossy, _) = render_toml(&mirror_scene(16, 0.2));
    assert!(mirror != glossy, "glossiness 0.2 should blur");
}

#[test]
fn ray_counts_are_the_exact_product_of_the_budgets() {
    // A floor filling the view under a rectangle light: every pixel sample
    // hits the floor and traces every shadow ray (nothing is below a horizon).
    let counts = |spp: u32, shadow: u32| {
        let toml = format!(
            "[render]\nwidth = 20\nheight = 10\nspp = {spp}\nshadow_rays = {shadow}\ndistribution = \"jitter\"\n\
             [camera]\nposition = [0.0, 2.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
             [[objects]]\ntype = \"quad\"\norigin = [-50.0, 0.0, -50.0]\nedge_u = [0.0, 0.0, 100.0]\nedge_v = [100.0, 0.0, 0.0]\n\
             [[lights]]\ntype = \"rect\"\norigin = [-0.5, 3.0, -0.5]\nedge_u = [1.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 1.0]\nradiance = [1.0, 1.0, 1.0]\n"
        );
        render_toml(&toml).1
    };
    for (spp, shadow) in [(1u64, 1u64), (4, 1), (1, 9), (4, 16), (9, 32)] {
        let r = counts(spp as u32, shadow as u32);
        assert_eq!(r.primary, 200 * spp);
        assert_eq!(
            r.shadow,
            200 * spp * shadow,
            "spp {spp}, shadow rays {shadow}"
        );
        assert_eq!(r.reflection + r.refraction, 0);
    }
}

#[test]
fn mutual_reflection_grows_exponentially() {
    // Inside a closed box of glossy mirrors every ray hits a mirror: with N
    // rays per reflection and depth 3, each pixel traces N + N² + N³.
    let box_scene = |n: u32| {
        let mut toml = format!(
            "[render]\nwidth = 4\nheight = 4\nmax_depth = 3\nreflection_rays = {n}\n[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\n[materials.m]\nalbedo = [0.0, 0.0, 0.0]\nreflectivity = 1.0\nglossiness = 0.1\n"
        );
        let quads: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
            ([-1.0, -1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
            ([-1.0, -1.0, 1.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0]),
            ([-1.0, -1.0, -1.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]),
            ([1.0, -1.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0]),
            ([-1.0, -1.0, -1.0], [0.0, 0.0, 2.0], [2.0, 0.0, 0.0]),
            ([-1.0, 1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0]),
        ];
        for (o, u, v) in quads {
            toml += &format!("[[objects]]\ntype = \"quad\"\nmaterial = \"m\"\norigin = {o:?}\nedge_u = {u:?}\nedge_v = {v:?}\n");
        }
        render_toml(&toml).1.reflection
    };
    for n in [1u64, 2, 4] {
        assert_eq!(box_scene(n as u32), 16 * (n + n * n + n * n * n), "N = {n}");
    }
}
