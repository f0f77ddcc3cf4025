//! Textures: values that vary over a surface, looked up at the surface
//! coordinates `(u, v)` of a [`SurfaceInteraction`] (Mitsuba 3's textures).
//!
//! Every parameter of a model that Mitsuba lets take a texture takes one
//! here (its schema type is [`Type::ColourTexture`](crate::description::Type::ColourTexture) or
//! [`Type::NumberTexture`](crate::description::Type::NumberTexture)): a colour, the texture of a model's colours; a
//! number, a roughness, an opacity, a blend weight or a bump map's heights
//! (read through their gradient, [`Texture::eval_1_grad`]). In a scene such
//! a parameter is written as
//!
//! * a plain value, 3 numbers or a number: a [`Texture::Constant`], which
//!   costs what a plain colour costs;
//! * a texture's table, its `type` and parameters:
//!   `reflectance = { type = "checkerboard", color0 = [0.9, 0.9, 0.9] }`;
//! * the name of a texture declared once under `[textures.NAME]`:
//!   `reflectance = "wood"`.
//!
//! A texture answers as a colour ([`Texture::eval`]) or as one value
//! ([`Texture::eval_1`], Mitsuba's `eval_1`: a grey colour's value, else the
//! luminance of the colour).
//!
//! | texture | what |
//! |---|---|
//! | [`checkerboard`](checkerboard::Checkerboard) | two colours or textures alternating in squares of side ½ in `(u, v)` (Mitsuba 3's `checkerboard`) |
//! | [`bitmap`](bitmap::Bitmap) | an image file (PNG, JPEG, OpenEXR, Radiance HDR), sRGB-decoded or raw, nearest or bilinear, repeated, mirrored or clamped (Mitsuba 3's `bitmap`) |
//! | [`mesh_attribute`](mesh_attribute::MeshAttribute) | an attribute of the mesh hit (a PLY file's vertex colours, other vertex or face values), interpolated over its triangles (Mitsuba 3's `mesh_attribute`) |
//! | [`rawconstant`](rawconstant::RawConstant) | one number or 3 numbers everywhere, taken as they are: no colour check, negative values allowed (Mitsuba 3's `rawconstant`) |
//!
//! Every texture takes `to_uv`, a 2D affine map applied to `(u, v)` before
//! the lookup ([`UvTransform`]), written as a table applied as scale, then
//! rotation, then translation:
//!
//! | key | type | default | meaning |
//! |---|---|---|---|
//! | `scale` | number or array of 2 numbers | `1` | uniform or per-axis scale of `(u, v)` |
//! | `rotate_degrees` | number | `0` | counter-clockwise rotation in the `(u, v)` plane |
//! | `translate` | array of 2 numbers | `[0, 0]` | offset added to `(u, v)` |
//! | `matrix` | 3×3 array of rows | — | instead of the keys above: the affine matrix acting on `(u, v, 1)` (last row `[0, 0, 1]`) |

mod common;

use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{
    checked_table, no_such_name, typed_table, Invalid, Kind, Node, Origin, Prop, Props, Schema,
    Value,
};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2};

pub use common::{one, UvTransform, TO_UV, TO_UV_KEYS};

/// What every texture model answers: its names and schema, its builder,
/// and its values at surface coordinates `(u, v)`.
pub trait TextureModel: Sized {
    /// The name scenes select the texture by.
    const NAME: &'static str;

    /// Its parameters.
    const SCHEMA: Schema;

    /// How Mitsuba's plugin of its name maps onto it.
    const MITSUBA: Mitsuba = Mitsuba::SAME;

    /// The texture of a scene's parameters: its files relative to
    /// `textures.base_dir`, the textures it holds read through `textures`.
    fn build(p: &Props, textures: &Textures) -> Result<Self, Invalid>;

    /// The colour at `uv`.
    fn eval(&self, uv: Vec2) -> Rgb;

    /// One value at `uv` (Mitsuba's `eval_1`).
    fn eval_1(&self, uv: Vec2) -> f32;

    /// [`eval`](Self::eval) at each point of `uvs`, into `out` (cleared
    /// first): the batch form, which a texture's kernel may take several
    /// lanes at a time; by default, one by one.
    #[inline]
    fn eval_all(&self, uvs: &[Vec2], out: &mut Vec<Rgb>) {
        out.clear();
        out.extend(uvs.iter().map(|&uv| self.eval(uv)));
    }

    /// [`eval_1`](Self::eval_1) at each point of `uvs`, into `out`
    /// (cleared first); by default, one by one.
    #[inline]
    fn eval_1_all(&self, uvs: &[Vec2], out: &mut Vec<f32>) {
        out.clear();
        out.extend(uvs.iter().map(|&uv| self.eval_1(uv)));
    }

    /// The derivatives of [`eval_1`](Self::eval_1) in `u` and `v` (0 for
    /// a texture constant where it is differentiable).
    fn eval_1_grad(&self, _uv: Vec2) -> Vec2 {
        Vec2::ZERO
    }

    /// The smallest and the largest value of each channel anywhere.
    fn bounds(&self) -> (Rgb, Rgb);

    /// The smallest and largest value [`eval_1`](Self::eval_1) gives.
    fn bounds_1(&self) -> (f32, f32);
}

/// Declares the textures' modules, and makes [`Texture`], a constant or
/// one of the textures listed (each `module::Model`, its variant named as
/// the model), and its dispatch.
macro_rules! textures {
    ($($module:ident::$variant:ident,)*) => {
        $(pub mod $module;)*

        /// A texture: a constant or one of the texture models.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Texture {
            /// The same colour everywhere: a plain value.
            Constant(Rgb),
            $($variant($module::$variant),)*
        }

        impl Texture {
            /// The names of the textures, as scenes select them.
            pub const NAMES: &'static [&'static str] =
                &[$(<$module::$variant as TextureModel>::NAME,)*];

            /// The textures' parameters.
            pub const SCHEMAS: &'static [&'static Schema] =
                &[$(&<$module::$variant as TextureModel>::SCHEMA,)*];

            /// The textures as the readers see them.
            pub const PLUGINS: &'static [Plugin] = &[$(Plugin::new(&<$module::$variant as TextureModel>::SCHEMA, <$module::$variant as TextureModel>::MITSUBA),)*];

            /// The texture `plugin` of the parameters `p`; `None` for a
            /// name that is not a texture's.
            fn build_model(
                plugin: &str,
                p: &Props,
                textures: &Textures,
            ) -> Option<Result<Texture, Invalid>> {
                match plugin {
                    $(<$module::$variant as TextureModel>::NAME => {
                        Some(<$module::$variant>::build(p, textures).map(Texture::$variant))
                    })*
                    _ => None,
                }
            }

            /// The colour at surface coordinates `uv`.
            pub fn eval_uv(&self, uv: Vec2) -> Rgb {
                match self {
                    Texture::Constant(c) => *c,
                    $(Texture::$variant(t) => t.eval(uv),)*
                }
            }

            /// The colour at each of `uvs`, into `out` (cleared first): the
            /// batch form (see [`TextureModel::eval_all`]).
            pub fn eval_all(&self, uvs: &[Vec2], out: &mut Vec<Rgb>) {
                match self {
                    Texture::Constant(c) => {
                        out.clear();
                        out.resize(uvs.len(), *c);
                    }
                    $(Texture::$variant(t) => t.eval_all(uvs, out),)*
                }
            }

            /// One value at each of `uvs`, into `out` (cleared first): the
            /// batch form (see [`TextureModel::eval_1_all`]).
            pub fn eval_1_all(&self, uvs: &[Vec2], out: &mut Vec<f32>) {
                match self {
                    Texture::Constant(c) => {
                        out.clear();
                        out.resize(uvs.len(), one(*c));
                    }
                    $(Texture::$variant(t) => t.eval_1_all(uvs, out),)*
                }
            }

            /// One value at surface coordinates `uv`.
            pub fn eval_1_uv(&self, uv: Vec2) -> f32 {
                match self {
                    Texture::Constant(c) => one(*c),
                    $(Texture::$variant(t) => t.eval_1(uv),)*
                }
            }

            /// [`eval_1_grad`](Self::eval_1_grad) at surface coordinates `uv`.
            pub fn eval_1_grad_uv(&self, uv: Vec2) -> Vec2 {
                match self {
                    Texture::Constant(_) => Vec2::ZERO,
                    $(Texture::$variant(t) => t.eval_1_grad(uv),)*
                }
            }

            /// The smallest and the largest value of each channel anywhere on the
            /// texture (for range checks).
            pub fn bounds(&self) -> (Rgb, Rgb) {
                match self {
                    Texture::Constant(c) => (*c, *c),
                    $(Texture::$variant(t) => t.bounds(),)*
                }
            }

            /// The smallest and largest value [`eval_1`](Self::eval_1) gives.
            pub fn bounds_1(&self) -> (f32, f32) {
                match self {
                    Texture::Constant(c) => (one(*c), one(*c)),
                    $(Texture::$variant(t) => t.bounds_1(),)*
                }
            }
        }
    };
}

// The textures: one line each.
textures! {
    checkerboard::Checkerboard,
    bitmap::Bitmap,
    rawconstant::RawConstant,
    mesh_attribute::MeshAttribute,
}

impl Texture {
    /// The colour at the interaction's `(u, v)`.
    #[inline]
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::MeshAttribute(t) => t.eval_at(si),
            _ => self.eval_uv(si.uv),
        }
    }

    /// One value at the interaction's `(u, v)` (Mitsuba's `eval_1`).
    #[inline]
    pub fn eval_1(&self, si: &SurfaceInteraction) -> f32 {
        match self {
            Texture::Constant(c) => one(*c),
            Texture::MeshAttribute(t) => t.eval_1_at(si),
            _ => self.eval_1_uv(si.uv),
        }
    }

    /// The derivatives of [`eval_1`](Self::eval_1) in `u` and `v` at the
    /// interaction's `(u, v)` (Mitsuba's `eval_1_grad`): 0 for a constant
    /// and a checkerboard (constant within its squares).
    pub fn eval_1_grad(&self, si: &SurfaceInteraction) -> Vec2 {
        self.eval_1_grad_uv(si.uv)
    }

    /// The constant's colour; `None` for a texture that varies.
    pub fn constant(&self) -> Option<Rgb> {
        match self {
            Texture::Constant(c) => Some(*c),
            _ => None,
        }
    }
}

/// The textures of a scene by name, and where its files are: what a model
/// reads its texture-typed parameters with ([`Textures::colour`],
/// [`Textures::number`]).
#[derive(Clone, Debug, Default)]
pub struct Textures {
    /// The folder relative file names start from.
    pub base_dir: PathBuf,
    named: HashMap<String, Texture>,
    /// The material being built (its index among the scene's), 0 outside
    /// one.
    material: Cell<u32>,
    /// The mesh attributes the materials read, to bind to the meshes.
    attributes: RefCell<Vec<AttributeUse>>,
}

/// A material's reading of a mesh attribute: which material, the texture
/// and where it is written.
#[derive(Clone, Debug)]
pub struct AttributeUse {
    pub material: u32,
    pub texture: mesh_attribute::MeshAttribute,
    pub origin: Origin,
}

impl Textures {
    /// No named textures; files relative to `base_dir`.
    pub fn new(base_dir: &Path) -> Textures {
        Textures {
            base_dir: base_dir.to_path_buf(),
            ..Textures::default()
        }
    }

    /// Textures read from here on are the material `index`'s.
    pub fn building_material(&self, index: u32) {
        self.material.set(index);
    }

    /// Notes that the material being built reads the mesh attribute `t`
    /// (written at `origin`).
    fn used(&self, t: &mesh_attribute::MeshAttribute, origin: &Origin) {
        self.attributes.borrow_mut().push(AttributeUse {
            material: self.material.get(),
            texture: t.clone(),
            origin: origin.clone(),
        });
    }

    /// The mesh attributes read by the materials (and by textures declared
    /// in the scene, material 0), in the order they were read.
    pub fn attribute_uses(&self) -> Vec<AttributeUse> {
        self.attributes.borrow().clone()
    }

    /// Builds the scene's named textures: the children of `root` of kind
    /// texture, each by its id.
    pub fn of_scene(root: &Node, base_dir: &Path) -> Result<Textures, Invalid> {
        let mut t = Textures::new(base_dir);
        for node in root.children_of(Kind::Texture) {
            let texture = t.build(&node.plugin, &node.plugin_origin, &node.props, &node.origin)?;
            if let Some(id) = &node.id {
                t.named.insert(id.clone(), texture);
            }
        }
        Ok(t)
    }

    /// The texture named `name`, if the scene declares one.
    pub fn get(&self, name: &str) -> Option<&Texture> {
        self.named.get(name)
    }

    /// Builds the texture `plugin` of the properties `props` (checked
    /// against its schema here, since a texture's table is checked as a
    /// whole when the scene is loaded).
    fn build(
        &self,
        plugin: &str,
        plugin_at: &Origin,
        props: &[Prop],
        origin: &Origin,
    ) -> Result<Texture, Invalid> {
        let (node, schema) = checked_table(
            Kind::Texture,
            Texture::SCHEMAS,
            (plugin, plugin_at),
            props,
            origin,
        )?;
        let p = Props::new(&node);
        let texture =
            Texture::build_model(plugin, &p, self).expect("every schema has a builder")?;
        p.finish(schema.what)?;
        Ok(texture)
    }

    /// The texture a parameter's value names: its table or a name.
    fn texture_of(
        &self,
        v: &crate::description::Located<Value>,
    ) -> Result<Option<Texture>, Invalid> {
        match &v.value {
            Value::String(name) => match self.named.get(name) {
                Some(t) => {
                    if let Texture::MeshAttribute(m) = t {
                        self.used(m, &v.origin);
                    }
                    Ok(Some(t.clone()))
                }
                None => Err(no_such_name(
                    Kind::Texture,
                    name,
                    self.named.keys(),
                    &v.origin,
                )),
            },
            Value::Table(props) => {
                let (plugin, at, rest) = typed_table(props, &v.origin, Kind::Texture)?;
                self.build(plugin, at, &rest, &v.origin).map(Some)
            }
            _ => Ok(None),
        }
    }

    /// A colour parameter: 3 numbers (finite, none negative), a texture's
    /// table or a texture's name; `default` when it is not there.
    pub fn colour(&self, p: &Props, name: &str, default: Rgb) -> Result<Texture, Invalid> {
        let Some(prop) = p.get(name) else {
            return Ok(Texture::Constant(default));
        };
        if let Some(t) = self.texture_of(&prop.value)? {
            return Ok(t);
        }
        let xs = crate::description::props::numbers(&prop.value, 3)?;
        let c = Rgb::new(xs[0], xs[1], xs[2]);
        if !c.is_finite() {
            return Err(p.error(name, format!("expected finite numbers, got {xs:?}")));
        }
        if c.min_element() < 0.0 {
            return Err(p.error(name, format!("must not be negative, got {xs:?}")));
        }
        Ok(Texture::Constant(c))
    }

    /// A number parameter: a number, a texture's table or a texture's name
    /// (read as one value); `None` when it is not there. A number is
    /// returned as it is, for the model's range check.
    pub fn number(&self, p: &Props, name: &str) -> Result<Option<NumberOr>, Invalid> {
        let Some(prop) = p.get(name) else {
            return Ok(None);
        };
        if let Some(t) = self.texture_of(&prop.value)? {
            return Ok(Some(NumberOr::Texture(t)));
        }
        crate::description::props::number(&prop.value).map(|x| Some(NumberOr::Number(x)))
    }
}

/// A number parameter as written: a plain number or a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum NumberOr {
    Number(f32),
    Texture(Texture),
}

#[cfg(test)]
mod tests;
