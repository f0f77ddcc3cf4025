//! `penumbra render`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::input::recording_reads;
use penumbra::integrator::Config;
use penumbra::io::output::{check_channels, write_bytes, write_image, Format};
use penumbra::render::{
    render_digest, render_progressive, stats_document, CheckpointError, Checkpointing, Ended,
    PassView, Progressive, RenderError, RenderOptions,
};
use penumbra::scene::{default_bunny_path, SceneSource};

use crate::error::{input, other, CliError};
use crate::flags::OptionFlags;
use crate::live::{Live, LiveArgs};
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
    /// End the render after this many seconds: no tile starts after it, the
    /// image holds the samples so far (and the checkpoint, with
    /// --checkpoint, the state to resume from).
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
    pub time_limit: Option<f64>,
    /// Save the render's state to this file every --checkpoint-interval
    /// seconds, at the end, and on SIGINT or SIGTERM (then the image of
    /// the samples so far is written too): --resume continues it to the
    /// image an uninterrupted render makes, bit for bit.
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Seconds between checkpoints (saved as tiles finish).
    #[arg(long, value_name = "SECONDS", default_value_t = 60.0, value_parser = positive_seconds)]
    pub checkpoint_interval: f64,
    /// Continue the render saved in this checkpoint: the same scene, files
    /// and pixel-changing options (threads, time limit and interval may
    /// differ); another render's checkpoint is refused.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// The live views (`--preview`).
    #[command(flatten)]
    pub live: LiveArgs,
    /// How a Mitsuba XML scene is read (`-D`, `-a`, `--sensor`, `--lenient`).
    #[command(flatten)]
    pub xml: XmlFlags,
    /// The render options (`--width`, `--spp`, `--metric`, ...).
    #[command(flatten)]
    pub options: OptionFlags,
}

/// Renders shorter than this never show a progress bar.
const BAR_DELAY: Duration = Duration::from_secs(1);

/// A number of seconds: finite and positive.
fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 && s < 1e12 => Ok(s),
        _ => Err(format!("`{text}` is not a positive number of seconds")),
    }
}

pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    // Check everything about the outputs before spending time on the render.
    Format::of(&args.output).map_err(input)?;
    check_parent(&args.output)?;
    if let Some(stats) = &args.stats {
        check_parent(stats)?;
    }
    if let Some(path) = &args.checkpoint {
        check_parent(path)?;
    }
    let opts = args
        .xml
        .load_options(args.bunny.clone().or_else(default_bunny_path));
    let choices = &args.options.0;
    let load = || -> Result<_, CliError> {
        let mut source = SceneSource::open(&args.scene, &opts).map_err(input)?;
        choices.overrides.apply(&mut source);
        let scene = source.build().map_err(input)?;
        Ok((source, scene))
    };
    // The files the scene reads are part of what a checkpoint is tied to:
    // their digests are taken only for a render with checkpoints.
    let checkpointing = args.checkpoint.is_some() || args.resume.is_some();
    let (built, reads) = match checkpointing {
        true => recording_reads(load),
        false => (load(), Vec::new()),
    };
    let (source, scene) = built?;
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
    let signals = Signals::install()?;
    let live = Live::start(&args.live, &args.output.display().to_string())?;
    let interrupt = || signals.either.load(Ordering::Relaxed) || live.stop_requested();
    let on_pass = |view: &PassView<'_>| live.pass(view);
    let checkpoint = checkpointing.then(|| Checkpointing {
        save: args.checkpoint.clone(),
        interval: Duration::from_secs_f64(args.checkpoint_interval),
        resume: args.resume.clone(),
        digest: render_digest(&source, &reads, None),
    });
    let run = Progressive {
        time_limit: args.time_limit.map(Duration::from_secs_f64),
        interrupt: Some(&interrupt),
        on_pass: live.wants_passes().then_some(&on_pass as _),
        checkpoint,
    };
    let (image, stats) =
        render_progressive(&scene, &render_opts, &progress, None, &run).map_err(|e| match e {
            RenderError::Checkpoint(CheckpointError::Write { .. }) => other(e),
            RenderError::Checkpoint(_) => input(e),
            e => other(e),
        })?;
    bar.finish_and_clear();
    live.finish(
        &image,
        &stats,
        match stats.ended {
            Ended::Complete => "finished",
            Ended::TimeLimit => "ended at its time limit",
            Ended::Interrupted => "stopped",
        },
    );
    if let Some(e) = &stats.checkpoint_error {
        eprintln!("warning: {e}");
    }
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
    match stats.ended {
        Ended::Complete => {}
        Ended::TimeLimit => eprintln!(
            "the render reached its time limit: the image holds the samples rendered so far{}",
            resumable(args)
        ),
        Ended::Interrupted if !signals.either.load(Ordering::Relaxed) => eprintln!(
            "stopped from the preview: the image holds the samples rendered so far{}",
            resumable(args)
        ),
        Ended::Interrupted => {
            let (code, name) = signals.which();
            return Err(CliError::Signal(
                code,
                format!(
                    "interrupted by {name}: the image holds the samples rendered so far{}",
                    resumable(args)
                ),
            ));
        }
    }
    if stats.checkpoint_error.is_some() {
        return Err(other("the render's checkpoint could not be saved"));
    }
    Ok(())
}

/// How to go on with a render ended early.
fn resumable(args: &RenderArgs) -> String {
    match &args.checkpoint {
        Some(path) => format!(
            "; continue it with --resume {}",
            penumbra::input::quote::quote(&path.display().to_string())
        ),
        None => String::new(),
    }
}

/// SIGINT and SIGTERM, caught: each ends the render cleanly (the image
/// and the checkpoint written); a second one ends the process at once.
struct Signals {
    int: Arc<AtomicBool>,
    term: Arc<AtomicBool>,
    /// Set by either.
    either: Arc<AtomicBool>,
}

impl Signals {
    fn install() -> Result<Signals, CliError> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        use signal_hook::flag;
        let (int, term) = (
            Arc::new(AtomicBool::new(false)),
            Arc::new(AtomicBool::new(false)),
        );
        let either = Arc::new(AtomicBool::new(false));
        for (signal, mine) in [(SIGINT, &int), (SIGTERM, &term)] {
            // The second signal ends the process (with the signal's status).
            flag::register_conditional_shutdown(signal, 128 + signal, Arc::clone(&either))
                .and_then(|_| flag::register(signal, Arc::clone(mine)))
                .and_then(|_| flag::register(signal, Arc::clone(&either)))
                .map_err(other)?;
        }
        Ok(Signals { int, term, either })
    }

    /// The exit status and name of the signal that ended the render.
    fn which(&self) -> (u8, &'static str) {
        if self.term.load(Ordering::Relaxed) && !self.int.load(Ordering::Relaxed) {
            (143, "SIGTERM")
        } else {
            (130, "SIGINT")
        }
    }
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
