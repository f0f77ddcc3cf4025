//! Image-wide settings after validation — the film's and the sampler's —
//! with the schemas of those two plugins; the names of the integrators and
//! of the adaptive sampling rules, which the render options offer. Each
//! integrator reads its own parameters (`integrator::Config`).

use std::sync::Arc;

use crate::description::check::int;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::{sensors, Mitsuba, Plugin};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::sampling::filter::FILTER_KEYS;
use crate::sampling::{
    Distribution, EffectSpec, Filter, FilterParams, PixelFilter, PointTable, MAX_RAYS,
};

/// Largest image side; keeps `width * height` and the film allocation sane.
pub const MAX_SIDE: u32 = 1 << 15;

/// Most replicas adaptive sampling may split a pixel's sets into.
pub const MAX_REPLICAS: u32 = 64;

/// Most pixels an image may have (16384 × 16384): the frame is held in
/// memory as 32-bit floats, 12 bytes a pixel, 3 GiB at this size.
pub const MAX_PIXELS: u64 = 1 << 28;

/// The integrators a scene may choose, by name. The integrators themselves
/// sit above the scene; their list (`integrator/plugins.rs`) makes their
/// dispatch and checks that it names these, in this order.
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
    /// The path tracer through participating media (Mitsuba 3's
    /// `volpath`).
    Volpath,
    /// The volumetric path tracer with spectral MIS (Mitsuba 3's
    /// `volpathmis`).
    Volpathmis,
    /// A particle tracer: paths from the emitters connected to the camera
    /// (Mitsuba 3's `ptracer`).
    Ptracer,
    /// The distance to the first hit (Mitsuba 3's `depth`).
    Depth,
    /// Arbitrary output variables of the first hit beside a held
    /// integrator's image (Mitsuba 3's `aov`).
    Aov,
    /// A held integrator's image with the first and second moments of its
    /// samples (Mitsuba 3's `moment`).
    Moment,
}

impl IntegratorChoice {
    pub const ALL: [IntegratorChoice; 10] = [
        IntegratorChoice::Whitted,
        IntegratorChoice::Path,
        IntegratorChoice::Direct,
        IntegratorChoice::Distributed,
        IntegratorChoice::Volpath,
        IntegratorChoice::Volpathmis,
        IntegratorChoice::Ptracer,
        IntegratorChoice::Depth,
        IntegratorChoice::Aov,
        IntegratorChoice::Moment,
    ];
    pub const NAMES: [&'static str; 10] = [
        "whitted",
        "path",
        "direct",
        "distributed",
        "volpath",
        "volpathmis",
        "ptracer",
        "depth",
        "aov",
        "moment",
    ];

    /// The name scenes select it by: its integrator's schema's (the
    /// integrators' list checks they agree).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    pub fn from_name(s: &str) -> Option<IntegratorChoice> {
        IntegratorChoice::ALL.into_iter().find(|c| c.name() == s)
    }
}

/// Image-wide settings after validation.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub seed: u64,
    /// Primary rays per pixel.
    pub spp: u32,
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
    /// Whether the samples are splatted into the pixels the filter covers
    /// (`splat`, with a filter other than the box) rather
    /// than drawn from it.
    pub splat: bool,
    /// The steps the splatting filter is tabulated at (`filter_steps`; 0:
    /// evaluated exactly).
    pub filter_steps: u32,
    /// The part of the `width` × `height` image that is rendered and
    /// written (the camera frames the whole); `None` for the whole.
    pub crop: Option<Crop>,
    /// The pixels sampled beyond the film on each side (`sample_border`
    /// with a splatting filter; else 0). `width`, `height` and `crop` are
    /// those of the frame sampled, the film grown by it: the film's pixel
    /// `(x, y)` is the frame's `(x + border, y + border)`, and the crop
    /// window is never `None` when it is not 0.
    pub border: u32,
    /// Whether the image carries an alpha channel `A` (`alpha`, Mitsuba's
    /// `pixel_format` `rgba`): per sample 1 where the camera ray meets a
    /// surface (or anywhere with a visible emitter at infinity), filtered
    /// as the colour is.
    pub alpha: bool,
}

/// A crop window: the `width` × `height` pixels from column `x`, row `y`
/// of the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
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
        param("filter", Type::Choice("pixel filter", &FILTERS)).penumbra_only(),
        param("filter_radius", Type::Number).penumbra_only(),
        param("filter_stddev", Type::Number).penumbra_only(),
        param("filter_b", Type::Number).penumbra_only(),
        param("filter_c", Type::Number).penumbra_only(),
        param("filter_lobes", Type::Int).penumbra_only(),
        param("splat", Type::Bool).penumbra_only(),
        param("filter_steps", Type::Int).penumbra_only(),
        param("sample_border", Type::Bool),
        param("alpha", Type::Bool).penumbra_only(),
        param("crop_offset_x", Type::Int),
        param("crop_offset_y", Type::Int),
        param("crop_width", Type::Int),
        param("crop_height", Type::Int),
    ],
};

/// How Mitsuba's `hdrfilm` maps onto the film.
pub const FILM_PLUGINS: [Plugin; 1] = [Plugin::new(
    &FILM,
    Mitsuba {
        differences: "`width` and `height` are 768 × 576 unless given, each at least 1; the crop \
            window (`crop_offset_x`, `crop_offset_y`, `crop_width`, `crop_height`) as Mitsuba's: \
            the image written is the crop, the camera frames the whole film; its \
            `<rfilter>` (`gaussian` without one) as `filter` and the `filter_*` keys, each sample \
            splatted by it (`splat`) as Mitsuba's film develops, weighted by the filter \
            tabulated at 31 steps (`filter_steps`) as Mitsuba's CPU variants weight them, only the samples of the crop \
            window's pixels (and of the border beyond it with `sample_border`) reaching it; \
            `pixel_format` `rgba` (and `luminance_alpha`, `xyza`) as `alpha`: an `A` channel \
            written beside the RGB; the luminance and XYZ formats are written as RGB, with a \
            warning; `file_format` and `component_format` are ignored with a warning: \
            the output's extension chooses the format",
        reads: &["file_format", "pixel_format", "component_format"],
        adapt: Some(Adapt::Held(sensors::hdrfilm)),
    },
)];

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
        param("spp", Type::Int).mitsuba("sample_count"),
        param("seed", Type::Int),
        param("shadow_rays", Type::Int).penumbra_only(),
        param("reflection_rays", Type::Int).penumbra_only(),
        param("refraction_rays", Type::Int).penumbra_only(),
        param("distribution", Type::Distribution).penumbra_only(),
        param("pixel_distribution", Type::Distribution).penumbra_only(),
        param("lens_distribution", Type::Distribution).penumbra_only(),
        param("time_distribution", Type::Distribution).penumbra_only(),
        param("shadow_distribution", Type::Distribution).penumbra_only(),
        param("reflection_distribution", Type::Distribution).penumbra_only(),
        param("refraction_distribution", Type::Distribution).penumbra_only(),
        param("points", Type::Path).penumbra_only(),
    ],
};

/// A Mitsuba sampler mapped by `adapt`, what differs said by
/// `differences`; `jitter` read where `reads` says.
const fn sampler(
    name: &'static [&'static str],
    differences: &'static str,
    reads: &'static [&'static str],
    adapt: Adapt,
) -> Plugin {
    Plugin::named(
        &SAMPLER,
        name,
        Mitsuba {
            differences,
            reads,
            adapt: Some(adapt),
        },
    )
}

/// How Mitsuba's samplers map onto the sampler: `sample_count` (4 unless
/// given) as `spp`, the camera sample's distribution and the bounces'
/// path sampler the nearest Penumbra has.
pub const SAMPLER_PLUGINS: [Plugin; 5] = [
    sampler(
        &["independent"],
        "`sample_count` is 4 unless given; the camera sample `random`, its film positions \
         `fast-random` (uniform over the pixel's square, as Mitsuba's; `random` fills the disk \
         inscribed in the pixel); the bounces independent",
        &[],
        Adapt::Held(sensors::independent),
    ),
    sampler(
        &["stratified"],
        "`sample_count` is 4 unless given; the camera sample `jitter` (`grid` without \
         `jitter`), the bounces `render.path_sampler = \"pmj02\"`: the nearest, with a warning",
        &["jitter"],
        Adapt::Held(sensors::stratified),
    ),
    sampler(
        &["multijitter"],
        "`sample_count` is 4 unless given; the camera sample `jitter`, the bounces \
         `render.path_sampler = \"pmj02\"`: the nearest, with a warning",
        &["jitter"],
        Adapt::Held(sensors::multijitter),
    ),
    sampler(
        &["ldsampler"],
        "`sample_count` is 4 unless given; the camera sample `sobol`, the bounces \
         `render.path_sampler = \"sobol\"`: the nearest, with a warning",
        &[],
        Adapt::Held(sensors::ldsampler),
    ),
    sampler(
        &["orthogonal"],
        "`sample_count` is 4 unless given; the camera sample `pmj02`, the bounces \
         `render.path_sampler = \"pmj02\"`: the nearest, with a warning, whatever its \
         `jitter` and `strength`",
        &["jitter", "strength"],
        Adapt::Held(sensors::orthogonal),
    ),
];

/// The render's sets of shadow, reflection and refraction rays, which
/// emitters and materials take unless they set their own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sets {
    pub shadow: EffectSpec,
    pub reflection: EffectSpec,
    pub refraction: EffectSpec,
}

/// The settings of the film and the sampler, from their parameters. The
/// `custom` distribution's points are left to the builder, which knows
/// whether they are needed.
pub fn read(film: &Props, sampler: &Props) -> Result<Settings, Invalid> {
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
    let splat = film.bool("splat")?.unwrap_or(false) && filter.filter() != Filter::Box;
    let crop = crop(film, width, height)?;
    let filter_steps = int(film, "filter_steps", 0, 0, 1024)?;
    let bordered = film.bool("sample_border")?.unwrap_or(false);
    let border = if splat && bordered {
        sample_border(filter.radius())
    } else {
        0
    };
    // The frame sampled: the film grown by the border on each side, its
    // crop window (the whole film where none is given) moved with it.
    let crop = match (border, crop) {
        (0, crop) => crop,
        (b, crop) => Some(crop.map_or(
            Crop {
                x: b,
                y: b,
                width,
                height,
            },
            |c| Crop {
                x: c.x + b,
                y: c.y + b,
                ..c
            },
        )),
    };
    let (width, height) = (width + 2 * border, height + 2 * border);
    let sets = sets(sampler)?;
    let d = sampler
        .distribution("distribution")?
        .unwrap_or(Distribution::Grid);
    let dist = |key: &str| -> Result<Distribution, Invalid> {
        Ok(sampler.distribution(key)?.unwrap_or(d))
    };
    Ok(Settings {
        width,
        height,
        seed: u64::from(int(sampler, "seed", 0, 0, i64::from(u32::MAX))?),
        spp: int(sampler, "spp", 1, 1, i64::from(MAX_RAYS))?,
        pixel: dist("pixel_distribution")?,
        lens: dist("lens_distribution")?,
        time: dist("time_distribution")?,
        shadow: sets.shadow,
        reflection: sets.reflection,
        refraction: sets.refraction,
        points: Arc::new(PointTable::NONE),
        filter,
        splat,
        filter_steps,
        crop,
        border,
        alpha: film.bool("alpha")?.unwrap_or(false),
    })
}

/// The pixels beyond the film a splatting filter of radius `r` needs
/// sampled, as Mitsuba's reconstruction filters count them: ⌈r − 1/2 − 2ε⌉
/// with Mitsuba's ray epsilon ε = 1500 · 2⁻²⁴, so that a radius ending on a
/// pixel's edge does not count the pixel beyond.
fn sample_border(r: f32) -> u32 {
    const RAY_EPSILON: f32 = 1500.0 / 16_777_216.0;
    (r - 0.5 - 2.0 * RAY_EPSILON).ceil().max(0.0) as u32
}

/// The film's crop window (Mitsuba's): the whole `width` × `height` image
/// unless `crop_*` say otherwise, refused where it leaves the image;
/// `None` for the whole image.
fn crop(film: &Props, width: u32, height: u32) -> Result<Option<Crop>, Invalid> {
    let max = i64::from(MAX_SIDE);
    let x = int(film, "crop_offset_x", 0, 0, max - 1)?;
    let y = int(film, "crop_offset_y", 0, 0, max - 1)?;
    let w = int(film, "crop_width", i64::from(width), 1, max)?;
    let h = int(film, "crop_height", i64::from(height), 1, max)?;
    for (offset, size, side, key) in [(x, w, width, "crop_width"), (y, h, height, "crop_height")] {
        if u64::from(offset) + u64::from(size) > u64::from(side) {
            let (o, s) = if key == "crop_width" {
                ("x", "width")
            } else {
                ("y", "height")
            };
            return Err(film.error(
                key,
                format!(
                    "the crop window leaves the image: crop_offset_{o} ({offset}) + {key} \
                     ({size}) is more than the image's {s} ({side})"
                ),
            ));
        }
    }
    let whole = (x, y, w, h) == (0, 0, width, height);
    Ok((!whole).then_some(Crop {
        x,
        y,
        width: w,
        height: h,
    }))
}

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
