//! The path tracer against closed-form answers: a closed box whose walls
//! all emit and reflect diffusely holds a radiance known at every depth.

mod common;

use common::*;
use penumbra::math::Rgb;
use penumbra::render::Image;
use penumbra::sampling::PathSampler;

/// A camera inside the cube [−1, 1]³ whose six walls face inward, each of
/// albedo `rho` (Lambertian) emitting radiance 1. Every wall is an area
/// light, sampled by next-event estimation and met by BSDF samples.
fn closed_box(rho: f32, render: &str) -> String {
    let walls = [
        ([-1, -1, -1], [0, 0, 2], [2, 0, 0]),
        ([-1, 1, -1], [2, 0, 0], [0, 0, 2]),
        ([-1, -1, -1], [0, 2, 0], [0, 0, 2]),
        ([1, -1, -1], [0, 0, 2], [0, 2, 0]),
        ([-1, -1, -1], [2, 0, 0], [0, 2, 0]),
        ([-1, -1, 1], [0, 2, 0], [2, 0, 0]),
    ];
    let mut s = format!(
        "[render]\nwidth = 16\nheight = 16\nintegrator = \"path\"\nseed = 3\n{render}\n\
         [camera]\nposition = [0.1, 0.2, 0.5]\nlook_at = [0.0, 0.0, -1.0]\nfov = 70\n\n\
         [materials.wall]\nalbedo = [{rho}, {rho}, {rho}]\nemission = [1, 1, 1]\n"
    );
    for (o, u, v) in walls {
        s += &format!(
            "\n[[objects]]\ntype = \"quad\"\nmaterial = \"wall\"\norigin = {o:?}\n\
             edge_u = {u:?}\nedge_v = {v:?}\n"
        );
    }
    s
}

fn mean(img: &Image) -> Rgb {
    let n = (img.width * img.height) as f32;
    let mut sum = Rgb::ZERO;
    for y in 0..img.height {
        for x in 0..img.width {
            sum += img.get(x, y);
        }
    }
    sum / n
}

fn assert_near(got: Rgb, want: f32, rel: f32, what: &str) {
    let err = (got - Rgb::splat(want)).abs().max_element() / want;
    assert!(
        err <= rel,
        "{what}: got {got:?}, want {want} (relative error {err})"
    );
}

/// Mitsuba's depth convention: a path of at most `d` vertices gathers the
/// emission of the first `d` surfaces, `1 + ρ + … + ρ^(d−1)`; unbounded,
/// `1 / (1 − ρ)`. Depth 0 renders black.
#[test]
fn a_closed_emitting_box_holds_the_radiance_of_each_depth() {
    let rho = 0.5f32;
    let black = render_toml(&closed_box(rho, "spp = 1\nmax_depth = 0")).0;
    assert_eq!(mean(&black), Rgb::ZERO);
    for (d, rel) in [(1, 1e-6), (2, 0.01), (3, 0.01)] {
        let (img, rays) = render_toml(&closed_box(rho, &format!("spp = 64\nmax_depth = {d}")));
        let want = (1.0 - rho.powi(d)) / (1.0 - rho);
        assert_near(mean(&img), want, rel, &format!("max_depth = {d}"));
        // A shadow ray per vertex that goes on.
        assert_eq!(rays.shadow > 0, d >= 2, "max_depth = {d}");
    }
    let (img, _) = render_toml(&closed_box(rho, "spp = 256"));
    assert_near(mean(&img), 1.0 / (1.0 - rho), 0.02, "unbounded");
}

/// Each pixel's samples are a function of the seed, the pixel and the
/// sample alone: the same bits on any number of threads and in any number
/// of passes.
#[test]
fn paths_are_the_same_on_any_threads_and_passes() {
    let toml = closed_box(0.7, "spp = 12\nmax_depth = 8\nrr_depth = 2");
    let s = scene(&toml);
    let (one, rays) = render_scene(&s, 1);
    let (three, rays3) = render_scene(&s, 3);
    assert_eq!(one.pixels, three.pixels);
    assert_eq!(rays, rays3);
    let passes = closed_box(0.7, "spp = 12\nmax_depth = 8\nrr_depth = 2\npasses = 5");
    let (five, _) = render_toml(&passes);
    assert_eq!(one.pixels, five.pixels);
}

/// The path integrator's parameters are checked at their place.
#[test]
fn bad_path_parameters_are_located() {
    for (line, want) in [
        (
            "max_depth = -2",
            "must be -1 (no bound) or an integer from 0 to",
        ),
        ("rr_depth = 0", "must be an integer from 1 to"),
        ("hide_emitters = 3", "hide_emitters"),
        ("metric = true", "metric"),
    ] {
        let e = try_scene(&closed_box(0.5, line))
            .err()
            .unwrap_or_else(|| panic!("{line} refused"))
            .to_string();
        assert!(e.starts_with("test.toml:"), "{line}: {e}");
        assert!(e.contains(want), "{line}: {e}");
    }
}

/// Emitters seen directly are black with `hide_emitters`; what they light
/// is not.
#[test]
fn hidden_emitters_still_light() {
    let (img, _) = render_toml(&closed_box(
        0.5,
        "spp = 64\nmax_depth = 2\nhide_emitters = true",
    ));
    assert_near(mean(&img), 0.5, 0.01, "hide_emitters");
}

/// Direct light two ways: `path` at depth 2 (a light sample and a BSDF
/// sample per vertex, weighed by MIS) and `whitted` at depth 0 (many
/// shadow rays on the light's surface) converge to the same image of a
/// floor lit by a rectangle light past a sphere's shadow.
#[test]
fn direct_light_is_whitteds_direct_light() {
    let scene = |render: &str| {
        format!(
            "[render]\nwidth = 24\nheight = 18\nseed = 5\n{render}\n\
             [camera]\nposition = [0, 2.5, 4]\nlook_at = [0, 0, 0]\nfov = 50\n\n\
             [materials.floor]\nalbedo = [0.6, 0.5, 0.4]\n\n\
             [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-4, 0, -4]\n\
             edge_u = [0, 0, 8]\nedge_v = [8, 0, 0]\n\n\
             [[objects]]\ntype = \"sphere\"\nmaterial = \"floor\"\ncenter = [0.3, 0.5, 0]\nradius = 0.5\n\n\
             [[lights]]\ntype = \"rect\"\norigin = [-0.5, 2, -0.5]\nedge_u = [1, 0, 0]\n\
             edge_v = [0, 0, 1]\nradiance = [4, 4, 4]\n"
        )
    };
    let (whitted, _) = render_toml(&scene(
        "max_depth = 0\nspp = 16\nshadow_rays = 64\ndistribution = \"jitter\"",
    ));
    let (path, _) = render_toml(&scene("integrator = \"path\"\nmax_depth = 2\nspp = 1024"));
    let (a, b) = (mean(&whitted), mean(&path));
    let err = ((a - b).abs() / a).max_element();
    assert!(err < 0.02, "whitted {a:?}, path {b:?}");
    // Pixel by pixel, within the noise of 1024 paths.
    let mut far = 0;
    for (p, w) in path.pixels.iter().zip(&whitted.pixels) {
        let e = ((*p - *w).abs() / w.max(Rgb::splat(0.05))).max_element();
        far += usize::from(e > 0.25);
    }
    assert!(
        far <= path.pixels.len() / 50,
        "{far} pixels differ by over 25%"
    );
}

/// `direct`: emission seen plus the direct light of the first surface,
/// `1 + ρ` in the closed box, for any split between emitter and BSDF
/// samples (each strategy alone, or both weighed by the power heuristic
/// with their counts); not both 0. Emitter samples alone need many: near
/// a wall's edge the neighbouring wall's samples weigh `cos θ / r²`, a
/// heavy tail whose small-sample means fall short (4 per pixel sample
/// give 2% less, 64 within 0.2%); the MIS splits are within 0.1%.
#[test]
fn direct_light_holds_for_any_split_of_samples() {
    for (e, b) in [(1, 1), (64, 0), (0, 4), (2, 3)] {
        let render =
            format!("integrator = \"direct\"\nspp = 64\nemitter_samples = {e}\nbsdf_samples = {b}");
        let (img, rays) =
            render_toml(&closed_box(0.5, &render).replace("integrator = \"path\"\n", ""));
        assert_near(
            mean(&img),
            1.5,
            0.01,
            &format!("{e} emitter, {b} BSDF samples"),
        );
        assert_eq!(rays.shadow > 0, e > 0);
    }
    let both = "integrator = \"direct\"\nemitter_samples = 0\nbsdf_samples = 0";
    let e = try_scene(&closed_box(0.5, both).replace("integrator = \"path\"\n", ""))
        .err()
        .expect("refused")
        .to_string();
    assert!(
        e.contains("render.bsdf_samples: a direct integrator needs"),
        "{e}"
    );
}

/// A first vertex's BSDF samples go on as paths of their own streams: the
/// image is the same on any threads and passes.
#[test]
fn split_paths_are_the_same_on_any_threads_and_passes() {
    let render = "integrator = \"direct\"\nspp = 6\nemitter_samples = 3\nbsdf_samples = 5";
    let toml = closed_box(0.6, render).replace("integrator = \"path\"\n", "");
    let s = scene(&toml);
    let (one, rays) = render_scene(&s, 1);
    let (three, rays3) = render_scene(&s, 3);
    assert_eq!(one.pixels, three.pixels);
    assert_eq!(rays, rays3);
    let (two, _) = render_toml(&toml.replace("spp = 6", "spp = 6\npasses = 2"));
    assert_eq!(one.pixels, two.pixels);
}

/// The built-in scene `name` at `width × height` and `spp`, which must be
/// path traced, rendered.
fn path_traced_builtin(
    name: &str,
    bunny: Option<std::path::PathBuf>,
    (width, height, spp): (u32, u32, u32),
) -> Image {
    let mut src = builtin(name, bunny);
    set(
        &mut src,
        penumbra::scene::Overrides {
            width: Some(width),
            height: Some(height),
            spp: Some(spp),
            ..Default::default()
        },
    );
    let s = src.build().unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(
        penumbra::integrator::Config::of(&s).unwrap().choice(),
        penumbra::scene::IntegratorChoice::Path
    );
    render_scene(&s, 2).0
}

/// The sum of the 6×6 pixels from (x0, y0).
fn patch(img: &Image, x0: u32, y0: u32) -> Rgb {
    let mut sum = Rgb::ZERO;
    for y in y0..y0 + 6 {
        for x in x0..x0 + 6 {
            sum += img.get(x, y);
        }
    }
    sum
}

/// The built-in Cornell box is path traced, and shows what only indirect
/// light gives: the white ceiling is redder beside the red wall (image
/// left) than beside the green one.
#[test]
fn the_cornell_box_bleeds_colour() {
    let img = path_traced_builtin("cornell-box", None, (48, 48, 32));
    let (left, right) = (patch(&img, 6, 2), patch(&img, 36, 2));
    assert!(
        left.r / left.g > 1.2 * right.r / right.g,
        "{left:?} {right:?}"
    );
    assert!(
        right.g / right.r > 1.2 * left.g / left.r,
        "{left:?} {right:?}"
    );
}

/// The built-in `bunny-gi` is path traced and bleeds colour: the floor
/// beside the orange wall (image left) is more orange than the floor on
/// the right, which the blue wall lights.
#[test]
fn the_bunny_in_its_corner_bleeds_colour() {
    let Some(bunny) = common::bunny() else { return };
    let img = path_traced_builtin("bunny-gi", Some(bunny), (64, 48, 16));
    let (left, right) = (patch(&img, 2, 40), patch(&img, 56, 40));
    assert!(
        left.r / left.b > 1.2 * right.r / right.b,
        "{left:?} {right:?}"
    );
}

/// The built-in `materials` scene needs no file and is path traced, and
/// every sphere shows: at 64 × 32 pixels and 4 spp, the camera ray through
/// each pixel's centre finds the material it sees first; 15 are seen (the
/// floor's and one per sphere), and the pixels of each are finite and not
/// black on average.
#[test]
fn every_sphere_of_the_materials_scene_shows() {
    use penumbra::camera::CameraSample;
    use penumbra::math::Vec2;
    let (w, h) = (64, 32);
    let mut src = builtin("materials", None);
    set(
        &mut src,
        penumbra::scene::Overrides {
            width: Some(w),
            height: Some(h),
            spp: Some(4),
            ..Default::default()
        },
    );
    let s = src.build().unwrap();
    assert_eq!(
        penumbra::integrator::Config::of(&s).unwrap().choice(),
        penumbra::scene::IntegratorChoice::Path
    );
    let img = render_scene(&s, 2).0;
    let mut regions = std::collections::BTreeMap::<u32, (Rgb, u32)>::new();
    let mut rays = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let c = img.get(x, y);
            assert!(c.is_finite(), "pixel ({x}, {y}): {c:?}");
            rays.clear();
            let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let sample = CameraSample {
                film,
                lens: Vec2::ZERO,
                time: 0.0,
            };
            s.camera.generate(&[sample], &mut rays);
            if let Some(hit) = s.world.intersect(&rays[0], 0.0, f32::INFINITY) {
                let r = regions.entry(hit.material).or_insert((Rgb::ZERO, 0));
                r.0 += c;
                r.1 += 1;
            }
        }
    }
    assert_eq!(regions.len(), 15, "materials seen: {regions:?}");
    for (material, (sum, n)) in regions {
        let m = sum / n as f32;
        assert!(
            m.luminance() > 0.02,
            "material {material}: mean {m:?} over {n} pixels"
        );
    }
}

/// `distributed`: the thesis's sets at the first vertices, each BSDF ray
/// going on as a path, converge to what `path` converges to, for square
/// and low-discrepancy distributions and sets reaching one or two
/// vertices; the shadow and reflection counts are the sets'.
#[test]
fn distributed_sets_hold_the_box_radiance() {
    for (dist, sets) in [("jitter", 1), ("sobol", 1), ("poisson", 2)] {
        for (d, want) in [(2, 1.5), (3, 1.75)] {
            let render = format!(
                "integrator = \"distributed\"\nspp = 16\nmax_depth = {d}\nsets_depth = {sets}\n\
                 shadow_rays = 4\nreflection_rays = 4\ndistribution = \"{dist}\""
            );
            let toml = closed_box(0.5, &render).replace("integrator = \"path\"\n", "");
            let (img, rays) = render_toml(&toml);
            assert_near(
                mean(&img),
                want,
                0.01,
                &format!("{dist}, sets to {sets}, depth {d}"),
            );
            // Six walls, each a light: a set of 4 toward each of the five
            // a wall sees, at each vertex drawing sets.
            assert!(rays.shadow >= 20 * rays.primary, "{rays:?}");
            assert!(rays.reflection >= 4 * rays.primary * 9 / 10, "{rays:?}");
        }
    }
    let s = scene(
        &closed_box(0.6, "integrator = \"distributed\"\nspp = 4\nmax_depth = 6\nrr_depth = 2\nshadow_rays = 3\nreflection_rays = 5\ndistribution = \"random\"")
            .replace("integrator = \"path\"\n", ""),
    );
    let (one, rays) = render_scene(&s, 1);
    let (three, rays3) = render_scene(&s, 3);
    assert_eq!(one.pixels, three.pixels);
    assert_eq!(rays, rays3);
}

/// A sphere of `material` (a TOML table body) alone in a constant
/// environment of radiance 1, filling most of a 24×24 frame.
fn furnace(material: &str, render: &str) -> String {
    format!(
        "[render]\nwidth = 24\nheight = 24\nintegrator = \"path\"\nbackground = [1, 1, 1]\n{render}\n\
         [camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 30\n\n\
         [materials.m]\n{material}\n\n\
         [[objects]]\ntype = \"sphere\"\nmaterial = \"m\"\nradius = 1\n"
    )
}

/// Furnace tests: in a uniform environment of radiance 1, a convex
/// diffuse sphere of albedo ρ reflects ρ; a smooth dielectric sphere, a
/// white conductor and a white sheet lose nothing, so every pixel is 1 (a
/// diamond's radiance scale inside, 1/2.4², and out again cancel); a
/// white rough conductor returns its directional albedo, what single
/// scattering gives (masking keeps it below 1, the more the rougher).
#[test]
fn furnaces() {
    let pixel = |img: &Image, x: u32, y: u32| img.get(x, y);
    let lossless = [
        "type = \"dielectric\"",
        "type = \"dielectric\"\nint_ior = \"diamond\"",
        "type = \"conductor\"",
        "type = \"thindielectric\"",
    ];
    for m in lossless {
        // No roulette: every event then weighs exactly 1.
        let (img, _) = render_toml(&furnace(m, "spp = 16\nrr_depth = 1000"));
        for (x, y) in [(12, 12), (8, 14), (15, 9)] {
            assert_near(pixel(&img, x, y), 1.0, 2e-3, m);
        }
    }
    // The background is sampled as an emitter too: ρ within noise.
    let (img, _) = render_toml(&furnace(
        "type = \"diffuse\"\nreflectance = [0.3, 0.5, 0.7]",
        "spp = 256",
    ));
    for (x, y) in [(12, 12), (8, 14), (15, 9)] {
        let c = pixel(&img, x, y);
        let err = ((c - Rgb::new(0.3, 0.5, 0.7)) / Rgb::new(0.3, 0.5, 0.7)).abs();
        assert!(err.max_element() < 0.02, "{c:?}");
    }
    // A white rough conductor returns its directional albedo, which
    // masking keeps below 1 and lowers with roughness: the centre pixel
    // (seen head-on) against ∫ f cos over the hemisphere on a fine grid.
    let mut albedos = Vec::new();
    for alpha in [0.05f32, 0.4, 1.0] {
        let m = format!("type = \"roughconductor\"\ndistribution = \"ggx\"\nalpha = {alpha}");
        let s = scene(&furnace(&m, "spp = 2048"));
        let (img, _) = render_scene(&s, 2);
        let got = (img.get(11, 11) + img.get(12, 12) + img.get(11, 12) + img.get(12, 11)) / 4.0;
        let rough = s.bsdfs.iter().find(|b| b.name() == "roughconductor");
        let want = albedo_head_on(rough.expect("the sphere's material"));
        assert_near(got, want, 0.02, &format!("alpha {alpha}"));
        albedos.push(want);
    }
    assert!(albedos[0] > 0.99, "{albedos:?}");
    assert!(
        albedos[1] < albedos[0] && albedos[2] < albedos[1] - 0.1,
        "{albedos:?}"
    );
}

/// `∫ f(n, wi) cos θ dwi` over the hemisphere of the normal `n = z`, on a
/// grid fine in θ (finest by the pole, where a narrow lobe peaks) and φ.
fn albedo_head_on(bsdf: &penumbra::bsdf::Bsdf) -> f32 {
    use penumbra::geometry::SurfaceInteraction;
    use penumbra::math::{Vec2, Vec3};
    let si = SurfaceInteraction {
        t: 1.0,
        p: Vec3::ZERO,
        time: 0.0,
        ng: Vec3::Z,
        n: Vec3::Z,
        uv: Vec2::ZERO,
        dpdu: Vec3::X,
        dpdv: Vec3::Y,
        prim: 0,
        bary: Vec2::ZERO,
        object: 0,
        material: 0,
        emitter: None,
    };
    let (nt, np) = (4000, 32);
    let dt = std::f64::consts::FRAC_PI_2 / f64::from(nt);
    let mut sum = 0.0f64;
    for i in 0..nt {
        let theta = (f64::from(i) + 0.5) * dt;
        let (st, c) = (theta.sin() as f32, theta.cos() as f32);
        for j in 0..np {
            let phi = (j as f32 + 0.5) / np as f32 * std::f32::consts::TAU;
            let wi = Vec3::new(st * phi.cos(), st * phi.sin(), c);
            sum += f64::from(bsdf.eval(&si, Vec3::Z, wi).r * c) * theta.sin();
        }
    }
    (sum * dt * std::f64::consts::TAU / f64::from(np)) as f32
}

/// The background is an emitter next-event estimation samples: a floor
/// under a constant sky of radiance L reflects ρ·L whether the light comes
/// from emitter samples alone, BSDF samples alone or both.
#[test]
fn the_sky_is_sampled_as_an_emitter() {
    let sky = |render: &str| {
        format!(
            "[render]\nwidth = 16\nheight = 16\nbackground = [2, 2, 2]\n{render}\n\
             [camera]\nposition = [0, 6, 0.01]\nlook_at = [0, 0, 0]\nfov = 20\n\n\
             [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.5, 0.4, 0.3]\n\n\
             [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-50, 0, -50]\n\
             edge_u = [0, 0, 100]\nedge_v = [100, 0, 0]\n"
        )
    };
    let want = Rgb::new(1.0, 0.8, 0.6);
    for (e, b) in [(64, 0), (0, 64), (8, 8)] {
        let render =
            format!("integrator = \"direct\"\nspp = 4\nemitter_samples = {e}\nbsdf_samples = {b}");
        let (img, rays) = render_toml(&sky(&render));
        // The whole frame is floor: its mean over 16 × 16 × 4 pixel samples.
        let c = mean(&img);
        let err = ((c - want) / want).abs().max_element();
        assert!(err < 0.03, "{e} emitter, {b} BSDF samples: {c:?}");
        assert_eq!(rays.shadow > 0, e > 0);
    }
}

/// A diffuse floor and back wall lit by a square light above and a sky:
/// soft shadows and one bounce of indirect light at `max_depth = 3`.
fn lit_corner(render: &str) -> String {
    format!(
        "[render]\nwidth = 20\nheight = 20\nintegrator = \"path\"\nmax_depth = 3\n\
         background = [0.2, 0.2, 0.3]\n{render}\n\
         [camera]\nposition = [0, 1.2, 4]\nlook_at = [0, 0.4, 0]\nfov = 45\n\n\
         [materials.white]\ntype = \"diffuse\"\nreflectance = [0.7, 0.7, 0.7]\n\n\
         [materials.red]\ntype = \"diffuse\"\nreflectance = [0.7, 0.1, 0.1]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"white\"\norigin = [-2, 0, 2]\n\
         edge_u = [4, 0, 0]\nedge_v = [0, 0, -4]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"red\"\norigin = [-2, 0, -1]\n\
         edge_u = [4, 0, 0]\nedge_v = [0, 3, 0]\n\n\
         [[objects]]\ntype = \"sphere\"\nmaterial = \"white\"\ncenter = [0.3, 0.5, 0.3]\n\
         radius = 0.5\n\n\
         [[lights]]\ntype = \"rect\"\norigin = [-0.5, 2.5, -0.2]\nedge_u = [1, 0, 0]\n\
         edge_v = [0, 0, 1]\nradiance = [12, 12, 12]\n"
    )
}

fn rel_mse(img: &Image, reference: &Image) -> f64 {
    let mut sum = 0.0f64;
    for (a, b) in img.pixels.iter().zip(&reference.pixels) {
        for (a, b) in a.to_array().into_iter().zip(b.to_array()) {
            let (a, b) = (f64::from(a), f64::from(b));
            sum += (a - b).powi(2) / (b * b + 0.01);
        }
    }
    sum / (3 * img.pixels.len()) as f64
}

/// Every path sampler converges to the same image: the furnace's diffuse
/// sphere reflects ρ at unbounded depth, and on a lit corner each
/// sequence's mean agrees with independent numbers'. A pixel's samples
/// stratified in every dimension of a bounce lower the error at equal
/// samples: at 16 spp every sequence's relative MSE against a 4096-spp
/// reference is at most half independent numbers' (0.28–0.34 measured).
#[test]
fn every_path_sampler_converges_and_sequences_lower_the_noise() {
    for name in PathSampler::NAMES {
        let (img, _) = render_toml(&furnace(
            "type = \"diffuse\"\nreflectance = [0.3, 0.5, 0.7]",
            &format!("spp = 64\npath_sampler = \"{name}\""),
        ));
        let mut sum = Rgb::ZERO;
        for (x, y) in [(11, 11), (12, 12), (11, 12), (12, 11)] {
            sum += img.get(x, y);
        }
        let c = sum / 4.0;
        let err = ((c - Rgb::new(0.3, 0.5, 0.7)) / Rgb::new(0.3, 0.5, 0.7)).abs();
        assert!(err.max_element() < 0.03, "{name}: {c:?}");
    }
    let reference = render_toml(&lit_corner("spp = 4096\nseed = 99")).0;
    let want = mean(&reference);
    let mut errors = Vec::new();
    for name in PathSampler::NAMES {
        // The mean over seeds of the relative MSE, and the image mean.
        let mut e = 0.0;
        let mut m = Rgb::ZERO;
        for seed in 0..4 {
            let toml = lit_corner(&format!(
                "spp = 16\nseed = {seed}\npath_sampler = \"{name}\""
            ));
            let img = render_toml(&toml).0;
            e += rel_mse(&img, &reference) / 4.0;
            m += mean(&img) / 4.0;
        }
        let off = ((m - want) / want).abs().max_element();
        assert!(off < 0.02, "{name}: mean {m:?} against {want:?}");
        errors.push((name, e));
    }
    eprintln!("relative MSE at 16 spp: {errors:?}");
    let independent = errors[0].1;
    for &(name, e) in &errors[1..] {
        assert!(e < 0.5 * independent, "{name}: {e} against {independent}");
    }
}

/// A sequence's numbers are a function of (seed, pixel, sample, bounce,
/// dimension): the same pixels on any thread count and pass split, for
/// `path` and for the split samples of `direct`.
#[test]
fn sequenced_paths_are_the_same_on_any_threads_and_passes() {
    for render in [
        "spp = 8\nmax_depth = 6\nrr_depth = 2\npath_sampler = \"sobol\"",
        "spp = 8\nmax_depth = 6\npath_sampler = \"zsobol\"",
        "spp = 4\nintegrator = \"direct\"\nemitter_samples = 3\nbsdf_samples = 2\n\
         path_sampler = \"pmj02\"",
    ] {
        let toml = closed_box(0.7, render).replace("integrator = \"path\"\n", "");
        let toml = if render.contains("direct") {
            toml
        } else {
            toml.replace("[render]\n", "[render]\nintegrator = \"path\"\n")
        };
        let s = scene(&toml);
        let (one, rays) = render_scene(&s, 1);
        let (three, rays3) = render_scene(&s, 3);
        assert_eq!(one.pixels, three.pixels, "{render}");
        assert_eq!(rays, rays3);
        let (passes, _) = render_toml(&toml.replace("[render]\n", "[render]\npasses = 3\n"));
        assert_eq!(one.pixels, passes.pixels, "{render}");
    }
    // The whitted integrator has no paths to sample.
    let error = |toml: &str| match try_scene(toml) {
        Ok(_) => panic!("should be refused:\n{toml}"),
        Err(e) => e.to_string(),
    };
    let err = error(
        &closed_box(0.5, "path_sampler = \"sobol\"")
            .replace("integrator = \"path\"", "integrator = \"whitted\""),
    );
    assert!(err.contains("path_sampler"), "{err}");
    let err = error(&closed_box(0.5, "path_sampler = \"jitter\""));
    assert!(err.contains("independent, sobol"), "{err}");
}

/// The wavefront's stages, as the statistics count them: every ray a path
/// follows is traced by a closest-hit call and its vertex shaded (misses
/// included), every shadow ray by an occlusion call; a 16×16 image at 32
/// samples fills a wave of 8,192 camera rays, and the closed box's one
/// material is shaded in one call per bounce; at one sample, a tile's
/// 4,096.
#[test]
fn the_stages_take_whole_waves() {
    use penumbra::render::{render, RenderOptions};
    let s = scene(&closed_box(0.5, "spp = 32\nmax_depth = 4"));
    let opts = RenderOptions {
        threads: Some(2),
        region: None,
    };
    let (_, stats) = render(&s, &opts, &|_, _| {}, None).expect("render");
    let (r, b) = (stats.rays, stats.batches);
    assert_eq!(b.closest_hit.items, r.primary + r.reflection + r.refraction);
    assert_eq!(b.shading.items, b.closest_hit.items);
    assert_eq!(b.occlusion.items, r.shadow);
    // One wave, four bounces: every path lives to the depth limit.
    assert_eq!(b.closest_hit.calls, 4);
    assert_eq!(b.closest_hit.mean(), 8192.0);
    assert_eq!(b.shading.calls, 4);
    assert_eq!(b.occlusion.calls, 3);
    // At one sample, a 64 × 64 tile's camera rays are one wave of 4,096.
    let one = closed_box(0.5, "spp = 1\nmax_depth = 1")
        .replace("width = 16\nheight = 16", "width = 128\nheight = 64");
    let (_, stats) = render(&scene(&one), &opts, &|_, _| {}, None).expect("render");
    assert_eq!(stats.batches.closest_hit.calls, 2);
    assert_eq!(stats.batches.closest_hit.mean(), 4096.0);
}

/// A wave takes fewer rows the more its paths grow: under `distributed`
/// every camera path of the closed box becomes 16 paths and 6 × 8 shadow
/// rays at its first vertex, so a wave is one row of 16 pixels at 32
/// samples (512 camera paths, 8,192 paths after), not the 8,192 camera
/// paths that would become 131,072.
#[test]
fn sets_do_not_grow_a_wave_past_its_size() {
    use penumbra::integrator::WAVE;
    use penumbra::render::{render, RenderOptions};
    let box_ = closed_box(
        0.5,
        "integrator = \"distributed\"\nspp = 32\nmax_depth = 3\nshadow_rays = 8\nreflection_rays = 16",
    )
    .replace("integrator = \"path\"\n", "");
    let opts = RenderOptions {
        threads: Some(2),
        region: None,
    };
    let (_, stats) = render(&scene(&box_), &opts, &|_, _| {}, None).expect("render");
    let b = stats.batches;
    // A wave per row, three bounces each.
    assert_eq!(b.closest_hit.calls, 16 * 3, "{b:?}");
    assert!(b.closest_hit.mean() <= WAVE as f64, "{b:?}");
    assert_eq!(stats.rays.primary, 16 * 16 * 32);
}

/// The thesis's shadow metric on `distributed`'s sets: in the closed box
/// every shadow ray reaches its wall, so each set stops after its first
/// `k` members and the box keeps its radiance; the members left are
/// counted as saved. With a sphere casting shadows inside, the sets across
/// its shadows go on, so fewer are saved, and the pixels stay the same on
/// any number of threads.
#[test]
fn the_shadow_metric_stops_distributed_shadow_sets() {
    let render = |metric: &str| {
        let r = format!(
            "integrator = \"distributed\"\nspp = 16\nmax_depth = 2\n\
             shadow_rays = 8\nreflection_rays = 2\ndistribution = \"jitter\"\n{metric}"
        );
        closed_box(0.5, &r).replace("integrator = \"path\"\n", "")
    };
    let on = "metric = true\nreflection_metric = false\nshadow_metric_rays = 2";
    let (img, rays) = render_toml(&render(on));
    let (_, all) = render_toml(&render(""));
    assert_near(mean(&img), 1.5, 0.01, "shadow metric");
    assert_eq!(rays.shadow * 4, all.shadow, "{rays:?} {all:?}");
    assert_eq!(rays.shadow + rays.saved.shadow, all.shadow);
    let sphere = "\n[materials.ball]\nalbedo = [0.5, 0.5, 0.5]\n\n\
                  [[objects]]\ntype = \"sphere\"\nmaterial = \"ball\"\ncenter = [0.3, -0.4, -0.3]\nradius = 0.35\n";
    let s = scene(&(render(on) + sphere));
    let (one, shadowed) = render_scene(&s, 1);
    let (three, shadowed3) = render_scene(&s, 3);
    assert_eq!(one.pixels, three.pixels);
    assert_eq!(shadowed, shadowed3);
    let (_, whole) = render_toml(&(render("") + sphere));
    assert!(shadowed.shadow > whole.shadow / 4, "{shadowed:?} {whole:?}");
    assert!(shadowed.shadow < whole.shadow, "{shadowed:?} {whole:?}");
    assert!(shadowed.saved.shadow > 0);
}

/// The reflection metric on `distributed`'s sets of BSDF samples at the
/// first vertex: each member's path is followed to its end before the set
/// is judged. In the closed box members bring similar light, so most sets
/// stop early and the box keeps its radiance, the members left counted as
/// saved; at threshold 0 no set stops, and the
/// rays are those of the render without the metric. Pixels do not depend
/// on the threads or the passes.
#[test]
fn the_reflection_metric_judges_whole_paths() {
    let render = |metric: &str| {
        let r = format!(
            "integrator = \"distributed\"\nspp = 16\nmax_depth = 3\n\
             shadow_rays = 2\nreflection_rays = 12\ndistribution = \"jitter\"\n{metric}"
        );
        closed_box(0.5, &r).replace("integrator = \"path\"\n", "")
    };
    let on = "metric = true\nshadow_metric = false\nmetric_min_rays = 3\nmetric_threshold = 0.2";
    let (img, rays) = render_toml(&render(on));
    let (_, all) = render_toml(&render(""));
    assert_near(mean(&img), 1.75, 0.01, "reflection metric");
    assert!(rays.saved.reflection > 0, "{rays:?}");
    assert!(rays.reflection < all.reflection, "{rays:?} {all:?}");
    // Every member traced goes on for one more bounce (no roulette before
    // depth 5): half the reflection rays are members, and with the members
    // saved they make the sets whole.
    assert_eq!(rays.reflection % 2, 0);
    assert_eq!(
        rays.reflection / 2 + rays.saved.reflection,
        12 * rays.primary
    );
    assert_eq!(all.reflection, 2 * 12 * all.primary);
    let never = "metric = true\nshadow_metric = false\nmetric_threshold = 0";
    let (img0, rays0) = render_toml(&render(never));
    assert_eq!(rays0, all);
    assert_near(mean(&img0), 1.75, 0.01, "threshold 0");
    let s = scene(&render(on));
    let (one, r1) = render_scene(&s, 1);
    let (three, r3) = render_scene(&s, 3);
    assert_eq!(one.pixels, three.pixels);
    assert_eq!(r1, r3);
    let (five, r5) = render_toml(&render(&format!("{on}\npasses = 5")));
    assert_eq!(one.pixels, five.pixels);
    assert_eq!(r1, r5);
}

/// A floor and a back wall lit by emitters of every kind and of powers
/// over three orders of magnitude: a large dim rectangle, a small bright
/// sphere, a disk facing the wall, a point light, a spot, a directional
/// light, a sky and an emitting object.
fn many_lights(render: &str) -> String {
    format!(
        "[render]\nwidth = 20\nheight = 20\nintegrator = \"path\"\nmax_depth = 3\n\
         background = [0.05, 0.05, 0.08]\n{render}\n\
         [camera]\nposition = [0, 1.2, 4]\nlook_at = [0, 0.4, 0]\nfov = 50\n\n\
         [materials.white]\ntype = \"diffuse\"\nreflectance = [0.7, 0.7, 0.7]\n\n\
         [materials.glow]\nalbedo = [0.5, 0.5, 0.5]\nemission = [3, 1, 0.5]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"white\"\norigin = [-3, 0, 3]\n\
         edge_u = [6, 0, 0]\nedge_v = [0, 0, -6]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"white\"\norigin = [-3, 0, -1]\n\
         edge_u = [6, 0, 0]\nedge_v = [0, 3, 0]\n\n\
         [[objects]]\ntype = \"sphere\"\nmaterial = \"glow\"\ncenter = [1.2, 0.2, 0.8]\n\
         radius = 0.2\n\n\
         [[lights]]\ntype = \"rect\"\norigin = [-2, 2.8, -0.8]\nedge_u = [4, 0, 0]\n\
         edge_v = [0, 0, 2]\nradiance = [0.3, 0.3, 0.3]\n\n\
         [[lights]]\ntype = \"sphere\"\ncenter = [-0.8, 0.6, 0.5]\nradius = 0.05\n\
         radiance = [400, 300, 200]\n\n\
         [[lights]]\ntype = \"disk\"\ncenter = [0.8, 1.5, 1.5]\nnormal = [0, -0.3, -1]\n\
         radius = 0.3\nradiance = [2, 4, 8]\n\n\
         [[lights]]\ntype = \"point\"\nposition = [1.5, 1.0, 0.0]\nintensity = [1, 2, 1]\n\n\
         [[lights]]\ntype = \"spot\"\nposition = [-1.5, 2.0, 1.0]\nlook_at = [-1.0, 0, 0]\n\
         intensity = [8, 8, 8]\ncutoff_angle = 30\n\n\
         [[lights]]\ntype = \"directional\"\ndirection = [0.3, -1, -0.4]\n\
         irradiance = [0.2, 0.2, 0.2]\n"
    )
}

/// Every light sampler converges to the same image: on a scene of
/// emitters of every kind, each sampler's image against another seed of
/// the same sampler (the noise alone) and against every other sampler's
/// differ by the same relative MSE within 50%, and the image means agree
/// within 1%. A sampler whose probabilities were not those its choices
/// were made with, in the shadow rays or in the weights of the emission
/// met, would move its image by more.
#[test]
fn every_light_sampler_converges_to_one_image() {
    let names = ["uniform", "power", "bvh"];
    let render = |name: &str, seed: u32| {
        render_toml(&many_lights(&format!(
            "spp = 1024\nseed = {seed}\nlight_sampler = \"{name}\""
        )))
        .0
    };
    let images: Vec<[Image; 2]> = names.iter().map(|n| [render(n, 1), render(n, 2)]).collect();
    for (a, name_a) in names.iter().enumerate() {
        let noise = rel_mse(&images[a][0], &images[a][1]);
        let m = mean(&images[a][0]);
        for (b, name_b) in names.iter().enumerate() {
            if a == b {
                continue;
            }
            let across = rel_mse(&images[a][0], &images[b][1]);
            let noise_b = rel_mse(&images[b][0], &images[b][1]);
            let both = 0.5 * (noise + noise_b);
            eprintln!("{name_a} against {name_b}: {across:.3e}; noise {noise:.3e}, {noise_b:.3e}");
            assert!(
                across < 1.5 * both,
                "{name_a} against {name_b}: relative MSE {across} over noise {both}"
            );
            let mb = mean(&images[b][1]);
            let off = ((m - mb) / mb).abs().max_element();
            assert!(off < 0.01, "{name_a} {m:?} against {name_b} {mb:?}");
        }
    }
}
