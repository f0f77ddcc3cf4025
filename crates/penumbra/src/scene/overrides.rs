//! Values given outside the scene file (command line, Python keyword
//! arguments) that win over the file's.

use super::desc::SceneDesc;
use super::points::Points;
use super::settings::StopRule;
use crate::sampling::{Distribution, Filter};

/// Settings that replace the scene description's. Ray counts and
/// distributions given here also replace per-light and per-material values:
/// a user asking for 16 shadow rays expects every light to use 16.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub max_depth: Option<u32>,
    pub seed: Option<u32>,
    pub spp: Option<u32>,
    pub passes: Option<u32>,
    pub shadow_rays: Option<u32>,
    pub reflection_rays: Option<u32>,
    pub refraction_rays: Option<u32>,
    /// Distribution for every effect (replaces every more specific one in the file).
    pub distribution: Option<Distribution>,
    pub pixel_distribution: Option<Distribution>,
    pub filter: Option<Filter>,
    pub lens_distribution: Option<Distribution>,
    pub time_distribution: Option<Distribution>,
    pub shadow_distribution: Option<Distribution>,
    pub reflection_distribution: Option<Distribution>,
    pub refraction_distribution: Option<Distribution>,
    /// The `custom` distribution's points.
    pub points: Option<Points>,
    pub aperture: Option<f32>,
    pub focal_distance: Option<f32>,
    /// Turn the acceleration metrics on or off.
    pub metric: Option<bool>,
    /// Turn the reflection/refraction or the shadow metric on or off
    /// (they act only with `metric` on).
    pub reflection_metric: Option<bool>,
    pub shadow_metric: Option<bool>,
    pub metric_threshold: Option<f32>,
    pub metric_min_rays: Option<u32>,
    pub shadow_metric_rays: Option<u32>,
    pub pixel_metric: Option<bool>,
    /// Adaptive sampling.
    pub noise_threshold: Option<f32>,
    pub stop_rule: Option<StopRule>,
    pub confidence: Option<f32>,
    pub replicas: Option<u32>,
    pub noise_floor: Option<f32>,
    pub min_spp: Option<u32>,
}

impl Overrides {
    pub fn apply(&self, desc: &mut SceneDesc) {
        let r = &mut desc.render;
        set(&mut r.width, self.width.map(i64::from));
        set(&mut r.height, self.height.map(i64::from));
        set(&mut r.max_depth, self.max_depth.map(i64::from));
        set(&mut r.seed, self.seed.map(i64::from));
        set(&mut r.spp, self.spp.map(i64::from));
        set(&mut r.passes, self.passes.map(i64::from));
        set(&mut r.shadow_rays, self.shadow_rays.map(i64::from));
        set(&mut r.reflection_rays, self.reflection_rays.map(i64::from));
        set(&mut r.refraction_rays, self.refraction_rays.map(i64::from));
        if let Some(d) = self.distribution {
            r.distribution = d;
            r.pixel_distribution = None;
            r.lens_distribution = None;
            r.time_distribution = None;
            r.shadow_distribution = None;
            r.reflection_distribution = None;
            r.refraction_distribution = None;
        }
        let shadow_d = self.shadow_distribution.or(self.distribution);
        let reflection_d = self.reflection_distribution.or(self.distribution);
        let refraction_d = self.refraction_distribution.or(self.distribution);
        set_some(&mut r.pixel_distribution, self.pixel_distribution);
        if let Some(f) = self.filter {
            r.filter = f;
        }
        set_some(&mut r.lens_distribution, self.lens_distribution);
        set_some(&mut r.time_distribution, self.time_distribution);
        set_some(&mut r.shadow_distribution, shadow_d);
        set_some(&mut r.reflection_distribution, reflection_d);
        set_some(&mut r.refraction_distribution, refraction_d);
        for l in &mut desc.lights {
            clear_if(&mut l.shadow_rays, self.shadow_rays.is_some());
            clear_if(&mut l.shadow_distribution, shadow_d.is_some());
        }
        for m in desc.materials.values_mut() {
            clear_if(&mut m.reflection_rays, self.reflection_rays.is_some());
            clear_if(&mut m.refraction_rays, self.refraction_rays.is_some());
            clear_if(&mut m.reflection_distribution, reflection_d.is_some());
            clear_if(&mut m.refraction_distribution, refraction_d.is_some());
        }
        match &self.points {
            // Taken from the working directory, not the scene's.
            Some(Points::File(path)) => {
                let path = std::path::absolute(path).unwrap_or_else(|_| path.clone());
                (r.points, r.points_table) = (Some(path), None);
            }
            Some(Points::Table(t)) => (r.points, r.points_table) = (None, Some(t.clone())),
            None => {}
        }
        set(&mut r.metric, self.metric);
        set(&mut r.reflection_metric, self.reflection_metric);
        set(&mut r.shadow_metric, self.shadow_metric);
        set(&mut r.metric_threshold, self.metric_threshold);
        set(&mut r.metric_min_rays, self.metric_min_rays.map(i64::from));
        set(
            &mut r.shadow_metric_rays,
            self.shadow_metric_rays.map(i64::from),
        );
        set(&mut r.pixel_metric, self.pixel_metric);
        set(&mut r.noise_threshold, self.noise_threshold);
        set(&mut r.stop_rule, self.stop_rule);
        set(&mut r.confidence, self.confidence);
        set(&mut r.replicas, self.replicas.map(i64::from));
        set(&mut r.noise_floor, self.noise_floor);
        set(&mut r.min_spp, self.min_spp.map(i64::from));
        set(&mut desc.camera.aperture, self.aperture);
        set_some(&mut desc.camera.focal_distance, self.focal_distance);
    }
}

fn set<T>(slot: &mut T, v: Option<T>) {
    if let Some(v) = v {
        *slot = v;
    }
}

fn set_some<T>(slot: &mut Option<T>, v: Option<T>) {
    if v.is_some() {
        *slot = v;
    }
}

fn clear_if<T>(slot: &mut Option<T>, cond: bool) {
    if cond {
        *slot = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::desc::{LightDesc, MaterialDesc};

    #[test]
    fn overrides_replace_per_light_and_per_material_values() {
        let mut d = SceneDesc::default();
        d.lights.push(LightDesc {
            shadow_rays: Some(3),
            shadow_distribution: Some(Distribution::Grid),
            ..Default::default()
        });
        d.materials.insert(
            "m".into(),
            MaterialDesc {
                reflection_rays: Some(5),
                ..Default::default()
            },
        );
        let o = Overrides {
            shadow_rays: Some(16),
            distribution: Some(Distribution::Poisson),
            ..Default::default()
        };
        o.apply(&mut d);
        assert_eq!(d.render.shadow_rays, 16);
        assert_eq!(d.lights[0].shadow_rays, None);
        assert_eq!(d.lights[0].shadow_distribution, None);
        assert_eq!(d.render.shadow_distribution, Some(Distribution::Poisson));
        assert_eq!(d.materials["m"].reflection_rays, Some(5), "not overridden");
        assert_eq!(d.render.distribution, Distribution::Poisson);
    }
}
