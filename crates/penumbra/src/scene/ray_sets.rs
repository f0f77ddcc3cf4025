//! The ray sets of a scene's effects: what each draws from which
//! distribution, and how many rays a set has.

use super::settings::Settings;
use crate::bsdf::{Bsdf, BsdfFlags};
use crate::emitter::Emitter;
use crate::sampling::{Distribution, EffectSpec};

/// Calls `f(what, rays, distribution)` for each kind of ray set the scene
/// draws: the pixel's film positions, lens positions and shutter times (of
/// `spp`), the blurred delta lobes of the BSDFs (a BSDF's lobes sharing one
/// set budget counted once), the area lights' shadow sets.
pub(super) fn each_set(
    s: &Settings,
    bsdfs: &[Bsdf],
    emitters: &[Emitter],
    mut f: impl FnMut(&'static str, u32, Distribution),
) {
    f("primary rays per pixel", s.spp, s.pixel);
    f("lens positions", s.spp, s.lens);
    f("shutter times", s.spp, s.time);
    for b in bsdfs {
        let mut seen: Vec<EffectSpec> = Vec::new();
        for (_, flags, set) in b.lobes().iter() {
            let Some(set) = set.filter(|_| flags.contains(BsdfFlags::DELTA | BsdfFlags::GLOSSY))
            else {
                continue;
            };
            if seen.contains(&set) {
                continue;
            }
            seen.push(set);
            let what = if flags.contains(BsdfFlags::TRANSMISSION) {
                "refraction rays"
            } else {
                "reflection rays"
            };
            f(what, set.rays, set.distribution);
        }
    }
    for e in emitters
        .iter()
        .filter(|e| !e.is_delta() && !e.is_infinite())
    {
        let shadow = e.shadow();
        f("shadow rays", shadow.rays, shadow.distribution);
    }
}

/// The sets drawn from the `custom` distribution: what, and of how many rays.
pub(super) fn custom_sets(
    s: &Settings,
    bsdfs: &[Bsdf],
    emitters: &[Emitter],
) -> Vec<(&'static str, u32)> {
    let mut sets = Vec::new();
    each_set(s, bsdfs, emitters, |what, rays, d| {
        if d == Distribution::Custom {
            sets.push((what, rays));
        }
    });
    sets
}
