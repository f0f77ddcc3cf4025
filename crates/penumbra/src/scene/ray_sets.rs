//! The ray sets of a scene's effects: what each draws from which
//! distribution, and how many rays a set has.

use super::light::Light;
use super::material::Material;
use super::settings::Settings;
use crate::sampling::Distribution;

/// Calls `f(what, rays, distribution)` for each kind of ray set the scene
/// draws: the pixel's film positions, lens positions and shutter times (of
/// `spp`), the blurry reflections and refractions of the materials that
/// have them, the area lights' shadow sets.
pub(super) fn each_set(
    s: &Settings,
    materials: &[Material],
    lights: &[Light],
    mut f: impl FnMut(&'static str, u32, Distribution),
) {
    f("primary rays per pixel", s.spp, s.pixel);
    f("lens positions", s.spp, s.lens);
    f("shutter times", s.spp, s.time);
    for m in materials {
        if m.reflectivity > 0.0 && m.glossiness > 0.0 {
            f(
                "reflection rays",
                m.reflection.rays,
                m.reflection.distribution,
            );
        }
        if m.transparency > 0.0 && m.translucency > 0.0 {
            f(
                "refraction rays",
                m.refraction.rays,
                m.refraction.distribution,
            );
        }
    }
    for l in lights.iter().filter(|l| !l.is_delta()) {
        f("shadow rays", l.shadow.rays, l.shadow.distribution);
    }
}

/// The sets drawn from the `custom` distribution: what, and of how many rays.
pub(super) fn custom_sets(
    s: &Settings,
    materials: &[Material],
    lights: &[Light],
) -> Vec<(&'static str, u32)> {
    let mut sets = Vec::new();
    each_set(s, materials, lights, |what, rays, d| {
        if d == Distribution::Custom {
            sets.push((what, rays));
        }
    });
    sets
}
