//! Mitsuba's plugins onto Penumbra's: the objects of a scene into the tree
//! a TOML scene lowers to, under the same plugin names, property names and
//! key paths (`objects[2].radius`), every value at its XML tag. The scene's
//! structure (groups, instances, the background, a shape's material and
//! emitter) and the integrator, sensor, film, filter and sampler are mapped
//! here; every other object through its plugin's schema
//! (`mapping.rs`, `materials.rs`).

use std::collections::HashSet;

use super::mapper::{
    children, float, get_bool, get_color, get_float, get_int, get_string, get_transform, located,
    matrix, obj_has, render, set, type_error, unsupported, vec3, Out,
};
use super::mapping::{mitsuba_keys, plugin_of, required};
use super::objects::{error_at, Child, Ids, Object, Place};
use super::parse::{clip, Reader};
use super::registry::{Adapt, Registry};
use super::spectrum::Use;
use super::transform::{self, Mat4};
use super::values::PropValue;
use crate::description::error::{KeyPath, SceneError};
use crate::description::tree::{Kind, Node, Prop, Value};
use crate::sampling::filter::{Filter, FilterParams, PixelFilter, FILTER_KEYS};

/// The plugins read by hand, by tag, in the order messages list them.
pub const SENSORS: &[&str] = &["perspective", "thinlens"];
pub const FILMS: &[&str] = &["hdrfilm"];
pub const RFILTERS: &[&str] = &[
    "box",
    "tent",
    "gaussian",
    "mitchell",
    "catmullrom",
    "lanczos",
];
pub const SAMPLERS: &[&str] = &[
    "independent",
    "stratified",
    "multijitter",
    "ldsampler",
    "orthogonal",
];
pub const INTEGRATORS: &[&str] = &["path", "direct"];

/// Mitsuba's film size when the film gives none.
pub const DEFAULT_WIDTH: i64 = 768;
pub const DEFAULT_HEIGHT: i64 = 576;
/// Mitsuba's samples per pixel when the sampler gives none.
pub const DEFAULT_SAMPLE_COUNT: i64 = 4;

/// Builds the tree of a scene object.
pub fn scene(
    root: &Object,
    ids: &Ids,
    reader: &Reader,
    registry: Registry,
    lenient: bool,
    warnings: &mut Vec<String>,
) -> Result<Node, SceneError> {
    let mut out = Out {
        ids,
        reader,
        registry,
        lenient,
        warnings,
        integrator: None,
        sensor: None,
        path_sampler: None,
        background: None,
        bsdfs: Vec::new(),
        textures: Vec::new(),
        texture_ids: root
            .children
            .iter()
            .filter_map(|(_, c)| match c {
                Child::Object(o) if o.tag == "texture" => o.id.clone(),
                _ => None,
            })
            .collect(),
        names: HashSet::new(),
        shapes: Vec::new(),
        lights: Vec::new(),
        default_material: [None, None],
    };
    out.no_props(root, &[])?;
    for (_, child) in &root.children {
        let obj = match child {
            Child::Object(o) => o.as_ref(),
            Child::Ref { at, .. } => {
                return Err(error_at(
                    at,
                    "a <ref> directly in <scene> is not supported: declare the object there",
                ))
            }
        };
        match obj.tag.as_str() {
            "integrator" => out.integrator(obj)?,
            "sensor" => out.sensor(obj)?,
            "shape" => out.shape(obj)?,
            "bsdf" => {
                out.material(obj)?;
            }
            "emitter" => out.emitter(obj)?,
            "texture" => out.texture(obj)?,
            other => {
                return Err(error_at(
                    &obj.at,
                    format!(
                        "<{other}> is not supported in a scene; Penumbra reads <integrator>, <sensor>, \
                         <shape>, <bsdf>, <emitter> and <texture>"
                    ),
                ))
            }
        }
    }
    let root_at = &root.at;
    let mut node = Node::new(Kind::Scene, "scene", root_at.origin(KeyPath::root()));
    let mut integrator = out
        .integrator
        .take()
        .unwrap_or_else(|| Node::new(Kind::Integrator, "path", root_at.origin(render())));
    if let Some((name, at)) = out.path_sampler.take() {
        set(&mut integrator, &render(), "path_sampler", &at, |p, at| {
            located(Value::String(name.into()), p, at)
        });
    }
    let Some(sensor) = out.sensor.take() else {
        return Err(error_at(
            &root.at,
            "the scene has no <sensor>; Penumbra renders through a perspective or thinlens sensor",
        ));
    };
    node.children.push(integrator);
    node.children.push(sensor);
    node.children.extend(out.background.take());
    out.textures.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut out.textures);
    out.bsdfs.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut out.bsdfs);
    // The groups (`groups.ID`, in name order) before the objects, where a
    // scene file's lowering puts them.
    let (mut groups, mut objects): (Vec<Node>, Vec<Node>) =
        out.shapes.drain(..).partition(|n| n.id.is_some());
    groups.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut groups);
    node.children.append(&mut objects);
    node.children.append(&mut out.lights);
    Ok(node)
}

/// The film's keys of a filter's parameters, their values and where the
/// XML gives them.
type FilterKeys = Vec<(&'static str, Value, Place)>;

impl Out<'_> {
    fn integrator(&mut self, obj: &Object) -> Result<(), SceneError> {
        if self.integrator.is_some() {
            return Err(error_at(&obj.at, "a second <integrator>: a scene has one"));
        }
        let known: &[&str] = match obj.plugin.as_str() {
            "path" => &["max_depth", "rr_depth", "hide_emitters"],
            "direct" => &[
                "emitter_samples",
                "bsdf_samples",
                "shading_samples",
                "hide_emitters",
            ],
            _ => return Err(unsupported(obj, "integrator", INTEGRATORS)),
        };
        self.no_props(obj, known)?;
        self.no_children(obj)?;
        let mut node = Node::new(
            Kind::Integrator,
            obj.plugin.clone(),
            obj.at.origin(render()),
        );
        node.plugin_origin = obj.plugin_at.origin(render().key("integrator"));
        for p in obj
            .props
            .iter()
            .filter(|p| known.contains(&p.name.as_str()))
        {
            let value = match &p.value {
                PropValue::Int(i) => Value::Int(*i),
                PropValue::Bool(b) => Value::Bool(*b),
                PropValue::Float(x) => Value::Float(*x),
                _ => return Err(type_error(p, "an integer or a boolean")),
            };
            set(&mut node, &render(), &p.name, &p.at, |path, at| {
                located(value, path, at)
            });
        }
        self.integrator = Some(node);
        Ok(())
    }

    fn sensor(&mut self, obj: &Object) -> Result<(), SceneError> {
        if self.sensor.is_some() {
            return Err(error_at(&obj.at, "a second <sensor>: Penumbra renders one"));
        }
        let thin = match obj.plugin.as_str() {
            "perspective" => false,
            "thinlens" => true,
            _ => return Err(unsupported(obj, "sensor", SENSORS)),
        };
        let mut known = vec![
            "fov",
            "fov_axis",
            "focal_length",
            "to_world",
            "near_clip",
            "far_clip",
        ];
        if thin {
            known.extend(["aperture_radius", "focus_distance"]);
        }
        self.no_props(obj, &known)?;
        let (mut film, mut sampler) = (None, None);
        for c in children(self.ids, obj)? {
            match c.tag.as_str() {
                "film" if film.is_none() => film = Some(c),
                "sampler" if sampler.is_none() => sampler = Some(c),
                "film" | "sampler" => {
                    return Err(error_at(&c.at, format!("a second <{}> in the sensor", c.tag)))
                }
                _ => {
                    return Err(error_at(
                        &c.at,
                        format!("a <{}> inside a sensor is not supported (a sensor holds a film and a sampler)", c.tag),
                    ))
                }
            }
        }
        let camera = KeyPath::root().key("camera");
        let mut node = Node::new(Kind::Sensor, "perspective", obj.at.origin(camera.clone()));
        node.plugin_origin = obj.plugin_at.origin(camera.clone());
        let (film_node, (width, height)) = self.film(film, obj)?;
        let sampler_node = self.sampler(sampler, obj)?;
        node.children = vec![film_node, sampler_node];

        let (m, m_at) = match get_transform(obj, "to_world")? {
            Some((m, at)) => (m, at.clone()),
            None => (transform::IDENTITY, obj.at.clone()),
        };
        if transform::det3(&m) < 0.0 {
            return Err(error_at(
                &m_at,
                "the sensor's `to_world` mirrors the image, which Penumbra's camera cannot",
            ));
        }
        let position = transform::point(&m, [0.0; 3]);
        let dir = transform::normalize(transform::vector(&m, [0.0, 0.0, 1.0]));
        let up = transform::normalize(transform::vector(&m, [0.0, 1.0, 0.0]));
        let look_at = [0, 1, 2].map(|i| position[i] + dir[i]);
        set(&mut node, &camera, "position", &m_at, |p, at| {
            vec3(position, p, at)
        });
        set(&mut node, &camera, "look_at", &m_at, |p, at| {
            vec3(look_at, p, at)
        });
        set(&mut node, &camera, "up", &m_at, |p, at| vec3(up, p, at));
        let (fov, fov_at) = self.vertical_fov(obj, width as f64 / height as f64)?;
        set(&mut node, &camera, "fov", &fov_at, |p, at| {
            float(fov, p, at)
        });
        if thin {
            let Some((radius, r_at)) = get_float(obj, "aperture_radius")? else {
                return Err(error_at(&obj.at, "thinlens: missing `aperture_radius`"));
            };
            set(&mut node, &camera, "aperture", r_at, |p, at| {
                float(radius, p, at)
            });
            let Some((focus, f_at)) = get_float(obj, "focus_distance")? else {
                return Err(error_at(&obj.at, "thinlens: missing `focus_distance`"));
            };
            set(&mut node, &camera, "focal_distance", f_at, |p, at| {
                float(focus, p, at)
            });
        }
        for clip_name in ["near_clip", "far_clip"] {
            if obj.prop(clip_name).is_some() {
                self.warnings.push(format!(
                    "the sensor's `{clip_name}` is ignored: Penumbra's camera does not clip"
                ));
            }
        }
        self.sensor = Some(node);
        Ok(())
    }

    /// Mitsuba's field of view (`fov` along `fov_axis`, or `focal_length`)
    /// as Penumbra's vertical one, for a film of aspect `aspect`.
    fn vertical_fov(&self, obj: &Object, aspect: f64) -> Result<(f64, Place), SceneError> {
        let half_tan = |deg: f64| (deg.to_radians() / 2.0).tan();
        let from_half_tan = |t: f64| 2.0 * t.atan().to_degrees();
        let (fov, axis, at) = match (get_float(obj, "fov")?, get_string(obj, "focal_length")?) {
            (Some(_), Some((_, at))) => {
                return Err(error_at(at, "give `fov` or `focal_length`, not both"))
            }
            (Some((f, at)), None) => {
                let axis = match get_string(obj, "fov_axis")? {
                    None => "x".to_string(),
                    Some((a, _)) => a.to_ascii_lowercase(),
                };
                (f, axis, at.clone())
            }
            (None, focal) => {
                let (text, at) = focal.unwrap_or(("50mm", &obj.at));
                let mm = text.strip_suffix("mm").unwrap_or(text);
                let value = super::number::number(mm)
                    .ok()
                    .filter(|v| *v > 0.0)
                    .ok_or_else(|| {
                        error_at(
                            at,
                            format!(
                                "`focal_length` `{}` is not a length such as 50mm",
                                clip(text)
                            ),
                        )
                    })?;
                let diagonal = 2.0
                    * ((36.0f64 * 36.0 + 24.0 * 24.0).sqrt() / (2.0 * value))
                        .atan()
                        .to_degrees();
                (diagonal, "diagonal".to_string(), at.clone())
            }
        };
        if !(fov > 0.0 && fov < 180.0) {
            return Err(error_at(
                &at,
                format!("`fov` must be between 0 and 180 degrees, got {fov}"),
            ));
        }
        let axis = match axis.as_str() {
            "smaller" if aspect > 1.0 => "y",
            "smaller" => "x",
            "larger" if aspect > 1.0 => "x",
            "larger" => "y",
            a => a,
        };
        let vertical = match axis {
            "x" => from_half_tan(half_tan(fov) / aspect),
            "y" => fov,
            "diagonal" => from_half_tan(half_tan(fov) / (1.0 + aspect * aspect).sqrt()),
            other => {
                let at = obj.prop("fov_axis").map_or(&at, |p| &p.at);
                return Err(error_at(
                    at,
                    format!(
                        "`fov_axis` `{}` is not one of x, y, diagonal, smaller, larger",
                        clip(other)
                    ),
                ));
            }
        };
        Ok((vertical, at))
    }

    /// The film node and the film's size.
    fn film(
        &mut self,
        film: Option<&Object>,
        sensor: &Object,
    ) -> Result<(Node, (i64, i64)), SceneError> {
        let at = film.map_or(&sensor.at, |f| &f.at).clone();
        let mut node = Node::new(Kind::Film, "hdrfilm", at.origin(render()));
        let mut size = (DEFAULT_WIDTH, DEFAULT_HEIGHT);
        let mut filter = (Filter::Gaussian, Vec::new(), at.clone());
        if let Some(f) = film {
            if f.plugin != "hdrfilm" {
                return Err(unsupported(f, "film", FILMS));
            }
            self.no_props(
                f,
                &[
                    "width",
                    "height",
                    "file_format",
                    "pixel_format",
                    "component_format",
                ],
            )?;
            for (name, slot) in [("width", &mut size.0), ("height", &mut size.1)] {
                if let Some((v, v_at)) = get_int(f, name)? {
                    if v < 1 {
                        return Err(error_at(
                            v_at,
                            format!("the film's `{name}` must be at least 1, got {v}"),
                        ));
                    }
                    *slot = v;
                }
            }
            for name in ["file_format", "pixel_format", "component_format"] {
                if obj_has(f, name) {
                    self.warnings.push(format!(
                        "the film's `{name}` is ignored: the output file's extension chooses the format"
                    ));
                }
            }
            for c in children(self.ids, f)? {
                if c.tag != "rfilter" {
                    return Err(error_at(
                        &c.at,
                        format!("a <{}> inside a film is not supported", c.tag),
                    ));
                }
                let (f, params) = self.rfilter(c)?;
                filter = (f, params, c.at.clone());
            }
        }
        let (w_at, h_at) = match film {
            Some(f) => (
                f.prop("width").map_or(&f.at, |p| &p.at).clone(),
                f.prop("height").map_or(&f.at, |p| &p.at).clone(),
            ),
            None => (at.clone(), at.clone()),
        };
        set(&mut node, &render(), "width", &w_at, |p, at| {
            located(Value::Int(size.0), p, at)
        });
        set(&mut node, &render(), "height", &h_at, |p, at| {
            located(Value::Int(size.1), p, at)
        });
        set(&mut node, &render(), "filter", &filter.2, |p, at| {
            located(Value::String(filter.0.name().into()), p, at)
        });
        for (key, value, at) in filter.1 {
            set(&mut node, &render(), key, &at, |p, at| {
                located(value, p, at)
            });
        }
        Ok((node, size))
    }

    /// The Penumbra filter of a reconstruction filter, and the film's
    /// `filter_*` keys of the parameters it gives (checked here, so that a
    /// bad value is an error at the XML's parameter). The box's `radius`
    /// is 0.5 and nothing else.
    fn rfilter(&mut self, f: &Object) -> Result<(Filter, FilterKeys), SceneError> {
        let Some(filter) = Filter::from_name(&f.plugin) else {
            return Err(unsupported(f, "rfilter", RFILTERS));
        };
        if filter == Filter::Box {
            self.no_props(f, &["radius"])?;
            if let Some((v, at)) = get_float(f, "radius")? {
                if v != 0.5 {
                    return Err(error_at(
                        at,
                        "the box filter's `radius` is 0.5; other values are not supported",
                    ));
                }
            }
            return Ok((filter, Vec::new()));
        }
        self.no_props(f, filter.params())?;
        let mut params = FilterParams::default();
        let mut keys = Vec::new();
        let key = |param: &str| {
            FILTER_KEYS
                .iter()
                .find(|(p, _)| *p == param)
                .map_or("filter", |(_, k)| *k)
        };
        for &param in filter.params() {
            if param == "lobes" {
                if let Some((v, at)) = get_int(f, param)? {
                    params.lobes = Some(v);
                    keys.push((key(param), Value::Int(v), at.clone()));
                }
            } else if let Some((v, at)) = get_float(f, param)? {
                let slot = match param {
                    "radius" => &mut params.radius,
                    "stddev" => &mut params.stddev,
                    "B" => &mut params.b,
                    _ => &mut params.c,
                };
                *slot = Some(v as f32);
                keys.push((key(param), Value::Float(v + 0.0), at.clone()));
            }
        }
        if let Err(e) = PixelFilter::new(filter, &params) {
            let at = f.prop(e.param).map_or(&f.at, |p| &p.at);
            return Err(error_at(
                at,
                format!(
                    "the {} rfilter's `{}` {}",
                    filter.name(),
                    e.param,
                    e.message
                ),
            ));
        }
        Ok((filter, keys))
    }

    fn sampler(&mut self, sampler: Option<&Object>, sensor: &Object) -> Result<Node, SceneError> {
        let at = sampler.map_or(&sensor.at, |s| &s.at).clone();
        let mut node = Node::new(Kind::Sampler, "sets", at.origin(render()));
        let mut count = (DEFAULT_SAMPLE_COUNT, at.clone());
        let mut distribution = "random";
        if let Some(s) = sampler {
            let known: &[&str] = match s.plugin.as_str() {
                "independent" | "ldsampler" | "orthogonal" => &["sample_count", "seed"],
                "stratified" | "multijitter" => &["sample_count", "seed", "jitter"],
                _ => return Err(unsupported(s, "sampler", SAMPLERS)),
            };
            self.no_props(s, known)?;
            self.no_children(s)?;
            let jitter = get_bool(s, "jitter")?.is_none_or(|(j, _)| j);
            distribution = match (s.plugin.as_str(), jitter) {
                ("independent", _) => "random",
                ("stratified", true) => "jitter",
                ("stratified", false) => "grid",
                ("multijitter", _) => "jitter",
                ("ldsampler", _) => "sobol",
                _ => "pmj02",
            };
            // The bounces' numbers: a sampler stratifying every dimension
            // becomes the nearest sequence of the path samplers.
            let path_sampler = match s.plugin.as_str() {
                "independent" => None,
                "ldsampler" => Some("sobol"),
                _ => Some("pmj02"),
            };
            self.path_sampler = path_sampler.map(|p| (p, s.plugin_at.clone()));
            if s.plugin != "independent" {
                self.warnings.push(format!(
                    "the `{}` sampler is rendered with Penumbra's `{distribution}` distribution \
                     for the camera sample and the `{}` path sampler for the bounces, its nearest",
                    s.plugin,
                    path_sampler.unwrap_or("independent")
                ));
            }
            if let Some((n, n_at)) = get_int(s, "sample_count")? {
                count = (n, n_at.clone());
            }
            if let Some((seed, seed_at)) = get_int(s, "seed")? {
                set(&mut node, &render(), "seed", seed_at, |p, at| {
                    located(Value::Int(seed), p, at)
                });
            }
        }
        set(&mut node, &render(), "spp", &count.1, |p, at| {
            located(Value::Int(count.0), p, at)
        });
        set(&mut node, &render(), "distribution", &at, |p, at| {
            located(Value::String(distribution.into()), p, at)
        });
        if distribution == "random" {
            // Mitsuba's independent film positions are uniform over the
            // pixel's square, and the box filter counts the whole square;
            // `random` fills the disk inscribed in it, which misses the
            // corners and puts an edge crossing a pixel in the wrong
            // proportion. `fast-random` read by its x and y is independent
            // and uniform over the square.
            set(&mut node, &render(), "pixel_distribution", &at, |p, at| {
                located(Value::String("fast-random".into()), p, at)
            });
        }
        Ok(node)
    }

    fn emitter(&mut self, obj: &Object) -> Result<(), SceneError> {
        match obj.plugin.as_str() {
            "constant" => {
                self.no_props(obj, &["radiance"])?;
                self.no_children(obj)?;
                if self.background.is_some() {
                    return Err(error_at(
                        &obj.at,
                        "a second `constant` emitter: Penumbra has one background",
                    ));
                }
                let path = render().key("background");
                let (radiance, at) = get_color(obj, "radiance", Use::Emission)?
                    .map_or(([1.0; 3], obj.at.clone()), |(c, at)| (c, at.clone()));
                let mut node = Node::new(Kind::Emitter, "constant", at.origin(path.clone()));
                let key = at.origin(path.clone());
                node.props
                    .push(Prop::new("radiance", key, vec3(radiance, path, &at)));
                self.background = Some(node);
            }
            "area" => {
                return Err(error_at(
                    &obj.at,
                    "an `area` emitter lights a shape: put it inside a <shape>",
                ))
            }
            _ => {
                self.no_children(obj)?;
                let base = KeyPath::root().key("lights").index(self.lights.len());
                let node = self.mapped(Kind::Emitter, obj, base)?;
                self.lights.push(node);
            }
        }
        Ok(())
    }

    fn shape(&mut self, obj: &Object) -> Result<(), SceneError> {
        // Groups are `groups.ID`, not objects.
        let objects = self.shapes.iter().filter(|n| n.id.is_none()).count();
        let base = KeyPath::root().key("objects").index(objects);
        let node = match obj.plugin.as_str() {
            "shapegroup" => self.shapegroup(obj)?,
            "instance" => self.instance(obj, base)?,
            _ => self.shape_node(obj, base)?,
        };
        self.shapes.push(node);
        Ok(())
    }

    /// A `shapegroup` as `[groups.ID]`: its shapes, each as an object of
    /// the group.
    fn shapegroup(&mut self, obj: &Object) -> Result<Node, SceneError> {
        self.no_props(obj, &[])?;
        let Some(id) = obj.id.clone() else {
            return Err(error_at(
                &obj.at,
                "a shapegroup needs an `id`, which its instances refer to",
            ));
        };
        let path = KeyPath::root().key("groups").key(&id);
        let mut node = Node::new(Kind::Shape, "shapegroup", obj.at.origin(path.clone()));
        node.plugin_origin = obj.plugin_at.origin(path.clone());
        node.id = Some(id);
        for c in children(self.ids, obj)? {
            if c.tag != "shape" {
                return Err(error_at(
                    &c.at,
                    format!("a shapegroup holds shapes, not a <{}>", c.tag),
                ));
            }
            let base = path.key("objects").index(node.children.len());
            let child = match c.plugin.as_str() {
                // Refused by the builder: groups do not nest.
                "shapegroup" | "instance" => {
                    let mut n = Node::new(Kind::Shape, c.plugin.clone(), c.at.origin(base.clone()));
                    n.plugin_origin = c.plugin_at.origin(base.key("type"));
                    n
                }
                _ => self.shape_node(c, base)?,
            };
            node.children.push(child);
        }
        Ok(node)
    }

    /// An `instance`: the shapegroup it refers to and its `to_world`.
    fn instance(&mut self, obj: &Object, base: KeyPath) -> Result<Node, SceneError> {
        self.no_props(obj, &["to_world"])?;
        let mut node = Node::new(Kind::Shape, "instance", obj.at.origin(base.clone()));
        node.plugin_origin = obj.plugin_at.origin(base.key("type"));
        let mut group = None;
        for (_, c) in &obj.children {
            let (id, at) = match c {
                Child::Ref { id, at } => (id.clone(), at),
                Child::Object(o) => {
                    return Err(error_at(
                        &o.at,
                        "an instance refers to a shapegroup by <ref id=\"...\"/>: declare the \
                         group with an id in the scene",
                    ))
                }
            };
            let target = self.ids.get(&id, at)?;
            if target.tag != "shape" || target.plugin != "shapegroup" {
                return Err(error_at(
                    at,
                    format!(
                        "an instance refers to a shapegroup; `{}` is a <{}> of type `{}`",
                        clip(&id),
                        target.tag,
                        clip(&target.plugin)
                    ),
                ));
            }
            if group.is_some() {
                return Err(error_at(at, "an instance refers to one shapegroup"));
            }
            group = Some((id, at.clone()));
        }
        let Some((id, at)) = group else {
            return Err(error_at(
                &obj.at,
                "an instance needs a <ref id=\"...\"/> to its shapegroup",
            ));
        };
        set(&mut node, &base, "group", &at, |p, at| {
            located(Value::String(id), p, at)
        });
        let to_world = get_transform(obj, "to_world")?.map(|(m, at)| (m, at.clone()));
        self.placement(&mut node, &base, &to_world);
        Ok(node)
    }

    /// The node of an object of `kind` at `base`, through the schema of
    /// the plugin of that kind that reads its plugin and the plugin's own
    /// adapter.
    fn mapped(&mut self, kind: Kind, obj: &Object, base: KeyPath) -> Result<Node, SceneError> {
        let plugin = plugin_of((self.registry)(kind), obj, kind.name())?;
        let schema = plugin.schema;
        let mut known = mitsuba_keys(schema);
        known.extend(plugin.mitsuba.reads);
        self.no_props(obj, &known)?;
        let mut node = Node::new(kind, schema.plugin, obj.at.origin(base.clone()));
        node.plugin_origin = obj.plugin_at.origin(base.key("type"));
        self.params(obj, schema, &mut node, &base)?;
        if let Some(Adapt::Node(adapt)) = plugin.mitsuba.adapt {
            adapt(obj, &mut node, &base)?;
        }
        required(obj, schema, &node)?;
        Ok(node)
    }

    /// The node of a shape other than a group or an instance, at `base`,
    /// with its material and the area emitter it carries.
    fn shape_node(&mut self, obj: &Object, base: KeyPath) -> Result<Node, SceneError> {
        let mut node = self.mapped(Kind::Shape, obj, base.clone())?;
        let mut material = None;
        let mut emitter = None;
        for c in children(self.ids, obj)? {
            match c.tag.as_str() {
                "bsdf" if material.is_none() => material = Some(self.material(c)?),
                "emitter" if emitter.is_none() => {
                    if c.plugin != "area" {
                        return Err(error_at(&c.plugin_at, format!("a shape carries an `area` emitter, not `{}`", clip(&c.plugin))));
                    }
                    self.no_children(c)?;
                    let mut e = self.mapped(Kind::Emitter, c, base.key("emitter"))?;
                    e.plugin_origin = e.origin.clone();
                    emitter = Some(e);
                }
                "bsdf" | "emitter" => {
                    return Err(error_at(&c.at, format!("a second <{}> in the shape", c.tag)))
                }
                other => {
                    return Err(error_at(&c.at, format!("a <{other}> inside a shape is not supported (a shape holds a bsdf and an area emitter)")))
                }
            }
        }
        let material = match (material, &emitter) {
            (Some(m), _) => m,
            (None, None) => self.default_material(&obj.at, false),
            // An emitter without a bsdf reflects nothing, as in Mitsuba.
            (None, Some(_)) => self.default_material(&obj.at, true),
        };
        set(&mut node, &base, "material", &obj.at, |p, at| {
            located(Value::String(material), p, at)
        });
        node.children.extend(emitter);
        Ok(node)
    }

    /// `to_world` as the shape's `transform = { matrix = ... }`.
    fn placement(&self, node: &mut Node, base: &KeyPath, to_world: &Option<(Mat4, Place)>) {
        let Some((m, at)) = to_world else {
            return;
        };
        let path = base.key("transform");
        let inner = path.key("matrix");
        let table = vec![Prop::new(
            "matrix",
            at.origin(inner.clone()),
            matrix(m, inner, at),
        )];
        set(node, base, "transform", at, |p, at| {
            located(Value::Table(table), p, at)
        });
    }
}
