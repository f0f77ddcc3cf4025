//! Property tags: `<integer>`, `<float>`, `<boolean>`, `<string>`,
//! `<point>`, `<vector>`, `<rgb>`, `<spectrum>` and `<transform>` read into
//! typed values, every number finite.

use super::number::{number, numbers};
use super::parse::{check_attrs, clip, error_at, Element, Reader};
use super::spectrum::{self, Spectrum};
use super::transform::{self, Mat4};
use crate::description::error::SceneError;
use crate::input;

/// A property's value.
#[derive(Clone, Debug, PartialEq)]
pub enum PropValue {
    Int(i64),
    Float(f64),
    Bool(bool),
    String(String),
    /// A `<point>` or `<vector>`.
    Vector([f64; 3]),
    Rgb([f64; 3]),
    Spectrum(Spectrum),
    Transform(Mat4),
}

impl PropValue {
    /// What the value is, for messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            PropValue::Int(_) => "an integer",
            PropValue::Float(_) => "a float",
            PropValue::Bool(_) => "a boolean",
            PropValue::String(_) => "a string",
            PropValue::Vector(_) => "a point or vector",
            PropValue::Rgb(_) => "an rgb colour",
            PropValue::Spectrum(_) => "a spectrum",
            PropValue::Transform(_) => "a transform",
        }
    }
}

fn attr_number(e: &Element, name: &str) -> Result<Option<f64>, SceneError> {
    match e.attr(name) {
        None => Ok(None),
        Some(a) => number(&a.value).map(Some).map_err(|m| error_at(&a.at, m)),
    }
}

/// `value="x, y, z"` (or one number for all three), or `x`, `y`, `z`
/// attributes, a missing one `missing`.
fn xyz(e: &Element, missing: Option<f64>) -> Result<[f64; 3], SceneError> {
    if let Some(a) = e.attr("value") {
        if ["x", "y", "z"].iter().any(|k| e.attr(k).is_some()) {
            return Err(error_at(
                &a.at,
                format!("<{}>: give `value` or x, y, z, not both", e.tag),
            ));
        }
        let v = numbers(&a.value).map_err(|m| error_at(&a.at, m))?;
        return match v.len() {
            1 => Ok([v[0]; 3]),
            3 => Ok([v[0], v[1], v[2]]),
            n => Err(error_at(
                &a.at,
                format!("<{}>: expected 1 or 3 numbers, got {n}", e.tag),
            )),
        };
    }
    let mut out = [0.0; 3];
    for (i, k) in ["x", "y", "z"].iter().enumerate() {
        out[i] = match (attr_number(e, k)?, missing) {
            (Some(x), _) => x,
            (None, Some(d)) => d,
            (None, None) => {
                return Err(error_at(
                    &e.at,
                    format!("<{}>: missing attribute `{k}`", e.tag),
                ))
            }
        };
    }
    Ok(out)
}

/// A `point`/`vector` attribute of `<lookat>`: "x, y, z".
fn triple(e: &Element, name: &str) -> Result<Option<[f64; 3]>, SceneError> {
    let Some(a) = e.attr(name) else {
        return Ok(None);
    };
    let v = numbers(&a.value).map_err(|m| error_at(&a.at, m))?;
    match v.len() {
        3 => Ok(Some([v[0], v[1], v[2]])),
        n => Err(error_at(
            &a.at,
            format!("`{name}`: expected 3 numbers, got {n}"),
        )),
    }
}

/// The value of a property tag (its `name` already checked by the caller).
pub fn read(e: &Element, reader: &Reader) -> Result<PropValue, SceneError> {
    let value_attr = || e.attr("value").expect("checked");
    match e.tag.as_str() {
        "integer" => {
            check_attrs(e, &["name", "value"], &["name", "value"])?;
            let a = value_attr();
            a.value
                .trim()
                .parse::<i64>()
                .map(PropValue::Int)
                .map_err(|_| {
                    error_at(
                        &a.at,
                        format!("`{}` is not an integer (64-bit)", clip(&a.value)),
                    )
                })
        }
        "float" => {
            check_attrs(e, &["name", "value"], &["name", "value"])?;
            let a = value_attr();
            number(&a.value)
                .map(PropValue::Float)
                .map_err(|m| error_at(&a.at, m))
        }
        "boolean" => {
            check_attrs(e, &["name", "value"], &["name", "value"])?;
            let a = value_attr();
            match a.value.trim().to_ascii_lowercase().as_str() {
                "true" => Ok(PropValue::Bool(true)),
                "false" => Ok(PropValue::Bool(false)),
                _ => Err(error_at(
                    &a.at,
                    format!("`{}` is not `true` or `false`", clip(&a.value)),
                )),
            }
        }
        "string" => {
            check_attrs(e, &["name", "value"], &["name", "value"])?;
            Ok(PropValue::String(value_attr().value.clone()))
        }
        "point" | "vector" => {
            check_attrs(e, &["name", "value", "x", "y", "z"], &["name"])?;
            xyz(e, None).map(PropValue::Vector)
        }
        "rgb" => {
            check_attrs(e, &["name", "value"], &["name", "value"])?;
            let a = value_attr();
            let v = numbers(&a.value).map_err(|m| error_at(&a.at, m))?;
            match v.len() {
                1 => Ok(PropValue::Rgb([v[0]; 3])),
                3 => Ok(PropValue::Rgb([v[0], v[1], v[2]])),
                n => Err(error_at(
                    &a.at,
                    format!("<rgb>: expected 1 or 3 numbers, got {n}"),
                )),
            }
        }
        "spectrum" => spectrum_tag(e, reader),
        "transform" => {
            check_attrs(e, &["name"], &["name"])?;
            transform_tag(e).map(PropValue::Transform)
        }
        other => Err(error_at(&e.at, format!("<{other}> is not a property tag"))),
    }
}

fn spectrum_tag(e: &Element, reader: &Reader) -> Result<PropValue, SceneError> {
    check_attrs(e, &["name", "value", "filename"], &["name"])?;
    match (e.attr("value"), e.attr("filename")) {
        (Some(a), None) => spectrum::parse(&a.value)
            .map(PropValue::Spectrum)
            .map_err(|m| error_at(&a.at, m)),
        (None, Some(a)) => {
            let rel = reader.resolve(&e.dir, &a.value);
            let full = rel.clone();
            let limit = input::size_limit(1 << 20).unwrap_or(1 << 20);
            let bytes = input::read_file_within(&full, limit)
                .map_err(|err| error_at(&a.at, format!("cannot read the spectrum: {err}")))?;
            let text = String::from_utf8(bytes).map_err(|_| {
                error_at(
                    &a.at,
                    format!("{}: the spectrum file is not UTF-8", rel.display()),
                )
            })?;
            spectrum::parse_file(&text)
                .map(PropValue::Spectrum)
                .map_err(|m| error_at(&a.at, format!("{}: {m}", rel.display())))
        }
        _ => Err(error_at(
            &e.at,
            "<spectrum>: give `value` or `filename` (one of them)",
        )),
    }
}

/// A `<transform>`'s operations, each applied after the ones before.
pub fn transform_tag(e: &Element) -> Result<Mat4, SceneError> {
    let mut m = transform::IDENTITY;
    for op in &e.children {
        let step = match op.tag.as_str() {
            "translate" => {
                check_attrs(op, &["value", "x", "y", "z"], &[])?;
                transform::translate(xyz(op, Some(0.0))?)
            }
            "scale" => {
                check_attrs(op, &["value", "x", "y", "z"], &[])?;
                transform::scale(xyz(op, Some(1.0))?)
            }
            "rotate" => {
                check_attrs(op, &["value", "x", "y", "z", "angle"], &["angle"])?;
                let axis = xyz(op, Some(0.0))?;
                if axis == [0.0; 3] {
                    return Err(error_at(&op.at, "<rotate>: the axis is zero"));
                }
                let angle = attr_number(op, "angle")?.expect("checked");
                transform::rotate(axis, angle)
            }
            "matrix" => {
                check_attrs(op, &["value"], &["value"])?;
                let a = op.attr("value").expect("checked");
                let v = numbers(&a.value).map_err(|m| error_at(&a.at, m))?;
                match v.len() {
                    16 => std::array::from_fn(|i| std::array::from_fn(|j| v[4 * i + j])),
                    9 => {
                        let mut m = transform::IDENTITY;
                        for i in 0..3 {
                            for j in 0..3 {
                                m[i][j] = v[3 * i + j];
                            }
                        }
                        m
                    }
                    n => {
                        return Err(error_at(
                            &a.at,
                            format!("<matrix>: expected 16 (or 9) numbers, got {n}"),
                        ))
                    }
                }
            }
            "lookat" => {
                check_attrs(op, &["origin", "target", "up"], &["origin", "target"])?;
                let origin = triple(op, "origin")?.expect("checked");
                let target = triple(op, "target")?.expect("checked");
                let up = match triple(op, "up")? {
                    Some(u) if u != [0.0; 3] => u,
                    _ => any_perpendicular(transform::sub(target, origin)),
                };
                transform::look_at(origin, target, up).ok_or_else(|| {
                    error_at(
                        &op.at,
                        "<lookat>: the origin and the target coincide, or `up` is along the view",
                    )
                })?
            }
            other => {
                return Err(error_at(
                    &op.at,
                    format!(
                    "<{}> is not a transform operation (translate, rotate, scale, matrix, lookat)",
                    clip(other)
                ),
                ))
            }
        };
        m = transform::mul(&step, &m);
    }
    if !transform::is_affine(&m) {
        return Err(error_at(
            &e.at,
            "<transform>: the last row must be 0 0 0 1 (an affine transform)",
        ));
    }
    if transform::is_singular(&m) {
        return Err(error_at(
            &e.at,
            "<transform>: the matrix is singular (it flattens space)",
        ));
    }
    Ok(m)
}

/// A direction across `d` (what `<lookat>` takes for a zero `up`).
fn any_perpendicular(d: [f64; 3]) -> [f64; 3] {
    if d[0].abs() > d[1].abs() {
        [-d[2], 0.0, d[0]]
    } else {
        [0.0, d[2], -d[1]]
    }
}
