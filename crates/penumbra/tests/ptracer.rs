//! The particle tracer (`ptracer`): against the path tracer on a diffuse
//! box (under a plain and a textured light), against the closed-form
//! irradiance of a point light, and the same bits however the work is cut.

mod common;

use common::*;
use penumbra::math::Rgb;
use penumbra::render::{render, Image, Region, RenderOptions};

/// A closed box [−1, 1]³ of diffuse walls (one red, one green), a diffuse
/// block on the floor, lit by a square area light under the ceiling and a
/// point light, seen from inside: no delta surface, every wall seen.
fn cornell(integrator: &str, seed: u32, render: &str) -> String {
    let walls = [
        ("white", [-1, -1, -1], [0, 0, 2], [2, 0, 0]),
        ("white", [-1, 1, -1], [2, 0, 0], [0, 0, 2]),
        ("red", [-1, -1, -1], [0, 2, 0], [0, 0, 2]),
        ("green", [1, -1, -1], [0, 0, 2], [0, 2, 0]),
        ("white", [-1, -1, -1], [2, 0, 0], [0, 2, 0]),
        ("white", [-1, -1, 1], [0, 2, 0], [2, 0, 0]),
    ];
    let mut s = format!(
        "[render]\nwidth = 24\nheight = 24\nintegrator = \"{integrator}\"\nseed = {seed}\n\
         {render}\n\
         [camera]\nposition = [0.0, 0.0, 0.95]\nlook_at = [0.0, -0.1, -1.0]\nfov = 80\n\n\
         [materials.white]\ntype = \"diffuse\"\nreflectance = [0.7, 0.7, 0.7]\n\
         [materials.red]\ntype = \"diffuse\"\nreflectance = [0.7, 0.15, 0.1]\n\
         [materials.green]\ntype = \"diffuse\"\nreflectance = [0.15, 0.6, 0.1]\n"
    );
    for (m, o, u, v) in walls {
        s += &format!(
            "\n[[objects]]\ntype = \"quad\"\nmaterial = \"{m}\"\norigin = {o:?}\n\
             edge_u = {u:?}\nedge_v = {v:?}\n"
        );
    }
    s += "\n[[objects]]\ntype = \"sphere\"\nmaterial = \"white\"\ncenter = [0.3, -0.6, -0.3]\n\
          radius = 0.4\n\
          \n[[lights]]\ntype = \"rect\"\norigin = [-0.3, 0.98, -0.6]\nedge_u = [0.6, 0, 0]\n\
          edge_v = [0, 0, 0.6]\nradiance = [6, 6, 6]\ncasts_shadows = true\n\
          \n[[lights]]\ntype = \"point\"\nposition = [-0.5, 0.3, 0.2]\nintensity = [0.6, 0.6, 0.6]\n";
    s
}

/// Per block of `b × b` pixels, the mean of each channel over renders of
/// one scene with different seeds, and its squared standard error,
/// estimated from the pixels: each pixel's sample variance over the
/// renders, over their count, summed over the block over its size squared.
fn blocks(images: &[Image], b: u32) -> Vec<([f64; 3], [f64; 3])> {
    let (w, h) = (images[0].width, images[0].height);
    let m = images.len() as f64;
    let mut out = Vec::new();
    for by in (0..h).step_by(b as usize) {
        for bx in (0..w).step_by(b as usize) {
            let (mut mean, mut var) = ([0f64; 3], [0f64; 3]);
            let n = f64::from(b * b);
            for y in by..by + b {
                for x in bx..bx + b {
                    for k in 0..3 {
                        let v: Vec<f64> = images
                            .iter()
                            .map(|i| f64::from(i.get(x, y).to_array()[k]))
                            .collect();
                        let mu = v.iter().sum::<f64>() / m;
                        let s2 = v.iter().map(|a| (a - mu) * (a - mu)).sum::<f64>() / (m - 1.0);
                        mean[k] += mu / n;
                        var[k] += s2 / m / (n * n);
                    }
                }
            }
            out.push((mean, var));
        }
    }
    out
}

/// On a diffuse box lit by an area light and a point light, the particle
/// tracer and the path tracer agree within noise: each block's mean (over
/// eight renders of each with different seeds) differs by less than 4.5
/// standard errors (a z-test, the errors measured from the pixels), and
/// the images' means by less than 1%.
#[test]
fn the_particle_tracer_agrees_with_the_path_tracer() {
    agree(|toml| toml, 64, 32);
}

/// The same through a rough glass ball (microfacet refraction, seen by the
/// camera): the radiance scaling of a refraction is undone along light
/// paths (the adjoint BSDF), else the ball would be off by η² = 2.25.
#[test]
fn the_particle_tracer_agrees_through_rough_glass() {
    let glass = |toml: String| {
        toml.replace(
            "material = \"white\"\ncenter",
            "material = \"glass\"\ncenter",
        ) + "\n[materials.glass]\ntype = \"roughdielectric\"\nalpha = 0.3\nint_ior = 1.5\n"
    };
    agree(glass, 128, 64);
}

/// The same seen through a thin lens focused on the back wall: each
/// connection goes to a point of the aperture.
#[test]
fn the_particle_tracer_agrees_through_a_thin_lens() {
    let lens = |toml: String| {
        toml.replace(
            "fov = 80\n",
            "fov = 80\naperture = 0.05\nfocal_distance = 1.9\n",
        )
    };
    agree(lens, 64, 32);
}

/// The same under a textured light: a checker of two colours (the
/// particle tracer draws its rays' origins uniformly on the light and
/// weighs them by the texture there; the path tracer sees the texture
/// where its rays hit the light and where its shadow rays end).
#[test]
fn the_particle_tracer_agrees_under_a_textured_light() {
    let checker = |toml: String| {
        toml.replace(
            "radiance = [6, 6, 6]",
            "radiance = { type = \"checkerboard\", color0 = [2, 2, 2], color1 = [12, 6, 3] }",
        )
    };
    agree(checker, 64, 32);
}

/// The z-test of both integrators on the box `edit` makes of [`cornell`],
/// at `spp_pt` and `spp_path` samples.
fn agree(edit: impl Fn(String) -> String, spp_pt: u32, spp_path: u32) {
    // Jittered film points: the default grid is a quadrature whose error at
    // an edge (the light's) is not noise.
    let render = |integrator: &str, seed: u32, spp: u32| {
        let extra = format!("spp = {spp}\nmax_depth = 6\npixel_distribution = \"jitter\"");
        render_toml(&edit(cornell(integrator, seed, &extra))).0
    };
    let pt: Vec<Image> = (1..=8)
        .map(|seed| render("ptracer", seed, spp_pt))
        .collect();
    let path: Vec<Image> = (1..=8).map(|seed| render("path", seed, spp_path)).collect();
    let (a, b) = (blocks(&pt, 6), blocks(&path, 6));
    let mut worst = 0f64;
    for (i, ((ma, va), (mb, vb))) in a.iter().zip(&b).enumerate() {
        for k in 0..3 {
            let se = (va[k] + vb[k]).sqrt().max(1e-4 * mb[k].abs());
            let z = (ma[k] - mb[k]) / se;
            worst = worst.max(z.abs());
            assert!(
                z.abs() < 4.5,
                "block {i} channel {k}: ptracer {} path {} (z = {z:.2})",
                ma[k],
                mb[k]
            );
        }
    }
    let mean = |v: &[Image]| v.iter().map(Image::mean).sum::<Rgb>();
    let (m1, m2) = (mean(&pt), mean(&path));
    let rel = ((m1 - m2).abs() / m2).max_element();
    assert!(rel < 0.01, "means {m1:?} vs {m2:?} ({rel})");
    eprintln!("worst |z| = {worst:.2}, means differ by {rel:.4}");
}

/// The light a diffuse plane of albedo ρ reflects under a point light of
/// intensity I at height h is `ρ / π · I cos θ / r²`: the particle tracer's
/// pixels, averaged over blocks, are within 4% of it, under a pinhole and
/// an orthographic camera looking straight down.
#[test]
fn a_plane_under_a_point_light_reflects_the_closed_form() {
    let (rho, intensity, h) = (0.6f32, 3.0f32, 1.5f32);
    for camera in [
        "position = [0, 4, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 40",
        "projection = \"orthographic\"\nposition = [0, 4, 0]\nlook_at = [0, 0, 0]\n\
         up = [0, 0, -1]\nview_width = 2.9",
    ] {
        let toml = format!(
            "[render]\nwidth = 32\nheight = 32\nintegrator = \"ptracer\"\nspp = 512\nseed = 4\n\
             max_depth = 2\n\n[camera]\n{camera}\n\n\
             [materials.plane]\ntype = \"diffuse\"\nreflectance = [{rho}, {rho}, {rho}]\n\n\
             [[objects]]\ntype = \"quad\"\nmaterial = \"plane\"\norigin = [-4, 0, -4]\n\
             edge_u = [0, 0, 8]\nedge_v = [8, 0, 0]\n\n\
             [[lights]]\ntype = \"point\"\nposition = [0, {h}, 0]\n\
             intensity = [{intensity}, {intensity}, {intensity}]\n"
        );
        let s = scene(&toml);
        let (img, _) = render_scene(&s, 2);
        // Where each pixel's centre sees the plane: the camera ray of the
        // centre, met with y = 0.
        let cam = &s.camera;
        let b = 8u32;
        for by in (0..32u32).step_by(b as usize) {
            for bx in (0..32u32).step_by(b as usize) {
                let (mut got, mut want) = (0f64, 0f64);
                for y in by..by + b {
                    for x in bx..bx + b {
                        let centre = penumbra::math::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                        let p = plane_point(cam, centre);
                        let to = penumbra::math::Vec3::new(0.0, h, 0.0) - p;
                        let cos = to.y / to.length();
                        let e = intensity * cos / to.length_squared();
                        want += f64::from(rho / std::f32::consts::PI * e);
                        got += f64::from(img.get(x, y).g);
                    }
                }
                let rel = (got - want).abs() / want;
                assert!(rel < 0.04, "{camera}: block ({bx}, {by}): {got} vs {want}");
            }
        }
    }
}

/// Where the camera ray through film position `f` meets the plane y = 0.
fn plane_point(cam: &penumbra::camera::Camera, f: penumbra::math::Vec2) -> penumbra::math::Vec3 {
    let mut rays = Vec::new();
    cam.generate(
        &[penumbra::camera::CameraSample {
            film: f,
            lens: penumbra::math::Vec2::ZERO,
            time: 0.0,
        }],
        &mut rays,
    );
    let r = rays[0];
    r.at(-r.origin.y / r.dir.y)
}

/// A frame of more than one tile (the particle tracer's are 64 pixels),
/// splatted through a Gaussian: the same bits on 1 and 3 threads, in 1 and
/// 3 passes (and by `samples_per_pass`), and a region cut across tiles
/// rendered alone has the frame's pixels.
#[test]
fn light_paths_give_the_same_bits_however_the_work_is_cut() {
    let base = |extra: &str| {
        cornell(
            "ptracer",
            7,
            &format!("spp = 3\nfilter = \"gaussian\"\n{extra}"),
        )
        .replace("width = 24\nheight = 24", "width = 80\nheight = 70")
    };
    let s = scene(&base(""));
    let (one, rays1) = render_scene(&s, 1);
    let (three, rays3) = render_scene(&s, 3);
    assert!(one.mean().g > 0.0);
    assert_eq!(one.pixels, three.pixels);
    assert_eq!(rays1, rays3);
    let (passes, _) = render_toml(&base("passes = 3"));
    assert_eq!(one.pixels, passes.pixels);
    let (by_size, _) = render_toml(&base("samples_per_pass = 1"));
    assert_eq!(one.pixels, by_size.pixels);
    for region in [
        Region {
            x0: 50,
            y0: 10,
            x1: 75,
            y1: 68,
        },
        Region {
            x0: 0,
            y0: 63,
            x1: 80,
            y1: 66,
        },
    ] {
        assert_region_is_the_frames(&s, &one, region, "ptracer");
    }
    // A cancelled render is refused, not half a frame.
    let cancel = std::sync::atomic::AtomicBool::new(true);
    let opts = RenderOptions {
        threads: Some(2),
        region: None,
    };
    assert!(render(&s, &opts, &|_, _| {}, Some(&cancel)).is_err());
}

/// Emitters seen directly are black with `hide_emitters` (the area light's
/// pixels), and `max_depth = 1` shows only them.
#[test]
fn max_depth_and_hidden_emitters_follow_mitsuba() {
    let img = |extra: &str| render_toml(&cornell("ptracer", 3, &format!("spp = 16\n{extra}"))).0;
    let black = img("max_depth = 0");
    assert!(black.pixels.iter().all(|p| *p == Rgb::ZERO));
    let seen = img("max_depth = 1");
    let lit: Vec<usize> = (0..seen.pixels.len())
        .filter(|&k| seen.pixels[k].g > 0.0)
        .collect();
    assert!(
        !lit.is_empty() && lit.len() < seen.pixels.len() / 4,
        "{}",
        lit.len()
    );
    // The light's radiance where the camera sees it whole.
    let centre = lit.iter().map(|&k| seen.pixels[k].g).fold(0f32, f32::max);
    assert!((centre - 6.0).abs() < 0.6, "{centre}");
    let hidden = img("max_depth = 1\nhide_emitters = true");
    assert!(hidden.pixels.iter().all(|p| *p == Rgb::ZERO));
    let direct = img("max_depth = 2\nhide_emitters = true");
    assert!(direct.mean().g > 0.0);
}

/// The particle tracer's parameters are checked at their place.
#[test]
fn bad_ptracer_parameters_are_located() {
    for (line, want) in [
        (
            "max_depth = -2",
            "must be -1 (no bound) or an integer from 0 to",
        ),
        ("rr_depth = 0", "must be an integer from 1 to"),
        ("metric = true", "metric"),
    ] {
        let e = try_scene(&cornell("ptracer", 1, line))
            .err()
            .unwrap_or_else(|| panic!("{line} refused"))
            .to_string();
        assert!(e.starts_with("test.toml:"), "{line}: {e}");
        assert!(e.contains(want), "{line}: {e}");
    }
}

/// A constant background seen directly: each emitter at infinity is
/// connected from the eye in a direction it draws, so every pixel sees its
/// radiance (within 5% over blocks of 16 pixels, 1% over the image: about
/// four standard deviations, the directions drawn over the whole sphere).
#[test]
fn the_background_is_seen_directly() {
    let toml = "[render]\nwidth = 16\nheight = 16\nintegrator = \"ptracer\"\nspp = 4096\nseed = 2\n\
                background = [0.5, 0.25, 1.0]\n\n\
                [camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = 60\n\n\
                [[objects]]\ntype = \"quad\"\norigin = [-1, -1, 3]\nedge_u = [2, 0, 0]\nedge_v = [0, 2, 0]\n";
    let (img, _) = render_toml(toml);
    let want = Rgb::new(0.5, 0.25, 1.0);
    let rel = ((img.mean() - want).abs() / want).max_element();
    assert!(rel < 0.01, "{:?}", img.mean());
    for by in (0..16).step_by(4) {
        for bx in (0..16).step_by(4) {
            let mut sum = Rgb::ZERO;
            for y in by..by + 4 {
                for x in bx..bx + 4 {
                    sum += img.get(x, y);
                }
            }
            let rel = ((sum / 16.0 - want).abs() / want).max_element();
            assert!(rel < 0.05, "block ({bx}, {by}): {:?}", sum / 16.0);
        }
    }
}
