//! The flags of a Mitsuba XML scene, shared by `render` and `convert`: as
//! Mitsuba's own command line names them where it has them.

use std::path::PathBuf;

use clap::Args;
use penumbra::scene::LoadOptions;

/// How a Mitsuba XML scene is read.
#[derive(Args, Clone, Debug, Default)]
pub struct XmlFlags {
    /// Sets a parameter `$NAME` of a Mitsuba XML scene, winning over its
    /// `<default>` (repeatable: -D spp=64 -D res=512).
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
    /// Adds a folder where a Mitsuba XML scene's files (meshes, images,
    /// includes) are looked for, after its `<path>` folders and before its
    /// own folder, as Mitsuba's `-a` (repeatable, or several separated by
    /// `;`; the first given is searched first).
    #[arg(
        short = 'a',
        long = "search",
        value_name = "DIR",
        value_delimiter = ';'
    )]
    pub search: Vec<PathBuf>,
    /// Which sensor of a Mitsuba XML scene renders, counted from 0 in the
    /// order the scene gives them (Mitsuba's `--sensor`).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub sensor: usize,
    /// Parameters of a Mitsuba XML scene that Penumbra does not read are
    /// warnings instead of errors (unsupported plugins stay errors).
    #[arg(long)]
    pub lenient: bool,
}

impl XmlFlags {
    /// The load options of these flags, and of the bunny `bunny`.
    pub fn load_options(&self, bunny: Option<PathBuf>) -> LoadOptions {
        LoadOptions {
            bunny,
            defines: self.define.clone(),
            lenient: self.lenient,
            search: self.search.clone(),
            sensor: self.sensor,
        }
    }
}

/// `NAME=VALUE`, the name of letters, digits and `_`.
pub fn parse_define(text: &str) -> Result<(String, String), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` is not NAME=VALUE"))?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!(
            "`{name}` is not a parameter name (letters, digits and _)"
        ));
    }
    Ok((name.to_string(), value.to_string()))
}
