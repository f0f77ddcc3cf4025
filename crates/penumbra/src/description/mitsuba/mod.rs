//! Mitsuba 3 XML scenes read into the [scene description](super): the same
//! tree of plugins a TOML scene lowers to, with Penumbra's plugin and
//! property names and the TOML key paths (`objects[0].radius`), every value
//! placed at its XML tag, so that one builder builds both. `docs/mitsuba.md`
//! is the user's reference; this is the reader's.
//!
//! # Steps
//!
//! 1. [`parse`]: each file is read through [`crate::input`] (a regular file
//!    only, the scene's size limit for each file and for all of them
//!    together), must be UTF-8 and is parsed by roxmltree with DTDs refused
//!    (no entity is ever expanded, nothing external is ever loaded). Every
//!    attribute has its `$name`s substituted (`-D name=value` first, then
//!    `<default name value>` in document order; an undefined name is an
//!    error); `<include filename>` is read in place relative to the
//!    including file (a `<scene>` root adds its children, any other root
//!    itself), refusing loops; `<path value>` adds a search folder for
//!    relative file names. Elements nest at most [`MAX_DEPTH`] deep,
//!    includes counted in, and includes at most [`MAX_INCLUDES`] deep.
//! 2. [`upgrade`]: the elements of files of a `version` below 2.0 get
//!    Mitsuba 3's parameter names (one warning for the scene).
//! 3. [`objects`]: elements into objects with typed properties
//!    ([`values`]: [`number`]s finite, [`transform`]s composed `M = op · M`,
//!    [`spectrum`]s), ids and aliases registered (each id once), references
//!    kept by id.
//! 4. [`plugins`]: objects onto Penumbra's plugins, references resolved.
//!    Sensors, films, reconstruction filters, samplers, shapes, emitters,
//!    BSDFs and textures map through the schemas of the [`Registry`] the
//!    caller hands in (`mapping.rs` holds the mapping, [`adapt`] and
//!    [`sensors`] what some plugins mean otherwise); the scene's structure
//!    and the integrator by hand:
//!
//! | Mitsuba | Penumbra node | key path |
//! |---|---|---|
//! | `<integrator>` `path`, `direct` (default `path`) | integrator of that name | `render` |
//! | `<sensor>` | the sensor that reads it, holding its film and sampler (Mitsuba's `hdrfilm` and `independent` where it holds none) | `camera` |
//! | `<film>` in the sensor, its `<rfilter>` | the film that reads it, the filter's parameters as its `filter_*` keys | `render` |
//! | `<sampler>` in the sensor | the sampler that reads it | `render` |
//! | `<emitter type="constant">` | emitter `constant` (radiance) | `render.background` |
//! | `<emitter>` of another type | the emitter of the registry that reads it | `lights[i]` |
//! | `<bsdf>` | the model that reads it, with its id or `bsdf_N` | `materials.NAME` |
//! | `<texture>` in `<scene>` | the texture that reads it | `textures.ID` |
//! | `<shape type="shapegroup">` | a group of shapes | `groups.ID` |
//! | `<shape type="instance">` | an `instance` of a group | `objects[i]` |
//! | `<shape>` of another type | the shape that reads it; `material`; an `area` emitter child | `objects[i]` |
//!
//! Anything else is an error at its tag naming what is supported. Every
//! error is a [`SceneError`] naming the file, line and column.
//!
//! Mitsuba's dict form (`mi.load_dict`, [`from_dict`]) is read by [`dict`]
//! into the same objects as step 3 makes, then mapped by step 4; its errors
//! name the dict's key path (`sphere.bsdf.reflectance`) instead.

pub mod adapt;
pub mod dict;
mod mapper;
mod mapping;
mod materials;
pub mod number;
pub mod objects;
pub mod parse;
pub mod plugins;
pub mod registry;
pub mod sensors;
pub mod spectrum;
pub mod transform;
pub mod upgrade;
pub mod values;
mod volumes;

use std::path::{Path, PathBuf};

use super::error::SceneError;
use super::tree::Node;
pub use parse::{Defines, MAX_DEPTH, MAX_INCLUDES};
pub use registry::{Mitsuba, Plugin, Registry};

/// A scene read from XML.
#[derive(Debug)]
pub struct Loaded {
    pub root: Node,
    /// Things to tell the user once (an upgraded old scene, a parameter
    /// without effect, an inexact sampler).
    pub warnings: Vec<String>,
}

/// Reads the XML scene at `path` (named so in errors), `defines` overriding
/// its defaults, each file and all of them together at most `limit` bytes.
pub fn from_xml_file(
    path: &Path,
    defines: &Defines,
    limit: u64,
    registry: Registry,
) -> Result<Loaded, SceneError> {
    from_xml_file_with(path, defines, limit, false, registry)
}

/// [`from_xml_file`], with `lenient` turning parameters Penumbra does not
/// read into warnings (unsupported plugins stay errors).
pub fn from_xml_file_with(
    path: &Path,
    defines: &Defines,
    limit: u64,
    lenient: bool,
    registry: Registry,
) -> Result<Loaded, SceneError> {
    let read = Read {
        defines,
        lenient,
        ..Read::default()
    };
    from_xml_file_read(path, &read, limit, registry)
}

/// How a Mitsuba XML scene is read beyond its text, as Mitsuba's command
/// line sets it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Read<'a> {
    /// `$name` parameters (`-D`), winning over the scene's `<default>`s.
    pub defines: &'a Defines,
    /// Parameters Penumbra does not read are warnings (`--lenient`).
    pub lenient: bool,
    /// Folders where files are looked for after the scene's `<path>`
    /// folders and before the scene's own folder (`-a`), the first given
    /// first.
    pub search: &'a [PathBuf],
    /// Which of the scene's sensors renders, counted from 0 in the order
    /// the scene gives them (`--sensor`).
    pub sensor: usize,
}

/// [`from_xml_file`] read as `read` says.
pub fn from_xml_file_read(
    path: &Path,
    read: &Read,
    limit: u64,
    registry: Registry,
) -> Result<Loaded, SceneError> {
    let (defines, lenient) = (read.defines, read.lenient);
    let scene_dir = path.parent().unwrap_or(Path::new(""));
    let mut reader = parse::Reader::new(scene_dir, defines, limit);
    reader.search = read.search.to_vec();
    let mut root = reader.file(path, 0)?;
    let mut warnings = Vec::new();
    if let Some((file, version)) = reader.old_files.first() {
        warnings.push(format!(
            "{}: a scene of Mitsuba version {} (before 2.0), upgraded as Mitsuba 3 upgrades it: \
             camelCase parameter names in snake_case, diffuse_reflectance as reflectance, \
             uoffset/voffset/uscale/vscale as to_uv{}",
            file.display(),
            parse::clip(version),
            match reader.old_files.len() {
                1 => String::new(),
                n => format!(" (and {} more old files)", n - 1),
            }
        ));
        upgrade::upgrade(&mut root);
    }
    let mut ids = objects::Ids::default();
    let scene = objects::read_scene(&root, &reader, &mut ids)?;
    // The elements are not needed once they are objects.
    drop(root);
    let sensor = read.sensor;
    let root = plugins::scene(
        &scene,
        &ids,
        &reader,
        registry,
        (lenient, sensor),
        &mut warnings,
    )?;
    Ok(Loaded { root, warnings })
}

/// Reads a scene in Mitsuba's dict form (see [`dict`]), relative file
/// names read from `base_dir`; `lenient` as for
/// [`from_xml_file_with`].
pub fn from_dict(
    d: &dict::DictValue,
    base_dir: &Path,
    lenient: bool,
    registry: Registry,
) -> Result<Loaded, SceneError> {
    let reader = parse::Reader::new(base_dir, &[], 0);
    let mut ids = objects::Ids::default();
    let scene = dict::read_scene(d, &mut ids, registry)?;
    let mut warnings = Vec::new();
    let root = plugins::scene(&scene, &ids, &reader, registry, (lenient, 0), &mut warnings)?;
    Ok(Loaded { root, warnings })
}
