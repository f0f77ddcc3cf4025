//! `penumbra render`.

use std::io::IsTerminal;
use std::path::Path;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::io::output::{write_bytes, write_image, Format};
use penumbra::render::{render, RenderOptions};
use penumbra::scene::{LoadOptions, SceneDesc, SceneSource};

use crate::error::{input, other, CliError};
use crate::report::{print_summary, stats_json};
use crate::{EffectArgs, RenderArgs};

/// Renders shorter than this never show a progress bar.
const BAR_DELAY: Duration = Duration::from_secs(1);

pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    // Check everything about the outputs before spending time on the render.
    Format::of(&args.output).map_err(input)?;
    check_parent(&args.output)?;
    if let Some(stats) = &args.stats {
        check_parent(stats)?;
    }
    let opts = LoadOptions {
        bunny: args.bunny.clone(),
    };
    let mut source = SceneSource::open(&args.scene, &opts).map_err(input)?;
    apply_overrides(&mut source.desc, args);
    let scene = source.build().map_err(input)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let bar = progress_bar(args.quiet);
    let started = Instant::now();
    let shown = OnceLock::new();
    let progress = |done: usize, total: usize| {
        if started.elapsed() >= BAR_DELAY && shown.set(()).is_ok() {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let render_opts = RenderOptions {
        threads: args.threads.map(|t| t as usize),
        region: None,
    };
    let (image, stats) = render(&scene, &render_opts, &progress, None).map_err(other)?;
    bar.finish_and_clear();
    if stats.bad_samples > 0 {
        let first: Vec<String> = stats
            .first_bad_samples
            .iter()
            .map(|b| format!("({}, {}) sample {}", b.x, b.y, b.sample))
            .collect();
        eprintln!(
            "warning: {} non-finite samples were discarded (pixel, sample): {}",
            stats.bad_samples,
            first.join(", ")
        );
    }
    write_image(&args.output, &image).map_err(other)?;
    let json = stats_json(&args.scene, &scene, &stats);
    if let Some(path) = &args.stats {
        let text = serde_json::to_string_pretty(&json).map_err(other)?;
        write_bytes(path, text.as_bytes()).map_err(other)?;
    }
    if !args.quiet {
        print_summary(&args.output, &json);
    }
    Ok(())
}

/// An output whose directory does not exist is an argument error.
fn check_parent(path: &Path) -> Result<(), CliError> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => Err(input(format!(
            "{}: directory {} does not exist",
            path.display(),
            dir.display()
        ))),
        _ => Ok(()),
    }
}

fn progress_bar(quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
    if let Ok(style) = ProgressStyle::with_template("{spinner} rendering [{bar:40}] {percent:>3}% tiles {pos}/{len}, {elapsed} elapsed, ~{eta} left") {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// Command-line values win over the file, including per-light and
/// per-material ray counts and distributions.
fn apply_overrides(desc: &mut SceneDesc, args: &RenderArgs) {
    let r = &mut desc.render;
    set(&mut r.width, args.width.map(i64::from));
    set(&mut r.height, args.height.map(i64::from));
    set(&mut r.max_depth, args.max_depth.map(i64::from));
    set(&mut r.seed, args.seed.map(i64::from));
    apply_effects(desc, &args.effects);
}

fn apply_effects(desc: &mut SceneDesc, e: &EffectArgs) {
    let r = &mut desc.render;
    set(&mut r.spp, e.spp.map(i64::from));
    set(&mut r.shadow_rays, e.shadow_rays.map(i64::from));
    set(&mut r.reflection_rays, e.reflection_rays.map(i64::from));
    set(&mut r.refraction_rays, e.refraction_rays.map(i64::from));
    if let Some(d) = e.distribution {
        r.distribution = d;
        for slot in [
            &mut r.pixel_distribution,
            &mut r.lens_distribution,
            &mut r.time_distribution,
            &mut r.shadow_distribution,
            &mut r.reflection_distribution,
            &mut r.refraction_distribution,
        ] {
            *slot = None;
        }
    }
    let pick = |cli: Option<_>, all: Option<_>| cli.or(all);
    let shadow_d = pick(e.shadow_distribution, e.distribution);
    let reflection_d = pick(e.reflection_distribution, e.distribution);
    let refraction_d = pick(e.refraction_distribution, e.distribution);
    set_opt(&mut r.pixel_distribution, e.pixel_distribution);
    set_opt(&mut r.lens_distribution, e.lens_distribution);
    set_opt(&mut r.time_distribution, e.time_distribution);
    set_opt(&mut r.shadow_distribution, shadow_d);
    set_opt(&mut r.reflection_distribution, reflection_d);
    set_opt(&mut r.refraction_distribution, refraction_d);
    for l in &mut desc.lights {
        if e.shadow_rays.is_some() {
            l.shadow_rays = None;
        }
        if shadow_d.is_some() {
            l.shadow_distribution = None;
        }
    }
    for m in desc.materials.values_mut() {
        if e.reflection_rays.is_some() {
            m.reflection_rays = None;
        }
        if e.refraction_rays.is_some() {
            m.refraction_rays = None;
        }
        if reflection_d.is_some() {
            m.reflection_distribution = None;
        }
        if refraction_d.is_some() {
            m.refraction_distribution = None;
        }
    }
    let c = &mut desc.camera;
    set(&mut c.aperture, e.aperture);
    if e.focal_distance.is_some() {
        c.focal_distance = e.focal_distance;
    }
}

fn set<T>(slot: &mut T, v: Option<T>) {
    if let Some(v) = v {
        *slot = v;
    }
}

fn set_opt<T>(slot: &mut Option<T>, v: Option<T>) {
    if v.is_some() {
        *slot = v;
    }
}
