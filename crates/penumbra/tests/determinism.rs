//! Reproducibility: the same scene and seed give the same pixels on any
//! number of threads and for any split into regions.

mod common;

use common::*;
use penumbra::render::Region;
use penumbra::scene::Overrides;

fn size(width: u32, height: u32) -> Overrides {
    Overrides {
        width: Some(width),
        height: Some(height),
        ..Default::default()
    }
}

/// An image's bits, pixel by pixel.
fn bits(img: &penumbra::render::Image) -> Vec<[u32; 3]> {
    img.pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

fn small_showcase() -> penumbra::scene::Scene {
    let mut src = builtin("showcase", None);
    set(&mut src, size(64, 48));
    src.build().expect("showcase builds")
}

#[test]
fn one_and_many_threads_give_identical_pixels() {
    let s = small_showcase();
    let (a, ra) = render_scene(&s, 1);
    let (b, rb) = render_scene(&s, 2);
    let (c, rc) = render_scene(&s, 5);
    assert!(a
        .pixels
        .iter()
        .zip(&b.pixels)
        .all(|(x, y)| x.to_array().map(f32::to_bits) == y.to_array().map(f32::to_bits)));
    assert!(a == c, "1 and 5 threads differ");
    assert_eq!(ra, rb);
    assert_eq!(ra, rc);
}

#[test]
fn regions_stitch_into_the_full_frame() {
    let s = small_showcase();
    let (full, _) = render_scene(&s, 2);
    let region = Region {
        x0: 13,
        y0: 7,
        x1: 50,
        y1: 40,
    };
    assert_region_is_the_frames(&s, &full, region, "showcase");
}

#[test]
fn a_different_seed_gives_different_noise() {
    let mut src = builtin("showcase", None);
    set(&mut src, size(32, 24));
    let a = render_scene(&src.build().unwrap(), 2).0;
    set(
        &mut src,
        Overrides {
            seed: Some(7),
            ..Default::default()
        },
    );
    let b = render_scene(&src.build().unwrap(), 2).0;
    assert!(a != b, "seeds 0 and 7 gave the same image");
}

#[test]
fn bunny_renders_identically_on_one_and_two_threads() {
    let Some(bunny) = bunny() else { return };
    let mut src = builtin("bunny", Some(bunny));
    set(&mut src, size(80, 60));
    let s = src.build().expect("bunny scene");
    assert!(
        render_scene(&s, 1) == render_scene(&s, 2),
        "1 and 2 threads differ"
    );
}

/// The filters with negative lobes weigh each sample by its own offset
/// only: the same pixels, bit for bit, on 1 and 3 threads, in 1 and 3
/// passes, and in a region cut across the tiles (what a worker of a
/// distributed render draws), for the Whitted and the path tracer.
#[test]
fn signed_filters_keep_pixels_independent() {
    use penumbra::sampling::Filter;
    use penumbra::scene::IntegratorChoice;
    for (filter, integrator) in [
        (Filter::Mitchell, IntegratorChoice::Whitted),
        (Filter::Lanczos, IntegratorChoice::Whitted),
        (Filter::Lanczos, IntegratorChoice::Path),
    ] {
        let build = |passes: u32| {
            let mut src = builtin("showcase", None);
            set(
                &mut src,
                Overrides {
                    filter: Some(filter),
                    integrator: Some(integrator),
                    spp: Some(6),
                    passes: Some(passes),
                    ..size(48, 40)
                },
            );
            src.build().expect("showcase builds")
        };
        let s = build(1);
        let (a, ra) = render_scene(&s, 1);
        let (b, rb) = render_scene(&s, 3);
        let what = format!("{filter:?} {integrator:?}");
        assert!(bits(&a) == bits(&b), "{what}: 1 and 3 threads differ");
        assert_eq!(ra, rb, "{what}");
        let (c, _) = render_scene(&build(3), 2);
        assert!(bits(&a) == bits(&c), "{what}: 1 and 3 passes differ");
        let region = Region {
            x0: 5,
            y0: 17,
            x1: 41,
            y1: 39,
        };
        assert_region_is_the_frames(&s, &a, region, &what);
    }
}

/// A splatting film adds each sample to the pixels around its own, across
/// tile borders: still the same pixels, bit for bit, on 1 and 3 threads,
/// in 1 and 3 passes, in regions cut across the tiles (each rendering the
/// samples of the pixels around it), and under adaptive sampling, for the
/// Whitted and the path tracer, with a positive and a signed filter.
#[test]
fn splatted_samples_give_the_same_pixels_on_any_threads_passes_and_regions() {
    use penumbra::sampling::Filter;
    use penumbra::scene::IntegratorChoice;
    for (filter, integrator, noise) in [
        (Filter::Gaussian, IntegratorChoice::Whitted, None),
        (Filter::Lanczos, IntegratorChoice::Path, None),
        (Filter::Gaussian, IntegratorChoice::Whitted, Some(0.05)),
    ] {
        let build = |passes: u32| {
            let mut src = builtin("showcase", None);
            set(
                &mut src,
                Overrides {
                    filter: Some(filter),
                    integrator: Some(integrator),
                    splat: Some(true),
                    spp: Some(6),
                    passes: Some(passes),
                    noise_threshold: noise,
                    ..size(48, 40)
                },
            );
            src.build().expect("showcase builds")
        };
        let s = build(1);
        assert!(s.settings.splat);
        let (a, ra) = render_scene(&s, 1);
        let (b, rb) = render_scene(&s, 3);
        let what = format!("{filter:?} {integrator:?} {noise:?}");
        assert!(bits(&a) == bits(&b), "{what}: 1 and 3 threads differ");
        assert_eq!(ra, rb, "{what}");
        let (c, _) = render_scene(&build(3), 2);
        assert!(bits(&a) == bits(&c), "{what}: 1 and 3 passes differ");
        for region in [
            Region {
                x0: 5,
                y0: 17,
                x1: 41,
                y1: 39,
            },
            Region {
                x0: 0,
                y0: 0,
                x1: 1,
                y1: 40,
            },
            Region {
                x0: 33,
                y0: 31,
                x1: 48,
                y1: 40,
            },
        ] {
            assert_region_is_the_frames(&s, &a, region, &what);
        }
    }
}

/// The box filter covers a sample's own pixel only: splatting by it is
/// drawing film points from it, bit for bit.
#[test]
fn splatting_by_the_box_is_the_pixels_own_samples() {
    let render = |splat: bool| {
        let mut src = builtin("showcase", None);
        set(
            &mut src,
            Overrides {
                splat: Some(splat),
                spp: Some(4),
                ..size(32, 24)
            },
        );
        let s = src.build().expect("showcase builds");
        assert!(!s.settings.splat);
        render_scene(&s, 2)
    };
    assert!(render(true) == render(false));
}

/// Splatting weighs each pixel's samples by the filter and divides by the
/// weights: a scene of one radiance everywhere (a constant environment
/// seen through nothing) gives that radiance in every pixel, whatever
/// the filter's shape, signed or not.
#[test]
fn a_uniform_scene_stays_uniform_under_splatting() {
    for filter in ["gaussian", "mitchell", "lanczos", "tent"] {
        let toml = format!(
            "[render]\nwidth = 20\nheight = 14\nspp = 5\nfilter = \"{filter}\"\nsplat = true\n\
             distribution = \"random\"\nintegrator = \"path\"\nbackground = [0.25, 0.5, 2.0]\n\
             [camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = 40\n"
        );
        let s = scene(&toml);
        assert!(s.settings.splat, "{filter}");
        let (img, _) = render_scene(&s, 2);
        for (k, p) in img.pixels.iter().enumerate() {
            let want = penumbra::math::Rgb::new(0.25, 0.5, 2.0);
            assert!(
                (*p - want).abs().max_element() <= 1e-6 * 2.0,
                "{filter}: pixel {k} is {p:?}"
            );
        }
    }
}

/// The driver keeps its workers, with their buffers, across tiles and
/// passes. A worker that rendered other tiles and passes before (one
/// thread does every job in turn) gives a tile the pixels a worker of its
/// own gives (the tile rendered alone), and the frame the pixels and ray
/// counts of three threads, for every integrator.
#[test]
fn kept_workers_carry_nothing_from_one_job_to_the_next() {
    use penumbra::scene::IntegratorChoice;
    for choice in IntegratorChoice::ALL {
        let build = |passes| {
            let mut src = builtin("showcase", None);
            let o = Overrides {
                integrator: Some(choice),
                spp: Some(4),
                passes,
                ..size(150, 70)
            };
            set(&mut src, o);
            src.build()
        };
        // `aov` and `depth` take no passes.
        let s = build(Some(2))
            .or_else(|_| build(None))
            .expect("showcase builds");
        let what = choice.name();
        let (one, a) = render_scene(&s, 1);
        let (three, b) = render_scene(&s, 3);
        assert_eq!(a, b, "{what}: ray counts on 1 and 3 threads");
        assert!(bits(&one) == bits(&three), "{what}: 1 and 3 threads differ");
        // The last 32-pixel tile of the second row of both tile grids.
        let region = Region {
            x0: 96,
            y0: 32,
            x1: 128,
            y1: 64,
        };
        assert_region_is_the_frames(&s, &one, region, what);
    }
}
