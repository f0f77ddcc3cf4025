//! The path tracers as plugins: the parameters of `path`, `direct` and
//! `distributed`, and the settings they are read into.

use crate::description::check::int;
use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::emitter::choice::LightChoice;
use crate::integrator::metric::{self, Metric};
use crate::sampling::{PathSampler, MAX_RAYS};

/// A parameter documented with the render options.
const fn param(name: &'static str, ty: Type) -> Param {
    Param::new(name, ty, "", "")
}

/// The type of `path_sampler`.
const PATH_SAMPLER: Type = Type::Choice("path sampler", &PathSampler::NAMES);

/// The type of `light_sampler`.
const LIGHT_SAMPLER: Type = Type::Choice("light sampler", &LightChoice::NAMES);

/// The path tracer's parameters (Mitsuba 3's `path`, whose names and
/// defaults they keep). The sampler's and film's are the same for every
/// integrator.
pub const PATH: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "path",
    what: "path integrator",
    doc: "a path tracer with next-event estimation and multiple importance sampling",
    mitsuba: &["path"],
    params: &[
        param("max_depth", Type::Int),
        param("rr_depth", Type::Int),
        param("hide_emitters", Type::Bool),
        param("path_sampler", PATH_SAMPLER).penumbra_only(),
        param("light_sampler", LIGHT_SAMPLER).penumbra_only(),
        param("passes", Type::Int).penumbra_only(),
    ],
};

/// The distributed path tracer's parameters: the path tracer's, the depth
/// its sets reach, and the thesis's metrics on its sets (not on a pixel's
/// camera rays).
pub const DISTRIBUTED: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "distributed",
    what: "distributed integrator",
    doc:
        "the path tracer drawing the thesis's sets at its first vertices, through media as volpath",
    mitsuba: &[],
    params: &[
        param("max_depth", Type::Int),
        param("rr_depth", Type::Int),
        param("hide_emitters", Type::Bool),
        param("sets_depth", Type::Int),
        param("path_sampler", PATH_SAMPLER),
        param("light_sampler", LIGHT_SAMPLER),
        param("passes", Type::Int),
        metric::PARAMS[0],
        metric::PARAMS[1],
        metric::PARAMS[2],
        metric::PARAMS[3],
        metric::PARAMS[4],
        metric::PARAMS[5],
    ],
};

/// The direct illumination integrator's parameters (Mitsuba 3's `direct`).
pub const DIRECT: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "direct",
    what: "direct integrator",
    doc: "direct light by emitter and BSDF samples",
    mitsuba: &["direct"],
    params: &[
        param("emitter_samples", Type::Int),
        param("bsdf_samples", Type::Int),
        param("shading_samples", Type::Int),
        param("hide_emitters", Type::Bool),
        param("path_sampler", PATH_SAMPLER).penumbra_only(),
        param("light_sampler", LIGHT_SAMPLER).penumbra_only(),
        param("passes", Type::Int).penumbra_only(),
    ],
};

/// The volumetric path tracer's parameters (Mitsuba 3's `volpath`, whose
/// names and defaults they keep).
pub const VOLPATH: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "volpath",
    what: "volpath integrator",
    doc: "the path tracer through participating media: delta tracking, phase functions, \
          next-event estimation through media and null surfaces",
    mitsuba: &["volpath"],
    params: &[
        param("max_depth", Type::Int),
        param("rr_depth", Type::Int),
        param("hide_emitters", Type::Bool),
        param("path_sampler", PATH_SAMPLER).penumbra_only(),
        param("light_sampler", LIGHT_SAMPLER).penumbra_only(),
        param("passes", Type::Int).penumbra_only(),
    ],
};

/// The volumetric path tracer with spectral MIS (Mitsuba 3's
/// `volpathmis`, whose names and defaults they keep).
pub const VOLPATHMIS: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "volpathmis",
    what: "volpathmis integrator",
    doc: "the volumetric path tracer with multiple importance sampling of distances (spectral \
          MIS over the colour channels) and of emission met through media",
    mitsuba: &["volpathmis"],
    params: &[
        param("max_depth", Type::Int),
        param("rr_depth", Type::Int),
        param("hide_emitters", Type::Bool),
        Param::new(
            "use_spectral_mis",
            Type::Bool,
            "true",
            "distances drawn by one colour channel are weighed by the mean of every channel's \
             density (off: by the path's channel alone, as `volpath`)",
        ),
        param("path_sampler", PATH_SAMPLER).penumbra_only(),
        param("light_sampler", LIGHT_SAMPLER).penumbra_only(),
        param("passes", Type::Int).penumbra_only(),
    ],
};

/// How Mitsuba 3's `path`, `volpath`, `volpathmis` and `direct` map onto
/// Penumbra's: their parameters under the same names, read as their types
/// say.
pub const PLUGINS: [Plugin; 4] = [
    Plugin::new(&PATH, Mitsuba::SAME),
    Plugin::new(
        &VOLPATH,
        Mitsuba::differs(
            "a homogeneous medium's shadow rays take its exact transmittance (Mitsuba's tracks \
             them, which has the same mean); an area emitter hidden by `hide_emitters` still \
             blocks camera rays",
        ),
    ),
    Plugin::new(
        &VOLPATHMIS,
        Mitsuba::differs(
            "an area emitter hidden by `hide_emitters` still blocks camera rays; with \
             `use_spectral_mis = false` a channel whose contribution vanishes is 0 and the others \
             go on (Mitsuba's path ends)",
        ),
    ),
    Plugin::new(
        &DIRECT,
        Mitsuba::differs(
            "`shading_samples` sets both sample counts, each of which \
             `emitter_samples` or `bsdf_samples` overrides where given (Mitsuba refuses \
             `shading_samples` beside either)",
        ),
    ),
];

/// The settings of the `path`, `direct` and `distributed` integrators, in
/// Mitsuba 3's terms (`direct` is a path of two vertices whose first takes
/// its own numbers of emitter and BSDF samples, without Russian roulette).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSettings {
    /// The longest path, in vertices counted from the camera (1: only
    /// emitters seen directly, 2: direct light); `None` for no bound.
    pub max_depth: Option<u32>,
    /// The depth from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Emitters seen directly by camera rays are black.
    pub hide_emitters: bool,
    /// Emitter samples at the first vertex (1 at every other).
    pub emitter_samples: u32,
    /// BSDF samples at the first vertex, each going on as its own path (1
    /// at every other).
    pub bsdf_samples: u32,
    /// Vertices below this depth draw the thesis's sets (`distributed`):
    /// a shadow set toward every emitter and a set of BSDF samples, from
    /// their distributions; 0 for `path` and `direct`.
    pub sets_depth: u32,
    /// Where the numbers of each bounce come from.
    pub sampler: PathSampler,
    /// How next-event estimation chooses its emitter.
    pub light_sampler: LightChoice,
    /// The thesis's metrics on the sets (`distributed`), if on.
    pub metric: Option<Metric>,
    /// Passes the samples are cut into.
    pub passes: u32,
    /// Paths are tracked through participating media (`volpath`).
    pub volumetric: bool,
    /// `volpathmis`: paths through media weighed by multiple importance
    /// sampling of their distances and of emission; `Some(true)` weighs
    /// the distances drawn by each colour channel (Mitsuba's
    /// `use_spectral_mis`). `None` for the other integrators.
    pub spectral_mis: Option<bool>,
}

impl Default for PathSettings {
    fn default() -> Self {
        PathSettings {
            max_depth: None,
            rr_depth: 5,
            hide_emitters: false,
            emitter_samples: 1,
            bsdf_samples: 1,
            sets_depth: 0,
            sampler: PathSampler::Independent,
            light_sampler: LightChoice::Bvh,
            metric: None,
            passes: 1,
            volumetric: false,
            spectral_mis: None,
        }
    }
}

impl PathSettings {
    /// What the three read alike on top of their own settings `s`: the
    /// path sampler, the light sampler, the passes and the metrics.
    pub(super) fn read_shared(mut s: PathSettings, i: &Props) -> Result<PathSettings, Invalid> {
        s.sampler = i
            .choice("path_sampler", "path sampler", &PathSampler::NAMES)?
            .and_then(PathSampler::from_name)
            .unwrap_or_default();
        s.light_sampler = i
            .choice("light_sampler", "light sampler", &LightChoice::NAMES)?
            .and_then(LightChoice::from_name)
            .unwrap_or_default();
        s.passes = int(i, "passes", 1, 1, i64::from(MAX_RAYS))?;
        s.metric = metric::read(i)?;
        Ok(s)
    }

    pub(super) fn depth(&self) -> i64 {
        self.max_depth.map_or(-1, i64::from)
    }
}

/// The `distributed` integrator's settings: the path tracer's and
/// `sets_depth` (1 to 64, default 1).
pub(super) fn distributed(i: &Props) -> Result<PathSettings, Invalid> {
    let sets_depth = int(i, "sets_depth", 1, 1, 64)?;
    Ok(PathSettings {
        sets_depth,
        ..path(i)?
    })
}

/// Mitsuba's `max_depth` of an integrator's parameters `i`: `None` for
/// no bound (−1, or not given), else at most `u32::MAX`.
pub(crate) fn max_depth(i: &Props) -> Result<Option<u32>, Invalid> {
    Ok(match i.int("max_depth")? {
        None | Some(-1) => None,
        Some(v) => Some(u32::try_from(v).map_err(|_| {
            i.error(
                "max_depth",
                format!(
                    "must be -1 (no bound) or an integer from 0 to {}, got {v}",
                    u32::MAX
                ),
            )
        })?),
    })
}

/// The `path` integrator's settings: Mitsuba's `max_depth` (−1 for no
/// bound), `rr_depth` (≥ 1) and `hide_emitters`.
pub(super) fn path(i: &Props) -> Result<PathSettings, Invalid> {
    let d = PathSettings::default();
    let max_depth = max_depth(i)?;
    Ok(PathSettings {
        max_depth,
        rr_depth: int(i, "rr_depth", i64::from(d.rr_depth), 1, i64::from(MAX_RAYS))?,
        hide_emitters: i.bool("hide_emitters")?.unwrap_or(d.hide_emitters),
        ..d
    })
}

/// The `volpath` integrator's settings: `path`'s, tracked through media.
pub(super) fn volpath(i: &Props) -> Result<PathSettings, Invalid> {
    Ok(PathSettings {
        volumetric: true,
        ..path(i)?
    })
}

/// The `volpathmis` integrator's settings: `volpath`'s and
/// `use_spectral_mis` (default true).
pub(super) fn volpathmis(i: &Props) -> Result<PathSettings, Invalid> {
    Ok(PathSettings {
        spectral_mis: Some(i.bool("use_spectral_mis")?.unwrap_or(true)),
        ..volpath(i)?
    })
}

/// The `direct` integrator's settings: Mitsuba's `emitter_samples` and
/// `bsdf_samples` (each 0 or more, not both 0), or `shading_samples` for
/// both, and `hide_emitters`.
pub(super) fn direct(i: &Props) -> Result<PathSettings, Invalid> {
    let count = |key: &str, default: u32| int(i, key, i64::from(default), 0, i64::from(MAX_RAYS));
    let both = count("shading_samples", 1)?;
    let emitter_samples = count("emitter_samples", both)?;
    let bsdf_samples = count("bsdf_samples", both)?;
    if emitter_samples == 0 && bsdf_samples == 0 {
        let key = if i.int("bsdf_samples")?.is_some() {
            "bsdf_samples"
        } else {
            "shading_samples"
        };
        return Err(i.error(
            key,
            "a direct integrator needs an emitter or a BSDF sample: emitter_samples and \
             bsdf_samples cannot both be 0",
        ));
    }
    Ok(PathSettings {
        max_depth: Some(2),
        rr_depth: u32::MAX,
        hide_emitters: i.bool("hide_emitters")?.unwrap_or(false),
        emitter_samples,
        bsdf_samples,
        ..PathSettings::default()
    })
}
