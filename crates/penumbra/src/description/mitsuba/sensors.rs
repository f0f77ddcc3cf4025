//! The parts of the mapping of Mitsuba's sensors, films, reconstruction
//! filters and samplers that their schemas cannot say, each named by the
//! plugin it completes (as its [`Adapt`](super::registry::Adapt)): a
//! sensor's `to_world` and field of view as the camera's, the film and
//! sampler it holds (Mitsuba's `hdrfilm` and `independent` where it holds
//! none), a film's size and filter, a sampler's distributions.

use std::rc::Rc;

use super::mapper::{
    float, get_bool, get_float, get_int, get_string, get_transform, located, obj_has, render, set,
    vec3,
};
use super::objects::{error_at, Object, Place};
use super::parse::clip;
use super::registry::Mapper;
use super::transform;
use crate::description::error::{KeyPath, SceneError};
use crate::description::tree::{Kind, Located, Node, Prop, Value};
use crate::sampling::filter::{Filter, FilterParams, PixelFilter, FILTER_KEYS};

/// Mitsuba's film size when the film gives none.
pub const DEFAULT_WIDTH: i64 = 768;
pub const DEFAULT_HEIGHT: i64 = 576;
/// Mitsuba's samples per pixel when the sampler gives none.
pub const DEFAULT_SAMPLE_COUNT: i64 = 4;

/// An object of Mitsuba's plugin `plugin` written nowhere but at `at`:
/// what Mitsuba makes of a film or sampler a sensor does not hold.
fn implied(tag: &str, plugin: &str, at: &Place) -> Object {
    Object {
        tag: tag.into(),
        plugin: plugin.into(),
        id: None,
        props: Vec::new(),
        children: Vec::new(),
        at: at.clone(),
        plugin_at: at.clone(),
    }
}

/// Mitsuba's `perspective`: the camera its `to_world` places, with its
/// field of view, principal point, clip planes, film and sampler.
pub fn perspective(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    sensor(m, obj, node, base, Model::Pinhole)
}

/// Mitsuba's `thinlens`: a `perspective` whose `aperture_radius`
/// (required) and `focus_distance` (the far clip plane where not given)
/// are the camera's `aperture` and `focal_distance`, without a principal
/// point offset.
pub fn thinlens(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    sensor(m, obj, node, base, Model::ThinLens)
}

/// Mitsuba's `orthographic`: the unit view (2 wide, 2 over the film's
/// aspect tall, centred on the axis) scaled by its `to_world`, with its
/// clip planes, film and sampler.
pub fn orthographic(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    sensor(m, obj, node, base, Model::Orthographic)
}

/// Which of Mitsuba's projective cameras a sensor is.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Model {
    Pinhole,
    ThinLens,
    Orthographic,
}

/// Mitsuba's clip planes when a sensor gives none.
pub const DEFAULT_NEAR_CLIP: f64 = 1e-2;
pub const DEFAULT_FAR_CLIP: f64 = 1e4;

/// A sensor: its film and sampler as the node's children; `to_world`'s
/// images of the origin, of one unit along +z and of +y as `position`,
/// `look_at` and `up` (one that mirrors the image refused; one that scales
/// refused as Mitsuba refuses it, but by an orthographic camera, whose
/// view it sizes); the field of view as the vertical `fov` for the film's
/// aspect; the clip planes (Mitsuba's 0.01 and 10⁴ where not given); for
/// a thin lens, the lens (without it, `focus_distance` is read and
/// unused, as by Mitsuba's pinhole and orthographic cameras).
fn sensor(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
    model: Model,
) -> Result<(), SceneError> {
    let (mut film, mut sampler, mut medium) = (None, None, None);
    for c in m.held(obj)? {
        match c.tag.as_str() {
            "medium" if medium.is_none() => medium = Some(m.medium(&c)?),
            "medium" => {
                return Err(error_at(&c.at, "a second <medium> in the sensor: the camera sits in one"))
            }
            "film" if film.is_none() => film = Some(c),
            "sampler" if sampler.is_none() => sampler = Some(c),
            "film" | "sampler" => {
                return Err(error_at(
                    &c.at,
                    format!("a second <{}> in the sensor", c.tag),
                ))
            }
            _ => {
                return Err(error_at(
                    &c.at,
                    format!(
                    "a <{}> inside a sensor is not supported (a sensor holds a film, a sampler and a medium)",
                    c.tag
                ),
                ))
            }
        }
    }
    let film = film.unwrap_or_else(|| Rc::new(implied("film", "hdrfilm", &obj.at)));
    let sampler = sampler.unwrap_or_else(|| Rc::new(implied("sampler", "independent", &obj.at)));
    let film = m.node(Kind::Film, &film, render())?;
    let sampler = m.node(Kind::Sampler, &sampler, render())?;
    let side = |name| match film.prop(name).map(|p| &p.value.value) {
        Some(Value::Int(v)) => *v,
        _ => 1,
    };
    let aspect = side("width") as f64 / side("height") as f64;
    node.children = vec![film, sampler];
    if let Some(name) = medium {
        let path = base.key("medium");
        node.props.push(Prop::new(
            "medium",
            obj.at.origin(path.clone()),
            Located::new(Value::String(name), obj.at.origin(path)),
        ));
    }

    let (m4, m_at) = match get_transform(obj, "to_world")? {
        Some((m4, at)) => (m4, at.clone()),
        None => (transform::IDENTITY, obj.at.clone()),
    };
    if transform::det3(&m4) < 0.0 {
        return Err(error_at(
            &m_at,
            "the sensor's `to_world` mirrors the image, which Penumbra's camera cannot",
        ));
    }
    let axes = [0, 1, 2].map(|i| {
        let mut e = [0.0; 3];
        e[i] = 1.0;
        transform::vector(&m4, e)
    });
    if model != Model::Orthographic && has_scale(&m4) {
        return Err(error_at(
            &m_at,
            "the sensor's `to_world` scales, which Mitsuba allows only an orthographic camera",
        ));
    }
    let skewed = (0..3).any(|i| {
        (i + 1..3).any(|j| {
            let (a, b) = (axes[i], axes[j]);
            transform::dot(a, b).abs() > 1e-3 * transform::length(a) * transform::length(b)
        })
    });
    if skewed {
        return Err(error_at(
            &m_at,
            "the sensor's `to_world` shears the view, which Penumbra's camera cannot",
        ));
    }
    let position = transform::point(&m4, [0.0; 3]);
    let dir = transform::normalize(axes[2]);
    let up = transform::normalize(axes[1]);
    let look_at = [0, 1, 2].map(|i| position[i] + dir[i]);
    set(node, base, "position", &m_at, |p, at| vec3(position, p, at));
    set(node, base, "look_at", &m_at, |p, at| vec3(look_at, p, at));
    set(node, base, "up", &m_at, |p, at| vec3(up, p, at));
    let (near, far, clip_at) = clip_planes(obj)?;
    if model == Model::Orthographic {
        let projection = Value::String("orthographic".into());
        set(node, base, "projection", &obj.plugin_at, |p, at| {
            located(projection, p, at)
        });
        // The unit view is [-1, 1] wide and [-1/aspect, 1/aspect] tall
        // before `to_world` scales it.
        let width = 2.0 * transform::length(axes[0]);
        let height = 2.0 * transform::length(axes[1]) / aspect;
        set(node, base, "view_width", &m_at, |p, at| float(width, p, at));
        set(node, base, "view_height", &m_at, |p, at| {
            float(height, p, at)
        });
        // Mitsuba's rays start on the near plane of the view's space,
        // which `to_world` scales along the axis, and run `far - near`.
        let (near, far) = {
            let axial = near * transform::length(axes[2]);
            (axial, axial + (far - near))
        };
        set(node, base, "near_clip", &clip_at, |p, at| {
            float(near, p, at)
        });
        set(node, base, "far_clip", &clip_at, |p, at| float(far, p, at));
        get_float(obj, "focus_distance")?;
        return Ok(());
    }
    set(node, base, "near_clip", &clip_at, |p, at| {
        float(near, p, at)
    });
    set(node, base, "far_clip", &clip_at, |p, at| float(far, p, at));
    let (fov, fov_at) = vertical_fov(obj, aspect)?;
    set(node, base, "fov", &fov_at, |p, at| float(fov, p, at));
    if model == Model::Pinhole {
        // Read as Mitsuba's perspective reads it: a pinhole focuses
        // everywhere, and the value has no effect.
        get_float(obj, "focus_distance")?;
        let x = get_float(obj, "principal_point_offset_x")?;
        let y = get_float(obj, "principal_point_offset_y")?;
        if let Some((_, at)) = x.or(y) {
            let offset = [x.map_or(0.0, |v| v.0), y.map_or(0.0, |v| v.0)];
            set(node, base, "principal_point_offset", at, |p, at| {
                let items = (0..2).map(|i| float(offset[i], p.index(i), at)).collect();
                located(Value::Array(items), p, at)
            });
        }
    } else {
        let Some((radius, r_at)) = get_float(obj, "aperture_radius")? else {
            return Err(error_at(&obj.at, "thinlens: missing `aperture_radius`"));
        };
        set(node, base, "aperture", r_at, |p, at| float(radius, p, at));
        // Mitsuba focuses on the far clip plane where not told.
        let (focus, f_at) = get_float(obj, "focus_distance")?.unwrap_or((far, &clip_at));
        set(node, base, "focal_distance", f_at, |p, at| {
            float(focus, p, at)
        });
    }
    Ok(())
}

/// True if `m`'s linear part is not a rotation, by Mitsuba's test: some
/// product of two of its rows differs from the identity's by more than
/// 10⁻³.
fn has_scale(m: &transform::Mat4) -> bool {
    (0..3).any(|i| {
        (i..3).any(|j| {
            let dot: f64 = (0..3).map(|k| m[i][k] * m[j][k]).sum();
            (dot - if i == j { 1.0 } else { 0.0 }).abs() > 1e-3
        })
    })
}

/// A sensor's `near_clip` and `far_clip`, Mitsuba's 0.01 and 10⁴ where
/// not given, refused as Mitsuba refuses them (`near_clip` not positive,
/// or not less than `far_clip`), with the place to name them at.
fn clip_planes(obj: &Object) -> Result<(f64, f64, Place), SceneError> {
    let near = get_float(obj, "near_clip")?;
    let far = get_float(obj, "far_clip")?;
    let near_at = near.map_or(&obj.at, |n| n.1);
    let (near_v, far_v) = (
        near.map_or(DEFAULT_NEAR_CLIP, |n| n.0),
        far.map_or(DEFAULT_FAR_CLIP, |f| f.0),
    );
    if !(near_v > 0.0 && near_v.is_finite()) {
        return Err(error_at(
            near_at,
            format!("the sensor's `near_clip` must be greater than 0, got {near_v}"),
        ));
    }
    if near_v >= far_v || far_v.is_nan() {
        let at = far.map_or(near_at, |f| f.1);
        return Err(error_at(
            at,
            format!("the sensor's `near_clip` ({near_v}) must be less than `far_clip` ({far_v})"),
        ));
    }
    let at = near.or(far).map_or(&obj.at, |v| v.1).clone();
    Ok((near_v, far_v, at))
}

/// Mitsuba's field of view (`fov` along `fov_axis`, or `focal_length`)
/// as Penumbra's vertical one, for a film of aspect `aspect`.
fn vertical_fov(obj: &Object, aspect: f64) -> Result<(f64, Place), SceneError> {
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

/// The steps Mitsuba's CPU variants tabulate a reconstruction filter at
/// (`MI_FILTER_RESOLUTION`).
const FILTER_STEPS: i64 = 31;

/// Mitsuba's `hdrfilm`: `width` and `height` at least 1, Mitsuba's
/// 768 × 576 where not given; its `<rfilter>` (Mitsuba's `gaussian`
/// without one) as `filter` and the `filter_*` keys of the parameters it
/// gives, each sample splatted by it (`splat`), as Mitsuba develops its
/// film; `pixel_format` with alpha as `alpha`. The output file's format
/// is its extension's, so the file and component formats the film names
/// are ignored, with a warning, and so are its luminance and XYZ pixel
/// formats (written as RGB).
pub fn hdrfilm(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    for (name, default) in [("width", DEFAULT_WIDTH), ("height", DEFAULT_HEIGHT)] {
        match get_int(obj, name)? {
            Some((v, v_at)) if v < 1 => {
                return Err(error_at(
                    v_at,
                    format!("the film's `{name}` must be at least 1, got {v}"),
                ))
            }
            Some(_) => {}
            None => set(node, base, name, &obj.at, |p, at| {
                located(Value::Int(default), p, at)
            }),
        }
    }
    if let Some((format, at)) = get_string(obj, "pixel_format")? {
        let format = format.to_ascii_lowercase();
        let alpha = match format.as_str() {
            "rgb" => false,
            "rgba" => true,
            "luminance" | "xyz" => false,
            "luminance_alpha" | "xyza" => true,
            other => {
                return Err(error_at(
                    at,
                    format!(
                        "`pixel_format` `{}` is not one of rgb, rgba, luminance, \
                         luminance_alpha, xyz, xyza",
                        clip(other)
                    ),
                ))
            }
        };
        if !matches!(format.as_str(), "rgb" | "rgba") {
            m.warn(format!(
                "the film's `pixel_format` `{format}` is written as RGB{}: Penumbra writes \
                 linear RGB only",
                if alpha { " with alpha" } else { "" }
            ));
        }
        if alpha {
            set(node, base, "alpha", at, |p, at| {
                located(Value::Bool(true), p, at)
            });
        }
    }
    for name in ["file_format", "component_format"] {
        if obj_has(obj, name) {
            m.warn(format!(
                "the film's `{name}` is ignored: the output file's extension chooses the format"
            ));
        }
    }
    set(node, base, "splat", &obj.at, |p, at| {
        located(Value::Bool(true), p, at)
    });
    set(node, base, "filter_steps", &obj.at, |p, at| {
        located(Value::Int(FILTER_STEPS), p, at)
    });
    let mut filter = None;
    for c in m.held(obj)? {
        if c.tag != "rfilter" {
            return Err(error_at(
                &c.at,
                format!("a <{}> inside a film is not supported", c.tag),
            ));
        }
        let n = m.node(Kind::Filter, &c, base.clone())?;
        checked(&c, &n)?;
        filter = Some((c, n));
    }
    let Some((rfilter, filter)) = filter else {
        set(node, base, "filter", &obj.at, |p, at| {
            located(Value::String(Filter::Gaussian.name().into()), p, at)
        });
        return Ok(());
    };
    set(node, base, "filter", &rfilter.at, |p, at| {
        located(Value::String(filter.plugin.clone()), p, at)
    });
    for p in filter.props {
        let key = FILTER_KEYS
            .iter()
            .find(|(param, _)| *param == p.name)
            .map_or("filter", |(_, k)| *k);
        let at = rfilter.prop(&p.name).map_or(&rfilter.at, |q| &q.at);
        set(node, base, key, at, |path, at| {
            located(p.value.value, path, at)
        });
    }
    Ok(())
}

/// Refuses a filter's parameter the film's filter would refuse, at the
/// `<rfilter>`'s parameter (`rfilter`, mapped as `filter`).
fn checked(rfilter: &Object, filter: &Node) -> Result<(), SceneError> {
    let kind = Filter::from_name(&filter.plugin).unwrap_or_default();
    let mut params = FilterParams::default();
    for p in &filter.props {
        match (p.name.as_str(), &p.value.value) {
            ("lobes", Value::Int(v)) => params.lobes = Some(*v),
            (name, Value::Float(v)) => {
                let slot = match name {
                    "radius" => &mut params.radius,
                    "stddev" => &mut params.stddev,
                    "B" => &mut params.b,
                    _ => &mut params.c,
                };
                *slot = Some(*v as f32);
            }
            _ => {}
        }
    }
    match PixelFilter::new(kind, &params) {
        Ok(_) => Ok(()),
        Err(e) => {
            let at = rfilter.prop(e.param).map_or(&rfilter.at, |p| &p.at);
            Err(error_at(
                at,
                format!("the {} rfilter's `{}` {}", kind.name(), e.param, e.message),
            ))
        }
    }
}

/// Mitsuba's `box` reconstruction filter: its `radius` is 0.5 and
/// nothing else.
pub fn box_filter(obj: &Object, _: &mut Node, _: &KeyPath) -> Result<(), SceneError> {
    match get_float(obj, "radius")? {
        Some((v, at)) if v != 0.5 => Err(error_at(
            at,
            "the box filter's `radius` is 0.5; other values are not supported",
        )),
        _ => Ok(()),
    }
}

/// Mitsuba's `independent`: the camera sample `random`, its film
/// positions `fast-random`; the bounces' numbers independent.
pub fn independent(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    sampler(m, obj, node, base, ("random", None))
}

/// Mitsuba's `stratified`: the camera sample `jitter` (`grid` without
/// `jitter`), the bounces `pmj02`.
pub fn stratified(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    m.no_children(obj)?;
    let jitter = get_bool(obj, "jitter")?.is_none_or(|(j, _)| j);
    let camera = if jitter { "jitter" } else { "grid" };
    sampler(m, obj, node, base, (camera, Some("pmj02")))
}

/// Mitsuba's `multijitter`: the camera sample `jitter`, the bounces
/// `pmj02`.
pub fn multijitter(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    m.no_children(obj)?;
    get_bool(obj, "jitter")?;
    sampler(m, obj, node, base, ("jitter", Some("pmj02")))
}

/// Mitsuba's `ldsampler`: the camera sample and the bounces `sobol`.
pub fn ldsampler(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    sampler(m, obj, node, base, ("sobol", Some("sobol")))
}

/// Mitsuba's `orthogonal`: the camera sample and the bounces `pmj02`
/// (its `jitter` and `strength` read, the nearest being the same for
/// every value).
pub fn orthogonal(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
) -> Result<(), SceneError> {
    get_bool(obj, "jitter")?;
    get_int(obj, "strength")?;
    sampler(m, obj, node, base, ("pmj02", Some("pmj02")))
}

/// A sampler whose camera sample is drawn by the distribution
/// `distribution` and whose bounces' numbers by the path sampler
/// `path_sampler` (`None`: independent ones), the nearest Penumbra has to
/// Mitsuba's (with a warning where it is not the same): `spp` Mitsuba's 4
/// unless `sample_count` is given.
fn sampler(
    m: &mut dyn Mapper,
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
    (distribution, path_sampler): (&'static str, Option<&'static str>),
) -> Result<(), SceneError> {
    m.no_children(obj)?;
    if let Some(p) = path_sampler {
        m.path_sampler(p, &obj.plugin_at);
    }
    if obj.plugin != "independent" {
        m.warn(format!(
            "the `{}` sampler is rendered with Penumbra's `{distribution}` distribution \
             for the camera sample and the `{}` path sampler for the bounces, its nearest",
            obj.plugin,
            path_sampler.unwrap_or("independent")
        ));
    }
    if node.prop("spp").is_none() {
        set(node, base, "spp", &obj.at, |p, at| {
            located(Value::Int(DEFAULT_SAMPLE_COUNT), p, at)
        });
    }
    set(node, base, "distribution", &obj.at, |p, at| {
        located(Value::String(distribution.into()), p, at)
    });
    if distribution == "random" {
        // Mitsuba's independent film positions are uniform over the
        // pixel's square, and the box filter counts the whole square;
        // `random` fills the disk inscribed in it, which misses the
        // corners and puts an edge crossing a pixel in the wrong
        // proportion. `fast-random` read by its x and y is independent
        // and uniform over the square.
        set(node, base, "pixel_distribution", &obj.at, |p, at| {
            located(Value::String("fast-random".into()), p, at)
        });
    }
    Ok(())
}
