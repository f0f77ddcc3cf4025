//! The `penumbra` command line.
//!
//! Exit status: 0 on success, 2 for invalid input (arguments, scene, mesh,
//! output path), 1 for anything else.

mod error;
mod render_cmd;
mod report;
mod reproduce_cmd;
mod samples_cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use penumbra::sampling::Distribution;

#[derive(Parser)]
#[command(name = "penumbra", version, about = "A stochastic (distributed) ray tracer", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file or a built-in scene to PNG or EXR.
    Render(RenderArgs),
    /// List the built-in scenes.
    Scenes,
    /// Print or draw the points of a ray distribution.
    Samples(SamplesArgs),
    /// Regenerate the thesis's evaluation (Tables 4.1-4.6, Figures 4.1-4.10, plots,
    /// a convergence study of the distributions) as report.md and report.html.
    Reproduce(ReproduceArgs),
}

/// Options of `penumbra reproduce`.
#[derive(Args)]
pub struct ReproduceArgs {
    /// The Stanford bunny PLY (else $PENUMBRA_BUNNY).
    #[arg(long, value_name = "PATH")]
    pub bunny: Option<PathBuf>,
    /// Output directory for the report, images and plots (default: reproduce).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// The same pipeline at a small resolution with reduced budgets (about a minute or two).
    #[arg(long)]
    pub quick: bool,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// No progress bar and no summary.
    #[arg(short, long)]
    pub quiet: bool,
}

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
    /// The Stanford bunny PLY for scenes that need it (else $PENUMBRA_BUNNY).
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

/// Options of `penumbra samples`.
#[derive(Args)]
pub struct SamplesArgs {
    /// grid, jitter, semi-jitter, poisson, random, fast-random, or `all` (PNG only).
    #[arg(long, short)]
    pub distribution: String,
    /// Number of points.
    #[arg(long, short, value_parser = clap::value_parser!(u32).range(1..=100000))]
    pub count: u32,
    #[arg(long, short, default_value_t = 1.0, value_parser = parse_positive)]
    pub radius: f32,
    #[arg(long, short, default_value_t = 0)]
    pub seed: u64,
    #[arg(long, short, value_enum, default_value = "json")]
    pub format: SampleFormat,
    /// Output file (default: standard output for JSON, samples.png for PNG).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum SampleFormat {
    Json,
    Png,
}

fn parse_distribution(s: &str) -> Result<Distribution, String> {
    Distribution::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Distribution::ALL.iter().map(|d| d.name()).collect();
        format!(
            "unknown distribution `{s}`; valid choices are: {}",
            names.join(", ")
        )
    })
}

fn parse_nonneg(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a finite number >= 0")),
    }
}

fn parse_positive(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a finite number > 0")),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render_cmd::run(&args),
        Command::Scenes => {
            report::print_scenes();
            Ok(())
        }
        Command::Samples(args) => samples_cmd::run(&args),
        Command::Reproduce(args) => reproduce_cmd::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
