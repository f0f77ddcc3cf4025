//! The shapes of a scene (`[[objects]]` of a scene file): their schemas,
//! and objects of the world made of them, meshes read once per file and
//! kind of normals.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::context::{resolve_mesh_path, BuildContext};
use super::error::BuildError;
use super::transform;
use crate::accel::world::{mesh_bvh, Object};
use crate::description::check::{finite3, finite3_value, nonzero3_value, positive, required};
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::{adapt, Mitsuba, Plugin};
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::cube::cube;
use crate::geometry::mesh_file::read_mesh_part;
use crate::geometry::quad::Quad;
use crate::geometry::{Cylinder, Disk, Mesh, MeshShape, Shape, ShapeModel, Sphere};
use crate::math::{Frame, Mat4, Vec2, Vec3};

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
const COMMON: [Param; 5] = [
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
];

pub const SPHERE: Schema = Schema {
    kind: Kind::Shape,
    plugin: "sphere",
    what: "sphere",
    doc: "a sphere",
    mitsuba: &["sphere"],
    params: &[
        Param::new(
            "center",
            Type::Vector,
            "[0, 0, 0]",
            "centre before the transform",
        ),
        Param::new(
            "radius",
            Type::Number,
            "1",
            "radius > 0 before the transform (a static sphere may only be scaled uniformly)",
        )
        .range(Range::Positive),
        COMMON[0],
        COMMON[1],
        COMMON[2],
        COMMON[3],
        COMMON[4],
    ],
};

pub const QUAD: Schema = Schema {
    kind: Kind::Shape,
    plugin: "quad",
    what: "quad",
    doc: "a parallelogram of a corner and two edges",
    mitsuba: &["rectangle"],
    params: &[
        Param::new("origin", Type::Vector, "required", "one corner").penumbra_only(),
        Param::new("edge_u", Type::Vector, "required", "first edge").penumbra_only(),
        Param::new(
            "edge_v",
            Type::Vector,
            "required",
            "second edge, not parallel to `edge_u`",
        )
        .penumbra_only(),
        COMMON[0],
        COMMON[1].penumbra_only(),
        COMMON[2],
        COMMON[3],
        COMMON[4],
    ],
};

pub const MESH: Schema = Schema {
    kind: Kind::Shape,
    plugin: "mesh",
    what: "mesh",
    doc: "a triangle mesh read from a PLY, OBJ or Mitsuba `.serialized` file",
    mitsuba: &["obj", "ply", "serialized"],
    params: &[
        Param::new("path", Type::Path, "required", "a `.ply` (ASCII, binary little/big endian; triangles and polygons), `.obj` or `.serialized` (Mitsuba's compressed meshes, versions 3 and 4) file, relative to the scene file; `\"@bunny\"` means the Stanford bunny (from `--bunny`, `bunny=` in Python or `$PENUMBRA_BUNNY`)").mitsuba("filename"),
        Param::new("smooth", Type::Bool, "false", "interpolate vertex normals (from the file, else computed, area-weighted); otherwise flat facets").penumbra_only(),
        Param::new("shape_index", Type::Int, "0", "which mesh of a `.serialized` file, which may hold several (0: the first); other files hold one").range(Range::NonNegative),
        Param::new("flip_tex_coords", Type::Bool, "false", "take the file's texture coordinates `(u, v)` as `(u, 1 − v)` (what Mitsuba's OBJ reader does by default; scenes read from Mitsuba XML set it for OBJ files)"),
        COMMON[0],
        COMMON[1],
        COMMON[2],
        COMMON[3],
        COMMON[4],
    ],
};

pub const RECTANGLE: Schema = Schema {
    kind: Kind::Shape,
    plugin: "rectangle",
    what: "rectangle",
    doc: "Mitsuba's rectangle: the square [−1, 1]² at z = 0 placed by the transform, facing +z",
    mitsuba: &[],
    params: &[COMMON[0], COMMON[1], COMMON[2], COMMON[3], COMMON[4]],
};

pub const DISK: Schema = Schema {
    kind: Kind::Shape,
    plugin: "disk",
    what: "disk",
    doc: "a flat disk",
    mitsuba: &["disk"],
    params: &[
        Param::new(
            "center",
            Type::Vector,
            "[0, 0, 0]",
            "centre before the transform",
        )
        .penumbra_only(),
        Param::new(
            "normal",
            Type::Vector,
            "[0, 0, 1]",
            "the side it faces before the transform (non-zero)",
        )
        .penumbra_only(),
        Param::new(
            "radius",
            Type::Number,
            "1",
            "radius > 0 before the transform (a static disk may only be scaled uniformly)",
        )
        .range(Range::Positive)
        .penumbra_only(),
        COMMON[0],
        COMMON[1],
        COMMON[2],
        COMMON[3],
        COMMON[4],
    ],
};

pub const CUBE: Schema = Schema {
    kind: Kind::Shape,
    plugin: "cube",
    what: "cube",
    doc: "Mitsuba's cube: the 24-vertex mesh of [−1, 1]³ placed by the transform",
    mitsuba: &["cube"],
    params: &[COMMON[0], COMMON[1], COMMON[2], COMMON[3], COMMON[4]],
};

pub const CYLINDER: Schema = Schema {
    kind: Kind::Shape,
    plugin: "cylinder",
    what: "cylinder",
    doc: "an open tube between two end points",
    mitsuba: &["cylinder"],
    params: &[
        Param::new(
            "p0",
            Type::Vector,
            "[0, 0, 0]",
            "centre of the first end before the transform",
        ),
        Param::new(
            "p1",
            Type::Vector,
            "[0, 0, 1]",
            "centre of the second end before the transform, ≠ `p0`",
        ),
        Param::new(
            "radius",
            Type::Number,
            "1",
            "radius > 0 before the transform (a static cylinder may only be scaled uniformly)",
        )
        .range(Range::Positive),
        COMMON[0],
        COMMON[1],
        COMMON[2],
        COMMON[3],
        COMMON[4],
    ],
};

pub const INSTANCE: Schema = Schema {
    kind: Kind::Shape,
    plugin: "instance",
    what: "instance",
    doc: "a group of shapes placed by an affine map",
    mitsuba: &["instance"],
    params: &[
        Param::new(
            "group",
            Type::String,
            "required",
            "name of a `[groups.NAME]` table: the shapes placed",
        )
        .penumbra_only(),
        Param::new(
            "transform",
            Type::Table(&transform::PARAMS),
            "identity",
            "placement of the group: any invertible affine map (shear and non-uniform scale included)",
        )
        .mitsuba("to_world"),
    ],
};

/// A group of shapes that instances place (`[groups.NAME]`; its shapes are
/// the node's children).
pub const SHAPEGROUP: Schema = Schema {
    kind: Kind::Shape,
    plugin: "shapegroup",
    what: "group",
    doc: "shapes that instances place, not rendered by themselves",
    mitsuba: &["shapegroup"],
    params: &[],
};

/// How Mitsuba's shapes map onto them.
const MESH_MITSUBA: Mitsuba = Mitsuba {
    differences: "`filename` is required; `face_normals` (default false) as `smooth = !face_normals`; an OBJ's `flip_tex_coords` is true unless given (as Mitsuba's OBJ reader), a PLY's and a `.serialized` file's is read and not applied",
    reads: &["face_normals"],
    adapt: Some(Adapt::Node(adapt::mesh)),
};

/// The shapes as the readers see them.
pub const PLUGINS: [Plugin; 9] = [
    Plugin::new(&SPHERE, Mitsuba::differs("only uniform scale outside a group")),
    Plugin::new(
        &QUAD,
        Mitsuba {
            differences: "the square [−1, 1]² at z = 0 through `to_world` as `origin`, `edge_u`, `edge_v`, ordered so that `edge_u × edge_v` is Mitsuba's normal",
            reads: &["to_world"],
            adapt: Some(Adapt::Node(adapt::rectangle)),
        },
    ),
    Plugin::new(&MESH, MESH_MITSUBA),
    Plugin::new(&RECTANGLE, Mitsuba::SAME),
    Plugin::new(&DISK, Mitsuba::differs("only uniform scale outside a group")),
    Plugin::new(&CUBE, Mitsuba::SAME),
    Plugin::new(
        &CYLINDER,
        Mitsuba::differs(
            "only uniform scale outside a group (Mitsuba also takes an elliptic tube)",
        ),
    ),
    Plugin::new(&INSTANCE, Mitsuba::differs("`<ref id=\"g\"/>` to a shapegroup as `group = \"g\"`")),
    Plugin::new(
        &SHAPEGROUP,
        Mitsuba::differs("`[groups.ID]`; a shape in it may carry an `area` emitter, each instance an emitter of its own (Mitsuba refuses it)"),
    ),
];

/// Every shape of a scene file.
pub const SCHEMAS: [&Schema; 9] = [
    &SPHERE,
    &QUAD,
    &MESH,
    &RECTANGLE,
    &DISK,
    &CUBE,
    &CYLINDER,
    &INSTANCE,
    &SHAPEGROUP,
];

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
}

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
    // Without a transform, a shape is taken as written, with no arithmetic.
    let given = transform::read(p, "transform")?;
    let start = given.unwrap_or(Mat4::IDENTITY);
    let as_written = given.is_none();
    let end = transform::read(p, "transform_end")?;
    let motion = match end {
        Some(end) => Some(transform::motion(p, &start, &end)?),
        None => None,
    };
    let flip_normals = p.bool("flip_normals")?.unwrap_or(false);
    let casts_shadows = p.bool("casts_shadows")?.unwrap_or(true);
    let shape = match plugin {
        "sphere" => {
            let center = finite3(p, "center", [0.0; 3])?;
            let radius = positive(p, "radius", 1.0)?;
            sphere(p, center, radius, &start, as_written || motion.is_some())?
        }
        "rectangle" => {
            let q = Quad::new(Vec3::new(-1.0, -1.0, 0.0), 2.0 * Vec3::X, 2.0 * Vec3::Y);
            Shape::Quad(if motion.is_some() {
                q
            } else {
                transform_rectangle(&q, &start)
            })
        }
        "disk" => {
            let center = finite3(p, "center", [0.0; 3])?;
            let normal = match p.numbers::<3>("normal")? {
                Some(n) => nonzero3_value(p, "normal", n)?.normalize(),
                None => Vec3::Z,
            };
            let radius = positive(p, "radius", 1.0)?;
            let frame = Frame::from_normal(normal);
            if as_written || motion.is_some() {
                Shape::Disk(Disk::new(center, frame, radius))
            } else {
                let s = uniform_scale(p, "disk", &start)?;
                Shape::Disk(placed(Disk::new(center, frame, radius), &start, s))
            }
        }
        "cylinder" => {
            let p0 = finite3(p, "p0", [0.0; 3])?;
            let p1 = finite3(p, "p1", [0.0, 0.0, 1.0])?;
            let radius = positive(p, "radius", 1.0)?;
            let Some(c) = Cylinder::new(p0, p1, radius) else {
                return Err(p.error("p1", "p0 and p1 must differ").into());
            };
            let m = if motion.is_some() {
                Mat4::IDENTITY
            } else {
                start
            };
            let s = uniform_scale(p, "cylinder", &m)?;
            Shape::Cylinder(placed(c, &m, s))
        }
        "cube" => {
            meshes.push(match motion {
                Some(_) => cube(),
                None => cube().transformed(&start),
            });
            Shape::MeshShape(MeshShape::new((meshes.len() - 1) as u32))
        }
        "quad" => {
            let q = quad(p, "quad")?;
            Shape::Quad(if as_written || motion.is_some() {
                q
            } else {
                placed(q, &start, 1.0)
            })
        }
        _ => {
            let file = required(p, p.string("path")?, "path", "mesh")?;
            let read = MeshRead {
                smooth: p.bool("smooth")?.unwrap_or(false),
                flip_tex_coords: p.bool("flip_tex_coords")?.unwrap_or(false),
            };
            let m = load_mesh(p, file, ctx, files, meshes, read)?;
            files.use_mesh(p, meshes[m].triangles.len())?;
            let mesh = if motion.is_some() {
                m
            } else {
                bake(meshes, m, &start)
            };
            Shape::MeshShape(MeshShape::new(mesh as u32))
        }
    };
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

/// Mitsuba's rectangle under `m`: its normal is the transformed +z, so a
/// mirroring transform takes the edges in the other order.
fn transform_rectangle(q: &Quad, m: &Mat4) -> Quad {
    let t = placed(*q, m, 1.0);
    if m.determinant() < 0.0 {
        Quad::new(t.origin, t.edge_v, t.edge_u)
    } else {
        t
    }
}

/// A static sphere stays analytic under translation, rotation and uniform
/// scale; anything else would make an ellipsoid, which we do not support.
/// `as_given`: the sphere is taken as given (a moving one is placed at
/// each ray's time).
fn sphere(
    p: &Props,
    center: Vec3,
    radius: f32,
    m: &Mat4,
    as_given: bool,
) -> Result<Shape, Invalid> {
    if as_given {
        return Ok(Shape::Sphere(Sphere::new(center, radius)));
    }
    let (scale, _, _) = m.to_scale_rotation_translation();
    let s = scale.abs();
    if (s.max_element() - s.min_element()) > 1e-4 * s.max_element() {
        return Err(p.error("transform", "a sphere can only be scaled uniformly"));
    }
    Ok(Shape::Sphere(placed(Sphere::new(center, radius), m, s.x)))
}

/// The parallelogram of `origin`, `edge_u` and `edge_v` (`what` names the
/// object in messages).
pub(super) fn quad(p: &Props, what: &str) -> Result<Quad, Invalid> {
    let origin = required(p, p.numbers::<3>("origin")?, "origin", what)?;
    let origin = finite3_value(p, "origin", origin)?;
    let eu = required(p, p.numbers::<3>("edge_u")?, "edge_u", what)?;
    let eu = nonzero3_value(p, "edge_u", eu)?;
    let ev = required(p, p.numbers::<3>("edge_v")?, "edge_v", what)?;
    let ev = nonzero3_value(p, "edge_v", ev)?;
    if eu.cross(ev).length() <= 1e-6 * eu.length() * ev.length() {
        return Err(p.error("edge_v", "edge_u and edge_v must not be parallel"));
    }
    Ok(Quad::new(origin, eu, ev))
}

/// How a mesh is made of its file's data: with its vertex normals (else
/// flat facets), with `v` of its texture coordinates flipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct MeshRead {
    smooth: bool,
    flip_tex_coords: bool,
}

fn load_mesh(
    p: &Props,
    file: &str,
    ctx: &BuildContext,
    files: &mut MeshFiles,
    meshes: &mut Vec<Mesh>,
    read: MeshRead,
) -> Result<usize, BuildError> {
    let path = resolve_mesh_path(p, file, ctx)?;
    let index = match p.int("shape_index")?.unwrap_or(0) {
        i @ 0..=0xFFFF_FFFF => i as u32,
        i => {
            return Err(p
                .error("shape_index", format!("must be at least 0, got {i}"))
                .into())
        }
    };
    let key = (FileKey::of(&path), index);
    if let Some(&i) = files.cache.get(&(key.0.clone(), index, read)) {
        return Ok(i);
    }
    if !files.files.contains_key(&key) {
        let data = read_mesh_part(&path, index).map_err(|error| BuildError::Mesh {
            origin: p
                .origin("path")
                .cloned()
                .unwrap_or_else(|| p.node_origin().clone()),
            error,
        })?;
        if data.triangles.is_empty() {
            return Err(p
                .error("path", format!("{} has no faces", path.display()))
                .into());
        }
        files.read += data.triangles.len() as u64;
        files.files.insert(key.clone(), data);
    }
    let data = &files.files[&key];
    let mut mesh = Mesh {
        positions: data
            .positions
            .iter()
            .map(|&v| Vec3::from_array(v))
            .collect(),
        normals: data.normals.as_ref().map(|ns| {
            ns.iter()
                .map(|&n| Vec3::from_array(n).normalize_or_zero())
                .collect()
        }),
        uvs: data.uvs.as_ref().map(|uvs| {
            uvs.iter()
                .map(|&[u, v]| Vec2::new(u, if read.flip_tex_coords { 1.0 - v } else { v }))
                .collect()
        }),
        triangles: data.triangles.clone(),
    };
    if !read.smooth {
        mesh.normals = None;
    } else if mesh.normals.is_none() {
        mesh.compute_vertex_normals();
    }
    meshes.push(mesh);
    files.cache.insert((key.0, index, read), meshes.len() - 1);
    Ok(meshes.len() - 1)
}

/// A static mesh baked into world space (cached meshes are copied first).
fn bake(meshes: &mut Vec<Mesh>, index: usize, m: &Mat4) -> usize {
    let baked = meshes[index].transformed(m);
    meshes.push(baked);
    meshes.len() - 1
}

#[cfg(test)]
mod tests {
    use crate::math::{Ray, Vec3};
    use crate::scene::{LoadOptions, SceneSource};

    /// An octahedron: smooth normals differ from the facets' everywhere
    /// but at the face centres.
    const OCTAHEDRON: &str = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
        f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

    /// Two objects share one mesh file, one flat and one smooth: each gets
    /// its own normals, whichever comes first (the cache keys a mesh by its
    /// file and its normals, not by its file alone).
    #[test]
    fn objects_sharing_a_file_keep_their_own_normals() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("o.obj"), OCTAHEDRON).unwrap();
        let object = |x: f32, smooth: bool| {
            format!(
                "[[objects]]\ntype = \"mesh\"\npath = \"o.obj\"\nsmooth = {smooth}\n\
                 transform = {{ translate = [{x}, 0, 0] }}\n"
            )
        };
        for first_smooth in [false, true] {
            let text = object(-2.0, first_smooth) + &object(2.0, !first_smooth);
            let src = SceneSource::from_toml(
                &text,
                std::path::Path::new("t.toml"),
                dir.path(),
                &LoadOptions::default(),
            )
            .unwrap();
            let scene = src.build().unwrap();
            // A ray at each object, off the centre of the face it hits.
            for (x, smooth) in [(-2.0, first_smooth), (2.0, !first_smooth)] {
                let ray = Ray::new(Vec3::new(x + 0.2, 0.1, 5.0), -Vec3::Z, 0.0);
                let hit = scene.world.intersect(&ray, 0.0, f32::INFINITY).unwrap();
                let bent = hit.n.dot(hit.ng) < 0.9999;
                assert_eq!(
                    bent, smooth,
                    "object at x = {x}, smooth first: {first_smooth}"
                );
            }
        }
    }

    /// `flip_tex_coords` takes `v` of the file's texture coordinates as
    /// `1 − v`, `u` kept; two objects of one file, flipped and not, each
    /// get their own (hit at the same point of the square).
    #[test]
    fn flip_tex_coords_flips_v() {
        let dir = tempfile::tempdir().unwrap();
        let square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
            vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
        std::fs::write(dir.path().join("s.obj"), square).unwrap();
        let object = |x: f32, flip: &str| {
            format!(
                "[[objects]]\ntype = \"mesh\"\npath = \"s.obj\"\n{flip}\n\
                 transform = {{ translate = [{x}, 0, 0] }}\n"
            )
        };
        let text = object(-2.0, "flip_tex_coords = true")
            + &object(2.0, "")
            + &object(5.0, "flip_tex_coords = false");
        let src = SceneSource::from_toml(
            &text,
            std::path::Path::new("t.toml"),
            dir.path(),
            &LoadOptions::default(),
        )
        .unwrap();
        let scene = src.build().unwrap();
        let (u, v) = (0.3, 0.2);
        let uv_at = |x: f32| {
            let ray = Ray::new(Vec3::new(x + u, v, 5.0), -Vec3::Z, 0.0);
            scene.world.intersect(&ray, 0.0, f32::INFINITY).unwrap().uv
        };
        let close = |a: crate::math::Vec2, b: (f32, f32)| {
            (a.x - b.0).abs() < 1e-5 && (a.y - b.1).abs() < 1e-5
        };
        assert!(close(uv_at(-2.0), (u, 1.0 - v)), "{}", uv_at(-2.0));
        assert!(close(uv_at(2.0), (u, v)), "{}", uv_at(2.0));
        assert!(close(uv_at(5.0), (u, v)), "{}", uv_at(5.0));
    }
}
