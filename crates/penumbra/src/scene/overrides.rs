//! Values given outside the scene file (command line, Python keyword
//! arguments) that win over the file's.

use super::load::SceneSource;
use super::points::Points;
use super::settings::{IntegratorChoice, StopRule};
use crate::description::{KeyPath, Kind, Located, Node, Origin, Value, RENDER_KEYS};
use crate::emitter::choice::LightChoice;
use crate::sampling::filter::FILTER_KEYS;
use crate::sampling::{Distribution, Filter, PathSampler};

/// Settings that replace the scene description's. Ray counts and
/// distributions given here also replace per-light and per-material values:
/// a user asking for 16 shadow rays expects every light to use 16.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    pub integrator: Option<IntegratorChoice>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub max_depth: Option<u32>,
    /// The path tracer's Russian roulette depth and hidden emitters.
    pub rr_depth: Option<u32>,
    pub hide_emitters: Option<bool>,
    /// The direct integrator's samples per shading point.
    pub emitter_samples: Option<u32>,
    pub bsdf_samples: Option<u32>,
    /// The distributed integrator's depth of sets.
    pub sets_depth: Option<u32>,
    /// The path tracers' source of per-bounce numbers.
    pub path_sampler: Option<PathSampler>,
    /// How the path tracers' next-event estimation chooses its emitter.
    pub light_sampler: Option<LightChoice>,
    pub seed: Option<u32>,
    pub spp: Option<u32>,
    pub passes: Option<u32>,
    pub shadow_rays: Option<u32>,
    pub reflection_rays: Option<u32>,
    pub refraction_rays: Option<u32>,
    /// Distribution for every effect (replaces every more specific one in the file).
    pub distribution: Option<Distribution>,
    pub pixel_distribution: Option<Distribution>,
    /// The pixel filter; the scene's parameters of another filter are
    /// dropped.
    pub filter: Option<Filter>,
    /// The filter's parameters (each taken by one filter).
    pub filter_radius: Option<f32>,
    pub filter_stddev: Option<f32>,
    pub filter_b: Option<f32>,
    pub filter_c: Option<f32>,
    pub filter_lobes: Option<u32>,
    /// Whether samples are splatted by the filter.
    pub splat: Option<bool>,
    /// The steps the splatting filter is tabulated at.
    pub filter_steps: Option<u32>,
    /// Whether the pixels within the filter's reach beyond the film are
    /// sampled.
    pub sample_border: Option<bool>,
    /// Whether the image carries an alpha channel.
    pub alpha: Option<bool>,
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
    /// Sets the values given on the scene's tree: each on the node its
    /// scene-file key goes to (the film, the sampler, the integrator, the
    /// sensor), its origin the key's path without a place in the file (the
    /// value came from elsewhere). A ray count or distribution given here
    /// also removes the materials' and emitters' own.
    pub fn apply(&self, src: &mut SceneSource) {
        let root = &mut src.root;
        if let (Some(i), Some(n)) = (self.integrator, root.child_mut(Kind::Integrator)) {
            // Another integrator's parameters mean nothing to this one: the
            // node is replaced whole (a Mitsuba scene's `path`, say).
            if n.plugin != i.name() {
                let dropped: Vec<String> =
                    n.props.iter().map(|p| format!("`{}`", p.name)).collect();
                src.warnings.push(format!(
                    "--integrator {} replaces the scene's integrator `{}`{}",
                    i.name(),
                    crate::input::quote::clip(&n.plugin, crate::input::quote::MAX_QUOTED_CHARS),
                    if dropped.is_empty() {
                        String::new()
                    } else {
                        format!(" and its parameters {}", dropped.join(", "))
                    }
                ));
                *n = Node::new(Kind::Integrator, i.name(), n.origin.clone());
            }
            n.plugin = i.name().to_string();
            n.plugin_origin = Origin::unlocated(KeyPath::root().key("render").key("integrator"));
        }
        let int = |v: Option<u32>| v.map(|n| Value::Int(i64::from(n)));
        let num = |v: Option<f32>| v.map(|x| Value::Float(f64::from(x)));
        let flag = |v: Option<bool>| v.map(Value::Bool);
        let name = |v: Option<&'static str>| v.map(|s| Value::String(s.to_string()));
        let dist = |d: Option<Distribution>| name(d.map(Distribution::name));
        set(root, "width", int(self.width));
        set(root, "height", int(self.height));
        set(root, "max_depth", int(self.max_depth));
        set(root, "rr_depth", int(self.rr_depth));
        set(root, "hide_emitters", flag(self.hide_emitters));
        set(root, "emitter_samples", int(self.emitter_samples));
        set(root, "bsdf_samples", int(self.bsdf_samples));
        set(root, "sets_depth", int(self.sets_depth));
        set(
            root,
            "path_sampler",
            name(self.path_sampler.map(PathSampler::name)),
        );
        set(
            root,
            "light_sampler",
            name(self.light_sampler.map(LightChoice::name)),
        );
        set(root, "seed", int(self.seed));
        set(root, "spp", int(self.spp));
        set(root, "passes", int(self.passes));
        set(root, "shadow_rays", int(self.shadow_rays));
        set(root, "reflection_rays", int(self.reflection_rays));
        set(root, "refraction_rays", int(self.refraction_rays));
        if let Some(d) = self.distribution {
            set(root, "distribution", dist(Some(d)));
            for key in [
                "pixel_distribution",
                "lens_distribution",
                "time_distribution",
                "shadow_distribution",
                "reflection_distribution",
                "refraction_distribution",
            ] {
                if let Some(n) = node(root, key) {
                    n.remove_prop(key);
                }
            }
        }
        let shadow_d = self.shadow_distribution.or(self.distribution);
        let reflection_d = self.reflection_distribution.or(self.distribution);
        let refraction_d = self.refraction_distribution.or(self.distribution);
        set(root, "pixel_distribution", dist(self.pixel_distribution));
        set(root, "filter", name(self.filter.map(Filter::name)));
        if let (Some(f), Some(film)) = (self.filter, node(root, "filter")) {
            for (param, key) in FILTER_KEYS {
                if !f.params().contains(&param) {
                    film.remove_prop(key);
                }
            }
        }
        set(root, "filter_radius", num(self.filter_radius));
        set(root, "filter_stddev", num(self.filter_stddev));
        set(root, "filter_b", num(self.filter_b));
        set(root, "filter_c", num(self.filter_c));
        set(root, "filter_lobes", int(self.filter_lobes));
        set(root, "splat", flag(self.splat));
        set(root, "filter_steps", int(self.filter_steps));
        set(root, "sample_border", flag(self.sample_border));
        set(root, "alpha", flag(self.alpha));
        set(root, "lens_distribution", dist(self.lens_distribution));
        set(root, "time_distribution", dist(self.time_distribution));
        set(root, "shadow_distribution", dist(shadow_d));
        set(root, "reflection_distribution", dist(reflection_d));
        set(root, "refraction_distribution", dist(refraction_d));
        let clear = |n: &mut Node, key: &str, cond: bool| {
            if cond {
                n.remove_prop(key);
            }
        };
        // The lights' own, and those of the emitters shapes carry (in
        // groups too).
        let emitters = |n: &mut Node| {
            clear(n, "shadow_rays", self.shadow_rays.is_some());
            clear(n, "shadow_distribution", shadow_d.is_some());
        };
        for n in root.children.iter_mut() {
            match n.kind {
                Kind::Emitter => emitters(n),
                // A shape's children: its emitter, or a group's shapes and
                // theirs.
                Kind::Shape => {
                    for c in n.children.iter_mut() {
                        match c.kind {
                            Kind::Emitter => emitters(c),
                            _ => c
                                .children
                                .iter_mut()
                                .filter(|e| e.kind == Kind::Emitter)
                                .for_each(emitters),
                        }
                    }
                }
                Kind::Bsdf => {
                    clear(n, "reflection_rays", self.reflection_rays.is_some());
                    clear(n, "refraction_rays", self.refraction_rays.is_some());
                    clear(n, "reflection_distribution", reflection_d.is_some());
                    clear(n, "refraction_distribution", refraction_d.is_some());
                }
                _ => {}
            }
        }
        match &self.points {
            // Taken from the working directory, not the scene's.
            Some(Points::File(path)) => {
                let path = std::path::absolute(path).unwrap_or_else(|_| path.clone());
                let text = path.to_string_lossy().into_owned();
                set(root, "points", Some(Value::String(text)));
                src.ctx.points = None;
            }
            Some(Points::Table(t)) => src.ctx.points = Some(t.clone()),
            None => {}
        }
        let root = &mut src.root;
        set(root, "metric", flag(self.metric));
        set(root, "reflection_metric", flag(self.reflection_metric));
        set(root, "shadow_metric", flag(self.shadow_metric));
        set(root, "metric_threshold", num(self.metric_threshold));
        set(root, "metric_min_rays", int(self.metric_min_rays));
        set(root, "shadow_metric_rays", int(self.shadow_metric_rays));
        set(root, "pixel_metric", flag(self.pixel_metric));
        set(root, "noise_threshold", num(self.noise_threshold));
        set(root, "stop_rule", name(self.stop_rule.map(StopRule::name)));
        set(root, "confidence", num(self.confidence));
        set(root, "replicas", int(self.replicas));
        set(root, "noise_floor", num(self.noise_floor));
        set(root, "min_spp", int(self.min_spp));
        set(root, "aperture", num(self.aperture));
        set(root, "focal_distance", num(self.focal_distance));
    }
}

/// The node a scene-file key of `[render]` or `[camera]` belongs to.
fn node<'a>(root: &'a mut Node, key: &str) -> Option<&'a mut Node> {
    let kind = RENDER_KEYS
        .iter()
        .find(|(k, _)| *k == key)
        .map_or(Kind::Sensor, |(_, kind)| *kind);
    match kind {
        Kind::Film | Kind::Sampler => root.child_mut(Kind::Sensor)?.child_mut(kind),
        // An integrator that holds another (`aov`, `moment`): the held
        // one's parameters (`max_depth`, `passes`, ...).
        Kind::Integrator => {
            let n = root.child_mut(kind)?;
            if n.child(kind).is_some() {
                n.child_mut(kind)
            } else {
                Some(n)
            }
        }
        kind => root.child_mut(kind),
    }
}

/// Sets `key` to `value` (if given) on its node.
fn set(root: &mut Node, key: &str, value: Option<Value>) {
    let Some(value) = value else { return };
    let table = if RENDER_KEYS.iter().any(|(k, _)| *k == key) {
        "render"
    } else {
        "camera"
    };
    let origin = Origin::unlocated(KeyPath::root().key(table).key(key));
    if let Some(n) = node(root, key) {
        n.set_prop(key, Located::new(value, origin));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::LoadOptions;

    #[test]
    fn overrides_replace_per_light_and_per_material_values() {
        let text = "[render]\nshadow_rays = 3\n[materials.m]\nreflection_rays = 5\n\
                    [[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [1, 1, 1]\n\
                    [[lights]]\ntype = \"rect\"\norigin = [0, 2, 0]\nedge_u = [1, 0, 0]\n\
                    edge_v = [0, 0, 1]\nradiance = [1, 1, 1]\nshadow_rays = 4\nshadow_distribution = \"grid\"\n";
        let here = std::path::Path::new(".");
        let mut src = SceneSource::from_toml(text, here, here, &LoadOptions::default()).unwrap();
        let o = Overrides {
            shadow_rays: Some(16),
            distribution: Some(Distribution::Poisson),
            ..Default::default()
        };
        o.apply(&mut src);
        let root = &src.root;
        let sampler = root
            .child(Kind::Sensor)
            .unwrap()
            .child(Kind::Sampler)
            .unwrap();
        assert_eq!(
            sampler.prop("shadow_rays").unwrap().value.value,
            Value::Int(16)
        );
        let poisson = Value::String("poisson".into());
        assert_eq!(
            sampler.prop("shadow_distribution").unwrap().value.value,
            poisson
        );
        assert_eq!(sampler.prop("distribution").unwrap().value.value, poisson);
        let rect = root
            .child(Kind::Shape)
            .unwrap()
            .child(Kind::Emitter)
            .unwrap();
        assert!(rect.prop("shadow_rays").is_none() && rect.prop("shadow_distribution").is_none());
        let m = root.child(Kind::Bsdf).unwrap();
        assert_eq!(
            m.prop("reflection_rays").unwrap().value.value,
            Value::Int(5),
            "not overridden"
        );
        let scene = src.build().unwrap();
        assert_eq!(scene.budgets.shadow[1].map(|s| s.rays), Some(16));
    }
}
