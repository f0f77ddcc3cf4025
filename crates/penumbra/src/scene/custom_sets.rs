//! Which effects draw from the `custom` distribution, and with sets of
//! which sizes.

use super::light::Light;
use super::material::Material;
use super::settings::Settings;
use crate::sampling::Distribution;

/// The effects that draw their sets from the `custom` distribution, with
/// their sets' sizes: the pixel's sets (of `spp`), the blurry reflections
/// and refractions of the materials that have them, the area lights'
/// shadow sets.
pub(super) fn custom_sets(
    s: &Settings,
    materials: &[Material],
    lights: &[Light],
) -> Vec<(&'static str, u32)> {
    let mut sets = Vec::new();
    let mut add = |what: &'static str, rays: u32, d: Distribution| {
        if d == Distribution::Custom {
            sets.push((what, rays));
        }
    };
    add("pixel positions", s.spp, s.pixel);
    add("lens positions", s.spp, s.lens);
    add("shutter times", s.spp, s.time);
    for m in materials {
        if m.reflectivity > 0.0 && m.glossiness > 0.0 {
            add(
                "reflection rays",
                m.reflection.rays,
                m.reflection.distribution,
            );
        }
        if m.transparency > 0.0 && m.translucency > 0.0 {
            add(
                "refraction rays",
                m.refraction.rays,
                m.refraction.distribution,
            );
        }
    }
    for l in lights.iter().filter(|l| !l.is_delta()) {
        add("shadow rays", l.shadow.rays, l.shadow.distribution);
    }
    sets
}
