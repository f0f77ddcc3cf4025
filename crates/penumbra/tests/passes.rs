//! Renders in passes: each pass adds the next range of every pixel's
//! samples to the film, and the image is the same bit for bit for any
//! number of passes — for every distribution, with the thesis's metrics,
//! and under every adaptive sampling rule.

mod common;

use common::*;
use penumbra::render::Image;
use penumbra::sampling::Distribution;
use penumbra::scene::{Overrides, Scene, StopRule};

fn bits(i: &Image) -> Vec<[u32; 3]> {
    i.pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// The showcase at 40×30 with every effect's sets, in `passes` passes.
fn showcase(passes: u32, o: &Overrides) -> Scene {
    let mut src = builtin("showcase", None);
    set(
        &mut src,
        Overrides {
            width: Some(40),
            height: Some(30),
            passes: Some(passes),
            ..o.clone()
        },
    );
    src.build().expect("showcase builds")
}

/// The image and ray counts of 1, 2, 3 and 7 passes are the same.
fn same_in_any_passes(o: &Overrides, what: &str) {
    let (one, rays) = render_scene(&showcase(1, o), 2);
    for passes in [2, 3, 7] {
        let (many, r) = render_scene(&showcase(passes, o), 2);
        assert_eq!(bits(&one), bits(&many), "{what}: {passes} passes");
        assert_eq!(rays, r, "{what}: {passes} passes");
    }
}

#[test]
fn every_distribution_gives_the_same_bits_in_any_passes() {
    for d in Distribution::ALL {
        let o = Overrides {
            spp: Some(6),
            shadow_rays: Some(4),
            reflection_rays: Some(4),
            refraction_rays: Some(4),
            distribution: Some(d),
            ..Default::default()
        };
        same_in_any_passes(&o, d.name());
    }
}

#[test]
fn the_metrics_give_the_same_bits_in_any_passes() {
    let o = Overrides {
        spp: Some(9),
        shadow_rays: Some(4),
        reflection_rays: Some(4),
        distribution: Some(Distribution::Jitter),
        metric: Some(true),
        pixel_metric: Some(true),
        metric_min_rays: Some(2),
        ..Default::default()
    };
    same_in_any_passes(&o, "metrics");
}

#[test]
fn every_stopping_rule_gives_the_same_bits_in_any_passes() {
    for rule in StopRule::ALL {
        let o = Overrides {
            spp: Some(48),
            distribution: Some(Distribution::Sobol),
            stop_rule: Some(rule),
            noise_threshold: Some(match rule {
                StopRule::Povray => 0.1,
                StopRule::Dammertz => 0.01,
                _ => 0.05,
            }),
            min_spp: Some(8),
            ..Default::default()
        };
        same_in_any_passes(&o, rule.name());
    }
}

/// More passes than samples: the passes beyond the samples add nothing.
#[test]
fn passes_beyond_the_samples_add_nothing() {
    let o = Overrides {
        spp: Some(1),
        distribution: Some(Distribution::Random),
        ..Default::default()
    };
    let (one, _) = render_scene(&showcase(1, &o), 2);
    let (two, _) = render_scene(&showcase(2, &o), 2);
    assert_eq!(
        bits(&one),
        bits(&two),
        "the second pass of one sample adds none"
    );
}
