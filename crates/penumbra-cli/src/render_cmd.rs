//! `penumbra render`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::io::output::{write_bytes, write_image, Format};
use penumbra::render::{render, stats_document, RenderOptions};
use penumbra::sampling::Distribution;
use penumbra::scene::{LoadOptions, Overrides, SceneSource};

use crate::error::{input, other, CliError};
use crate::flags::{parse_distribution, parse_nonneg, parse_positive};
use crate::report::print_summary;

/// Options of `penumbra render`. Every option given here wins over the value
/// in the scene file (ray counts and distributions override per-light and
/// per-material values too).
#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML) or built-in scene name (see `penumbra scenes`).
    #[arg(default_value = "showcase")]
    pub scene: String,
    /// Output image; the extension picks the format: .png (8-bit sRGB) or .exr (32-bit linear).
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    pub width: Option<u32>,
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    pub height: Option<u32>,
    /// Levels of reflection/refraction rays (the thesis's recursion depth, default 3).
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=64))]
    pub max_depth: Option<u32>,
    /// Seed of every random number; the same seed gives the same pixels.
    #[arg(long)]
    pub seed: Option<u32>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Write render statistics as JSON to this file.
    #[arg(long, value_name = "PATH")]
    pub stats: Option<PathBuf>,
    /// The Stanford bunny PLY for scenes that need it (else $PENUMBRA_BUNNY, else ../shared/data/bunny.ply).
    #[arg(long, value_name = "PATH")]
    pub bunny: Option<PathBuf>,
    /// No progress bar and no summary.
    #[arg(short, long)]
    pub quiet: bool,
    #[command(flatten)]
    pub effects: EffectArgs,
}

/// Ray budgets, distributions and lens settings.
#[derive(Args)]
pub struct EffectArgs {
    /// Primary rays per pixel (supersampling, depth of field, motion blur).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub spp: Option<u32>,
    /// Shadow rays per area light (penumbra).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub shadow_rays: Option<u32>,
    /// Rays per blurry reflection.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub reflection_rays: Option<u32>,
    /// Rays per blurry refraction.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub refraction_rays: Option<u32>,
    /// Distribution for every effect.
    #[arg(long, value_parser = parse_distribution)]
    pub distribution: Option<Distribution>,
    #[arg(long, value_parser = parse_distribution)]
    pub pixel_distribution: Option<Distribution>,
    #[arg(long, value_parser = parse_distribution)]
    pub lens_distribution: Option<Distribution>,
    #[arg(long, value_parser = parse_distribution)]
    pub time_distribution: Option<Distribution>,
    #[arg(long, value_parser = parse_distribution)]
    pub shadow_distribution: Option<Distribution>,
    #[arg(long, value_parser = parse_distribution)]
    pub reflection_distribution: Option<Distribution>,
    #[arg(long, value_parser = parse_distribution)]
    pub refraction_distribution: Option<Distribution>,
    /// Lens radius (0 = pinhole).
    #[arg(long, value_parser = parse_nonneg)]
    pub aperture: Option<f32>,
    /// Distance to the plane in focus.
    #[arg(long, value_parser = parse_positive)]
    pub focal_distance: Option<f32>,
    /// Turn on the acceleration metrics (thesis §3.4): stop a set of rays once more would not change it.
    #[arg(long, overrides_with = "no_metric")]
    pub metric: bool,
    /// Turn the acceleration metrics off (the default unless the scene turns them on).
    #[arg(long)]
    pub no_metric: bool,
    /// With the metrics on, stop reflection and refraction sets by the α/threshold rule (the default).
    #[arg(long, overrides_with = "no_reflection_metric")]
    pub reflection_metric: bool,
    /// With the metrics on, trace every reflection and refraction ray (the shadow metric alone, say).
    #[arg(long)]
    pub no_reflection_metric: bool,
    /// With the metrics on, stop shadow sets by the k rule (the default).
    #[arg(long, overrides_with = "no_shadow_metric")]
    pub shadow_metric: bool,
    /// With the metrics on, trace every shadow ray (the reflection metric alone, say).
    #[arg(long)]
    pub no_shadow_metric: bool,
    /// Relative change of a set's running average below which it stops (default 0.01).
    #[arg(long, value_name = "T", value_parser = parse_nonneg)]
    pub metric_threshold: Option<f32>,
    /// α: rays always traced before the reflection/refraction metric applies (default 4).
    #[arg(long, value_name = "ALPHA", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub metric_min_rays: Option<u32>,
    /// k: shadow rays after which an all-lit or all-blocked set stops (default 4).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub shadow_metric_rays: Option<u32>,
    /// Apply the metric to the primary rays of each pixel too.
    #[arg(long)]
    pub pixel_metric: bool,
}

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
