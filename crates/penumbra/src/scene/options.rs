//! The render options, defined once.
//!
//! [`OPTIONS`] lists every setting a user chooses for a render: its name,
//! value type and range, default, one-line meaning, and where it appears —
//! a key of the scene file's `[render]` or `[camera]` table, a flag of
//! `penumbra render`, a keyword argument of the Python `render` functions.
//! The front ends are made from it:
//!
//! * the command line builds its flags from it (clap's builder API), with
//!   its ranges, value names and help;
//! * the Python module accepts, checks and exports (`RENDER_OPTIONS`)
//!   exactly its keyword arguments, and `python -m penumbra` builds its
//!   flags from it;
//! * the options tables of README.md, docs/scene-format.md and
//!   docs/python.md are [`markdown`] tables of it, kept in step by a test
//!   (`PENUMBRA_UPDATE_DOCS=1 cargo test --release -p penumbra --test options`
//!   rewrites them);
//! * the scene file's `[render]` keys are routed by
//!   [`RENDER_KEYS`](crate::description::RENDER_KEYS) to the film, the
//!   sampler and the integrator, whose schemas (and the sensor's, for
//!   `[camera]`) read them; tests check their names, defaults and accepted
//!   ranges against this table.
//!
//! Adding an option is one entry here, plus its field in [`Overrides`] (and,
//! for a scene-file key, its route and its parameter in the schema of the
//! plugin that reads it) and the code that uses it.

use std::path::PathBuf;

use super::overrides::Overrides;
use super::points::Points;
use super::settings::{IntegratorChoice, StopRule};
use crate::emitter::choice::LightChoice;
use crate::sampling::{Distribution, Filter, PathSampler};

pub mod markdown;

pub use super::settings::{MAX_REPLICAS, MAX_SIDE};
pub use crate::sampling::MAX_RAYS;

/// One render option.
#[derive(Clone, Copy, Debug)]
pub struct RenderOption {
    /// The scene-file key and the Python keyword argument; the flag is
    /// `--` and the name with dashes (`max_depth` is `--max-depth`).
    pub name: &'static str,
    pub kind: Kind,
    /// The value when neither the scene file nor a front end gives one.
    pub default: DefaultValue,
    /// What it does: one line, lower case (`--help` capitalises it).
    pub doc: &'static str,
    /// The scene-file table that has it as a key, if any.
    pub table: Option<Table>,
    /// Its `penumbra render` flag, if any.
    pub flag: Option<Flag>,
    /// Whether the Python render functions take it as a keyword argument.
    pub python: bool,
    /// Keeps a value given on the command line or in Python. Only called with
    /// a value of this option's [`Kind`]; `None` for a scene-file-only key.
    pub set: Option<fn(&mut Choices, Value)>,
}

/// The value type and the values allowed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// An integer in `min..=max`.
    Int { min: u32, max: u32 },
    /// A finite number ≥ 0.
    NonNegative,
    /// A finite number > 0.
    Positive,
    /// On or off.
    Switch,
    /// A ray distribution, by name ([`Distribution::name`]).
    Distribution,
    /// A pixel filter, by name ([`Filter::name`]).
    Filter,
    /// An adaptive sampling rule, by name ([`StopRule::name`]).
    StopRule,
    /// An integrator, by name ([`IntegratorChoice::name`]).
    Integrator,
    /// A path sampler, by name ([`PathSampler::name`]).
    PathSampler,
    /// A light sampler, by name ([`LightChoice::name`]).
    LightSampler,
    /// A number in `[lo, hi]`.
    Between(f32, f32),
    /// A linear RGB colour with no negative channel (scene file only).
    Colour,
    /// A file. A path is no [`Value`]: front ends keep it with
    /// [`RenderOption::store_file`], and an option of this kind has no
    /// `set`.
    File,
}

/// A value of an option.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Int(u32),
    Number(f32),
    Switch(bool),
    Distribution(Distribution),
    Filter(Filter),
    StopRule(StopRule),
    Integrator(IntegratorChoice),
    PathSampler(PathSampler),
    LightSampler(LightChoice),
    Colour([f32; 3]),
}

impl Value {
    pub fn int(self) -> Option<u32> {
        match self {
            Value::Int(n) => Some(n),
            _ => None,
        }
    }

    pub fn number(self) -> Option<f32> {
        match self {
            Value::Number(x) => Some(x),
            _ => None,
        }
    }

    pub fn switch(self) -> Option<bool> {
        match self {
            Value::Switch(b) => Some(b),
            _ => None,
        }
    }

    pub fn distribution(self) -> Option<Distribution> {
        match self {
            Value::Distribution(d) => Some(d),
            _ => None,
        }
    }

    pub fn filter(self) -> Option<Filter> {
        match self {
            Value::Filter(f) => Some(f),
            _ => None,
        }
    }

    pub fn stop_rule(self) -> Option<StopRule> {
        match self {
            Value::StopRule(r) => Some(r),
            _ => None,
        }
    }

    pub fn integrator(self) -> Option<IntegratorChoice> {
        match self {
            Value::Integrator(i) => Some(i),
            _ => None,
        }
    }

    pub fn path_sampler(self) -> Option<PathSampler> {
        match self {
            Value::PathSampler(p) => Some(p),
            _ => None,
        }
    }

    pub fn light_sampler(self) -> Option<LightChoice> {
        match self {
            Value::LightSampler(c) => Some(c),
            _ => None,
        }
    }
}

/// Where an option's default comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    Fixed(Value),
    /// The value of the option of this name (the per-effect distributions
    /// follow `distribution`).
    Follows(&'static str),
    /// Worked out from the scene or the machine, as the text says.
    Computed(&'static str),
}

/// A table of the scene file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Table {
    Render,
    Camera,
}

impl Table {
    pub fn name(self) -> &'static str {
        match self {
            Table::Render => "render",
            Table::Camera => "camera",
        }
    }
}

/// A `penumbra render` flag: `--NAME VALUE`, or `--NAME` for a switch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flag {
    /// What `--help` calls the value; `None`: the name in capitals.
    pub metavar: Option<&'static str>,
    /// For a switch, the help of its `--no-NAME` flag, which turns it off
    /// (of the two, the last one given wins); `None`: no such flag.
    pub off: Option<&'static str>,
}

impl Flag {
    const PLAIN: Option<Flag> = Some(Flag {
        metavar: None,
        off: None,
    });

    const fn metavar(name: &'static str) -> Option<Flag> {
        Some(Flag {
            metavar: Some(name),
            off: None,
        })
    }

    const fn with_off(help: &'static str) -> Option<Flag> {
        Some(Flag {
            metavar: None,
            off: Some(help),
        })
    }
}

/// What a front end was given: the values that replace the scene's, and the
/// render's thread count.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Choices {
    pub overrides: Overrides,
    /// Worker threads; `None`: every core.
    pub threads: Option<u32>,
}

impl RenderOption {
    /// The command-line flag, `--max-depth` for `max_depth`.
    pub fn long(&self) -> String {
        self.name.replace('_', "-")
    }

    /// The `--no-...` flag of a switch that has one.
    pub fn long_off(&self) -> Option<String> {
        self.flag
            .and_then(|f| f.off)
            .map(|_| format!("no-{}", self.long()))
    }

    /// What `--help` calls the value.
    pub fn metavar(&self) -> String {
        match self.flag.and_then(|f| f.metavar) {
            Some(m) => m.to_string(),
            None => self.name.to_uppercase(),
        }
    }

    /// Keeps the file given for an option of [`Kind::File`] in `choices`.
    pub fn store_file(&self, choices: &mut Choices, path: PathBuf) {
        if self.kind == Kind::File && self.name == "points" {
            choices.overrides.points = Some(Points::File(path));
        }
    }

    /// Keeps `value` (which must be of this option's kind) in `choices`.
    pub fn store(&self, choices: &mut Choices, value: Value) {
        if let Some(set) = self.set {
            set(choices, value);
        }
    }
}

/// The option of this name.
pub fn find(name: &str) -> Option<&'static RenderOption> {
    OPTIONS.iter().find(|o| o.name == name)
}

/// The names of the options the Python render functions take, in order.
pub fn python_names() -> impl Iterator<Item = &'static str> {
    OPTIONS.iter().filter(|o| o.python).map(|o| o.name)
}

const fn int(n: u32) -> DefaultValue {
    DefaultValue::Fixed(Value::Int(n))
}

const fn switch(b: bool) -> DefaultValue {
    DefaultValue::Fixed(Value::Switch(b))
}

const RAYS: Kind = Kind::Int {
    min: 1,
    max: MAX_RAYS,
};
const SIDE: Kind = Kind::Int {
    min: 1,
    max: MAX_SIDE,
};
const CROP_OFFSET: Kind = Kind::Int {
    min: 0,
    max: MAX_SIDE - 1,
};
const FOLLOWS_DISTRIBUTION: DefaultValue = DefaultValue::Follows("distribution");

/// Every render option, in the order of `--help`, the docs and Python's
/// `RENDER_OPTIONS`.
pub const OPTIONS: &[RenderOption] = &[
    RenderOption {
        name: "integrator",
        kind: Kind::Integrator,
        default: DefaultValue::Fixed(Value::Integrator(IntegratorChoice::Whitted)),
        doc: "the light-transport algorithm: whitted (the thesis's distributed Whitted ray tracer), \
              path (a path tracer with next-event estimation, as Mitsuba 3's `path`), direct \
              (direct light by emitter and BSDF samples, as Mitsuba 3's `direct`), distributed \
              (the path tracer drawing the thesis's sets at its first vertices, through media as \
              volpath), volpath (the path tracer through participating media, as Mitsuba 3's `volpath`), \
              volpathmis (volpath with spectral MIS of distances and MIS of emission met through \
              media, as Mitsuba 3's `volpathmis`), ptracer (a particle \
              tracer: paths from the emitters connected to the camera, as Mitsuba 3's `ptracer`), \
              depth (the distance to the first hit, as Mitsuba 3's `depth`), aov (variables of the \
              first hit as channels beside a held integrator's image, as Mitsuba 3's `aov`) or \
              moment (a held integrator's image with the moments of its samples as channels, as \
              Mitsuba 3's `moment`)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.integrator = v.integrator()),
    },
    RenderOption {
        name: "width",
        kind: SIDE,
        default: int(800),
        doc: "image width in pixels",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.width = v.int()),
    },
    RenderOption {
        name: "height",
        kind: SIDE,
        default: int(600),
        doc: "image height in pixels",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.height = v.int()),
    },
    RenderOption {
        name: "spp",
        kind: RAYS,
        default: int(1),
        doc: "primary rays per pixel (supersampling, depth of field, motion blur)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.spp = v.int()),
    },
    RenderOption {
        name: "passes",
        kind: RAYS,
        default: int(1),
        doc: "passes the render is made in, each adding the next part of every pixel's samples to the film; the image is the same bit for bit for any number",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.passes = v.int()),
    },
    RenderOption {
        name: "samples_per_pass",
        kind: RAYS,
        default: DefaultValue::Computed("`spp`"),
        doc: "ptracer: light paths per pixel in each pass (Mitsuba's), the passes at least \
              `spp / samples_per_pass`; the image is the same for any number",
        table: Some(Table::Render),
        flag: None,
        python: false,
        set: None,
    },
    RenderOption {
        name: "shadow_rays",
        kind: RAYS,
        default: int(1),
        doc: "shadow rays per area light and shading point (penumbra)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.shadow_rays = v.int()),
    },
    RenderOption {
        name: "reflection_rays",
        kind: RAYS,
        default: int(1),
        doc: "rays per blurry reflection",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.reflection_rays = v.int()),
    },
    RenderOption {
        name: "refraction_rays",
        kind: RAYS,
        default: int(1),
        doc: "rays per blurry refraction",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.refraction_rays = v.int()),
    },
    RenderOption {
        name: "distribution",
        kind: Kind::Distribution,
        default: DefaultValue::Fixed(Value::Distribution(Distribution::Grid)),
        doc: "distribution of every effect unless a more specific option says otherwise",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.distribution = v.distribution()),
    },
    RenderOption {
        name: "pixel_distribution",
        kind: Kind::Distribution,
        default: FOLLOWS_DISTRIBUTION,
        doc: "film positions of the primary rays (radius: half a pixel)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.pixel_distribution = v.distribution()),
    },
    RenderOption {
        name: "lens_distribution",
        kind: Kind::Distribution,
        default: FOLLOWS_DISTRIBUTION,
        doc: "lens positions (depth of field)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.lens_distribution = v.distribution()),
    },
    RenderOption {
        name: "time_distribution",
        kind: Kind::Distribution,
        default: FOLLOWS_DISTRIBUTION,
        doc: "shutter times (motion blur), stratified in 1D",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.time_distribution = v.distribution()),
    },
    RenderOption {
        name: "shadow_distribution",
        kind: Kind::Distribution,
        default: FOLLOWS_DISTRIBUTION,
        doc: "shadow rays towards area lights",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.shadow_distribution = v.distribution()),
    },
    RenderOption {
        name: "reflection_distribution",
        kind: Kind::Distribution,
        default: FOLLOWS_DISTRIBUTION,
        doc: "blurry reflection rays",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.reflection_distribution = v.distribution()),
    },
    RenderOption {
        name: "refraction_distribution",
        kind: Kind::Distribution,
        default: FOLLOWS_DISTRIBUTION,
        doc: "blurry refraction rays",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.refraction_distribution = v.distribution()),
    },
    RenderOption {
        name: "points",
        kind: Kind::File,
        default: DefaultValue::Computed("none; `custom` needs one"),
        doc: "point sets of the custom distribution: a JSON or .npy file",
        table: Some(Table::Render),
        flag: Flag::metavar("FILE"),
        python: true,
        set: None,
    },
    RenderOption {
        name: "filter",
        kind: Kind::Filter,
        default: DefaultValue::Fixed(Value::Filter(Filter::Box)),
        doc: "pixel filter the film points are drawn by and the samples weighted by: box (the \
              pixel), tent, gaussian, mitchell, catmullrom or lanczos",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.filter = v.filter()),
    },
    RenderOption {
        name: "filter_radius",
        kind: Kind::Positive,
        default: DefaultValue::Computed("1 (tent only)"),
        doc: "the tent filter's radius in pixels (Mitsuba's `radius`)",
        table: Some(Table::Render),
        flag: Flag::metavar("R"),
        python: true,
        set: Some(|c, v| c.overrides.filter_radius = v.number()),
    },
    RenderOption {
        name: "filter_stddev",
        kind: Kind::Positive,
        default: DefaultValue::Computed("0.5 (gaussian only)"),
        doc: "the gaussian filter's standard deviation in pixels; its radius is 4 of them \
              (Mitsuba's `stddev`)",
        table: Some(Table::Render),
        flag: Flag::metavar("SIGMA"),
        python: true,
        set: Some(|c, v| c.overrides.filter_stddev = v.number()),
    },
    RenderOption {
        name: "filter_b",
        kind: Kind::Between(0.0, 1.0),
        default: DefaultValue::Computed("1/3 (mitchell only)"),
        doc: "the mitchell filter's blur B (Mitsuba's `B`)",
        table: Some(Table::Render),
        flag: Flag::metavar("B"),
        python: true,
        set: Some(|c, v| c.overrides.filter_b = v.number()),
    },
    RenderOption {
        name: "filter_c",
        kind: Kind::Between(0.0, 1.0),
        default: DefaultValue::Computed("1/3 (mitchell only)"),
        doc: "the mitchell filter's ringing C (Mitsuba's `C`)",
        table: Some(Table::Render),
        flag: Flag::metavar("C"),
        python: true,
        set: Some(|c, v| c.overrides.filter_c = v.number()),
    },
    RenderOption {
        name: "filter_lobes",
        kind: Kind::Int { min: 1, max: 32 },
        default: DefaultValue::Computed("3 (lanczos only)"),
        doc: "the lanczos filter's lobes; its radius is as many pixels (Mitsuba's `lobes`)",
        table: Some(Table::Render),
        flag: Flag::metavar("N"),
        python: true,
        set: Some(|c, v| c.overrides.filter_lobes = v.int()),
    },
    RenderOption {
        name: "splat",
        kind: Kind::Switch,
        default: switch(false),
        doc: "each sample is added to every pixel the filter covers, weighted by it (Mitsuba's \
              hdrfilm, the default for its scenes), rather than film points drawn from the filter \
              each adding to its own pixel; the box filter is the same either way",
        table: Some(Table::Render),
        flag: Flag::with_off(
            "add each sample to its own pixel, its film point drawn from the filter (a Mitsuba \
             scene splats unless told so)",
        ),
        python: true,
        set: Some(|c, v| c.overrides.splat = v.switch()),
    },
    RenderOption {
        name: "filter_steps",
        kind: Kind::Int { min: 0, max: 1024 },
        default: int(0),
        doc: "with `splat`, the filter is tabulated at this many steps over its radius and each \
              sample weighted by the step it falls in, as Mitsuba's CPU variants weight it (31 \
              steps, set for its scenes); 0 evaluates the filter exactly",
        table: Some(Table::Render),
        flag: Flag::metavar("N"),
        python: true,
        set: Some(|c, v| c.overrides.filter_steps = v.int()),
    },
    RenderOption {
        name: "sample_border",
        kind: Kind::Switch,
        default: switch(false),
        doc: "with `splat`, the pixels within the filter's reach beyond the image (or its crop \
              window) are sampled too, so that the pixels along its edges get the samples the \
              pixels inside do (Mitsuba's hdrfilm `sample_border`); without it an edge pixel gets \
              only the samples from inside",
        table: Some(Table::Render),
        flag: Flag::with_off("sample only the film's pixels (or its crop window's)"),
        python: true,
        set: Some(|c, v| c.overrides.sample_border = v.switch()),
    },
    RenderOption {
        name: "alpha",
        kind: Kind::Switch,
        default: switch(false),
        doc: "the image carries an alpha channel `A`: the share of a pixel's samples whose \
              camera ray meets a surface (or any, with a visible emitter at infinity), filtered \
              as the colour is (Mitsuba's hdrfilm `pixel_format` `rgba`); written to EXR as \
              `A`, to PNG as 8-bit RGBA; aov and moment write their own channels instead, \
              ptracer refuses it",
        table: Some(Table::Render),
        flag: Flag::with_off("write RGB only"),
        python: true,
        set: Some(|c, v| c.overrides.alpha = v.switch()),
    },
    RenderOption {
        name: "crop_offset_x",
        kind: CROP_OFFSET,
        default: int(0),
        doc: "left column of the part of the image rendered and written (the crop window, \
              Mitsuba's); the camera frames the whole `width` × `height` image",
        table: Some(Table::Render),
        flag: None,
        python: false,
        set: None,
    },
    RenderOption {
        name: "crop_offset_y",
        kind: CROP_OFFSET,
        default: int(0),
        doc: "top row of the crop window",
        table: Some(Table::Render),
        flag: None,
        python: false,
        set: None,
    },
    RenderOption {
        name: "crop_width",
        kind: SIDE,
        default: DefaultValue::Computed("`width`"),
        doc: "width of the crop window; `crop_offset_x + crop_width` at most `width`",
        table: Some(Table::Render),
        flag: None,
        python: false,
        set: None,
    },
    RenderOption {
        name: "crop_height",
        kind: SIDE,
        default: DefaultValue::Computed("`height`"),
        doc: "height of the crop window; `crop_offset_y + crop_height` at most `height`",
        table: Some(Table::Render),
        flag: None,
        python: false,
        set: None,
    },
    RenderOption {
        name: "aperture",
        kind: Kind::NonNegative,
        default: DefaultValue::Fixed(Value::Number(0.0)),
        doc: "lens radius in scene units; 0 is a pinhole (everything sharp)",
        table: Some(Table::Camera),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.aperture = v.number()),
    },
    RenderOption {
        name: "focal_distance",
        kind: Kind::Positive,
        default: DefaultValue::Computed("distance to `look_at`"),
        doc: "distance of the plane in focus (measured along the view axis)",
        table: Some(Table::Camera),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.focal_distance = v.number()),
    },
    RenderOption {
        name: "max_depth",
        kind: Kind::Int { min: 0, max: 64 },
        default: int(3),
        doc: "whitted: levels of reflection/refraction rays (the thesis's recursion depth), 0 \
              disables them; path and ptracer: the longest path in vertices, as Mitsuba counts them (1: \
              emitters seen, 2: direct light; default and -1 in a scene file: no bound)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.max_depth = v.int()),
    },
    RenderOption {
        name: "rr_depth",
        kind: RAYS,
        default: int(5),
        doc: "path, distributed and ptracer: the depth from which Russian roulette may end a path",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.rr_depth = v.int()),
    },
    RenderOption {
        name: "hide_emitters",
        kind: Kind::Switch,
        default: switch(false),
        doc: "path, direct, distributed and ptracer: emitters seen directly are black (what \
              they light is not)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.hide_emitters = v.switch()),
    },
    RenderOption {
        name: "sets_depth",
        kind: Kind::Int { min: 1, max: 64 },
        default: int(1),
        doc: "distributed: the vertices from the camera that draw the thesis's sets (shadow_rays \
              toward every light, a set of reflection_rays from the BSDF, each ray going on as a \
              path)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.sets_depth = v.int()),
    },
    RenderOption {
        name: "path_sampler",
        kind: Kind::PathSampler,
        default: DefaultValue::Fixed(Value::PathSampler(PathSampler::Independent)),
        doc: "path, direct and distributed: where the numbers of each bounce come from: \
              independent, or a low-discrepancy sequence (sobol, zsobol, pmj02, pmj02bn, halton, \
              r2) stratifying a pixel's samples in every dimension",
        table: Some(Table::Render),
        flag: Flag::metavar("SAMPLER"),
        python: true,
        set: Some(|c, v| c.overrides.path_sampler = v.path_sampler()),
    },
    RenderOption {
        name: "light_sampler",
        kind: Kind::LightSampler,
        default: DefaultValue::Fixed(Value::LightSampler(LightChoice::Bvh)),
        doc: "path, direct and distributed: how next-event estimation chooses its emitter: \
              uniform, in proportion to power, or down a light BVH by how much each emitter may \
              light the point (as pbrt-v4)",
        table: Some(Table::Render),
        flag: Flag::metavar("SAMPLER"),
        python: true,
        set: Some(|c, v| c.overrides.light_sampler = v.light_sampler()),
    },
    RenderOption {
        name: "emitter_samples",
        kind: Kind::Int {
            min: 0,
            max: MAX_RAYS,
        },
        default: int(1),
        doc: "direct: emitter samples at each shading point (with bsdf_samples, not both 0)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.emitter_samples = v.int()),
    },
    RenderOption {
        name: "bsdf_samples",
        kind: Kind::Int {
            min: 0,
            max: MAX_RAYS,
        },
        default: int(1),
        doc: "direct: BSDF samples at each shading point",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.bsdf_samples = v.int()),
    },
    RenderOption {
        name: "seed",
        kind: Kind::Int {
            min: 0,
            max: u32::MAX,
        },
        default: int(0),
        doc: "seed of every random number; the same seed gives the same pixels on any thread count",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.seed = v.int()),
    },
    RenderOption {
        name: "background",
        kind: Kind::Colour,
        default: DefaultValue::Fixed(Value::Colour([0.0; 3])),
        doc: "radiance of rays that hit nothing",
        table: Some(Table::Render),
        flag: None,
        python: false,
        set: None,
    },
    RenderOption {
        name: "metric",
        kind: Kind::Switch,
        default: switch(false),
        doc: "the acceleration metrics of thesis §3.4: stop a set of rays once more would not \
              change it (off: the plain algorithm)",
        table: Some(Table::Render),
        flag: Flag::with_off("turn the acceleration metrics off"),
        python: true,
        set: Some(|c, v| c.overrides.metric = v.switch()),
    },
    RenderOption {
        name: "reflection_metric",
        kind: Kind::Switch,
        default: switch(true),
        doc: "with the metrics on, stop reflection and refraction sets by the α/threshold rule \
              (off, with the shadow metric on: the shadow metric alone, as in the thesis's Table 4.6)",
        table: Some(Table::Render),
        flag: Flag::with_off("with the metrics on, trace every reflection and refraction ray"),
        python: true,
        set: Some(|c, v| c.overrides.reflection_metric = v.switch()),
    },
    RenderOption {
        name: "shadow_metric",
        kind: Kind::Switch,
        default: switch(true),
        doc: "with the metrics on, stop shadow sets by the k rule \
              (off: the reflection metric alone, as in the thesis's Table 4.4)",
        table: Some(Table::Render),
        flag: Flag::with_off("with the metrics on, trace every shadow ray"),
        python: true,
        set: Some(|c, v| c.overrides.shadow_metric = v.switch()),
    },
    RenderOption {
        name: "metric_threshold",
        kind: Kind::NonNegative,
        default: DefaultValue::Fixed(Value::Number(0.01)),
        doc: "a reflection/refraction set stops once its running average changes by less than \
              this, relative to the average's largest channel",
        table: Some(Table::Render),
        flag: Flag::metavar("T"),
        python: true,
        set: Some(|c, v| c.overrides.metric_threshold = v.number()),
    },
    RenderOption {
        name: "metric_min_rays",
        kind: RAYS,
        default: int(4),
        doc: "rays always traced before the α/threshold rule applies (α)",
        table: Some(Table::Render),
        flag: Flag::metavar("ALPHA"),
        python: true,
        set: Some(|c, v| c.overrides.metric_min_rays = v.int()),
    },
    RenderOption {
        name: "shadow_metric_rays",
        kind: RAYS,
        default: int(4),
        doc: "shadow rays after which a set stops if all reached the light or all were blocked (k)",
        table: Some(Table::Render),
        flag: Flag::metavar("K"),
        python: true,
        set: Some(|c, v| c.overrides.shadow_metric_rays = v.int()),
    },
    RenderOption {
        name: "pixel_metric",
        kind: Kind::Switch,
        default: switch(false),
        doc: "with the metrics on, apply the α/threshold rule to the primary rays of each pixel too",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.pixel_metric = v.switch()),
    },
    RenderOption {
        name: "noise_threshold",
        kind: Kind::NonNegative,
        default: DefaultValue::Fixed(Value::Number(0.0)),
        doc: "adaptive sampling: a pixel stops taking camera rays (up to spp) once its noise, \
              in the measure of stop_rule, is below this (0: off, every pixel takes spp)",
        table: Some(Table::Render),
        flag: Flag::metavar("T"),
        python: true,
        set: Some(|c, v| c.overrides.noise_threshold = v.number()),
    },
    RenderOption {
        name: "stop_rule",
        kind: Kind::StopRule,
        default: DefaultValue::Fixed(Value::StopRule(StopRule::Calibrated)),
        doc: "the adaptive sampling rule: calibrated (replicas' confidence interval), cycles, \
              povray (its sampling method 3) or dammertz (hierarchical blocks)",
        table: Some(Table::Render),
        flag: Flag::metavar("RULE"),
        python: true,
        set: Some(|c, v| c.overrides.stop_rule = v.stop_rule()),
    },
    RenderOption {
        name: "confidence",
        kind: Kind::Between(0.5, 0.999),
        default: DefaultValue::Fixed(Value::Number(0.9)),
        doc: "confidence of the interval the calibrated and povray rules bound the noise by",
        table: Some(Table::Render),
        flag: Flag::metavar("C"),
        python: true,
        set: Some(|c, v| c.overrides.confidence = v.number()),
    },
    RenderOption {
        name: "replicas",
        kind: Kind::Int {
            min: 2,
            max: MAX_REPLICAS,
        },
        default: int(8),
        doc: "independently scrambled replicas of a pixel's sets (and of its shadow, reflection \
              and refraction sets) whose spread the calibrated rule reads the noise from",
        table: Some(Table::Render),
        flag: Flag::metavar("R"),
        python: true,
        set: Some(|c, v| c.overrides.replicas = v.int()),
    },
    RenderOption {
        name: "noise_floor",
        kind: Kind::Positive,
        default: DefaultValue::Fixed(Value::Number(1.0)),
        doc: "the calibrated rule stops a pixel or set when its interval's half-width is at most \
              noise_threshold × max(value, noise_floor): relative to values above the floor, \
              absolute below it",
        table: Some(Table::Render),
        flag: Flag::metavar("F"),
        python: true,
        set: Some(|c, v| c.overrides.noise_floor = v.number()),
    },
    RenderOption {
        name: "min_spp",
        kind: Kind::Int {
            min: 0,
            max: MAX_RAYS,
        },
        default: int(0),
        doc: "camera rays a pixel takes before the adaptive sampling rule may stop it \
              (0: the rule's own)",
        table: Some(Table::Render),
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.overrides.min_spp = v.int()),
    },
    RenderOption {
        name: "threads",
        kind: Kind::Int { min: 1, max: 1024 },
        default: DefaultValue::Computed("all cores"),
        doc: "worker threads; the pixels do not depend on it",
        table: None,
        flag: Flag::PLAIN,
        python: true,
        set: Some(|c, v| c.threads = v.int()),
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_snake_case_and_fronts_can_store_their_values() {
        for (i, o) in OPTIONS.iter().enumerate() {
            assert!(
                o.name.bytes().all(|b| b.is_ascii_lowercase() || b == b'_'),
                "{}",
                o.name
            );
            assert!(OPTIONS[..i].iter().all(|p| p.name != o.name), "{}", o.name);
            let front = o.flag.is_some() || o.python;
            assert_eq!(
                front,
                o.set.is_some() || o.kind == Kind::File,
                "{}: a front end needs `set`",
                o.name
            );
            assert!(front || o.table.is_some(), "{}: set nowhere", o.name);
            let off = o.flag.and_then(|f| f.off).is_some();
            assert!(
                !off || o.kind == Kind::Switch,
                "{}: only switches have --no-",
                o.name
            );
            if let DefaultValue::Follows(other) = o.default {
                assert_eq!(find(other).map(|p| p.kind), Some(o.kind), "{}", o.name);
            }
        }
    }

    /// A value of every option's kind other than its default, stored through
    /// `set`, lands in `Choices`: no entry's setter is a no-op or writes
    /// another option's field.
    #[test]
    fn every_setter_stores_its_own_value() {
        let mut seen = Vec::new();
        for o in OPTIONS.iter().filter(|o| o.set.is_some()) {
            let mut c = Choices::default();
            o.store(&mut c, sample(o.kind));
            assert_ne!(c, Choices::default(), "{} stored nothing", o.name);
            let text = format!("{c:?}");
            assert!(
                !seen.contains(&text),
                "{} stores where another does",
                o.name
            );
            seen.push(text);
        }
    }

    /// A valid value of `kind` that no option has as its default.
    pub(crate) fn sample(kind: Kind) -> Value {
        match kind {
            Kind::Int { min, max } => Value::Int(max.min(min.max(7))),
            Kind::NonNegative | Kind::Positive => Value::Number(0.5),
            Kind::Between(lo, _) => Value::Number(lo),
            Kind::Switch => Value::Switch(true),
            Kind::Distribution => Value::Distribution(Distribution::Poisson),
            Kind::Filter => Value::Filter(Filter::Gaussian),
            Kind::StopRule => Value::StopRule(StopRule::Cycles),
            Kind::Integrator => Value::Integrator(IntegratorChoice::Whitted),
            Kind::PathSampler => Value::PathSampler(PathSampler::Sequence(Distribution::Sobol)),
            Kind::LightSampler => Value::LightSampler(LightChoice::Power),
            Kind::Colour => Value::Colour([0.5; 3]),
            Kind::File => unreachable!("a file option has no setter"),
        }
    }

    /// Every file option's front-end value lands in `Choices`.
    #[test]
    fn file_options_store_their_file() {
        for o in OPTIONS.iter().filter(|o| o.kind == Kind::File) {
            let mut c = Choices::default();
            o.store_file(&mut c, PathBuf::from("p.json"));
            assert_ne!(c, Choices::default(), "{} stored nothing", o.name);
        }
    }
}
