//! Progressive renders: a render interrupted after any tile and resumed
//! from its checkpoint, as often as it takes, gives the bits and the ray
//! counts of the render made at once — for every kind of integrator state
//! (the thesis's metrics, adaptive sampling, a splatting film, a light
//! tracer's light image, media); a checkpoint of another render is
//! refused; a time limit ends a render with a checkpoint that resumes.

mod common;

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use common::*;
use penumbra::render::{
    render_progressive, CheckpointError, Checkpointing, DigestInput, Ended, Image, PassView,
    Progressive, RenderError, RenderOptions, RenderStats,
};
use penumbra::sampling::{Distribution, Filter};
use penumbra::scene::{IntegratorChoice, Overrides, Scene, StopRule};

fn bits(i: &Image) -> (Vec<[u32; 3]>, Vec<u32>) {
    let pixels = i
        .pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    let extra = i
        .extra
        .as_ref()
        .map(|e| e.values.iter().map(|v| v.to_bits()).collect())
        .unwrap_or_default();
    (pixels, extra)
}

/// The built-in `name` at 40×30 in 3 passes with `o`.
fn builtin_scene(name: &str, o: Overrides) -> Scene {
    let mut src = builtin(name, None);
    set(
        &mut src,
        Overrides {
            width: Some(40),
            height: Some(30),
            passes: Some(3),
            ..o
        },
    );
    src.build().expect("the scene builds")
}

fn opts() -> RenderOptions {
    RenderOptions {
        threads: Some(2),
        region: None,
    }
}

/// One leg of a render: resumed from `resume` if given, saving to `path`
/// every `interval`, interrupted once `stop_at` tiles (of every pass, the
/// resumed ones included) are done.
fn leg(
    scene: &Scene,
    path: &Path,
    resume: bool,
    interval: Duration,
    stop_at: Option<usize>,
) -> Result<(Image, RenderStats), RenderError> {
    let flag = AtomicBool::new(false);
    let progress = |done: usize, _: usize| {
        if stop_at.is_some_and(|s| done >= s) {
            flag.store(true, Ordering::Relaxed);
        }
    };
    let interrupt = || flag.load(Ordering::Relaxed);
    let run = Progressive {
        interrupt: Some(&interrupt),
        checkpoint: Some(Checkpointing {
            save: Some(path.to_path_buf()),
            interval,
            resume: resume.then(|| path.to_path_buf()),
            digest: DigestInput::new().add(b"the test's scene").finish(),
        }),
        ..Progressive::default()
    };
    render_progressive(scene, &opts(), &progress, None, &run)
}

/// Interrupted after each of `stops` more tiles, then resumed to the end:
/// the image and the ray counts are those of the render made at once.
fn resumes_to_the_same_bits(scene: &Scene, stops: &[usize], what: &str) {
    let (whole, rays) = render_scene(scene, 2);
    for interval in [Duration::ZERO, Duration::from_secs(3600)] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("render.ckpt");
        let mut at = 0;
        let mut resume = false;
        let mut interrupted = 0;
        for &k in stops {
            at += k;
            let (_, stats) = leg(scene, &path, resume, interval, Some(at)).expect(what);
            if stats.ended == Ended::Complete {
                break;
            }
            assert_eq!(stats.ended, Ended::Interrupted, "{what}");
            assert!(path.is_file(), "{what}: the checkpoint is saved");
            interrupted += 1;
            resume = true;
        }
        assert!(interrupted >= 2, "{what}: interrupted {interrupted} times");
        let (image, stats) = leg(scene, &path, resume, interval, None).expect(what);
        assert_eq!(stats.ended, Ended::Complete, "{what}");
        assert!(stats.checkpoint_error.is_none(), "{what}");
        assert!(
            bits(&image) == bits(&whole),
            "{what}: resumed image differs"
        );
        assert_eq!(stats.rays, rays, "{what}: ray counts");
    }
}

#[test]
fn the_thesis_sets_and_metrics_resume_to_the_same_bits() {
    let scene = builtin_scene(
        "showcase",
        Overrides {
            spp: Some(4),
            shadow_rays: Some(4),
            reflection_rays: Some(4),
            distribution: Some(Distribution::Jitter),
            metric: Some(true),
            ..Default::default()
        },
    );
    resumes_to_the_same_bits(&scene, &[1, 2, 3, 5], "distributed sets with both metrics");
}

#[test]
fn adaptive_sampling_resumes_to_the_same_bits() {
    for rule in [StopRule::Calibrated, StopRule::Dammertz] {
        let scene = builtin_scene(
            "showcase",
            Overrides {
                spp: Some(32),
                noise_threshold: Some(0.05),
                stop_rule: Some(rule),
                ..Default::default()
            },
        );
        resumes_to_the_same_bits(&scene, &[1, 1, 2], rule.name());
    }
}

#[test]
fn a_splatting_film_resumes_to_the_same_bits() {
    let scene = builtin_scene(
        "showcase",
        Overrides {
            integrator: Some(IntegratorChoice::Path),
            spp: Some(4),
            filter: Some(Filter::Gaussian),
            splat: Some(true),
            ..Default::default()
        },
    );
    resumes_to_the_same_bits(&scene, &[1, 1, 1], "path, gaussian splatting film");
}

#[test]
fn a_light_tracer_resumes_to_the_same_bits() {
    let scene = builtin_scene(
        "showcase",
        Overrides {
            integrator: Some(IntegratorChoice::Ptracer),
            spp: Some(3),
            ..Default::default()
        },
    );
    let (image, _) = render_scene(&scene, 2);
    assert!(image.mean().g > 0.0);
    resumes_to_the_same_bits(&scene, &[1, 1, 1], "ptracer");
}

#[test]
fn media_resume_to_the_same_bits() {
    for integrator in [IntegratorChoice::Volpath, IntegratorChoice::Distributed] {
        let scene = builtin_scene(
            "fog",
            Overrides {
                integrator: Some(integrator),
                spp: Some(4),
                ..Default::default()
            },
        );
        resumes_to_the_same_bits(&scene, &[1, 1, 1], integrator.name());
    }
}

#[test]
fn a_checkpoint_of_another_render_is_refused_and_kept() {
    let scene = builtin_scene("showcase", Overrides::default());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("render.ckpt");
    let (_, stats) = leg(&scene, &path, false, Duration::ZERO, Some(2)).unwrap();
    assert_eq!(stats.ended, Ended::Interrupted);
    let before = std::fs::read(&path).unwrap();
    let run = Progressive {
        checkpoint: Some(Checkpointing {
            save: Some(path.clone()),
            interval: Duration::ZERO,
            resume: Some(path.clone()),
            digest: DigestInput::new().add(b"another scene").finish(),
        }),
        ..Progressive::default()
    };
    let e = render_progressive(&scene, &opts(), &|_, _| {}, None, &run).unwrap_err();
    assert!(
        matches!(
            e,
            RenderError::Checkpoint(CheckpointError::OtherRender { .. })
        ),
        "{e}"
    );
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the checkpoint is kept"
    );
    // Another scene under the same digest: its tiles are not this render's.
    let mut other = builtin("showcase", None);
    set(
        &mut other,
        Overrides {
            width: Some(64),
            height: Some(30),
            passes: Some(3),
            ..Default::default()
        },
    );
    let other = other.build().unwrap();
    let e = leg(&other, &path, true, Duration::ZERO, None).unwrap_err();
    assert!(e.to_string().contains("not this render's"), "{e}");
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the checkpoint is kept"
    );
}

#[test]
fn a_time_limit_ends_the_render_with_a_checkpoint_that_resumes() {
    let scene = builtin_scene("showcase", Overrides::default());
    let (whole, _) = render_scene(&scene, 2);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("render.ckpt");
    let checkpoint = Checkpointing {
        save: Some(path.clone()),
        interval: Duration::from_secs(3600),
        resume: None,
        digest: DigestInput::new().add(b"the test's scene").finish(),
    };
    let run = Progressive {
        time_limit: Some(Duration::from_nanos(1)),
        checkpoint: Some(checkpoint.clone()),
        ..Progressive::default()
    };
    let (image, stats) = render_progressive(&scene, &opts(), &|_, _| {}, None, &run).unwrap();
    assert_eq!(stats.ended, Ended::TimeLimit);
    assert_eq!((image.width, image.height), (40, 30));
    let run = Progressive {
        checkpoint: Some(Checkpointing {
            resume: Some(path.clone()),
            ..checkpoint
        }),
        ..Progressive::default()
    };
    let (image, stats) = render_progressive(&scene, &opts(), &|_, _| {}, None, &run).unwrap();
    assert_eq!(stats.ended, Ended::Complete);
    assert!(bits(&image) == bits(&whole));
}

/// The image after each pass but the last is handed out, whole-sized,
/// each pass's closer to the final image than none.
#[test]
fn the_image_is_shown_after_each_pass() {
    let scene = builtin_scene("showcase", Overrides::default());
    let seen = Mutex::new(Vec::new());
    let on_pass = |v: &PassView<'_>| {
        assert_eq!((v.image.width, v.image.height), (40, 30));
        seen.lock()
            .unwrap()
            .push((v.pass, v.passes, v.image.mean(), v.stats.rays.primary));
    };
    let run = Progressive {
        on_pass: Some(&on_pass),
        ..Progressive::default()
    };
    let (image, stats) = render_progressive(&scene, &opts(), &|_, _| {}, None, &run).unwrap();
    let seen = seen.into_inner().unwrap();
    assert_eq!(
        seen.iter().map(|s| (s.0, s.1)).collect::<Vec<_>>(),
        [(1, 3), (2, 3)]
    );
    assert!(seen[0].3 < seen[1].3 && seen[1].3 < stats.rays.primary);
    // The passes' images are the final one's samples so far: their means
    // are of the same order.
    for s in &seen {
        let (a, b) = (s.2.g, image.mean().g);
        assert!(
            (a - b).abs() < 0.5 * b,
            "pass {}: mean {a} against {b}",
            s.0
        );
    }
}

/// A checkpoint whose tile states do not fit the render (made under the
/// same digest by another adaptive rule's settings, as a crafted file
/// could be) is refused, not resumed into an out-of-bounds index.
#[test]
fn a_tile_state_of_another_shape_is_refused() {
    let adaptive = |replicas: u32| {
        builtin_scene(
            "showcase",
            Overrides {
                spp: Some(32),
                noise_threshold: Some(0.05),
                stop_rule: Some(StopRule::Calibrated),
                replicas: Some(replicas),
                ..Default::default()
            },
        )
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("render.ckpt");
    let (_, stats) = leg(&adaptive(4), &path, false, Duration::ZERO, Some(2)).unwrap();
    assert_eq!(stats.ended, Ended::Interrupted);
    let e = leg(&adaptive(8), &path, true, Duration::ZERO, None).unwrap_err();
    assert!(e.to_string().contains("not this render's"), "{e}");
    // And the same settings resume.
    let (_, stats) = leg(&adaptive(4), &path, true, Duration::ZERO, None).unwrap();
    assert_eq!(stats.ended, Ended::Complete);
}
