//! `penumbra explore`.

use std::net::IpAddr;
use std::path::PathBuf;

use clap::Args;
use penumbra::scene::{default_bunny_path, LoadOptions};

use crate::error::{input, CliError};
use crate::explore::{Explorer, Setup};
use crate::flags::OptionFlags;
use crate::preview::DEFAULT_BIND;

/// Options of `penumbra explore`.
#[derive(Args)]
#[command(
    after_help = "The page shows the image refining pass by pass with its ray statistics (the \
rays the metrics saved among them). Its controls are the render options the thesis's study \
varies: the integrator, samples and passes, each effect's ray count and distribution, the \
metrics; drag the image to orbit the camera around the point it looks at, turn the wheel to \
move it closer or further, shift-drag to pan. Each change restarts the render. The page can open \
the built-in scenes and the files named here, no other file. The option flags give the settings \
the page starts from; unless --passes or the page chooses, a render is made in as many passes as \
samples, at most 16."
)]
pub struct ExploreArgs {
    /// Scene files (TOML, or Mitsuba 3 XML) or built-in scene names the page
    /// may open, besides the built-ins; the first is shown [default: showcase].
    pub scenes: Vec<String>,
    /// The port to serve the page on (any free port when none is given); its
    /// address, with the run's token, is printed at start.
    #[arg(long, default_value_t = 0)]
    pub port: u16,
    /// The address the page listens on.
    #[arg(long, value_name = "ADDR", default_value_t = DEFAULT_BIND)]
    pub bind: IpAddr,
    /// The Stanford bunny PLY for scenes that need it (else $PENUMBRA_BUNNY).
    #[arg(long, value_name = "PATH")]
    pub bunny: Option<PathBuf>,
    /// The render options (`--width`, `--spp`, `--threads`, ...).
    #[command(flatten)]
    pub options: OptionFlags,
}

pub fn run(args: &ExploreArgs) -> Result<(), CliError> {
    let load = LoadOptions {
        bunny: args.bunny.clone().or_else(default_bunny_path),
        ..LoadOptions::default()
    };
    let explorer = Explorer::start(Setup {
        bind: args.bind,
        port: args.port,
        scenes: args.scenes.clone(),
        load,
        choices: args.options.0.clone(),
    })
    .map_err(input)?;
    eprintln!("explore: {}", explorer.url());
    explorer.wait();
    Ok(())
}
