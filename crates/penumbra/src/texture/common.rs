//! What the textures share: the transform of surface coordinates
//! (`to_uv`) and a colour read as one value.

use crate::description::{Invalid, Param, Props, Type, Value};
use crate::math::{Rgb, Vec2};

/// A colour as one value: a grey's value (exactly), else its luminance.
#[inline]
pub fn one(c: Rgb) -> f32 {
    if c.r == c.g && c.g == c.b {
        c.r
    } else {
        c.luminance()
    }
}

/// Mitsuba's `to_uv`: the affine map `(u, v) ↦ (a·u + b·v + c, d·u + e·v + f)`,
/// rows `[a, b, c]` and `[d, e, f]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    pub rows: [[f32; 3]; 2],
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform::IDENTITY
    }
}

/// The keys of a `to_uv` table.
pub const TO_UV_KEYS: &[Param] = &[
    Param::new(
        "scale",
        Type::Scale2,
        "1",
        "uniform or per-axis scale of (u, v)",
    ),
    Param::new(
        "rotate_degrees",
        Type::Number,
        "0",
        "counter-clockwise rotation",
    ),
    Param::new(
        "translate",
        Type::Numbers(2),
        "[0, 0]",
        "offset added to (u, v)",
    ),
    Param::new(
        "matrix",
        Type::Matrix3,
        "",
        "the affine matrix acting on (u, v, 1)",
    ),
];

/// The schema entry of `to_uv`, which every texture takes.
pub const TO_UV: Param = Param::new(
    "to_uv",
    Type::Table(TO_UV_KEYS),
    "identity",
    "a 2D affine map of (u, v) before the lookup: `scale`, `rotate_degrees`, `translate` (in that order) or a 3×3 `matrix`",
);

impl UvTransform {
    pub const IDENTITY: UvTransform = UvTransform {
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    };

    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let [a, b] = &self.rows;
        Vec2::new(
            a[0] * uv.x + a[1] * uv.y + a[2],
            b[0] * uv.x + b[1] * uv.y + b[2],
        )
    }

    /// A texture's `to_uv` (identity without one).
    pub fn read(p: &Props) -> Result<UvTransform, Invalid> {
        let Some(t) = p.table("to_uv")? else {
            return Ok(UvTransform::IDENTITY);
        };
        let out = if let Some(m) = t.matrix3("matrix")? {
            if ["scale", "rotate_degrees", "translate"]
                .iter()
                .any(|k| t.has(k))
            {
                return Err(t.error("matrix", "give either `matrix` or the other keys, not both"));
            }
            if m[2] != [0.0, 0.0, 1.0] {
                return Err(t.error("matrix", "must be affine: its last row is [0, 0, 1]"));
            }
            UvTransform { rows: [m[0], m[1]] }
        } else {
            let (sx, sy) = match t.get("scale") {
                None => (1.0, 1.0),
                Some(prop) => match &prop.value.value {
                    Value::Array(_) => {
                        let xs = crate::description::props::numbers(&prop.value, 2)?;
                        (xs[0], xs[1])
                    }
                    _ => {
                        let s = crate::description::props::number(&prop.value)?;
                        (s, s)
                    }
                },
            };
            let angle = t.f32("rotate_degrees")?.unwrap_or(0.0).to_radians();
            let [tx, ty] = t.numbers::<2>("translate")?.unwrap_or([0.0; 2]);
            let (s, c) = angle.sin_cos();
            UvTransform {
                rows: [[c * sx, -s * sy, tx], [s * sx, c * sy, ty]],
            }
        };
        if out.rows.iter().flatten().any(|x| !x.is_finite()) {
            return Err(p.error("to_uv", "expected finite numbers"));
        }
        t.finish("to_uv")?;
        Ok(out)
    }
}
