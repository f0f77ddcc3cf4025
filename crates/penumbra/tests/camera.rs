//! The camera as a render sees it: clip planes that hide what lies before
//! the near one or beyond the far one (and change nothing between them), a
//! principal point offset that moves the image, an orthographic view of
//! the size asked for, and a crop window that renders exactly its part of
//! the full image.

mod common;

use common::{render_scene, scene};
use penumbra::math::Rgb;
use penumbra::render::Image;

const INTEGRATORS: [&str; 4] = ["whitted", "path", "direct", "distributed"];

/// Two glowing spheres on the view axis of a camera at z = 5 looking down
/// -z: a red one 1.5 away (its near side at 1.4), a green one 5 away (its
/// near side at 4.5), behind it and seen around it; black elsewhere.
fn two_spheres(integrator: &str, camera: &str) -> String {
    let depth = if integrator == "path" {
        "max_depth = 1\n"
    } else {
        ""
    };
    format!(
        "[render]\nwidth = 16\nheight = 16\nspp = 4\nintegrator = \"{integrator}\"\n\
         {depth}\n\
         [camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 20\n{camera}\n\n\
         [materials.black]\nalbedo = [0, 0, 0]\n\n\
         [[objects]]\ntype = \"sphere\"\nmaterial = \"black\"\ncenter = [0, 0, 3.5]\n\
         radius = 0.1\nemitter = {{ type = \"area\", radiance = [1, 0, 0] }}\n\n\
         [[objects]]\ntype = \"sphere\"\nmaterial = \"black\"\ncenter = [0, 0, 0]\n\
         radius = 0.5\nemitter = {{ type = \"area\", radiance = [0, 1, 0] }}\n"
    )
}

fn bits(image: &Image) -> Vec<[u32; 3]> {
    image
        .pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// The mean of the centre's 2 × 2 pixels (which both spheres cover).
fn centre(image: &Image) -> Rgb {
    let (x, y) = (image.width / 2, image.height / 2);
    (image.get(x - 1, y - 1) + image.get(x, y - 1) + image.get(x - 1, y) + image.get(x, y)) * 0.25
}

#[test]
fn clip_planes_hide_what_lies_outside_them_and_nothing_else() {
    for integrator in INTEGRATORS {
        let render = |camera: &str| render_scene(&scene(&two_spheres(integrator, camera)), 2).0;
        let open = render("");
        let red = centre(&open);
        assert!(red.r > 0.9 && red.g == 0.0, "{integrator}: {red:?}");
        // Planes that cut nothing leave every bit as it was.
        let wide = render("near_clip = 0.5\nfar_clip = 1000");
        assert_eq!(bits(&open), bits(&wide), "{integrator}");
        // The red sphere lies before a near plane at 2: the green one shows.
        let near = centre(&render("near_clip = 2"));
        assert!(near.r == 0.0 && near.g > 0.9, "{integrator}: {near:?}");
        // The green sphere lies beyond a far plane at 4 too: nothing shows.
        let both = centre(&render("near_clip = 2\nfar_clip = 4"));
        assert_eq!(both, Rgb::ZERO, "{integrator}");
        // A far plane at 4 alone keeps the red sphere, and the green one
        // beside it disappears (its rim, seen past the red one).
        let far = render("far_clip = 4");
        assert_eq!(centre(&far), red, "{integrator}");
        assert!(open.mean().g > 0.0, "{integrator}");
        assert_eq!(far.mean().g, 0.0, "{integrator}");
    }
}

/// One glowing sphere on the axis of a 64 × 32 image; `camera` adds to
/// the camera.
fn one_sphere(camera: &str, render: &str) -> String {
    format!(
        "[render]\nwidth = 64\nheight = 32\nspp = 16\nintegrator = \"path\"\n\
         distribution = \"jitter\"\n{render}\n\n\
         [camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 30\n{camera}\n\n\
         [materials.black]\nalbedo = [0, 0, 0]\n\n\
         [[objects]]\ntype = \"sphere\"\nmaterial = \"black\"\ncenter = [0, 0, 0]\n\
         radius = 0.6\nemitter = {{ type = \"area\", radiance = [1, 1, 1] }}\n"
    )
}

/// The image's brightness-weighted centre, in pixels, and its total.
fn centroid(image: &Image) -> (f64, f64, f64) {
    let (mut sx, mut sy, mut total) = (0.0, 0.0, 0.0);
    for y in 0..image.height {
        for x in 0..image.width {
            let v = f64::from(image.get(x, y).r);
            sx += v * (f64::from(x) + 0.5);
            sy += v * (f64::from(y) + 0.5);
            total += v;
        }
    }
    (sx / total, sy / total, total)
}

#[test]
fn the_principal_point_offset_moves_the_image_by_its_share_of_the_film() {
    let base = render_scene(&scene(&one_sphere("", "")), 2).0;
    let (x0, y0, t0) = centroid(&base);
    assert!(
        (x0 - 32.0).abs() < 0.05 && (y0 - 16.0).abs() < 0.05,
        "{x0} {y0}"
    );
    // 0.125 of 64 pixels to the right, 0.25 of 32 up: the image's content
    // moves 8 pixels left and 8 down.
    let shifted = one_sphere("principal_point_offset = [0.125, -0.25]", "");
    let (x, y, t) = centroid(&render_scene(&scene(&shifted), 2).0);
    assert!(
        (x - 24.0).abs() < 0.05 && (y - 24.0).abs() < 0.05,
        "{x} {y}"
    );
    // The same light, but for the noise of other film positions.
    assert!((t - t0).abs() < 1e-2 * t0, "{t} {t0}");
}

#[test]
fn an_orthographic_camera_sees_its_view_at_true_size() {
    // A view 4 × 2 around a sphere of radius 0.6: the sphere covers
    // pi · 0.36 of its 8 square units, whatever the distance.
    for position in ["[0, 0, 5]", "[0, 0, 50]"] {
        let camera =
            format!("projection = \"orthographic\"\nview_width = 4\nposition = {position}\n")
                .replace("position = [0, 0, 5]\nlook_at", "look_at");
        let text =
            one_sphere(&camera, "").replace("[camera]\nposition = [0, 0, 5]\n", "[camera]\n");
        let image = render_scene(&scene(&text), 2).0;
        let covered = f64::from(image.mean().r) * 8.0;
        let want = std::f64::consts::PI * 0.36;
        assert!(
            (covered - want).abs() < 0.01 * want,
            "{position}: {covered} {want}"
        );
        let (x, y, _) = centroid(&image);
        assert!(
            (x - 32.0).abs() < 0.05 && (y - 16.0).abs() < 0.05,
            "{x} {y}"
        );
    }
}

#[test]
fn a_crop_window_renders_exactly_its_part_of_the_image() {
    for integrator in INTEGRATORS {
        let full_text = one_sphere("", "").replace("\"path\"", &format!("\"{integrator}\""));
        let full = render_scene(&scene(&full_text), 2).0;
        let crop = "crop_offset_x = 21\ncrop_offset_y = 5\ncrop_width = 19\ncrop_height = 13";
        let cropped_text = one_sphere("", crop).replace("\"path\"", &format!("\"{integrator}\""));
        let part = render_scene(&scene(&cropped_text), 2).0;
        assert_eq!((part.width, part.height), (19, 13));
        for y in 0..13 {
            for x in 0..19 {
                let (a, b) = (part.get(x, y), full.get(x + 21, y + 5));
                assert_eq!(
                    a.to_array().map(f32::to_bits),
                    b.to_array().map(f32::to_bits)
                );
            }
        }
        assert!(part.mean().r > 0.0, "{integrator}");
    }
}

#[test]
fn a_crop_window_must_lie_in_the_image() {
    let text = one_sphere("", "crop_offset_x = 60\ncrop_width = 5");
    let e = common::try_scene(&text).err().expect("refused").to_string();
    assert!(
        e.contains("render.crop_width") && e.contains("leaves the image"),
        "{e}"
    );
}
