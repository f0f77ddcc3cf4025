//! The pixel filters as the film's plugins: the parameters of each (Mitsuba
//! 3's, whose names and defaults they keep), which a scene file gives as
//! the film's `filter_*` keys (see [`sampling::filter`](crate::sampling::filter))
//! and a Mitsuba scene in the film's `<rfilter>`.

use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::{sensors, Mitsuba, Plugin};
use crate::description::{Kind, Param, Range, Schema, Type};

/// The schema of the filter of Mitsuba's name `name[0]`.
const fn filter(
    name: &'static [&'static str],
    doc: &'static str,
    params: &'static [Param],
) -> Schema {
    Schema {
        kind: Kind::Filter,
        plugin: name[0],
        what: "pixel filter",
        doc,
        mitsuba: name,
        params,
    }
}

pub const BOX: Schema = filter(
    &["box"],
    "every point of the pixel's square counts the same",
    &[],
);

pub const TENT: Schema = filter(
    &["tent"],
    "a weight falling linearly to 0 at `radius`",
    &[Param::new("radius", Type::Number, "1", "the radius, in pixels").range(Range::Positive)],
);

pub const GAUSSIAN: Schema = filter(
    &["gaussian"],
    "a Gaussian cut at 4 standard deviations",
    &[Param::new(
        "stddev",
        Type::Number,
        "0.5",
        "the standard deviation, in pixels",
    )
    .range(Range::Positive)],
);

pub const MITCHELL: Schema = filter(
    &["mitchell"],
    "Mitchell and Netravali's cubic of radius 2, negative in part",
    &[
        Param::new("B", Type::Number, "1/3", "the cubic's B").range(Range::Unit),
        Param::new("C", Type::Number, "1/3", "the cubic's C").range(Range::Unit),
    ],
);

pub const CATMULLROM: Schema = filter(
    &["catmullrom"],
    "the Mitchell–Netravali cubic of B = 0, C = 1/2",
    &[],
);

pub const LANCZOS: Schema = filter(
    &["lanczos"],
    "a windowed sinc of radius `lobes`, negative in part",
    &[
        Param::new("lobes", Type::Int, "3", "the lobes on each side")
            .range(Range::Between(1.0, 32.0)),
    ],
);

/// How Mitsuba's reconstruction filters map onto the film's filters, in
/// the order of [`Filter::ALL`](crate::sampling::Filter::ALL).
pub const PLUGINS: [Plugin; 6] = [
    Plugin::new(
        &BOX,
        Mitsuba {
            differences: "`radius` at 0.5 only",
            reads: &["radius"],
            adapt: Some(Adapt::Node(sensors::box_filter)),
        },
    ),
    Plugin::new(&TENT, Mitsuba::SAME),
    Plugin::new(
        &GAUSSIAN,
        Mitsuba::differs(
            "the same profile; Mitsuba's scalar variants (`scalar_rgb`) weigh samples by a \
             table of 31 steps over the radius, each holding the profile's value at its inner \
             end, which blurs a little more: an emitter's edge rows seen through it are 3–5% \
             brighter there than in Penumbra or in Mitsuba's `llvm_ad_rgb`, which evaluates \
             the profile itself",
        ),
    ),
    Plugin::new(&MITCHELL, Mitsuba::differs("`B` and `C` in [0, 1]")),
    Plugin::new(&CATMULLROM, Mitsuba::SAME),
    Plugin::new(&LANCZOS, Mitsuba::differs("`lobes` from 1 to 32")),
];
