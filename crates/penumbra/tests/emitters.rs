//! The spot, directional and environment-map emitters rendered by every
//! integrator against closed-form answers.

mod common;

use common::*;
use penumbra::math::Rgb;
use penumbra::render::Image;

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

/// A diffuse floor of reflectance [0.5, 0.4, 0.3] at y = 0, seen from
/// straight above through a narrow frame, lit by `light` (a `[[lights]]`
/// body), rendered by `integrator`.
fn floor(light: &str, integrator: &str) -> String {
    format!(
        "[render]\nwidth = 8\nheight = 8\nspp = 4\nintegrator = \"{integrator}\"\n\n\
         [camera]\nposition = [0, 6, 0.01]\nlook_at = [0, 0, 0]\nfov = 2\n\n\
         [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.5, 0.4, 0.3]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-50, 0, -50]\n\
         edge_u = [0, 0, 100]\nedge_v = [100, 0, 0]\n\n\
         [[lights]]\n{light}\n"
    )
}

const INTEGRATORS: [&str; 4] = ["whitted", "direct", "path", "distributed"];

/// A directional light at 60° from the floor's normal gives it the
/// irradiance E cos 60°: the floor's radiance is ρ E cos 60° / π, with a
/// shadow ray that leaves the scene (nothing blocks it).
#[test]
fn a_directional_light_lights_a_floor() {
    let light = "type = \"directional\"\ndirection = [0, -1, 1.7320508]\nirradiance = [2, 2, 2]";
    let want = Rgb::new(0.5, 0.4, 0.3) * (2.0 * 0.5 / std::f32::consts::PI);
    for integrator in INTEGRATORS {
        let (img, _) = render_toml(&floor(light, integrator));
        let c = mean(&img);
        let err = ((c - want) / want).abs().max_element();
        assert!(err < 1e-3, "{integrator}: {c:?} vs {want:?}");
    }
    // A board between the floor and the light (out of the camera's view)
    // casts its shadow.
    let blocked = floor(light, "path")
        + "\n[[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-5, 3, -8]\n\
           edge_u = [0, 0, 4]\nedge_v = [10, 0, 0]\n";
    let (img, _) = render_toml(&blocked);
    assert_eq!(mean(&img), Rgb::ZERO);
}

/// A spot 2 above the floor pointing down gives the point under it the
/// irradiance I / 4; turned 25° away (past its beam width of 15°, inside
/// its cutoff of 30°) it gives I (30 − 25)/(30 − 15) / 4, Mitsuba's
/// falloff.
#[test]
fn a_spot_light_lights_a_floor_with_its_falloff() {
    let rho = Rgb::new(0.5, 0.4, 0.3) / std::f32::consts::PI;
    // tan 25° · 2 = 0.9326153.
    let cases = [
        ("[0, 0, 0]", 3.0 / 4.0),
        ("[0, 0, 0.9326153]", 3.0 * (5.0 / 15.0) / 4.0),
    ];
    for (look_at, e) in cases {
        let light = format!(
            "type = \"spot\"\nposition = [0, 2, 0]\nlook_at = {look_at}\nintensity = [3, 3, 3]\n\
             cutoff_angle = 30\nbeam_width = 15"
        );
        let want = rho * e;
        for integrator in INTEGRATORS {
            let (img, _) = render_toml(&floor(&light, integrator));
            // The frame is about 0.2 across: the centre pixels.
            let c = (img.get(3, 3) + img.get(4, 4) + img.get(3, 4) + img.get(4, 3)) / 4.0;
            let err = ((c - want) / want).abs().max_element();
            assert!(err < 0.01, "{integrator}, {look_at}: {c:?} vs {want:?}");
        }
    }
    // Outside the cone: nothing.
    let light = "type = \"spot\"\nposition = [0, 2, 0]\nlook_at = [0, 2, 1]";
    let (img, _) = render_toml(&floor(light, "path"));
    assert_eq!(mean(&img), Rgb::ZERO);
}

/// A sphere of albedo ρ in a constant-valued environment map of radiance
/// 1 (an EXR file) renders as in a `constant` background: ρ within noise,
/// the two images alike.
#[test]
fn a_constant_envmap_renders_like_constant() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("white.exr");
    let img = image::Rgb32FImage::from_pixel(32, 16, image::Rgb([1.0, 1.0, 1.0]));
    image::DynamicImage::ImageRgb32F(img)
        .save_with_format(&path, image::ImageFormat::OpenExr)
        .unwrap();
    let scene = |sky: &str| {
        format!(
            "[render]\nwidth = 24\nheight = 24\nintegrator = \"path\"\nspp = 256\n{sky}\n\
             [camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 30\n\n\
             [materials.m]\ntype = \"diffuse\"\nreflectance = [0.3, 0.5, 0.7]\n\n\
             [[objects]]\ntype = \"sphere\"\nmaterial = \"m\"\nradius = 1\n"
        )
    };
    let envmap = format!(
        "\n[[lights]]\ntype = \"envmap\"\nfilename = {:?}\n",
        path.display().to_string()
    );
    let (map, _) = render_toml(&(scene("") + &envmap));
    let (constant, _) = render_toml(&scene("background = [1, 1, 1]"));
    let rho = Rgb::new(0.3, 0.5, 0.7);
    for (x, y) in [(12, 12), (8, 14), (15, 9)] {
        for img in [&map, &constant] {
            let c = img.get(x, y);
            let err = ((c - rho) / rho).abs().max_element();
            assert!(err < 0.02, "{c:?}");
        }
    }
    // The corners see the sky itself.
    assert_eq!(map.get(0, 0), Rgb::ONE);
    let (m, c) = (mean(&map), mean(&constant));
    assert!(((m - c) / c).abs().max_element() < 0.01, "{m:?} vs {c:?}");
}

/// A `sky` of one radiance everywhere and no sun is a `constant`
/// background: a diffuse sphere in it renders the same image within noise.
#[test]
fn a_uniform_sky_renders_like_constant() {
    let scene = |sky: &str| {
        format!(
            "[render]\nwidth = 24\nheight = 24\nintegrator = \"path\"\nspp = 256\n{sky}\n\
             [camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 30\n\n\
             [materials.m]\ntype = \"diffuse\"\nreflectance = [0.3, 0.5, 0.7]\n\n\
             [[objects]]\ntype = \"sphere\"\nmaterial = \"m\"\nradius = 1\n"
        )
    };
    let sky = "\n[[lights]]\ntype = \"sky\"\nzenith = [1, 1, 1]\nhorizon = [1, 1, 1]\n\
               ground = [1, 1, 1]\nsun_irradiance = [0, 0, 0]\nresolution = 64\n";
    let (map, _) = render_toml(&(scene("") + sky));
    let (constant, _) = render_toml(&scene("background = [1, 1, 1]"));
    let rho = Rgb::new(0.3, 0.5, 0.7);
    for (x, y) in [(12, 12), (8, 14), (15, 9)] {
        let c = map.get(x, y);
        assert!(((c - rho) / rho).abs().max_element() < 0.02, "{c:?}");
    }
    assert_eq!(map.get(0, 0), Rgb::ONE);
    let (m, c) = (mean(&map), mean(&constant));
    assert!(((m - c) / c).abs().max_element() < 0.01, "{m:?} vs {c:?}");
}

/// A sky that is only a sun, 60° from the zenith, gives a floor the
/// irradiance `E cos 60°` as a directional light would (a uniform disc
/// wholly above a surface's horizon gives it its irradiance facing it
/// times the cosine of its centre): the floor's radiance is
/// ρ E cos 60° / π within 2%, the map's pixels and the noise.
#[test]
fn a_skys_sun_lights_a_floor_as_its_irradiance_says() {
    let light = "type = \"sky\"\nzenith = [0, 0, 0]\nhorizon = [0, 0, 0]\nground = [0, 0, 0]\n\
                 sun_direction = [0, 1, -1.7320508]\nsun_radius = 3\nsun_irradiance = [2, 2, 2]";
    let want = Rgb::new(0.5, 0.4, 0.3) * (2.0 * 0.5 / std::f32::consts::PI);
    for integrator in ["direct", "path"] {
        let toml = floor(light, integrator).replace("spp = 4", "spp = 64");
        let (img, _) = render_toml(&toml);
        let c = mean(&img);
        let err = ((c - want) / want).abs().max_element();
        assert!(err < 0.02, "{integrator}: {c:?} vs {want:?}");
    }
}

/// A rectangle light of an uneven bitmap over a diffuse floor renders, its
/// points drawn by the texture, as the same light drawn uniformly over its
/// area: per block of 8 × 6 pixels, the mean difference of the two renders
/// (independent noise, the same scene) within 4.5 standard errors of 0.
#[test]
fn a_rectangle_drawn_by_its_texture_renders_as_drawn_uniformly() {
    use penumbra::emitter::Emitter;
    use penumbra::render::{render, RenderOptions};
    use penumbra::scene::{LoadOptions, SceneSource};
    let dir = tempfile::tempdir().unwrap();
    let (tw, th) = (8u32, 4u32);
    let mut tex = Image::new(tw, th);
    for y in 0..th {
        for x in 0..tw {
            tex.pixels[(y * tw + x) as usize] = match (x, y) {
                (5, 1) => Rgb::new(60.0, 40.0, 30.0),
                (0, _) => Rgb::ZERO,
                _ => Rgb::new(0.5, 0.6, 0.8),
            };
        }
    }
    penumbra::io::output::write_image(&dir.path().join("light.exr"), &tex).unwrap();
    let toml =
        "[render]\nwidth = 24\nheight = 18\nspp = 256\nintegrator = \"path\"\nmax_depth = 2\n\
                pixel_distribution = \"fast-random\"\n\n\
                [camera]\nposition = [0, 3, 4]\nlook_at = [0, 0, 0]\nfov = 50\n\n\
                [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.5, 0.4, 0.3]\n\n\
                [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-3, 0, -3]\n\
                edge_u = [0, 0, 6]\nedge_v = [6, 0, 0]\n\n\
                [[lights]]\ntype = \"rect\"\norigin = [-0.8, 1.5, -0.5]\nedge_u = [1.6, 0, 0]\n\
                edge_v = [0, 0, 1]\nradiance = { type = \"bitmap\", filename = \"light.exr\" }\n";
    let build = |seed: u32| {
        let text = toml.replace("spp = 256", &format!("spp = 256\nseed = {seed}"));
        let src = SceneSource::from_toml(
            &text,
            &dir.path().join("s.toml"),
            dir.path(),
            &LoadOptions::default(),
        )
        .unwrap();
        src.build().unwrap()
    };
    let by_texture = build(1);
    let drawn = by_texture
        .emitters
        .iter()
        .filter(|e| matches!(e, Emitter::Area(a) if a.by_texture.is_some()))
        .count();
    assert_eq!(drawn, 1, "the light is drawn by its texture");
    let mut uniform = build(2);
    for e in &mut uniform.emitters {
        if let Emitter::Area(a) = e {
            *a = a.clone().uniform();
        }
    }
    let opts = RenderOptions {
        threads: Some(2),
        region: None,
    };
    let a = render(&by_texture, &opts, &|_, _| {}, None).unwrap().0;
    let b = render(&uniform, &opts, &|_, _| {}, None).unwrap().0;
    assert!(mean(&a).r > 0.01, "a lit floor");
    for by in 0..3 {
        for bx in 0..3 {
            let d: Vec<f64> = (0..6)
                .flat_map(|y| (0..8).map(move |x| (bx * 8 + x, by * 6 + y)))
                .map(|(x, y)| {
                    let (p, q) = (a.get(x, y), b.get(x, y));
                    f64::from((p.r + p.g + p.b) - (q.r + q.g + q.b))
                })
                .collect();
            let n = d.len() as f64;
            let m = d.iter().sum::<f64>() / n;
            let var = d.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0);
            let z = m / (var / n).sqrt().max(1e-12);
            assert!(z.abs() < 4.5, "block ({bx}, {by}): z = {z}");
        }
    }
}
