//! Known-answer tests: rendered radiance against closed-form values.

mod common;

use std::f32::consts::PI;

use common::*;
use penumbra::math::{Rgb, Vec3};

/// A camera straight above the origin looking down, 11x11 pixels: the centre
/// pixel's single grid ray hits the floor exactly at the origin. It sits low,
/// below every light, since light surfaces are visible and would hide the floor.
fn looking_down(extra: &str) -> String {
    format!(
        r#"
[render]
width = 11
height = 11
max_depth = 3

[camera]
position = [0.0, 0.5, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 10

[materials.floor]
albedo = [0.5, 0.25, 0.1]

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

fn centre(toml: &str) -> Rgb {
    let (img, _) = render_toml(toml);
    img.get(5, 5)
}

fn assert_close(got: Rgb, want: Rgb, rel: f32) {
    let err = ((got - want).abs() / want.max(Rgb::splat(1e-6))).max_element();
    assert!(
        err <= rel,
        "got {got:?}, want {want:?} (relative error {err})"
    );
}

#[test]
fn point_light_at_the_foot_gives_rho_i_over_pi_h2() {
    let h = 2.0;
    let i = 10.0;
    let toml = looking_down(&format!(
        "[[lights]]\ntype = \"point\"\nposition = [0.0, {h}, 0.0]\nintensity = [{i}, {i}, {i}]\n"
    ));
    let want = Rgb::new(0.5, 0.25, 0.1) * i / (PI * h * h);
    assert_close(centre(&toml), want, 1e-4);
}

#[test]
fn point_light_off_axis_follows_cosine_over_r2() {
    // Light at (x, h): irradiance I cos θ / r² = I h / r³.
    let (x, h, i) = (1.5f32, 2.0f32, 8.0f32);
    let toml = looking_down(&format!(
        "[[lights]]\ntype = \"point\"\nposition = [{x}, {h}, 0.0]\nintensity = [{i}, {i}, {i}]\n"
    ));
    let r = (x * x + h * h).sqrt();
    let want = Rgb::new(0.5, 0.25, 0.1) / PI * (i * h / (r * r * r));
    assert_close(centre(&toml), want, 1e-4);
}

#[test]
fn sphere_light_with_one_ray_is_exact() {
    // An unoccluded sphere light fully above the horizon: E = L π (R/d)² cos θ.
    let (d, r, l) = (2.5f32, 0.4f32, 6.0f32);
    let toml = looking_down(&format!(
        "[[lights]]\ntype = \"sphere\"\ncenter = [0.0, {d}, 0.0]\nradius = {r}\nradiance = [{l}, {l}, {l}]\nmodel = \"thesis\"\n"
    ));
    let want = Rgb::new(0.5, 0.25, 0.1) / PI * (l * PI * (r / d) * (r / d));
    assert_close(centre(&toml), want, 1e-4);
}

/// Irradiance at the origin (normal +y) from a polygon of constant radiance
/// `l`: E = l/2 · Σ Θ_i (n · unit(v_i × v_{i+1})), the classic contour integral.
fn polygon_irradiance(vertices: &[Vec3], l: f32) -> f32 {
    let n = Vec3::Y;
    let mut sum = 0.0;
    for k in 0..vertices.len() {
        let a = vertices[k].normalize();
        let b = vertices[(k + 1) % vertices.len()].normalize();
        let theta = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += theta * n.dot(a.cross(b).normalize());
    }
    0.5 * l * sum.abs()
}

#[test]
fn surface_model_converges_to_rectangle_irradiance() {
    let l = 10.0;
    let (o, eu, ev) = (
        Vec3::new(-0.3, 1.5, -0.8),
        Vec3::new(1.2, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.9),
    );
    let light = format!(
        "[[lights]]\ntype = \"rect\"\norigin = {:?}\nedge_u = {:?}\nedge_v = {:?}\nradiance = [{l}, {l}, {l}]\nmodel = \"surface\"\nshadow_rays = 4096\nshadow_distribution = \"jitter\"\n",
        o.to_array(),
        eu.to_array(),
        ev.to_array()
    );
    // The light faces down: edge_u × edge_v = (0, -1.08, 0).
    let e = polygon_irradiance(&[o, o + eu, o + eu + ev, o + ev], l);
    let want = Rgb::new(0.5, 0.25, 0.1) / PI * e;
    assert_close(centre(&looking_down(&light)), want, 5e-3);
}

#[test]
fn surface_model_converges_for_disk_and_sphere_lights() {
    let l = 5.0;
    // Disk of radius a facing down at height h above the point: E = π L a² / (h² + a²).
    let (a, h) = (0.7f32, 1.3f32);
    let disk = format!(
        "[[lights]]\ntype = \"disk\"\ncenter = [0.0, {h}, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = {a}\nradiance = [{l}, {l}, {l}]\nshadow_rays = 4096\nshadow_distribution = \"jitter\"\n"
    );
    let want = Rgb::new(0.5, 0.25, 0.1) / PI * (PI * l * a * a / (h * h + a * a));
    assert_close(centre(&looking_down(&disk)), want, 5e-3);
    // A sphere light off to the side, fully above the horizon.
    let (c, r) = (Vec3::new(0.8, 1.6, 0.3), 0.5f32);
    let sphere = format!(
        "[[lights]]\ntype = \"sphere\"\ncenter = {:?}\nradius = {r}\nradiance = [{l}, {l}, {l}]\nshadow_rays = 4096\nshadow_distribution = \"jitter\"\n",
        c.to_array()
    );
    let cos = c.normalize().y;
    let want = Rgb::new(0.5, 0.25, 0.1) / PI * (l * PI * r * r / c.length_squared() * cos);
    assert_close(centre(&looking_down(&sphere)), want, 5e-3);
}

#[test]
fn perfect_mirror_shows_the_background_exactly() {
    let toml = r#"
[render]
width = 9
height = 9
background = [0.3, 0.6, 0.9]

[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 10

[materials.mirror]
albedo = [0.0, 0.0, 0.0]
reflectivity = 1.0

[[objects]]
type = "quad"
material = "mirror"
origin = [-5.0, -5.0, 0.0]
edge_u = [10.0, 0.0, 0.0]
edge_v = [0.0, 10.0, 0.0]
"#;
    let (img, stats) = render_toml(toml);
    assert_eq!(img.get(4, 4), Rgb::new(0.3, 0.6, 0.9));
    assert_eq!(stats.reflection, 81, "one mirror ray per pixel");
}

#[test]
fn glass_slab_at_normal_incidence_transmits_one_minus_fresnel_squared() {
    // A slab of thickness 0.1, max depth 2: the camera ray refracts in and out;
    // each interface transmits 1 - F with F = 0.04 at normal incidence; the
    // background behind has radiance 1. Fresnel reflections see black.
    let toml = r#"
[render]
width = 9
height = 9
max_depth = 2
background = [1.0, 1.0, 1.0]

[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov = 5

[materials.glass]
albedo = [0.0, 0.0, 0.0]
transparency = 1.0
ior = 1.5
translucency = 0.0

[materials.black]
albedo = [0.0, 0.0, 0.0]

[[objects]]
type = "quad"
material = "glass"
origin = [-5.0, -5.0, 0.0]
edge_u = [10.0, 0.0, 0.0]
edge_v = [0.0, 10.0, 0.0]

[[objects]]
type = "quad"
material = "glass"
origin = [-5.0, -5.0, -0.1]
edge_u = [0.0, 10.0, 0.0]
edge_v = [10.0, 0.0, 0.0]

# A black wall behind the camera so the Fresnel reflections add nothing.
[[objects]]
type = "quad"
material = "black"
origin = [-50.0, -50.0, 10.0]
edge_u = [100.0, 0.0, 0.0]
edge_v = [0.0, 100.0, 0.0]
"#;
    let (img, _) = render_toml(toml);
    let want = (1.0f32 - 0.04) * (1.0 - 0.04);
    assert_close(img.get(4, 4), Rgb::splat(want), 1e-3);
}

#[test]
fn energy_is_never_created() {
    // A closed white room lit by one light: every pixel is bounded by the
    // brightest possible single bounce, and mirrors/glass only redistribute.
    let toml = r#"
[render]
width = 24
height = 24
max_depth = 6
shadow_rays = 4
reflection_rays = 2
refraction_rays = 2

[camera]
position = [0.0, 1.0, 2.5]
look_at = [0.0, 1.0, 0.0]
fov = 60

[materials.white]
albedo = [1.0, 1.0, 1.0]

[materials.mirror]
albedo = [0.0, 0.0, 0.0]
reflectivity = 1.0
glossiness = 0.1

[materials.glass]
albedo = [0.0, 0.0, 0.0]
transparency = 1.0
translucency = 0.05

[[objects]]
type = "sphere"
material = "mirror"
center = [-0.5, 0.5, 0.0]
radius = 0.4

[[objects]]
type = "sphere"
material = "glass"
center = [0.5, 0.5, 0.0]
radius = 0.4

[[objects]]
type = "quad"
material = "white"
origin = [-3.0, 0.0, -3.0]
edge_u = [0.0, 0.0, 6.0]
edge_v = [6.0, 0.0, 0.0]

[[lights]]
type = "point"
position = [0.0, 2.0, 1.0]
intensity = [1.0, 1.0, 1.0]
"#;
    let (img, _) = render_toml(toml);
    // The brightest diffuse point: albedo/π · I / r² with r ≥ 1 (light at height 2, floor at 0... r ≥ 2).
    let bound = 1.0 / PI * 1.0 / 4.0;
    for p in &img.pixels {
        assert!(
            p.max_element() <= bound * 1.0001,
            "pixel {p:?} exceeds the single-bounce bound {bound}"
        );
    }
}

/// A material of another model plugs in by name: the floor as Mitsuba's
/// `diffuse` of reflectance ρ under a point light at height h renders
/// ρ I / (π h²), through the Whitted integrator; seen from below, the
/// one-sided model is black.
#[test]
fn a_diffuse_floor_gives_rho_i_over_pi_h2() {
    let (h, i) = (2.0, 10.0);
    let rho = Rgb::new(0.5, 0.25, 0.1);
    let light = format!(
        "[[lights]]\ntype = \"point\"\nposition = [0.0, {h}, 0.0]\nintensity = [{i}, {i}, {i}]\n"
    );
    let toml = looking_down(&light).replace(
        "[materials.floor]\nalbedo = [0.5, 0.25, 0.1]",
        "[materials.floor]\ntype = \"diffuse\"\nreflectance = [0.5, 0.25, 0.1]",
    );
    assert!(toml.contains("\"diffuse\""));
    assert_close(centre(&toml), rho * (i / (PI * h * h)), 1e-4);
    // edge_u × edge_v is the quad's normal: with the edges swapped the
    // floor faces down, away from the camera and the light.
    let flipped = toml.replace(
        "edge_u = [0.0, 0.0, 100.0]\nedge_v = [100.0, 0.0, 0.0]",
        "edge_u = [100.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 100.0]",
    );
    assert_eq!(centre(&flipped), Rgb::ZERO);
    // Its parameters are checked as any model's.
    let bad = toml.replace(
        "reflectance = [0.5, 0.25, 0.1]",
        "reflectance = [0.5, 1.5, 0.1]",
    );
    let e = try_scene(&bad).err().expect("refused").to_string();
    assert!(
        e.contains("materials.floor.reflectance: must not exceed 1"),
        "{e}"
    );
    let bad = toml.replace(
        "reflectance = [0.5, 0.25, 0.1]",
        "albedo = [0.5, 0.25, 0.1]",
    );
    let e = try_scene(&bad).err().expect("refused").to_string();
    assert!(
        e.contains(
            "`albedo` does not apply to a diffuse material; a diffuse material takes: reflectance"
        ),
        "{e}"
    );
}

/// Emitters live on shapes: a quad of an emitting material, and the same
/// rectangle as a mesh of two triangles (sampled by area through its
/// table), light the floor with the rectangle's exact irradiance, as a
/// rectangle light does.
#[test]
fn emitting_objects_light_like_a_light_of_their_shape() {
    let l = 10.0;
    let (o, eu, ev) = (
        Vec3::new(-0.3, 1.5, -0.8),
        Vec3::new(1.2, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.9),
    );
    let e = polygon_irradiance(&[o, o + eu, o + eu + ev, o + ev], l);
    let want = Rgb::new(0.5, 0.25, 0.1) / PI * e;
    let sets = "[render]\nshadow_rays = 4096\nshadow_distribution = \"jitter\"\n";
    let glow = format!("[materials.glow]\nalbedo = [0, 0, 0]\nemission = [{l}, {l}, {l}]\n");
    let quad = format!(
        "{glow}[[objects]]\ntype = \"quad\"\nmaterial = \"glow\"\norigin = {:?}\nedge_u = {:?}\nedge_v = {:?}\n",
        o.to_array(),
        eu.to_array(),
        ev.to_array()
    );
    let scene = |extra: &str| looking_down(extra).replace("[render]\n", sets);
    assert_close(centre(&scene(&quad)), want, 5e-3);

    let dir = tempfile::tempdir().unwrap();
    let [a, b, c, d] = [o, o + eu, o + eu + ev, o + ev].map(|v| v.to_array());
    // Faces wound as the quad, so that they face down too.
    let obj = format!(
        "v {} {} {}\nv {} {} {}\nv {} {} {}\nv {} {} {}\nf 1 2 3\nf 1 3 4\n",
        a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]
    );
    let path = dir.path().join("glow.obj");
    std::fs::write(&path, obj).unwrap();
    let mesh = format!(
        "{glow}[[objects]]\ntype = \"mesh\"\nmaterial = \"glow\"\npath = {:?}\n",
        path.to_str().unwrap()
    );
    assert_close(centre(&scene(&mesh)), want, 5e-3);

    // A mesh of no area cannot emit; an emitting object that moves must
    // keep its proportions.
    let stretching = format!("{quad}transform_end = {{ scale = [2, 1, 1] }}\n");
    let e = try_scene(&scene(&stretching))
        .err()
        .expect("refused")
        .to_string();
    assert!(
        e.contains(
            "materials.glow.emission: an emitting quad that moves or is placed by an \
             instance must keep its proportions"
        ),
        "{e}"
    );
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    let e = try_scene(&scene(&mesh)).err().expect("refused").to_string();
    assert!(e.contains("an emitting mesh must have a surface"), "{e}");
}

/// The mean of `f` over [0, 1] and its variance there (the midpoint rule
/// over 4,000 points).
fn mean_and_variance(f: impl Fn(f32) -> f32) -> (f32, f32) {
    let n = 4000;
    let v: Vec<f64> = (0..n)
        .map(|k| f64::from(f((k as f32 + 0.5) / n as f32)))
        .collect();
    let mean = v.iter().sum::<f64>() / f64::from(n);
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / f64::from(n);
    (mean as f32, var as f32)
}

/// A moving emitter is sampled where it is at the ray's time: a quad light
/// sliding 1.5 along x over the shutter (and a sphere light moving and
/// growing) lights the floor's centre with the time average of its exact
/// irradiance, within 3σ of the primary rays' times (the shadow rays add
/// little beside them); the irradiance at shutter open is far from it.
#[test]
fn a_moving_emitter_gives_the_time_averaged_irradiance() {
    let l = 10.0;
    let (o, eu, ev) = (
        Vec3::new(-0.3, 1.5, -0.6),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.9),
    );
    let slide = Vec3::new(1.5, 0.0, 0.0);
    let at = |t: f32| {
        let o = o + t * slide;
        polygon_irradiance(&[o, o + eu, o + eu + ev, o + ev], l)
    };
    let (mean, var) = mean_and_variance(at);
    let spp = 256.0;
    let rho = Rgb::new(0.5, 0.25, 0.1) / PI;
    let sigma = (var / spp).sqrt() + 2e-3 * mean;
    let sets = "[render]\nspp = 256\nshadow_rays = 64\nshadow_distribution = \"jitter\"\n";
    let glow = format!("[materials.glow]\nalbedo = [0, 0, 0]\nemission = [{l}, {l}, {l}]\n");
    let quad = format!(
        "{glow}[[objects]]\ntype = \"quad\"\nmaterial = \"glow\"\norigin = {:?}\nedge_u = {:?}\n\
         edge_v = {:?}\ntransform_end = {{ translate = {:?} }}\n",
        o.to_array(),
        eu.to_array(),
        ev.to_array(),
        slide.to_array(),
    );
    let got = centre(&looking_down(&quad).replace("[render]\n", sets)).r / rho.r;
    assert!(
        (got - mean).abs() < 3.0 * sigma,
        "{got} vs {mean} ± {sigma}"
    );
    assert!(
        (at(0.0) - mean).abs() > 20.0 * sigma,
        "the light moves far enough: {} vs {mean} ± {sigma}",
        at(0.0)
    );

    // A sphere of radius 0.3 at (−0.8, 1.2, 0) at shutter open, moving
    // to (0.6, 1.2, 0) and doubling: E = L π sin²θ cos φ = L π r² h / d³.
    let sphere = |t: f32| {
        let c = Vec3::new(-0.8 + 1.4 * t, 1.2, 0.0);
        let r = 0.3 * (1.0 + t);
        l * PI * r * r * c.y / c.length().powi(3)
    };
    let (mean, var) = mean_and_variance(sphere);
    let sigma = (var / spp).sqrt() + 2e-3 * mean;
    let ball = format!(
        "{glow}[[objects]]\ntype = \"sphere\"\nmaterial = \"glow\"\ncenter = [0, 0, 0]\nradius = 0.3\n\
         transform = {{ translate = [-0.8, 1.2, 0] }}\n\
         transform_end = {{ scale = 2, translate = [0.6, 1.2, 0] }}\n"
    );
    let got = centre(&looking_down(&ball).replace("[render]\n", sets)).r / rho.r;
    assert!(
        (got - mean).abs() < 3.0 * sigma,
        "{got} vs {mean} ± {sigma}"
    );
}

/// Each instance of a group holding an emitting shape is an emitter of
/// its own (where Mitsuba refuses an emitter in a group): a quad in a
/// group, placed twice (once translated, once sheared and stretched along
/// x, which keeps a flat light uniform), lights the floor with the sum of
/// the two placed rectangles' exact irradiance.
#[test]
fn each_instance_of_an_emitting_group_is_an_emitter() {
    let l = 10.0;
    let glow = format!("[materials.glow]\nalbedo = [0, 0, 0]\nemission = [{l}, {l}, {l}]\n");
    let group = format!(
        "{glow}[[groups.lamp.objects]]\ntype = \"quad\"\nmaterial = \"glow\"\n\
         origin = [0, 0, 0]\nedge_u = [0.5, 0, 0]\nedge_v = [0, 0, 0.4]\n\
         [[objects]]\ntype = \"instance\"\ngroup = \"lamp\"\ntransform = {{ translate = [-0.7, 1.5, -0.2] }}\n\
         [[objects]]\ntype = \"instance\"\ngroup = \"lamp\"\n\
         transform = {{ matrix = [[1.5, 0.4, 0, 0.2], [0, 1, 0, 1.2], [0, 0, 1, -0.3], [0, 0, 0, 1]] }}\n"
    );
    let first = [
        Vec3::new(-0.7, 1.5, -0.2),
        Vec3::new(-0.2, 1.5, -0.2),
        Vec3::new(-0.2, 1.5, 0.2),
        Vec3::new(-0.7, 1.5, 0.2),
    ];
    let place = |p: Vec3| Vec3::new(1.5 * p.x + 0.4 * p.y + 0.2, p.y + 1.2, p.z - 0.3);
    let corners = [
        Vec3::ZERO,
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(0.5, 0.0, 0.4),
        Vec3::new(0.0, 0.0, 0.4),
    ];
    let second = corners.map(place);
    let e = polygon_irradiance(&first, l) + polygon_irradiance(&second, l);
    let want = Rgb::new(0.5, 0.25, 0.1) / PI * e;
    let sets = "[render]\nshadow_rays = 4096\nshadow_distribution = \"jitter\"\n";
    let toml = looking_down(&group).replace("[render]\n", sets);
    assert_close(centre(&toml), want, 5e-3);
    let scene = scene(&toml);
    assert_eq!(scene.emitters.len(), 2);
}

/// Any shape can carry an emitter: a quad holding an `area` emitter child
/// in the description (as Mitsuba's scenes attach emitters to shapes)
/// lights the floor as the rectangle light of the same quad does; a scene
/// names `area` only on a shape. (Such a shape casts shadows, as any
/// shape: under the thesis model, whose targets leave the light's
/// surface, it would shadow some of its own, which is why a scene's
/// lights do not cast shadows.)
#[test]
fn a_shape_carrying_an_area_emitter_is_a_light() {
    use penumbra::description::{Kind, Located, Node, Origin, Value};
    use penumbra::scene::{LoadOptions, SceneSource};
    let quad = "origin = [-0.3, 1.5, -0.8]\nedge_u = [1.2, 0.0, 0.0]\nedge_v = [0.0, 0.0, 0.9]\n";
    let model = "surface";
    let light = format!(
        "[[lights]]\ntype = \"rect\"\n{quad}radiance = [10, 10, 10]\nmodel = \"{model}\"\nshadow_rays = 16\n"
    );
    let want = centre(&looking_down(&light));
    let object = format!("[[objects]]\ntype = \"quad\"\n{quad}");
    let here = std::path::Path::new(".");
    let text = looking_down(&object);
    let opts = LoadOptions::default();
    let mut src = SceneSource::from_toml(&text, here, here, &opts).unwrap();
    let origin = Origin::unlocated(Default::default());
    let mut area = Node::new(Kind::Emitter, "area", origin.clone());
    let value = |v: Value| Located::new(v, origin.clone());
    let ten = || value(Value::Int(10));
    area.set_prop("radiance", value(Value::Array(vec![ten(), ten(), ten()])));
    area.set_prop("model", value(Value::String(model.into())));
    area.set_prop("shadow_rays", value(Value::Int(16)));
    let shapes = src
        .root
        .children
        .iter_mut()
        .filter(|c| c.kind == Kind::Shape);
    shapes.last().unwrap().children.push(area);
    let scene = src.build().unwrap();
    let (img, _) = render_scene(&scene, 2);
    assert_close(img.get(5, 5), want, 1e-6);
    assert_eq!(scene.emitters.len(), 1);
    let bad = looking_down("[[lights]]\ntype = \"area\"\nradiance = [1, 1, 1]\n");
    let e = try_scene(&bad).err().expect("refused").to_string();
    assert!(
        e.contains(
            "unknown light type `area`; valid choices are: point, constant, spot, projector, directional, envmap, sky, rect, sphere, quad"
        ),
        "{e}"
    );
}

/// A camera above a horizontal quad at the origin looking straight down
/// (the centre pixel's ray meets it at normal incidence), with `material`
/// the quad's and `extra` appended.
fn above_a_quad(material: &str, extra: &str) -> String {
    format!(
        r#"
[render]
width = 11
height = 11
max_depth = 3
{extra}
[camera]
position = [0.0, 0.5, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 10

[materials.quad]
{material}

[[objects]]
type = "quad"
material = "quad"
origin = [-50.0, 0.0, -50.0]
edge_u = [0.0, 0.0, 100.0]
edge_v = [100.0, 0.0, 0.0]
"#
    )
}

/// A `conductor` of `material = "none"` is a perfect mirror: looking down
/// at it, the camera sees a diffuse ceiling lit by a point light between
/// them with the ceiling's exact radiance ρ I / (π d²); gold sees it times
/// its Fresnel reflectance at normal incidence; from behind the one-sided
/// mirror is black.
#[test]
fn a_conductor_mirrors_a_lit_diffuse_ceiling_exactly() {
    let (rho, i, d) = (Rgb::new(0.6, 0.3, 0.2), 5.0f32, 1.0f32);
    let ceiling = format!(
        "[materials.ceiling]\ntype = \"diffuse\"\nreflectance = [0.6, 0.3, 0.2]\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"ceiling\"\norigin = [-50.0, 2.0, -50.0]\n\
         edge_u = [100.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 100.0]\n\
         [[lights]]\ntype = \"point\"\nposition = [0.0, {}, 0.0]\nintensity = [{i}, {i}, {i}]\n",
        2.0 - d
    );
    let mirror = above_a_quad("type = \"conductor\"\nmaterial = \"none\"", "") + &ceiling;
    let want = rho * (i / (PI * d * d));
    assert_close(centre(&mirror), want, 1e-4);
    // Gold: F = ((η − 1)² + k²) / ((η + 1)² + k²) per channel.
    let gold = above_a_quad("type = \"conductor\"\nmaterial = \"Au\"", "") + &ceiling;
    let f = |eta: f32, k: f32| ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k);
    // Gold's index as Mitsuba 3.9's RGB variants give it.
    let fresnel = Rgb::new(
        f(0.143036, 3.983),
        f(0.375307, 2.38556),
        f(1.44205, 1.60336),
    );
    assert_close(centre(&gold), want * fresnel, 1e-4);
    // Its normal turned down (the ceiling's edges are written the other
    // way round, so only the mirror's change).
    let behind = mirror.replace(
        "edge_u = [0.0, 0.0, 100.0]\nedge_v = [100.0, 0.0, 0.0]",
        "edge_u = [100.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 100.0]",
    );
    assert_ne!(behind, mirror);
    assert_eq!(centre(&behind), Rgb::ZERO);
}

/// A `dielectric` slab (two parallel quads, normals outward) over a
/// constant background L, seen at normal incidence through the Whitted
/// integrator with `max_depth = 3`: the camera sees the top's reflection
/// F L, and what crosses both faces, (1 − F)² L, plus what crosses after
/// one inner round trip within the depth, (1 − F)² F L — the radiance
/// scales 1/η² entering and η² leaving cancel. F = ((η − 1)/(η + 1))² for
/// bk7 in air, Mitsuba's defaults.
#[test]
fn a_dielectric_slab_passes_the_fresnel_transmittance() {
    let l = 2.0f32;
    let bottom =
        "[[objects]]\ntype = \"quad\"\nmaterial = \"quad\"\norigin = [-50.0, -0.2, -50.0]\n\
                  edge_u = [100.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 100.0]\n";
    let toml = above_a_quad(
        "type = \"dielectric\"",
        &format!("background = [{l}, {l}, {l}]"),
    ) + bottom;
    let eta = 1.5046f32 / 1.000277;
    let f = ((eta - 1.0) / (eta + 1.0)).powi(2);
    let want = f * l + (1.0 - f) * (1.0 - f) * (1.0 + f) * l;
    assert_close(centre(&toml), Rgb::splat(want), 1e-4);
    // Water, named, and a tinted transmission (once in, once out).
    let water = toml.replace(
        "type = \"dielectric\"",
        "type = \"dielectric\"\nint_ior = \"water\"\nspecular_transmittance = [0.5, 1.0, 1.0]",
    );
    let eta = 1.333f32 / 1.000277;
    let f = ((eta - 1.0) / (eta + 1.0)).powi(2);
    let through = |t: f32| f * l + t * t * (1.0 - f) * (1.0 - f) * (1.0 + f) * l;
    assert_close(
        centre(&water),
        Rgb::new(through(0.5), through(1.0), through(1.0)),
        1e-4,
    );
    // A thin sheet (one quad) reflects R' = 2F/(1 + F) and passes the rest.
    let thin = above_a_quad(
        "type = \"thindielectric\"\nint_ior = 1.5\next_ior = 1.0",
        &format!("background = [{l}, {l}, {l}]"),
    );
    assert_close(centre(&thin), Rgb::splat(l), 1e-5);
}

/// The new materials' keys are checked where the scene writes them: a name
/// that is not an index's, a negative roughness, a key of another model.
#[test]
fn material_keys_are_checked_at_their_place() {
    for (material, want) in [
        (
            "type = \"dielectric\"\nint_ior = \"glass\"",
            "materials.quad.int_ior: unknown index of refraction `glass`; valid choices are: vacuum, helium,",
        ),
        (
            "type = \"roughconductor\"\nalpha = -0.1",
            "materials.quad.alpha: must be between 0 and 100, got -0.1",
        ),
        (
            "type = \"conductor\"\nint_ior = 1.5",
            "`int_ior` does not apply to a conductor material; a conductor material takes: material, eta, k, specular_reflectance",
        ),
        (
            "type = \"roughdielectric\"\nint_ior = 1.0\next_ior = \"vacuum\"",
            "materials.quad.int_ior: must differ from `ext_ior`",
        ),
    ] {
        let e = try_scene(&above_a_quad(material, ""))
            .err()
            .expect("refused")
            .to_string();
        assert!(e.contains(want), "{material}: {e}");
    }
}

/// A shadow ray crossing a mask of textured opacity keeps `1 − opacity` of
/// the light where it crosses: a point light straight above the floor's
/// centre, a mask quad between them whose checkerboard opacity is 0.2 on
/// one square and 0.7 on the other; moving the quad so that the ray crosses
/// the other square dims the floor by the other factor.
#[test]
fn a_textured_mask_lets_through_one_minus_its_opacity_where_crossed() {
    let (h, i) = (2.0, 10.0);
    let light = format!(
        "[[lights]]\ntype = \"point\"\nposition = [0.0, {h}, 0.0]\nintensity = [{i}, {i}, {i}]\n"
    );
    let mask = |x0: f32| {
        format!(
            r#"{light}
[materials.paint]
type = "diffuse"

[materials.leaf]
type = "mask"
opacity = {{ type = "checkerboard", color0 = [0.2, 0.2, 0.2], color1 = [0.7, 0.7, 0.7] }}
bsdf = "paint"

[[objects]]
type = "quad"
material = "leaf"
origin = [{x0}, 1.0, -0.25]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 2.0]
"#
        )
    };
    let open = centre(&looking_down(&light));
    let want = Rgb::new(0.5, 0.25, 0.1) * (i / (PI * h * h));
    assert_close(open, want, 1e-3);
    // Crossed at (u, v) = (0.125, 0.125), then at (0.625, 0.125). Read as
    // one value, a checkerboard has color1 in the first square and color0
    // in the second (Mitsuba's `eval_1`, squares swapped).
    assert_close(centre(&looking_down(&mask(-0.25))), want * 0.3, 1e-3);
    assert_close(centre(&looking_down(&mask(-1.25))), want * 0.8, 1e-3);
}

/// A light of a shape's type is that shape carrying an `area` emitter, of
/// the black `penumbra:light` material and casting no shadow: written out
/// as such an object, the scene renders the same bits. A light may take
/// any shape and set `casts_shadows` itself.
#[test]
fn a_light_of_a_shape_type_is_that_shape_with_an_area_emitter() {
    let quad = "origin = [-0.3, 1.5, -0.8]\nedge_u = [1.2, 0.0, 0.0]\nedge_v = [0.0, 0.0, 0.9]\n";
    let emitter = "radiance = [10, 10, 10]\nshadow_rays = 4\n";
    let light = looking_down(&format!("[[lights]]\ntype = \"rect\"\n{quad}{emitter}"));
    let object = looking_down(&format!(
        "[materials.\"penumbra:light\"]\nalbedo = [0, 0, 0]\nshininess = 0\nior = 1\nglossiness = 0\ntranslucency = 0\n\
         [[objects]]\ntype = \"quad\"\n{quad}casts_shadows = false\nmaterial = \"penumbra:light\"\n\
         emitter = {{ radiance = [10, 10, 10], shadow_rays = 4 }}\n"
    ));
    let bits = |toml: &str| {
        let (img, stats) = render_toml(toml);
        let px: Vec<u32> = (0..11 * 11)
            .flat_map(|i| img.get(i % 11, i / 11).to_array())
            .map(f32::to_bits)
            .collect();
        (px, stats.total())
    };
    let (a, b) = (bits(&light), bits(&object));
    assert_eq!(a, b);
    // Not vacuous: the floor is lit.
    assert!(centre(&light).max_element() > 0.1);

    // A tube light over the floor lights it; the lowered shape casts no
    // shadow unless the light says so.
    let tube = |casts: &str| {
        looking_down(&format!(
            "[[lights]]\ntype = \"cylinder\"\np0 = [-0.5, 1, 0]\np1 = [0.5, 1, 0]\nradius = 0.1\n\
             radiance = [5, 5, 5]\nshadow_rays = 16\n{casts}"
        ))
    };
    let scene = try_scene(&tube("")).unwrap();
    let lights: Vec<_> = scene
        .world
        .objects
        .iter()
        .filter(|o| o.emitter.is_some())
        .collect();
    assert_eq!(lights.len(), 1);
    assert!(!lights[0].casts_shadows);
    assert!(centre(&tube("")).max_element() > 0.01);
    let scene = try_scene(&tube("casts_shadows = true\n")).unwrap();
    assert!(scene
        .world
        .objects
        .iter()
        .any(|o| o.emitter.is_some() && o.casts_shadows));
}
