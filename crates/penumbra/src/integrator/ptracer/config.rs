//! The particle tracer as a plugin: the parameters of `ptracer` (Mitsuba
//! 3's, under its names and defaults) and the settings they are read into.

use crate::description::check::int;
use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::sampling::MAX_RAYS;

/// A parameter documented with the render options.
const fn param(name: &'static str, ty: Type) -> Param {
    Param::new(name, ty, "", "")
}

/// The particle tracer's parameters (Mitsuba 3's `ptracer`).
pub const PTRACER: Schema = Schema {
    kind: Kind::Integrator,
    plugin: "ptracer",
    what: "ptracer integrator",
    doc: "a particle tracer: paths from the emitters, each vertex connected to the camera",
    mitsuba: &["ptracer"],
    params: &[
        param("max_depth", Type::Int),
        param("rr_depth", Type::Int),
        param("hide_emitters", Type::Bool),
        Param::new(
            "samples_per_pass",
            Type::Int,
            "all",
            "light paths per pixel of the frame in each pass (Mitsuba's); the passes are \
             the budget cut as evenly as it goes, and the image is the same for any cut",
        ),
        param("passes", Type::Int).penumbra_only(),
    ],
};

/// How Mitsuba 3's `ptracer` maps onto Penumbra's: the same parameters.
pub const PLUGINS: [Plugin; 1] = [Plugin::new(&PTRACER, Mitsuba::SAME)];

/// The settings of the particle tracer, in Mitsuba 3's terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PtracerSettings {
    /// The longest path, in vertices counted from the camera (1: only the
    /// emitters seen directly, 2: direct light); `None` for no bound.
    pub max_depth: Option<u32>,
    /// The depth from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Emitters seen directly are black (what they light is not).
    pub hide_emitters: bool,
    /// Light paths per pixel of the frame in each pass, if given.
    pub samples_per_pass: Option<u32>,
    /// Passes the samples are cut into (at least; `samples_per_pass` may
    /// ask for more).
    pub passes: u32,
}

impl Default for PtracerSettings {
    fn default() -> Self {
        PtracerSettings {
            max_depth: None,
            rr_depth: 5,
            hide_emitters: false,
            samples_per_pass: None,
            passes: 1,
        }
    }
}

impl PtracerSettings {
    /// The passes of a render of `spp` light paths per pixel.
    pub fn passes_of(&self, spp: u32) -> u32 {
        let by_size = self.samples_per_pass.map_or(1, |n| spp.div_ceil(n.max(1)));
        self.passes.max(by_size).max(1)
    }
}

/// The `ptracer` integrator's settings: Mitsuba's `max_depth` (−1 for no
/// bound), `rr_depth` (≥ 1), `hide_emitters` and `samples_per_pass`, and
/// `passes`.
pub(super) fn read(i: &Props) -> Result<PtracerSettings, Invalid> {
    let d = PtracerSettings::default();
    let max_depth = crate::integrator::path::max_depth(i)?;
    let samples_per_pass = match i.int("samples_per_pass")? {
        None => None,
        Some(_) => Some(int(i, "samples_per_pass", 1, 1, i64::from(MAX_RAYS))?),
    };
    Ok(PtracerSettings {
        max_depth,
        rr_depth: int(i, "rr_depth", i64::from(d.rr_depth), 1, i64::from(MAX_RAYS))?,
        hide_emitters: i.bool("hide_emitters")?.unwrap_or(d.hide_emitters),
        samples_per_pass,
        passes: int(i, "passes", 1, 1, i64::from(MAX_RAYS))?,
    })
}
