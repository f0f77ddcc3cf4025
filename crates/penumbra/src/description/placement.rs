//! Placements: a transform table (`scale`, then `rotate_axis` and
//! `rotate_degrees`, then `translate`; or a `matrix`) read as a matrix. The
//! scene's objects and the volumes of participating media are placed by
//! one.

use super::check::{finite3_value, nonzero3, range};
use super::{Invalid, Param, Props, Scale, Type};
use crate::math::{Mat4, Quat, Vec3};

/// The keys of a transform table.
pub const PARAMS: [Param; 5] = [
    Param::new("scale", Type::Scale, "1", "uniform or per-axis scale, non-zero"),
    Param::new("rotate_axis", Type::Vector, "[0, 1, 0]", "rotation axis ≠ 0 (needs `rotate_degrees`)"),
    Param::new("rotate_degrees", Type::Number, "0", "rotation angle, right-handed about the axis"),
    Param::new("translate", Type::Vector, "[0, 0, 0]", "translation"),
    Param::new("matrix", Type::Matrix4, "—", "instead of the keys above: a row-major affine matrix acting on column vectors (last row `[0, 0, 0, 1]`)"),
];

/// The placement `name` of an object (`transform`, `transform_end`): the
/// identity when absent.
pub fn read(object: &Props, name: &str) -> Result<Option<Mat4>, Invalid> {
    let Some(t) = object.table(name)? else {
        return Ok(None);
    };
    let m = matrix_of(&t)?;
    t.finish("transform")?;
    Ok(Some(m))
}

fn matrix_of(t: &Props) -> Result<Mat4, Invalid> {
    if let Some(rows) = t.matrix4("matrix")? {
        if ["scale", "rotate_axis", "rotate_degrees", "translate"]
            .iter()
            .any(|k| t.has(k))
        {
            return Err(t.error(
                "matrix",
                "`matrix` excludes scale, rotate_axis, rotate_degrees and translate",
            ));
        }
        return matrix(t, rows);
    }
    let scale = match t.scale("scale")? {
        None => Vec3::ONE,
        Some(Scale::Uniform(s)) => Vec3::splat(s),
        Some(Scale::PerAxis(v)) => finite3_value(t, "scale", v)?,
    };
    if !scale.is_finite() || scale.abs().min_element() < 1e-12 {
        return Err(t.error("scale", "scale factors must be finite and non-zero"));
    }
    let rotation = match (t.has("rotate_axis"), t.f32("rotate_degrees")?) {
        (false, None) => Quat::IDENTITY,
        (_, Some(_)) => {
            let axis = nonzero3(t, "rotate_axis", [0.0, 1.0, 0.0])?;
            let deg = range(t, "rotate_degrees", 0.0, -1e6, 1e6)?;
            Quat::from_axis_angle(axis.normalize(), deg.to_radians())
        }
        (true, None) => {
            return Err(t.error("rotate_axis", "`rotate_axis` needs `rotate_degrees`"));
        }
    };
    let translate = match t.numbers::<3>("translate")? {
        Some(v) => finite3_value(t, "translate", v)?,
        None => Vec3::ZERO,
    };
    Ok(Mat4::from_scale_rotation_translation(
        scale, rotation, translate,
    ))
}

fn matrix(t: &Props, rows: [[f32; 4]; 4]) -> Result<Mat4, Invalid> {
    if rows.iter().flatten().any(|x| !x.is_finite()) {
        return Err(t.error("matrix", "matrix entries must be finite"));
    }
    if rows[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(t.error(
            "matrix",
            "the last row of the matrix must be [0, 0, 0, 1] (affine)",
        ));
    }
    let m = Mat4::from_cols_array_2d(&rows).transpose();
    if m.determinant().abs() < 1e-12 {
        return Err(t.error("matrix", "the matrix is singular"));
    }
    Ok(m)
}
