//! `penumbra convert`: a Mitsuba 3 XML scene as a TOML scene file.

use std::path::{Path, PathBuf};

use clap::Args;
use penumbra::scene::{convert, SceneSource};

use crate::error::{input, other, CliError};
use crate::xml_flags::XmlFlags;

#[derive(Args)]
#[command(
    after_help = "The TOML file holds only documented scene-file keys (docs/scene-format.md) and \
reads back into the scene the XML file describes, so both render the same pixels with the same \
seed. Meshes are referenced, not copied: their file names stay as written when the output goes \
into the XML file's folder and become absolute otherwise. The output is written whole or not at \
all, and never over the input."
)]
pub struct ConvertArgs {
    /// The Mitsuba 3 XML scene to convert.
    pub scene: PathBuf,
    /// The TOML scene file to write.
    #[arg(short, long, value_name = "PATH")]
    pub output: PathBuf,
    /// How the XML scene is read (`-D`, `-a`, `--sensor`, `--lenient`).
    #[command(flatten)]
    pub xml: XmlFlags,
}

pub fn run(args: &ConvertArgs) -> Result<(), CliError> {
    let scene = &args.scene;
    if !scene
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
    {
        return Err(input(format!(
            "{}: convert reads Mitsuba 3 XML scenes (.xml)",
            scene.display()
        )));
    }
    let out_dir = match args.output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !out_dir.is_dir() {
        return Err(input(format!(
            "{}: directory {} does not exist",
            args.output.display(),
            out_dir.display()
        )));
    }
    if same_file(scene, &args.output) {
        return Err(input(format!(
            "{}: the output is the input scene; choose another file",
            args.output.display()
        )));
    }
    let opts = args.xml.load_options(None);
    let source = SceneSource::open(&scene.to_string_lossy(), &opts).map_err(input)?;
    for w in &source.warnings {
        eprintln!("warning: {w}");
    }
    let text = convert::to_toml(&source, &out_dir).map_err(input)?;
    // Into a file beside the output, renamed over it once whole, with the
    // mode of any new file.
    penumbra::io::output::write_bytes(&args.output, text.as_bytes())
        .map_err(|e| other(e.to_string()))?;
    Ok(())
}

/// Whether two paths name one file (the second may not exist).
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
