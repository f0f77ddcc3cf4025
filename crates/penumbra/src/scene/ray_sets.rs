//! The ray sets of a scene's effects: the budgets its description gives
//! each emitter and material ([`Budgets`]), what each set draws from which
//! distribution, and how many rays a set has.

use std::collections::HashMap;

use super::settings::Settings;
use crate::bsdf::{Bsdf, BsdfFlags, MAX_LOBES};
use crate::description::{Node, Type, Value};
use crate::sampling::{Distribution, EffectSpec};

/// The sets of rays a scene's description asks of its emitters and
/// materials, by index, read once when the scene is built: the thesis's
/// per-light shadow sets and per-material ray sets. The scene keeps them
/// as described; the integrators that trace the thesis's sets read them
/// into their own tables (`integrator::RaySets`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Budgets {
    /// By emitter: the shadow set its area emitter's `shadow_rays` and
    /// `shadow_distribution` ask for (the render's where they are not
    /// given, and for a material's emission); `None` for the emitters
    /// without those keys (point, spot and directional lights, those at
    /// infinity).
    pub shadow: Vec<Option<EffectSpec>>,
    /// By material, by lobe slot: the set the lobe asks for (the thesis
    /// material's `reflection_rays` and `refraction_rays` with their
    /// distributions, in the slots of its mirror and dielectric); `None`
    /// where the material sets none, and the render's sets apply.
    pub lobes: Vec<[Option<EffectSpec>; MAX_LOBES]>,
}

/// The sets the lobes of `model`, built from `node`, ask for, by slot: the
/// thesis material's own; for a material holding others, those of the
/// materials it names (`held`, by name), each from the slot after the
/// lobes of the ones named before it (its parameters of type material in
/// the order of its schema), as the holding models place their lobes; none
/// for the other models.
pub(super) fn lobe_sets(
    model: &Bsdf,
    node: &Node,
    held: &HashMap<String, (usize, [Option<EffectSpec>; MAX_LOBES])>,
) -> [Option<EffectSpec>; MAX_LOBES] {
    if let Some(sets) = model.own_sets() {
        return sets;
    }
    let mut sets = [None; MAX_LOBES];
    let schema = Bsdf::SCHEMAS.iter().find(|s| s.plugin == node.plugin);
    let names = schema
        .into_iter()
        .flat_map(|s| s.params)
        .filter(|param| param.ty == Type::Material)
        .filter_map(|param| match &node.prop(param.name)?.value.value {
            Value::String(name) => held.get(name.as_str()),
            _ => None,
        });
    let mut at = 0;
    for (slots, own) in names {
        for (k, set) in own[..*slots].iter().enumerate() {
            if let Some(slot) = sets.get_mut(at + k) {
                *slot = *set;
            }
        }
        at += slots;
    }
    sets
}

/// Calls `f(what, rays, distribution)` for each kind of ray set the scene
/// draws: the pixel's film positions, lens positions and shutter times (of
/// `spp`), the blurred delta lobes of the BSDFs (a BSDF's lobes sharing one
/// set budget counted once), the area lights' shadow sets.
pub(super) fn each_set(
    s: &Settings,
    bsdfs: &[Bsdf],
    budgets: &Budgets,
    mut f: impl FnMut(&'static str, u32, Distribution),
) {
    f("primary rays per pixel", s.spp, s.pixel);
    f("lens positions", s.spp, s.lens);
    f("shutter times", s.spp, s.time);
    for (b, sets) in bsdfs.iter().zip(&budgets.lobes) {
        let mut seen: Vec<EffectSpec> = Vec::new();
        for (k, flags) in b.lobes().iter() {
            let Some(set) =
                sets[k].filter(|_| flags.contains(BsdfFlags::DELTA | BsdfFlags::GLOSSY))
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
    for shadow in budgets.shadow.iter().flatten() {
        f("shadow rays", shadow.rays, shadow.distribution);
    }
}

/// The sets drawn from the `custom` distribution: what, and of how many rays.
pub(super) fn custom_sets(
    s: &Settings,
    bsdfs: &[Bsdf],
    budgets: &Budgets,
) -> Vec<(&'static str, u32)> {
    let mut sets = Vec::new();
    each_set(s, bsdfs, budgets, |what, rays, d| {
        if d.needs_table() {
            sets.push((what, rays));
        }
    });
    sets
}

#[cfg(test)]
mod tests {
    use crate::bsdf::{BsdfFlags, MAX_LOBES};
    use crate::sampling::{Distribution, EffectSpec};
    use crate::scene::{LoadOptions, Scene, SceneSource};

    fn build(toml: &str) -> Scene {
        let here = std::path::Path::new(".");
        let src = SceneSource::from_toml(toml, here, here, &LoadOptions::default());
        src.and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"))
    }

    fn spec(rays: u32, distribution: Distribution) -> EffectSpec {
        EffectSpec { rays, distribution }
    }

    /// Each emitter's shadow set is the one its description asks for, in
    /// the order of the emitters, the tree's: the emitting objects' (an
    /// `emitter` table's keys, the render's for a material's emission),
    /// then the lights' (an area light's own keys, none for a point
    /// light), then those at infinity (none).
    #[test]
    fn shadow_sets_follow_the_emitters() {
        let scene = build(
            "[render]\nshadow_rays = 2\nshadow_distribution = \"jitter\"\n\
             [materials.glow]\nemission = [1, 1, 1]\n\
             [[objects]]\ntype = \"sphere\"\nmaterial = \"glow\"\ncenter = [0, 1, 0]\nradius = 0.2\n\
             [[objects]]\ntype = \"sphere\"\ncenter = [1, 1, 0]\nradius = 0.2\n\
             emitter = { radiance = [1, 1, 1], shadow_rays = 5, shadow_distribution = \"poisson\" }\n\
             [[lights]]\ntype = \"constant\"\nradiance = [0.1, 0.1, 0.1]\n\
             [[lights]]\ntype = \"rect\"\norigin = [0, 3, 0]\nedge_u = [1, 0, 0]\n\
             edge_v = [0, 0, 1]\nradiance = [1, 1, 1]\nshadow_rays = 9\n\
             [[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = [1, 1, 1]\n",
        );
        let jitter = Distribution::Jitter;
        assert_eq!(
            scene.budgets.shadow,
            [
                Some(spec(2, jitter)),
                Some(spec(5, Distribution::Poisson)),
                Some(spec(9, jitter)),
                None,
                None,
            ]
        );
        assert!(scene.emitters[4].is_infinite());
    }

    /// A material's lobes ask for the sets of its description: the thesis
    /// material's in the slots of its mirror and dielectric; a material
    /// holding others, those of the held ones in the slots their lobes take
    /// in it. Every slot with a set is a delta lobe of the built material.
    #[test]
    fn lobe_sets_follow_the_slots() {
        let scene = build(
            "[render]\nreflection_rays = 2\nrefraction_rays = 3\n\
             [materials.a_mirror]\nreflectivity = 0.8\nglossiness = 0.1\nreflection_rays = 4\n\
             reflection_distribution = \"poisson\"\n\
             [materials.b_glass]\ntransparency = 0.9\ntranslucency = 0.1\n\
             [materials.c_paint]\ntype = \"roughplastic\"\n\
             [materials.d_blend]\ntype = \"blendbsdf\"\nbsdf_0 = \"c_paint\"\nbsdf_1 = \"a_mirror\"\n\
             [materials.e_two]\ntype = \"twosided\"\nbsdf = \"c_paint\"\nback = \"a_mirror\"\n\
             [materials.f_leaf]\ntype = \"mask\"\nopacity = 0.5\nbsdf = \"a_mirror\"\n\
             [[objects]]\ntype = \"sphere\"\ncenter = [0, 1, 0]\nradius = 0.2\n",
        );
        // Named in the order they are written, whichever order the reader
        // keeps tables in: material `k` of the list is index `k + 1`.
        let index = |name: &str| {
            let names = [
                "a_mirror", "b_glass", "c_paint", "d_blend", "e_two", "f_leaf",
            ];
            1 + names.iter().position(|n| *n == name).unwrap()
        };
        let lobes = &scene.budgets.lobes;
        assert_eq!(lobes.len(), scene.bsdfs.len());
        let mut mirror = [None; MAX_LOBES];
        mirror[0] = Some(spec(4, Distribution::Poisson));
        assert_eq!(lobes[index("a_mirror")], mirror);
        let refraction = Some(spec(3, Distribution::Grid));
        assert_eq!(lobes[index("b_glass")][1..3], [refraction, refraction]);
        assert_eq!(lobes[index("c_paint")], [None; MAX_LOBES]);
        assert_eq!(lobes[index("f_leaf")], mirror);
        let offset = scene.bsdfs[index("c_paint")].lobes().slots();
        assert!(offset > 0);
        for name in ["d_blend", "e_two"] {
            let mut placed = [None; MAX_LOBES];
            placed[offset] = mirror[0];
            assert_eq!(lobes[index(name)], placed, "{name}");
        }
        for (b, sets) in scene.bsdfs.iter().zip(lobes) {
            let flags = b.lobes().flags;
            for (k, set) in sets.iter().enumerate() {
                assert!(
                    set.is_none() || flags[k].contains(BsdfFlags::DELTA),
                    "{}",
                    b.name()
                );
            }
        }
    }
}
