//! The film's alpha channel (`alpha`, Mitsuba's `pixel_format` `rgba`):
//! 1 where a pixel is covered, 0 on the background, the covered share at
//! an edge; the same bits on any number of threads and passes.

mod common;

use common::{scene, try_scene};
use penumbra::render::{render, Image, Region, RenderOptions};
use penumbra::scene::{LoadOptions, Scene, SceneSource};

fn run(s: &Scene, threads: usize, region: Option<Region>) -> Image {
    let opts = RenderOptions {
        threads: Some(threads),
        region,
    };
    render(s, &opts, &|_, _| {}, None).expect("render").0
}

/// The alpha of `img`, pixel by pixel.
fn alpha(img: &Image) -> Vec<f32> {
    let extra = img.extra.as_ref().expect("an alpha channel");
    assert_eq!(extra.names, ["A"]);
    extra.channel(0).collect()
}

const W: u32 = 40;
const H: u32 = 30;
const FOV: f32 = 40.0;
/// The column the quad's right edge crosses, and how much of it the quad
/// covers.
const EDGE_COLUMN: u32 = 20;
const COVERED: f32 = 0.3;

/// A camera at the origin looking down −z at a quad at distance 3 whose
/// right edge crosses column `EDGE_COLUMN`, covering `COVERED` of it, and
/// which covers every column left of it top to bottom.
fn edge_scene(render: &str) -> String {
    let t = (FOV.to_radians() * 0.5).tan();
    let sx = ((EDGE_COLUMN as f32 + COVERED) / W as f32 * 2.0 - 1.0) * t * W as f32 / H as f32;
    let edge = 3.0 * sx;
    format!(
        "[render]\nwidth = {W}\nheight = {H}\nalpha = true\n{render}\n\n\
         [camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = {FOV}\n\n\
         [materials.white]\nalbedo = [0.5, 0.5, 0.5]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"white\"\norigin = [-10, -8, -3]\n\
         edge_u = [{}, 0, 0]\nedge_v = [0, 16, 0]\n\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 0, 0]\nintensity = [1, 1, 1]\n",
        edge + 10.0
    )
}

/// Covered pixels have alpha 1 and background pixels 0, exactly; the
/// pixels the edge crosses have the covered share within noise (256
/// uniform film points each, the box filter: a binomial share).
#[test]
fn alpha_is_the_covered_share_of_a_pixel() {
    let spp = 256;
    for integrator in ["whitted", "path"] {
        let s = scene(&edge_scene(&format!(
            "integrator = \"{integrator}\"\nspp = {spp}\npixel_distribution = \"fast-random\"\n\
             filter = \"box\""
        )));
        let img = run(&s, 2, None);
        let a = alpha(&img);
        let sigma = (COVERED * (1.0 - COVERED) / spp as f32).sqrt();
        let mut sum = 0.0;
        for y in 0..H {
            for x in 0..W {
                let v = a[(y * W + x) as usize];
                match x.cmp(&EDGE_COLUMN) {
                    std::cmp::Ordering::Less => assert_eq!(v, 1.0, "{integrator} ({x}, {y})"),
                    std::cmp::Ordering::Greater => assert_eq!(v, 0.0, "{integrator} ({x}, {y})"),
                    std::cmp::Ordering::Equal => {
                        assert!(
                            (v - COVERED).abs() < 5.0 * sigma,
                            "{integrator} ({x}, {y}): alpha {v}, covered {COVERED} ± {sigma}"
                        );
                        sum += v;
                    }
                }
            }
        }
        let mean = sum / H as f32;
        let sigma_mean = sigma / (H as f32).sqrt();
        assert!(
            (mean - COVERED).abs() < 4.0 * sigma_mean,
            "{integrator}: the edge column's mean alpha {mean}, covered {COVERED} ± {sigma_mean}"
        );
        // The colour is premultiplied: the background is black, the
        // covered pixels lit.
        let lit = img.pixels[(H / 2 * W + 2) as usize];
        assert!(lit.r > 0.0);
        assert_eq!(img.pixels[(H / 2 * W + W - 1) as usize].r, 0.0);
    }
}

/// With a splatting Gaussian filter an edge's alpha is the filtered
/// coverage; its bits are the same on 1 and 3 threads, in 1 or 3 passes,
/// and in a region of the frame.
#[test]
fn alpha_keeps_its_bits_on_threads_passes_and_regions() {
    let render = |passes: u32| {
        scene(&edge_scene(&format!(
            "integrator = \"path\"\nspp = 12\npasses = {passes}\npixel_distribution = \"fast-random\"\n\
             filter = \"gaussian\"\nsplat = true"
        )))
    };
    let one = render(1);
    let base = run(&one, 1, None);
    let bits = |img: &Image| alpha(img).iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let a = alpha(&base);
    assert!(a.iter().any(|&v| v > 0.0 && v < 1.0), "a fractional edge");
    assert!(a.iter().all(|&v| (0.0..=1.0 + 1e-6).contains(&v)));
    assert_eq!(bits(&run(&one, 3, None)), bits(&base), "3 threads");
    assert_eq!(bits(&run(&render(3), 3, None)), bits(&base), "3 passes");
    let region = Region {
        x0: EDGE_COLUMN - 3,
        y0: 4,
        x1: EDGE_COLUMN + 5,
        y1: 11,
    };
    let part = alpha(&run(&one, 3, Some(region)));
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            let k = ((y - region.y0) * region.width() + x - region.x0) as usize;
            assert_eq!(
                part[k].to_bits(),
                a[(y * W + x) as usize].to_bits(),
                "({x}, {y})"
            );
        }
    }
}

/// An emitter at infinity covers every pixel, unless the integrator hides
/// the emitters.
#[test]
fn an_emitter_at_infinity_covers_the_background_unless_hidden() {
    let with_sky = |hide: bool| {
        scene(&edge_scene(&format!(
            "integrator = \"path\"\nspp = 2\nbackground = [0.2, 0.2, 0.2]\nhide_emitters = {hide}"
        )))
    };
    let seen = alpha(&run(&with_sky(false), 2, None));
    assert!(seen.iter().all(|&v| v == 1.0));
    let hidden = alpha(&run(&with_sky(true), 2, None));
    assert_eq!(hidden[(W - 1) as usize], 0.0);
    assert_eq!(hidden[0], 1.0);
}

/// `ptracer`, whose samples land anywhere, refuses the film's alpha,
/// saying why; `aov` writes its own channels (its `N.A` is the alpha)
/// without it.
#[test]
fn ptracer_refuses_alpha_and_aov_writes_its_own() {
    let opts = RenderOptions {
        threads: Some(1),
        region: None,
    };
    let s = try_scene(&edge_scene("integrator = \"ptracer\"")).expect("the scene builds");
    let e = render(&s, &opts, &|_, _| {}, None).unwrap_err();
    assert!(e.to_string().contains("`alpha`"), "{e}");
    let s = scene(&edge_scene(
        "integrator = \"aov\"\naovs = \"dd:depth\"\nnested = { type = \"path\", name = \"img\" }",
    ));
    let img = run(&s, 1, None);
    let names = &img.extra.as_ref().unwrap().names;
    assert_eq!(names.join(" "), "img.R img.G img.B img.A dd.T");
}

/// Mitsuba's `pixel_format`: `rgba` gives the alpha channel, `rgb` none,
/// `luminance` is written as RGB with a warning, an unknown one is refused
/// at its place.
#[test]
fn mitsuba_pixel_format_chooses_the_alpha() {
    let dir = tempfile::tempdir().unwrap();
    let load = |format: &str| {
        let xml = format!(
            "<scene version=\"3.0.0\"><integrator type=\"path\"/>\
             <sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\
             <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/>\
             <integer name=\"height\" value=\"6\"/>\
             <string name=\"pixel_format\" value=\"{format}\"/></film>\
             <sampler type=\"independent\"><integer name=\"sample_count\" value=\"4\"/></sampler>\
             </sensor>\
             <shape type=\"sphere\"><point name=\"center\" value=\"0, 0, 4\"/>\
             <float name=\"radius\" value=\"0.6\"/></shape></scene>"
        );
        let path = dir.path().join("s.xml");
        std::fs::write(&path, xml).unwrap();
        SceneSource::open(path.to_str().unwrap(), &LoadOptions::default())?.build()
    };
    let s = load("rgba").unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let a = alpha(&run(&s, 1, None));
    // The sphere covers the centre, not the corner (beyond the
    // Gaussian filter's reach of it).
    assert!(a[3 * 8 + 4] > 0.5, "{}", a[3 * 8 + 4]);
    assert_eq!(a[0], 0.0);
    assert!(run(&load("RGB").unwrap(), 1, None).extra.is_none());
    let lum = load("luminance_alpha").unwrap();
    assert!(
        lum.warnings.iter().any(|w| w.contains("luminance_alpha")),
        "{:?}",
        lum.warnings
    );
    assert!(lum.settings.alpha);
    let Err(e) = load("cmyk") else {
        panic!("an unknown pixel format is read");
    };
    let e = e.to_string();
    assert!(e.contains("s.xml:1:") && e.contains("cmyk"), "{e}");
}
