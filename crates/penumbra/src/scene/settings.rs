//! Image-wide settings after validation — the film's, the sampler's and
//! the integrator's — with the schemas of those three plugins, and the
//! settings of the thesis's acceleration metrics and of the adaptive
//! sampling rules (whose rules live in the integrator).

use std::sync::Arc;

use crate::description::check::{int, range};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::emitter::choice::LightChoice;
use crate::sampling::filter::FILTER_KEYS;
use crate::sampling::{
    Distribution, EffectSpec, Filter, FilterParams, PathSampler, PixelFilter, PointTable, MAX_RAYS,
};

/// Largest image side; keeps `width * height` and the film allocation sane.
pub const MAX_SIDE: u32 = 1 << 15;

/// Most replicas adaptive sampling may split a pixel's sets into.
pub const MAX_REPLICAS: u32 = 64;

/// Most pixels an image may have (16384 × 16384): the frame is held in
/// memory as 32-bit floats, 12 bytes a pixel, 3 GiB at this size.
pub const MAX_PIXELS: u64 = 1 << 28;

/// The integrators a scene may choose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorChoice {
    /// The thesis's distributed Whitted tracer.
    Whitted,
    /// A unidirectional path tracer (Mitsuba 3's `path`).
    Path,
    /// Direct illumination by emitter and BSDF samples (Mitsuba 3's
    /// `direct`).
    Direct,
    /// The thesis's sets at the first vertices of a path tracer.
    Distributed,
}

impl IntegratorChoice {
    pub const ALL: [IntegratorChoice; 4] = [
        IntegratorChoice::Whitted,
        IntegratorChoice::Path,
        IntegratorChoice::Direct,
        IntegratorChoice::Distributed,
    ];
    pub const NAMES: [&'static str; 4] = ["whitted", "path", "direct", "distributed"];

    pub fn name(self) -> &'static str {
        match self {
            IntegratorChoice::Whitted => "whitted",
            IntegratorChoice::Path => "path",
            IntegratorChoice::Direct => "direct",
            IntegratorChoice::Distributed => "distributed",
        }
    }

    pub fn from_name(s: &str) -> Option<IntegratorChoice> {
        IntegratorChoice::ALL.into_iter().find(|c| c.name() == s)
    }
}

/// The settings of the `path` and `direct` integrators, in Mitsuba 3's
/// terms (`direct` is a path of two vertices whose first takes its own
/// numbers of emitter and BSDF samples, without Russian roulette).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
        }
    }
}

/// Image-wide settings after validation.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// The integrator chosen.
    pub integrator: IntegratorChoice,
    pub width: u32,
    pub height: u32,
    /// Levels of reflection/refraction rays (the thesis's recursion depth).
    pub max_depth: u32,
    /// The path tracer's settings (its defaults unless it is chosen).
    pub path: PathSettings,
    pub seed: u64,
    /// Primary rays per pixel.
    pub spp: u32,
    /// Passes the render is made in.
    pub passes: u32,
    pub pixel: Distribution,
    pub lens: Distribution,
    pub time: Distribution,
    /// The sets of shadow, reflection and refraction rays of emitters and
    /// lobes that set none of their own.
    pub shadow: EffectSpec,
    pub reflection: EffectSpec,
    pub refraction: EffectSpec,
    /// The `custom` distribution's points ([`PointTable::NONE`] when none
    /// are given, which only a render without `custom` may have).
    pub points: Arc<PointTable>,
    /// The pixel filter the film points are drawn by, and the samples
    /// weighted by.
    pub filter: PixelFilter,
    /// The acceleration metrics, if on.
    pub metric: Option<Metric>,
    /// Adaptive sampling: the rule that stops a pixel's camera rays before
    /// `spp`, if on.
    pub stopping: Option<Stopping>,
}

impl Settings {
    /// `max_depth` as the chosen integrator counts it (−1: no bound), as
    /// reports show it.
    pub fn depth(&self) -> i64 {
        match self.integrator {
            IntegratorChoice::Whitted => i64::from(self.max_depth),
            IntegratorChoice::Path | IntegratorChoice::Direct | IntegratorChoice::Distributed => {
                self.path.max_depth.map_or(-1, i64::from)
            }
        }
    }
}

/// Settings of the metrics; `None` in the scene settings means they are all
/// off (the scene builder never makes one with all three rules off).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metric {
    /// Apply the α/threshold rule to reflection and refraction sets.
    pub reflections: bool,
    /// Apply the k rule to shadow sets.
    pub shadows: bool,
    /// Largest relative change of the running average that stops a set.
    pub threshold: f32,
    /// α: rays always traced before the reflection/refraction metric applies.
    pub min_rays: u32,
    /// k: shadow rays after which an all-lit or all-blocked set stops.
    pub shadow_rays: u32,
    /// Apply the α/threshold rule to the primary rays of a pixel too.
    pub pixels: bool,
}

/// Settings of adaptive sampling: a pixel takes camera rays in passes until
/// its rule judges its noise below `threshold`, or it reaches the budget
/// (`spp`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stopping {
    pub rule: StopRule,
    /// The noise a pixel may keep, in the rule's own measure (> 0).
    pub threshold: f32,
    /// The confidence of the rules that bound the error by an interval
    /// (`calibrated`, `povray`), from 0.5 to 0.999.
    pub confidence: f32,
    /// Independently scrambled replicas of a pixel's sets (`calibrated`), ≥ 2.
    pub replicas: u32,
    /// The value below which the calibrated rule's threshold is absolute:
    /// a half-width of `threshold · max(value, floor)` is allowed (> 0).
    pub floor: f32,
    /// Camera rays a pixel takes before the rule may stop it; 0: the rule's own.
    pub min_spp: u32,
}

/// An adaptive sampling rule, by the name users write.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum StopRule {
    /// Replicas' spread gives a confidence interval of the pixel's mean.
    #[default]
    Calibrated,
    /// Blender Cycles' adaptive sampling.
    Cycles,
    /// POV-Ray's stochastic anti-aliasing (`Sampling_Method 3`).
    Povray,
    /// Dammertz et al.'s hierarchical stopping condition (2009).
    Dammertz,
}

impl StopRule {
    pub const ALL: [StopRule; 4] = [
        StopRule::Calibrated,
        StopRule::Cycles,
        StopRule::Povray,
        StopRule::Dammertz,
    ];

    /// The name users write (the serde name too).
    pub fn name(self) -> &'static str {
        match self {
            StopRule::Calibrated => "calibrated",
            StopRule::Cycles => "cycles",
            StopRule::Povray => "povray",
            StopRule::Dammertz => "dammertz",
        }
    }

    pub fn from_name(s: &str) -> Option<StopRule> {
        StopRule::ALL.into_iter().find(|r| r.name() == s)
    }
}

/// A parameter documented with the render options.
const fn param(name: &'static str, ty: Type) -> Param {
    Param::new(name, ty, "", "")
}

const FILTERS: [&str; 6] = [
    "box",
    "tent",
    "gaussian",
    "mitchell",
    "catmullrom",
    "lanczos",
];

const STOP_RULES: [&str; 4] = ["calibrated", "cycles", "povray", "dammertz"];

/// The film's parameters (documented with the render options).
pub const FILM: Schema = Schema {
    kind: Kind::Film,
    plugin: "hdrfilm",
    what: "film",
    doc: "the image: its size and reconstruction filter",
    mitsuba: &["hdrfilm"],
    params: &[
        param("width", Type::Int),
        param("height", Type::Int),
        param("filter", Type::Choice("pixel filter", &FILTERS)),
        param("filter_radius", Type::Number),
        param("filter_stddev", Type::Number),
        param("filter_b", Type::Number),
        param("filter_c", Type::Number),
        param("filter_lobes", Type::Int),
    ],
};

/// The sampler's parameters (documented with the render options).
pub const SAMPLER: Schema = Schema {
    kind: Kind::Sampler,
    plugin: "sets",
    what: "sampler",
    doc: "the samples: per-pixel counts, seeds and the distribution of each effect",
    mitsuba: &[
        "independent",
        "stratified",
        "multijitter",
        "ldsampler",
        "orthogonal",
    ],
    params: &[
        param("seed", Type::Int),
        param("spp", Type::Int),
        param("shadow_rays", Type::Int),
        param("reflection_rays", Type::Int),
        param("refraction_rays", Type::Int),
        param("distribution", Type::Distribution),
        param("pixel_distribution", Type::Distribution),
        param("lens_distribution", Type::Distribution),
        param("time_distribution", Type::Distribution),
        param("shadow_distribution", Type::Distribution),
        param("reflection_distribution", Type::Distribution),
        param("refraction_distribution", Type::Distribution),
        param("points", Type::Path),
    ],
};

/// The `whitted` integrator's parameters (documented with the render options).
pub const WHITTED: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "whitted",
    what: "whitted integrator",
    doc: "the thesis's distributed Whitted ray tracer",
    mitsuba: &[],
    params: &[
        param("max_depth", Type::Int),
        param("passes", Type::Int),
        param("metric", Type::Bool),
        param("reflection_metric", Type::Bool),
        param("shadow_metric", Type::Bool),
        param("metric_threshold", Type::Number),
        param("metric_min_rays", Type::Int),
        param("shadow_metric_rays", Type::Int),
        param("pixel_metric", Type::Bool),
        param("noise_threshold", Type::Number),
        param(
            "stop_rule",
            Type::Choice("adaptive sampling rule", &STOP_RULES),
        ),
        param("confidence", Type::Number),
        param("replicas", Type::Int),
        param("noise_floor", Type::Number),
        param("min_spp", Type::Int),
    ],
};

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
        param("path_sampler", PATH_SAMPLER),
        param("light_sampler", LIGHT_SAMPLER),
        param("passes", Type::Int),
    ],
};

/// The type of `path_sampler`.
const PATH_SAMPLER: Type = Type::Choice("path sampler", &PathSampler::NAMES);

/// The type of `light_sampler`.
const LIGHT_SAMPLER: Type = Type::Choice("light sampler", &LightChoice::NAMES);

/// The distributed path tracer's parameters: the path tracer's, the depth
/// its sets reach, and the thesis's metrics on its sets (not on a pixel's
/// camera rays).
pub const DISTRIBUTED: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "distributed",
    what: "distributed integrator",
    doc: "the path tracer drawing the thesis's sets at its first vertices",
    mitsuba: &[],
    params: &[
        param("max_depth", Type::Int),
        param("rr_depth", Type::Int),
        param("hide_emitters", Type::Bool),
        param("sets_depth", Type::Int),
        param("path_sampler", PATH_SAMPLER),
        param("light_sampler", LIGHT_SAMPLER),
        param("passes", Type::Int),
        param("metric", Type::Bool),
        param("reflection_metric", Type::Bool),
        param("shadow_metric", Type::Bool),
        param("metric_threshold", Type::Number),
        param("metric_min_rays", Type::Int),
        param("shadow_metric_rays", Type::Int),
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
        param("path_sampler", PATH_SAMPLER),
        param("light_sampler", LIGHT_SAMPLER),
        param("passes", Type::Int),
    ],
};

/// The render's sets of shadow, reflection and refraction rays, which
/// emitters and materials take unless they set their own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sets {
    pub shadow: EffectSpec,
    pub reflection: EffectSpec,
    pub refraction: EffectSpec,
}

/// The settings of the film, the sampler and the integrator (named
/// `integrator`), from their parameters. The `custom` distribution's
/// points are left to the builder, which knows whether they are needed.
pub fn read(
    film: &Props,
    sampler: &Props,
    (integrator, name): (&Props, &str),
) -> Result<Settings, Invalid> {
    let width = int(film, "width", 800, 1, i64::from(MAX_SIDE))?;
    let height = int(film, "height", 600, 1, i64::from(MAX_SIDE))?;
    let pixels = u64::from(width) * u64::from(height);
    if pixels > MAX_PIXELS {
        return Err(film.error(
            "height",
            format!(
                "a {width} x {height} image has {pixels} pixels, more than the {MAX_PIXELS} \
                 (16384 x 16384) an image may have"
            ),
        ));
    }
    let filter = pixel_filter(film)?;
    let sets = sets(sampler)?;
    let d = sampler
        .distribution("distribution")?
        .unwrap_or(Distribution::Grid);
    let dist = |key: &str| -> Result<Distribution, Invalid> {
        Ok(sampler.distribution(key)?.unwrap_or(d))
    };
    let choice = IntegratorChoice::from_name(name).unwrap_or(IntegratorChoice::Whitted);
    let i = integrator;
    let (max_depth, mut path) = match choice {
        IntegratorChoice::Whitted => (int(i, "max_depth", 3, 0, 64)?, PathSettings::default()),
        IntegratorChoice::Path => (0, path_settings(i)?),
        IntegratorChoice::Direct => (0, direct_settings(i)?),
        IntegratorChoice::Distributed => {
            let sets_depth = int(i, "sets_depth", 1, 1, 64)?;
            let path = path_settings(i)?;
            (0, PathSettings { sets_depth, ..path })
        }
    };
    if choice != IntegratorChoice::Whitted {
        path.sampler = i
            .choice("path_sampler", "path sampler", &PathSampler::NAMES)?
            .and_then(PathSampler::from_name)
            .unwrap_or_default();
        path.light_sampler = i
            .choice("light_sampler", "light sampler", &LightChoice::NAMES)?
            .and_then(LightChoice::from_name)
            .unwrap_or_default();
    }
    Ok(Settings {
        integrator: choice,
        width,
        height,
        max_depth,
        path,
        seed: u64::from(int(sampler, "seed", 0, 0, i64::from(u32::MAX))?),
        spp: int(sampler, "spp", 1, 1, i64::from(MAX_RAYS))?,
        passes: int(i, "passes", 1, 1, i64::from(MAX_RAYS))?,
        pixel: dist("pixel_distribution")?,
        lens: dist("lens_distribution")?,
        time: dist("time_distribution")?,
        shadow: sets.shadow,
        reflection: sets.reflection,
        refraction: sets.refraction,
        points: Arc::new(PointTable::NONE),
        filter,
        metric: metric(i)?,
        stopping: stopping(i)?,
    })
}

/// The `path` integrator's settings: Mitsuba's `max_depth` (−1 for no
/// bound), `rr_depth` (≥ 1) and `hide_emitters`.
/// The film's pixel filter, its parameters read from the `filter_*` keys:
/// a bad value, or a key of another filter's parameter, is an error at
/// that key.
fn pixel_filter(film: &Props) -> Result<PixelFilter, Invalid> {
    let filter = match film.choice("filter", "pixel filter", &FILTERS)? {
        Some(f) => Filter::from_name(f).unwrap_or(Filter::Box),
        None => Filter::Box,
    };
    let params = FilterParams {
        radius: film.f32("filter_radius")?,
        stddev: film.f32("filter_stddev")?,
        b: film.f32("filter_b")?,
        c: film.f32("filter_c")?,
        lobes: film.int("filter_lobes")?,
    };
    PixelFilter::new(filter, &params).map_err(|e| {
        let key = FILTER_KEYS
            .iter()
            .find(|(p, _)| *p == e.param)
            .map_or("filter", |(_, k)| *k);
        film.error(key, e.message)
    })
}

fn path_settings(i: &Props) -> Result<PathSettings, Invalid> {
    let d = PathSettings::default();
    let max_depth = match i.int("max_depth")? {
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
    };
    Ok(PathSettings {
        max_depth,
        rr_depth: int(i, "rr_depth", i64::from(d.rr_depth), 1, i64::from(MAX_RAYS))?,
        hide_emitters: i.bool("hide_emitters")?.unwrap_or(d.hide_emitters),
        ..d
    })
}

/// The `direct` integrator's settings: Mitsuba's `emitter_samples` and
/// `bsdf_samples` (each 0 or more, not both 0), or `shading_samples` for
/// both, and `hide_emitters`.
fn direct_settings(i: &Props) -> Result<PathSettings, Invalid> {
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
        sets_depth: 0,
        sampler: PathSampler::Independent,
        light_sampler: LightChoice::Bvh,
    })
}

/// The render's sets (see [`Sets`]).
fn sets(sampler: &Props) -> Result<Sets, Invalid> {
    let d = sampler
        .distribution("distribution")?
        .unwrap_or(Distribution::Grid);
    let spec = |rays: &str, dist: &str| -> Result<EffectSpec, Invalid> {
        Ok(EffectSpec {
            rays: int(sampler, rays, 1, 1, i64::from(MAX_RAYS))?,
            distribution: sampler.distribution(dist)?.unwrap_or(d),
        })
    };
    Ok(Sets {
        shadow: spec("shadow_rays", "shadow_distribution")?,
        reflection: spec("reflection_rays", "reflection_distribution")?,
        refraction: spec("refraction_rays", "refraction_distribution")?,
    })
}

/// Adaptive sampling's settings; `None` when `noise_threshold` is 0.
fn stopping(i: &Props) -> Result<Option<Stopping>, Invalid> {
    let threshold = range(i, "noise_threshold", 0.0, 0.0, 1e6)?;
    let rule = match i.choice("stop_rule", "adaptive sampling rule", &STOP_RULES)? {
        Some(r) => StopRule::from_name(r).unwrap_or_default(),
        None => StopRule::default(),
    };
    let s = Stopping {
        rule,
        threshold,
        confidence: range(i, "confidence", 0.9, 0.5, 0.999)?,
        replicas: int(i, "replicas", 8, 2, i64::from(MAX_REPLICAS))?,
        floor: range(i, "noise_floor", 1.0, 1e-6, 1e6)?,
        min_spp: int(i, "min_spp", 0, 0, i64::from(MAX_RAYS))?,
    };
    let metric = i.bool("metric")?.unwrap_or(false);
    if threshold > 0.0 && metric && i.bool("pixel_metric")?.unwrap_or(false) {
        return Err(i.error(
            "noise_threshold",
            "adaptive sampling and `pixel_metric` both stop a pixel's camera rays: \
             turn one of them off",
        ));
    }
    Ok((threshold > 0.0).then_some(s))
}

fn metric(i: &Props) -> Result<Option<Metric>, Invalid> {
    let m = Metric {
        reflections: i.bool("reflection_metric")?.unwrap_or(true),
        shadows: i.bool("shadow_metric")?.unwrap_or(true),
        threshold: range(i, "metric_threshold", 0.01, 0.0, 1e6)?,
        min_rays: int(i, "metric_min_rays", 4, 1, i64::from(MAX_RAYS))?,
        shadow_rays: int(i, "shadow_metric_rays", 4, 1, i64::from(MAX_RAYS))?,
        pixels: i.bool("pixel_metric")?.unwrap_or(false),
    };
    let any = m.reflections || m.shadows || m.pixels;
    Ok((i.bool("metric")?.unwrap_or(false) && any).then_some(m))
}
