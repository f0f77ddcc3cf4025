//! `mesh_attribute`: an attribute of the mesh that was hit, a PLY file's
//! vertex colours or other vertex or face values (Mitsuba 3's
//! `mesh_attribute`). `name` is Mitsuba's: `vertex_NAME` or `face_NAME`
//! (`vertex_color` for a PLY file's `r, g, b` or `red, green, blue`; the
//! PLY reader's docs give the other names). A vertex
//! attribute is interpolated with the point's barycentric weights on its
//! triangle, `b0 v0 + b1 v1 + b2 v2`; a face attribute is constant on each
//! face. The value is multiplied by `scale`.
//!
//! As Mitsuba's: a 1-value attribute reads as a grey colour and as itself;
//! a 3-value one as a colour, and as 0 when read as one value; a 4-value
//! one (a colour with alpha) as 0. A shape whose material reads an
//! attribute its file does not have is refused when the scene is built,
//! naming the file; a shape that is not a mesh read from a file has none.
//! The values are not known when a material is built: its range checks
//! take them as [0, 1] (Mitsuba checks none).
//! The texture is looked up at the point itself: inside another texture
//! (a checkerboard's colour) or a spot light it is refused.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `name` | string | **required** | the attribute: `vertex_...` or `face_...` |
//! | `scale` | number | `1` | a factor applied to the value |

use std::sync::{Arc, OnceLock};

use super::{TextureModel, Textures};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::geometry::mesh_file::MeshAttribute as Values;
use crate::geometry::{Mesh, SurfaceInteraction};
use crate::math::{Rgb, Vec2};

/// Its parameters.
const SCHEMA: Schema = Schema {
    kind: Kind::Texture,
    plugin: "mesh_attribute",
    what: "mesh attribute texture",
    doc: "an attribute of the mesh hit (a PLY file's vertex colours, other vertex or face values), interpolated over its triangles",
    mitsuba: &["mesh_attribute"],
    params: &[
        Param::new(
            "name",
            Type::String,
            "required",
            "the attribute: `vertex_NAME` (interpolated) or `face_NAME` (constant on a face); `vertex_color` for a PLY file's r, g, b",
        ),
        Param::new("scale", Type::Number, "1", "a factor applied to the value"),
    ],
};

/// The attribute of each object of the world: its mesh (an index into
/// `meshes`) and the values, for the objects whose mesh has it.
#[derive(Debug)]
pub struct Bound {
    pub meshes: Arc<[Mesh]>,
    pub objects: Vec<Option<(u32, Arc<Values>)>>,
}

/// The mesh attribute texture (see the [module docs](self)). Its values
/// are bound to the world's objects once the world is built.
#[derive(Clone, Debug)]
pub struct MeshAttribute {
    pub name: String,
    pub scale: f32,
    pub bound: Arc<OnceLock<Bound>>,
}

impl PartialEq for MeshAttribute {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
            && self.scale == other.scale
            && Arc::ptr_eq(&self.bound, &other.bound)
    }
}

impl MeshAttribute {
    /// The attribute's values at the hit, as many as the attribute has
    /// (up to 4), blended as Mitsuba blends them; `None` where the object
    /// has no such attribute.
    fn at(&self, si: &SurfaceInteraction) -> Option<(usize, [f32; 4])> {
        let b = self.bound.get()?;
        let (mesh, a) = b.objects.get(si.object as usize)?.as_ref()?;
        let tri = si.prim as usize;
        let dim = a.dim.min(4);
        let value = |i: usize| {
            let mut out = [0.0f32; 4];
            if let Some(v) = a.values.get(i * a.dim..i * a.dim + dim) {
                out[..dim].copy_from_slice(v);
            }
            out
        };
        let out = if a.per_face {
            value(tri)
        } else {
            let [i0, i1, i2] = *b.meshes.get(*mesh as usize)?.triangles.get(tri)?;
            let (v0, v1, v2) = (value(i0 as usize), value(i1 as usize), value(i2 as usize));
            let (b1, b2) = (si.bary.x, si.bary.y);
            let b0 = 1.0 - b1 - b2;
            std::array::from_fn(|k| v0[k].mul_add(b0, v1[k].mul_add(b1, v2[k] * b2)))
        };
        Some((dim, out))
    }

    /// The colour at the hit.
    pub fn eval_at(&self, si: &SurfaceInteraction) -> Rgb {
        match self.at(si) {
            Some((1, v)) => Rgb::splat(v[0] * self.scale),
            Some((3, v)) => Rgb::new(v[0], v[1], v[2]) * self.scale,
            _ => Rgb::ZERO,
        }
    }

    /// One value at the hit.
    pub fn eval_1_at(&self, si: &SurfaceInteraction) -> f32 {
        match self.at(si) {
            Some((1, v)) => v[0] * self.scale,
            _ => 0.0,
        }
    }
}

impl TextureModel for MeshAttribute {
    const NAME: &'static str = "mesh_attribute";
    const SCHEMA: Schema = SCHEMA;
    const MITSUBA: Mitsuba = Mitsuba::differs(
        "an attribute a mesh lacks is refused when the scene is built (Mitsuba: when rendered); refused inside another texture (Mitsuba reads it there)",
    );

    fn build(p: &Props, textures: &Textures) -> Result<MeshAttribute, Invalid> {
        let Some(name) = p.string("name")? else {
            return Err(p.node_error("missing field `name` (`vertex_...` or `face_...`)"));
        };
        if !(name.starts_with("vertex_") || name.starts_with("face_")) {
            return Err(p.error(
                "name",
                format!(
                    "must start with `vertex_` or `face_`, got `{}`",
                    crate::input::quote::clip(name, crate::input::quote::MAX_QUOTED_CHARS)
                ),
            ));
        }
        let scale = p.f32("scale")?.unwrap_or(1.0);
        if !scale.is_finite() {
            return Err(p.error("scale", "must be finite"));
        }
        let t = MeshAttribute {
            name: name.to_string(),
            scale,
            bound: Arc::new(OnceLock::new()),
        };
        textures.used(&t, p.node_origin());
        Ok(t)
    }

    /// Without the hit there is no attribute: 0 (a mesh attribute is read
    /// at the hit, through [`Texture::eval`](super::Texture::eval)).
    fn eval(&self, _uv: Vec2) -> Rgb {
        Rgb::ZERO
    }

    fn eval_1(&self, _uv: Vec2) -> f32 {
        0.0
    }

    /// Not known when a material is built (the attribute is bound to the
    /// meshes later): taken as [0, 1] by the models' range checks, which
    /// Mitsuba does not make for attributes.
    fn bounds(&self) -> (Rgb, Rgb) {
        (Rgb::ZERO, Rgb::ONE)
    }

    fn bounds_1(&self) -> (f32, f32) {
        (0.0, 1.0)
    }
}
