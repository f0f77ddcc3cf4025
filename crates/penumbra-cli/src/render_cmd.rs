//! `penumbra render`.

use std::io::IsTerminal;
use std::path::Path;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::io::output::{write_bytes, write_image, Format};
use penumbra::render::{render, stats_document, RenderOptions};
use penumbra::scene::{default_bunny_path, LoadOptions, Overrides, SceneSource};

use crate::error::{input, other, CliError};
use crate::report::print_summary;
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
        bunny: args.bunny.clone().or_else(default_bunny_path),
    };
    let mut source = SceneSource::open(&args.scene, &opts).map_err(input)?;
    overrides(args).apply(&mut source.desc);
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
    let json = stats_document(&args.scene, &scene, &stats);
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

/// Command-line values win over the file (see [`Overrides`]).
fn overrides(args: &RenderArgs) -> Overrides {
    let e: &EffectArgs = &args.effects;
    Overrides {
        width: args.width,
        height: args.height,
        max_depth: args.max_depth,
        seed: args.seed,
        spp: e.spp,
        shadow_rays: e.shadow_rays,
        reflection_rays: e.reflection_rays,
        refraction_rays: e.refraction_rays,
        distribution: e.distribution,
        pixel_distribution: e.pixel_distribution,
        lens_distribution: e.lens_distribution,
        time_distribution: e.time_distribution,
        shadow_distribution: e.shadow_distribution,
        reflection_distribution: e.reflection_distribution,
        refraction_distribution: e.refraction_distribution,
        aperture: e.aperture,
        focal_distance: e.focal_distance,
        metric: switch(e.metric, e.no_metric),
        reflection_metric: switch(e.reflection_metric, e.no_reflection_metric),
        shadow_metric: switch(e.shadow_metric, e.no_shadow_metric),
        metric_threshold: e.metric_threshold,
        metric_min_rays: e.metric_min_rays,
        shadow_metric_rays: e.shadow_metric_rays,
        pixel_metric: e.pixel_metric.then_some(true),
    }
}

/// A `--x`/`--no-x` pair (clap keeps only the last one given): on, off, or
/// as the scene says.
fn switch(on: bool, off: bool) -> Option<bool> {
    match (on, off) {
        (true, _) => Some(true),
        (_, true) => Some(false),
        _ => None,
    }
}
