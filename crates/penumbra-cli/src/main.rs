//! The `penumbra` command line.
//!
//! Exit status: 0 on success, 2 for invalid input (arguments, scene, mesh,
//! output path, checkpoint), 130 or 143 for a render ended by SIGINT or
//! SIGTERM (its image and checkpoint written), 1 for anything else.

mod convert_cmd;
mod error;
mod explore;
mod explore_cmd;
mod flags;
mod live;
mod preview;
mod render_cmd;
mod report;
mod reproduce_cmd;
mod samples_cmd;
mod xml_flags;

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use penumbra::input::quote::bounded;
use penumbra::simd::KernelSet;

use convert_cmd::ConvertArgs;
use explore_cmd::ExploreArgs;
use render_cmd::RenderArgs;
use reproduce_cmd::ReproduceArgs;
use samples_cmd::SamplesArgs;

/// The version line: the crate's version and the kernel sets this
/// processor supports, the one used by default first.
fn version() -> &'static str {
    static VERSION: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    VERSION.get_or_init(|| {
        let sets: Vec<&str> = KernelSet::supported().iter().map(|k| k.name()).collect();
        format!(
            "{} (kernels: {}; supported: {})",
            env!("CARGO_PKG_VERSION"),
            penumbra::simd::active(),
            sets.join(", ")
        )
    })
}

#[derive(Parser)]
#[command(name = "penumbra", version = version(), about = "A stochastic (distributed) ray tracer", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Largest input file (scene, mesh) read, in bytes or with K, M, G or T (8G)
    /// [default: 4M for scene files, 4G for other files; also $PENUMBRA_MAX_FILE_SIZE]
    #[arg(long, global = true, value_name = "SIZE", value_parser = flags::parse_size)]
    max_file_size: Option<u64>,
    /// Instruction set of the tracing kernels: avx512, avx2, neon or portable
    /// (every set gives the same pixels) [default: the widest this processor
    /// supports; also $PENUMBRA_SIMD]
    #[arg(long, global = true, value_name = "KERNELS")]
    simd: Option<String>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file or a built-in scene to PNG or EXR.
    Render(Box<RenderArgs>),
    /// Convert a Mitsuba 3 XML scene into a TOML scene file.
    Convert(ConvertArgs),
    /// List the built-in scenes.
    Scenes,
    /// Print or draw the points of a ray distribution.
    Samples(SamplesArgs),
    /// Serve a page to explore a scene: orbit and dolly the camera, switch the
    /// integrator, each effect's distribution and ray count and the metrics,
    /// and watch the image re-render with its ray statistics.
    Explore(Box<ExploreArgs>),
    /// Regenerate the thesis's evaluation (Tables 4.1-4.6, Figures 4.1-4.10, plots,
    /// a convergence study of the distributions) as report.md and report.html.
    Reproduce(ReproduceArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(limit) = cli.max_file_size {
        penumbra::input::set_max_file_size(limit);
    }
    let kernels = match &cli.simd {
        Some(name) => penumbra::simd::set_active_name(name).map(Some),
        None => penumbra::simd::from_env(),
    };
    if let Err(e) = kernels {
        eprintln!("error: {}", bounded(&e.to_string()));
        return ExitCode::from(2);
    }
    let result = match cli.command {
        Command::Render(args) => render_cmd::run(&args),
        Command::Convert(args) => convert_cmd::run(&args),
        Command::Scenes => {
            report::print_scenes();
            Ok(())
        }
        Command::Samples(args) => samples_cmd::run(&args),
        Command::Reproduce(args) => reproduce_cmd::run(&args),
        Command::Explore(args) => explore_cmd::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Bounded whatever the input: quoted values cut, a few lines at most.
            eprintln!("error: {}", bounded(&e.to_string()));
            ExitCode::from(e.exit_code())
        }
    }
}
