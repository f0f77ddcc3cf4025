//! The shapes of a scene (`[[objects]]` of a scene file): one file per
//! shape plugin, with its schema, how Mitsuba's plugin maps onto it and
//! its builder; the list below makes the registry. Objects of the world
//! are made of them, meshes read once per file and kind of normals.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::context::BuildContext;
use super::error::BuildError;
use super::transform;
use crate::accel::world::{mesh_bvh, Object};
use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Param, Props, Schema, Type};
use crate::geometry::{Mesh, Shape, ShapeModel};
use crate::math::Mat4;

mod group;

/// Triangles a scene may always hold, counting a mesh once for every
/// object that uses it (each is a copy in world space, or a BVH of its own).
pub const INSTANCED_TRIANGLES: u64 = 1 << 22;

/// How many times the triangles of its mesh files a scene may hold, when
/// that is more than [`INSTANCED_TRIANGLES`]: objects sharing a mesh
/// multiply it, and a few hundred bytes of scene naming one small mesh
/// thousands of times would otherwise fill memory (as entities do in the
/// "billion laughs" of XML, whose parsers bound the same ratio).
pub const INSTANCING_FACTOR: u64 = 16;

/// The keys every object has besides its shape's.
/// How Mitsuba's analytic shapes map: through the schema, with
/// `differences`, reading `silhouette_sampling_weight`, which weights
/// Mitsuba's projective sampling of derivatives only and changes nothing in
/// a rendered image.
const fn analytic(differences: &'static str) -> Mitsuba {
    Mitsuba {
        differences,
        reads: &["silhouette_sampling_weight"],
        adapt: None,
    }
}

const COMMON: [Param; 7] = [
    Param::new(
        "material",
        Type::Material,
        "the default material",
        "name of a `[materials.NAME]` table",
    ),
    Param::new(
        "transform",
        Type::Table(&transform::PARAMS),
        "identity",
        "placement (at frame time 0)",
    )
    .mitsuba("to_world"),
    Param::new(
        "transform_end",
        Type::Table(&transform::PARAMS),
        "none",
        "placement at frame time 1: the object moves during the exposure",
    )
    .penumbra_only(),
    Param::new(
        "flip_normals",
        Type::Bool,
        "false",
        "turn the normals the other way: into a sphere, cube or cylinder, against a flat shape's or a mesh's winding (a one-sided light then emits to the other side)",
    ),
    Param::new(
        "casts_shadows",
        Type::Bool,
        "true",
        "whether it blocks shadow rays; `false` lets light through it, as through a `[[lights]]` light's surface (Cycles' shadow visibility)",
    )
    .penumbra_only(),
    Param::new(
        "interior",
        Type::String,
        "none",
        "name of the `[media.NAME]` medium inside the shape (Mitsuba's nested `interior` medium); \
         its surface should then be a `null` material where the medium has no visible boundary",
    )
    .penumbra_only(),
    Param::new(
        "exterior",
        Type::String,
        "none",
        "name of the `[media.NAME]` medium outside the shape (Mitsuba's nested `exterior` medium)",
    )
    .penumbra_only(),
];

/// Makes the shapes' registry from one line per shape plugin (a module
/// holding its `SCHEMA`, `MITSUBA` and `build`): their schemas, their
/// plugins as the readers see them, then the group's and the instance's,
/// and the builder by name.
macro_rules! shapes {
    ($($plugin:ident,)*) => {
        $(mod $plugin;)*

        /// Every shape of a scene file, in the order messages list them.
        pub const SCHEMAS: &[&Schema] = &[
            $(&$plugin::SCHEMA,)*
            &group::INSTANCE,
            &group::SHAPEGROUP,
        ];

        /// The shapes as the readers see them.
        pub const PLUGINS: &[Plugin] = &[
            $(Plugin::new(&$plugin::SCHEMA, $plugin::MITSUBA),)*
            Plugin::new(&group::INSTANCE, group::INSTANCE_MITSUBA),
            Plugin::new(&group::SHAPEGROUP, group::SHAPEGROUP_MITSUBA),
        ];

        /// The shape `plugin` of the parameters `p`, placed by `at`;
        /// `None` for a name no shape plugin has (a group, an instance).
        fn build(
            plugin: &str,
            p: &Props,
            at: &Placing,
            load: &mut Loading,
        ) -> Option<Result<Shape, BuildError>> {
            $(if plugin == $plugin::SCHEMA.plugin {
                return Some($plugin::build(p, at, load));
            })*
            None
        }
    };
}

// The shape plugins: one line each.
shapes! {
    sphere,
    quad,
    mesh,
    rectangle,
    disk,
    cube,
    cylinder,
}

use mesh::MeshRead;

/// Where an object is, as its shape's builder reads it.
struct Placing {
    /// Its transform at frame time 0 (the identity if none is given).
    start: Mat4,
    /// No transform is given: the shape is taken as written, with no
    /// arithmetic.
    as_written: bool,
    /// It moves (`transform_end`): the shape stays in its own space.
    moving: bool,
}

/// Where a shape's builder loads meshes: the scene's context, its meshes
/// so far and the files read.
struct Loading<'a> {
    ctx: &'a BuildContext,
    meshes: &'a mut Vec<Mesh>,
    files: &'a mut MeshFiles,
}

/// The meshes read so far (each file once) and the triangles the objects
/// using them add up to.
#[derive(Default)]
pub(super) struct MeshFiles {
    /// Meshes by file, mesh in the file and how it is read (normals,
    /// texture coordinates): a file named by several paths (`m.ply`,
    /// `./m.ply`, a link to it) is read once, and counted once in `read`;
    /// objects that use it flat and smooth, or flipped and not, get a mesh
    /// each.
    cache: HashMap<(FileKey, u32, MeshRead), usize>,
    /// Triangles in the files read.
    read: u64,
    /// Files read.
    files: HashMap<(FileKey, u32), crate::geometry::mesh_file::MeshData>,
    /// Triangles of the objects, a mesh counted once for each object using it.
    used: u64,
    /// The attributes of the meshes read from files (a PLY file's vertex
    /// colours...), by mesh, and the file each was read from.
    pub(super) attributes: HashMap<usize, MeshAttributes>,
}

/// A mesh's attributes and the file they were read from.
pub(crate) type MeshAttributes = (
    Arc<[Arc<crate::geometry::mesh_file::MeshAttribute>]>,
    PathBuf,
);

/// Which file a path names: on Unix its device and inode, elsewhere its
/// canonical path (the path as given if it cannot be resolved; reading it
/// then fails with the error to report).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum FileKey {
    Inode(u64, u64),
    Path(PathBuf),
}

impl FileKey {
    fn of(path: &Path) -> FileKey {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            // stat only: it follows links and never blocks, whatever the file is.
            if let Ok(m) = std::fs::metadata(path) {
                return FileKey::Inode(m.dev(), m.ino());
            }
        }
        FileKey::Path(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()))
    }
}

impl MeshFiles {
    /// Counts an object's use of a mesh of `triangles`, refusing it past the
    /// instancing bound.
    fn use_mesh(&mut self, p: &Props, triangles: usize) -> Result<(), Invalid> {
        let used = self.used + triangles as u64;
        let limit = INSTANCED_TRIANGLES.max(INSTANCING_FACTOR * self.read);
        if used > limit {
            return Err(p.error(
                "path",
                format!(
                    "the objects so far use meshes of {used} triangles in all (a mesh counted \
                     once for each object using it), more than a scene may: {INSTANCED_TRIANGLES} \
                     or {INSTANCING_FACTOR} times the {} triangles of its mesh files",
                    self.read
                ),
            ));
        }
        self.used = used;
        Ok(())
    }
}

/// The object of shape `plugin` with the parameters `p` (its material
/// already resolved), its mesh loaded into `meshes` (and baked into world
/// space when it does not move).
pub(super) fn object(
    plugin: &str,
    p: &Props,
    material: u32,
    ctx: &BuildContext,
    meshes: &mut Vec<Mesh>,
    files: &mut MeshFiles,
) -> Result<Object, BuildError> {
    let given = transform::read(p, "transform")?;
    let start = given.unwrap_or(Mat4::IDENTITY);
    let end = transform::read(p, "transform_end")?;
    let motion = match end {
        Some(end) => Some(transform::motion(p, &start, &end)?),
        None => None,
    };
    let flip_normals = p.bool("flip_normals")?.unwrap_or(false);
    let casts_shadows = p.bool("casts_shadows")?.unwrap_or(true);
    let at = Placing {
        start,
        as_written: given.is_none(),
        moving: motion.is_some(),
    };
    let mut load = Loading { ctx, meshes, files };
    let Some(shape) = build(plugin, p, &at, &mut load) else {
        return Err(p
            .node_error(format!("`{plugin}` is not a shape an object takes"))
            .into());
    };
    let shape = shape?;
    let mesh_bvh = match (shape.as_mesh(), motion) {
        (Some(mesh), Some(_)) => Some(mesh_bvh(&meshes[mesh.mesh as usize])),
        _ => None,
    };
    Ok(Object {
        shape,
        material,
        emitter: None,
        casts_shadows,
        motion,
        placement: None,
        flip_normals,
        mesh_bvh,
    })
}

/// The uniform scale of a placement `m` of a shape that stays analytic
/// (`what`) only under rotation, translation and uniform scale.
fn uniform_scale(p: &Props, what: &str, m: &Mat4) -> Result<f32, Invalid> {
    let (scale, _, _) = m.to_scale_rotation_translation();
    let s = scale.abs();
    if (s.max_element() - s.min_element()) > 1e-4 * s.max_element() {
        return Err(p.error(
            "transform",
            format!("a {what} can only be scaled uniformly"),
        ));
    }
    Ok(s.x)
}

/// The analytic shape `s` carried by the similarity `m` of scale `scale`
/// (see [`ShapeModel::transformed`]).
fn placed<S: ShapeModel + Copy>(s: S, m: &Mat4, scale: f32) -> S {
    s.transformed(m, scale).unwrap_or(s)
}
