//! The thesis's ray sets as the integrators that trace them read them:
//! [`RaySets`], a table by emitter and one by material and lobe, built once
//! per render from the budgets the scene's description gives
//! ([`Budgets`](crate::scene::Budgets)).

use crate::bsdf::MAX_LOBES;
use crate::sampling::{Distribution, EffectSpec};
use crate::scene::Scene;

/// The shadow set of an emitter without extent: one ray (every ray would
/// be the same).
pub const ONE_RAY: EffectSpec = EffectSpec {
    rays: 1,
    distribution: Distribution::Grid,
};

/// The sets `whitted` and `distributed` trace, looked up by index in their
/// shading loops.
#[derive(Clone, Debug, PartialEq)]
pub struct RaySets {
    /// By emitter: the rays of a shadow set toward it and their
    /// distribution. An area light's are its own (`shadow_rays`,
    /// `shadow_distribution`, else the render's); a point, spot or
    /// directional light's [`ONE_RAY`]; an emitter at infinity takes the
    /// render's shadow set (`distributed` samples it; `whitted` sees it
    /// only through rays that hit nothing).
    pub shadow: Vec<EffectSpec>,
    /// By material, by lobe slot: the set the lobe asks for (the thesis
    /// material's `reflection_rays` and `refraction_rays`); `None` where the
    /// material sets none, and the render's sets apply.
    pub lobes: Vec<[Option<EffectSpec>; MAX_LOBES]>,
}

impl RaySets {
    /// The sets of `scene`'s emitters and materials.
    pub fn new(scene: &Scene) -> RaySets {
        let budgets = &scene.budgets;
        let shadow = scene
            .emitters
            .iter()
            .zip(&budgets.shadow)
            .map(|(e, own)| {
                if e.is_infinite() {
                    scene.settings.shadow
                } else if e.is_delta() {
                    ONE_RAY
                } else {
                    own.unwrap_or(ONE_RAY)
                }
            })
            .collect();
        RaySets {
            shadow,
            lobes: budgets.lobes.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{LoadOptions, SceneSource};

    /// An area light's shadow set is its own, a point light's one ray, and
    /// an emitter at infinity's the render's; the lobes' sets are the
    /// scene's.
    #[test]
    fn emitters_take_their_own_one_or_the_renders_set() {
        let toml = "[render]\nshadow_rays = 3\nshadow_distribution = \"random\"\n\
                    [materials.m]\nreflectivity = 0.5\nreflection_rays = 6\n\
                    [[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = [1, 1, 1]\n\
                    [[lights]]\ntype = \"disk\"\ncenter = [0, 3, 0]\nnormal = [0, -1, 0]\n\
                    radius = 0.5\nradiance = [1, 1, 1]\nshadow_rays = 7\n\
                    [[lights]]\ntype = \"constant\"\nradiance = [0.1, 0.1, 0.1]\n";
        let here = std::path::Path::new(".");
        let src = SceneSource::from_toml(toml, here, here, &LoadOptions::default());
        let scene = src
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"));
        let sets = RaySets::new(&scene);
        let random = |rays| EffectSpec {
            rays,
            distribution: Distribution::Random,
        };
        assert_eq!(sets.shadow, [ONE_RAY, random(7), random(3)]);
        assert_eq!(sets.lobes, scene.budgets.lobes);
        assert_eq!(sets.lobes[1][0].map(|s| s.rays), Some(6));
    }
}
