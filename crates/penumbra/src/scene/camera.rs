//! The sensor: a pinhole camera, a thin lens when `aperture > 0`, or an
//! orthographic camera; its clip planes and its shutter (`[camera]` of a
//! scene file).

use super::settings::Settings;
use crate::camera::{Camera, CameraSpec, Projection};
use crate::description::check::{finite3, nonzero3, positive, range};
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::{sensors, Mitsuba, Plugin};
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::Vec2;

/// The camera's projections, by the name `projection` takes.
const PROJECTIONS: [&str; 2] = ["perspective", "orthographic"];

/// The parameters of the `perspective` sensor.
pub const PERSPECTIVE: Schema = Schema {
    kind: Kind::Sensor,
    plugin: "perspective",
    what: "camera",
    doc: "a pinhole, thin-lens or orthographic camera, with depth of field, clip planes and a \
          moving position",
    mitsuba: &["perspective", "thinlens", "orthographic"],
    params: &[
        Param::new(
            "projection",
            Type::Choice("projection", &PROJECTIONS),
            "\"perspective\"",
            "`perspective` (rays from the eye spread by `fov`) or `orthographic` (parallel rays \
             along the view axis from a `view_width` × `view_height` rectangle centred on the eye)",
        )
        .penumbra_only(),
        Param::new(
            "position",
            Type::Vector,
            "[0, 1, 5]",
            "eye position at shutter open",
        )
        .penumbra_only(),
        Param::new(
            "look_at",
            Type::Vector,
            "[0, 0, 0]",
            "point at the image centre",
        )
        .penumbra_only(),
        Param::new(
            "up",
            Type::Vector,
            "[0, 1, 0]",
            "up direction; must not be parallel to the view",
        )
        .penumbra_only(),
        Param::new("fov", Type::Number, "40", "vertical field of view, degrees")
            .range(Range::Between(0.01, 179.0))
            .penumbra_only(),
        Param::new(
            "view_width",
            Type::Number,
            "2",
            "orthographic: width of the view in scene units",
        )
        .range(Range::Positive)
        .penumbra_only(),
        Param::new(
            "view_height",
            Type::Number,
            "`view_width` over the image's aspect",
            "orthographic: height of the view in scene units",
        )
        .range(Range::Positive)
        .penumbra_only(),
        Param::new(
            "near_clip",
            Type::Number,
            "0",
            "distance from the eye, along the view axis, of the plane before which nothing is seen",
        )
        .range(Range::NonNegative)
        .penumbra_only(),
        Param::new(
            "far_clip",
            Type::Number,
            "infinity",
            "distance from the eye, along the view axis, of the plane beyond which nothing is \
             seen; more than `near_clip`",
        )
        .range(Range::Positive)
        .penumbra_only(),
        Param::new(
            "principal_point_offset",
            Type::Numbers(2),
            "[0, 0]",
            "shift of the image centre in image widths (x, to the right) and heights (y, down)",
        )
        .penumbra_only(),
        Param::new(
            "aperture",
            Type::Number,
            "0",
            "lens radius in scene units; 0 is a pinhole (everything sharp)",
        )
        .range(Range::NonNegative)
        .penumbra_only(),
        Param::new(
            "focal_distance",
            Type::Number,
            "distance to `look_at`",
            "distance of the plane in focus (measured along the view axis)",
        )
        .range(Range::Positive)
        .penumbra_only(),
        Param::new(
            "shutter",
            Type::Numbers(2),
            "[0, 1]",
            "exposed part of the frame, 0 ≤ open ≤ close ≤ 1",
        )
        .penumbra_only(),
        Param::new(
            "position_end",
            Type::Vector,
            "`position`",
            "eye position at frame time 1 (camera motion blur)",
        )
        .penumbra_only(),
        Param::new(
            "look_at_end",
            Type::Vector,
            "`look_at`",
            "target at frame time 1",
        )
        .penumbra_only(),
        Param::new(
            "medium",
            Type::String,
            "none",
            "name of the `[media.NAME]` medium the camera sits in (Mitsuba's sensor's nested \
             medium); read by `volpath` and `volpathmis`",
        )
        .penumbra_only(),
    ],
};

/// What Mitsuba's perspective cameras read: the camera is placed by
/// `to_world` and its field of view given Mitsuba's way; every projective
/// camera of Mitsuba reads `focus_distance`, which a pinhole does not use.
const SENSOR_KEYS: [&str; 9] = [
    "fov",
    "fov_axis",
    "focal_length",
    "to_world",
    "near_clip",
    "far_clip",
    "focus_distance",
    "principal_point_offset_x",
    "principal_point_offset_y",
];

/// How Mitsuba's `perspective`, `thinlens` and `orthographic` map onto the
/// camera.
pub const PLUGINS: [Plugin; 3] = [
    Plugin::named(
        &PERSPECTIVE,
        &["perspective"],
        Mitsuba {
            differences: "`to_world` as `position` (its origin), `look_at` (one unit along its \
                +z) and `up` (its +y), one that mirrors or scales refused (Mitsuba refuses a \
                scale too); `fov` along `fov_axis` (`x` by default, `y`, `diagonal`, `smaller`, \
                `larger`) or `focal_length` (default `50mm`, of a 36 × 24 mm film, along the \
                diagonal) as the vertical `fov` of the film's aspect; `near_clip` and \
                `far_clip` (Mitsuba's 0.01 and 10⁴ unless given) as the camera's; \
                `principal_point_offset_x` and `_y` as `principal_point_offset`; \
                `focus_distance` read and unused, as by Mitsuba's pinhole",
            reads: &SENSOR_KEYS,
            adapt: Some(Adapt::Held(sensors::perspective)),
        },
    ),
    Plugin::named(
        &PERSPECTIVE,
        &["thinlens"],
        Mitsuba {
            differences: "as `perspective`, without a principal point offset (Mitsuba's has \
                none); `aperture_radius` (required) and `focus_distance` (the far clip plane \
                where not given, as Mitsuba's) as `aperture` and `focal_distance`",
            reads: &[
                "fov",
                "fov_axis",
                "focal_length",
                "to_world",
                "near_clip",
                "far_clip",
                "aperture_radius",
                "focus_distance",
            ],
            adapt: Some(Adapt::Held(sensors::thinlens)),
        },
    ),
    Plugin::named(
        &PERSPECTIVE,
        &["orthographic"],
        Mitsuba {
            differences: "`projection = \"orthographic\"`; `to_world` places it as it places \
                `perspective` and scales its unit view (2 wide, 2 over the film's aspect tall) \
                into `view_width` and `view_height` (one that mirrors or shears refused); \
                `near_clip` and `far_clip` (0.01 and 10⁴ unless given) as the camera's, the \
                near plane moved by `to_world`'s scale along the axis as Mitsuba moves the \
                rays' origins; `focus_distance` read and unused",
            reads: &["to_world", "near_clip", "far_clip", "focus_distance"],
            adapt: Some(Adapt::Held(sensors::orthographic)),
        },
    ),
];

/// The camera of the sensor's parameters `p`, for an image of `s`.
pub fn build(p: &Props, s: &Settings) -> Result<Camera, Invalid> {
    let film = (s.width - 2 * s.border, s.height - 2 * s.border);
    let position = finite3(p, "position", [0.0, 1.0, 5.0])?;
    let look_at = finite3(p, "look_at", [0.0, 0.0, 0.0])?;
    let up = nonzero3(p, "up", [0.0, 1.0, 0.0])?;
    let position_end = finite3(p, "position_end", position.to_array())?;
    let look_at_end = finite3(p, "look_at_end", look_at.to_array())?;
    for (eye, target, key) in [
        (position, look_at, "look_at"),
        (position_end, look_at_end, "look_at_end"),
    ] {
        let view = target - eye;
        if view.length_squared() <= 0.0 {
            return Err(p.error(
                key,
                "the camera must look at a point other than its position",
            ));
        }
        if view.normalize().cross(up.normalize()).length() < 1e-4 {
            return Err(p.error("up", "`up` must not be parallel to the viewing direction"));
        }
    }
    let projection = match p.choice("projection", "projection", &PROJECTIONS)? {
        Some("orthographic") => Projection::Orthographic,
        _ => Projection::Perspective,
    };
    let fov = range(p, "fov", 40.0, 0.01, 179.0)?;
    let aperture = range(p, "aperture", 0.0, 0.0, f32::MAX)?;
    if projection == Projection::Orthographic && aperture > 0.0 {
        return Err(p.error("aperture", "an orthographic camera has no lens"));
    }
    let view_width = positive(p, "view_width", 2.0)?;
    let view_height = positive(p, "view_height", view_width * film.1 as f32 / film.0 as f32)?;
    let near_clip = range(p, "near_clip", 0.0, 0.0, f32::MAX)?;
    let far_clip = match p.f32("far_clip")? {
        None => f32::INFINITY,
        Some(f) if f > near_clip => f,
        Some(f) => {
            return Err(p.error(
                "far_clip",
                format!("must be more than `near_clip` ({near_clip}), got {f}"),
            ))
        }
    };
    let principal = p
        .numbers::<2>("principal_point_offset")?
        .unwrap_or([0.0; 2]);
    if !principal.iter().all(|v| v.is_finite()) {
        return Err(p.error(
            "principal_point_offset",
            format!("expected finite numbers, got {principal:?}"),
        ));
    }
    let focal_distance = match p.f32("focal_distance")? {
        Some(_) => positive(p, "focal_distance", 1.0)?,
        None => (look_at - position).length(),
    };
    let shutter = p.numbers::<2>("shutter")?.unwrap_or([0.0, 1.0]);
    let [open, close] = shutter;
    if !(open.is_finite() && close.is_finite() && 0.0 <= open && open <= close && close <= 1.0) {
        return Err(p.error(
            "shutter",
            format!("must be [open, close] with 0 <= open <= close <= 1, got {shutter:?}"),
        ));
    }
    Ok(Camera::new(CameraSpec {
        projection,
        position: [position, position_end],
        look_at: [look_at, look_at_end],
        up,
        fov: fov.to_radians(),
        view_size: Vec2::new(view_width, view_height),
        near_clip,
        far_clip,
        principal_point: Vec2::from_array(principal),
        aperture,
        focal_distance,
        shutter: [open, close],
        width: film.0,
        height: film.1,
        border: s.border,
    }))
}
