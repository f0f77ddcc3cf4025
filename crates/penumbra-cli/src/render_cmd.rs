//! `penumbra render`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::integrator::Config;
use penumbra::io::output::{check_channels, write_bytes, write_image, Format};
use penumbra::render::{render, stats_document, RenderOptions};
use penumbra::scene::{default_bunny_path, SceneSource};

use crate::error::{input, other, CliError};
use crate::flags::OptionFlags;
use crate::report::print_summary;
use crate::xml_flags::XmlFlags;

/// Options of `penumbra render`.
#[derive(Args)]
#[command(
    after_help = "The render options win over the scene file's values (the ray counts and \
distributions over per-light and per-material values too); a default is what a scene file that \
does not set the option gets. A Mitsuba 3 XML scene (.xml) takes its `$name` parameters from \
-D name=value (see docs/mitsuba.md); --integrator whitted renders one whose integrator Penumbra \
does not have."
)]
pub struct RenderArgs {
    /// Scene file (TOML, or Mitsuba 3 XML when it ends in .xml) or built-in
    /// scene name (see `penumbra scenes`).
    #[arg(default_value = "showcase")]
    pub scene: String,
    /// Output image; the extension picks the format: .png (8-bit sRGB) or .exr (32-bit linear).
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,
    /// Write render statistics as JSON to this file.
    #[arg(long, value_name = "PATH")]
    pub stats: Option<PathBuf>,
    /// The Stanford bunny PLY for scenes that need it (else $PENUMBRA_BUNNY).
    #[arg(long, value_name = "PATH")]
    pub bunny: Option<PathBuf>,
    /// No progress bar and no summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// How a Mitsuba XML scene is read (`-D`, `-a`, `--sensor`, `--lenient`).
    #[command(flatten)]
    pub xml: XmlFlags,
    /// The render options (`--width`, `--spp`, `--metric`, ...).
    #[command(flatten)]
    pub options: OptionFlags,
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
    let opts = args
        .xml
        .load_options(args.bunny.clone().or_else(default_bunny_path));
    let mut source = SceneSource::open(&args.scene, &opts).map_err(input)?;
    let choices = &args.options.0;
    choices.overrides.apply(&mut source);
    let scene = source.build().map_err(input)?;
    // Channels beside the image (`aov`, `moment`) need an EXR output.
    if let Ok(config) = Config::of(&scene) {
        let channels = config.channels();
        check_channels(&args.output, &channels).map_err(input)?;
        let name = config.choice().name();
        if channels.is_empty() && matches!(name, "aov" | "moment") {
            eprintln!(
                "warning: the `{name}` integrator has no variables (`aovs`) or held integrator \
                 (`nested`): the image is black and no channel is written"
            );
        }
    }
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
        threads: choices.threads.map(|t| t as usize),
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
