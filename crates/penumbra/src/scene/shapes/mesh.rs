//! The `mesh` shape, a triangle mesh read from a file (Mitsuba's `obj`,
//! `ply` and `serialized`): its schema and builder, and the reading of its
//! file, once per file and kind of normals.

use std::sync::Arc;

use super::{FileKey, Loading, MeshFiles, Placing, COMMON};
use crate::description::check::required;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::{adapt, Mitsuba};
use crate::description::{Kind, Param, Props, Range, Schema, Type};
use crate::geometry::mesh_file::read_mesh_part;
use crate::geometry::{Mesh, MeshShape, Shape};
use crate::math::{Mat4, Vec2, Vec3};
use crate::scene::context::{resolve_mesh_path, BuildContext};
use crate::scene::BuildError;

pub const SCHEMA: Schema = Schema {
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
        COMMON[5],
        COMMON[6],
    ],
};

/// How Mitsuba's mesh plugins map onto it.
pub const MITSUBA: Mitsuba = Mitsuba {
    differences: "`filename` is required; `face_normals` (default false) as `smooth = !face_normals`; an OBJ's `flip_tex_coords` is true unless given (as Mitsuba's OBJ reader), a PLY's false unless given, a `.serialized` file's read and not applied (as Mitsuba's readers)",
    reads: &["face_normals"],
    adapt: Some(Adapt::Node(adapt::mesh)),
};

/// The mesh of the parameters `p`, its file read into `load` (once), baked
/// into world space by `at` when it does not move.
pub(super) fn build(p: &Props, at: &Placing, load: &mut Loading) -> Result<Shape, BuildError> {
    let file = required(p, p.string("path")?, "path", "mesh")?;
    let read = MeshRead {
        smooth: p.bool("smooth")?.unwrap_or(false),
        flip_tex_coords: p.bool("flip_tex_coords")?.unwrap_or(false),
    };
    let m = load_mesh(p, file, load.ctx, load.files, load.meshes, read)?;
    load.files.use_mesh(p, load.meshes[m].triangles.len())?;
    let mesh = if at.moving {
        m
    } else {
        bake(load.meshes, m, &at.start)
    };
    if let Some(a) = load.files.attributes.get(&m).cloned() {
        load.files.attributes.insert(mesh, a);
    }
    Ok(Shape::MeshShape(MeshShape::new(mesh as u32)))
}

/// How a mesh is made of its file's data: with its vertex normals (else
/// flat facets), with `v` of its texture coordinates flipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) struct MeshRead {
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
    let values = data.attributes.iter().cloned().map(Arc::new).collect();
    files.attributes.insert(meshes.len() - 1, (values, path.clone()));
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

    /// A square of two triangles whose corners are red, green, blue and
    /// white (`uchar`), with a float `heat_0` per vertex and a `grade_x`
    /// per face.
    const SQUARE_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\n\
        property float x\nproperty float y\nproperty float z\n\
        property uchar red\nproperty uchar green\nproperty uchar blue\n\
        property float heat_0\n\
        element face 2\nproperty list uchar int vertex_indices\nproperty float grade_x\n\
        end_header\n\
        0 0 0 255 0 0 0\n1 0 0 0 255 0 1\n1 1 0 0 0 255 2\n0 1 0 255 255 255 3\n\
        3 0 1 2 0.25\n3 0 2 3 0.75\n";

    /// `mesh_attribute` reads the mesh hit: a vertex attribute interpolated
    /// with the hit's barycentric weights (at (0.6, 0.3) on the triangle
    /// (0,0), (1,0), (1,1) they are 0.4, 0.3, 0.3), a face attribute
    /// constant on its face, times `scale`; as one value, a colour is 0.
    #[test]
    fn mesh_attributes_are_read_at_the_hit() {
        use crate::bsdf::Bsdf;
        use crate::math::Vec2;

        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("s.ply"), SQUARE_PLY).unwrap();
        let object = |x: f32, material: &str| {
            format!(
                "[[objects]]\ntype = \"mesh\"\npath = \"s.ply\"\nmaterial = \"{material}\"\n\
                 transform = {{ translate = [{x}, 0, 0] }}\n"
            )
        };
        let material = |name: &str, attribute: &str| {
            format!(
                "[materials.{name}]\ntype = \"diffuse\"\n\
                 reflectance = {{ type = \"mesh_attribute\", name = \"{attribute}\", scale = 0.5 }}\n"
            )
        };
        let text = material("colour", "vertex_color")
            + &material("heat", "vertex_heat")
            + "[textures.grade]\ntype = \"mesh_attribute\"\nname = \"face_grade\"\n"
            + "[materials.grade]\ntype = \"diffuse\"\nreflectance = \"grade\"\n"
            + &object(0.0, "colour")
            + &object(2.0, "heat")
            + &object(4.0, "grade");
        let build = |text: &str| {
            SceneSource::from_toml(
                text,
                std::path::Path::new("t.toml"),
                dir.path(),
                &LoadOptions::default(),
            )
            .and_then(|s| s.build())
        };
        let scene = build(&text).unwrap_or_else(|e| panic!("{e}"));
        let at = |x: f32, y: f32| {
            let ray = Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z, 0.0);
            let hit = scene.world.intersect(&ray, 0.0, f32::INFINITY).unwrap();
            let Bsdf::Diffuse(d) = &scene.bsdfs[hit.material as usize] else {
                panic!("a diffuse")
            };
            (d.reflectance.eval(&hit), d.reflectance.eval_1(&hit), hit)
        };
        let close = |a: crate::math::Rgb, b: [f32; 3]| {
            (a - crate::math::Rgb::from_array(b)).abs().max_element() < 1e-5
        };
        let (c, one, hit) = at(0.6, 0.3);
        assert!((hit.bary - Vec2::new(0.3, 0.3)).length() < 1e-5, "{}", hit.bary);
        assert!(close(c, [0.2, 0.15, 0.15]), "{c:?}");
        assert_eq!(one, 0.0);
        // On the other triangle (0,0), (1,1), (0,1): 0.4 red, 0.3 blue, 0.3
        // white, halved.
        let (c, _, _) = at(0.3, 0.6);
        assert!(close(c, [0.35, 0.15, 0.3]), "{c:?}");
        // One value: 0.4 · 0 + 0.3 · 1 + 0.3 · 2, halved.
        let (c, one, _) = at(2.6, 0.3);
        assert!(close(c, [0.45; 3]), "{c:?}");
        assert!((one - 0.45).abs() < 1e-5);
        let (c, _, _) = at(4.6, 0.3);
        assert_eq!(c, crate::math::Rgb::splat(0.25));
        let (c, _, _) = at(4.3, 0.6);
        assert_eq!(c, crate::math::Rgb::splat(0.75));

        // An attribute the file does not have, at the texture, naming the
        // file and what it has; a shape that is no mesh file has none.
        let e = build(&(material("m", "vertex_nothing") + &object(0.0, "m")))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("materials.m.reflectance"), "{e}");
        assert!(e.contains("s.ply has no attribute `vertex_nothing`"), "{e}");
        assert!(e.contains("it has: vertex_color, vertex_heat, face_grade"), "{e}");
        let e = build(&(material("m", "vertex_color") + "[[objects]]\ntype = \"sphere\"\nmaterial = \"m\"\n"))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("not a mesh read from a file"), "{e}");
        // Values that are not finite are kept in the file's attributes and
        // refused where a texture reads them.
        let huge = SQUARE_PLY.replace("0 0 0 255 0 0 0\n", "0 0 0 255 0 0 1e300\n");
        std::fs::write(dir.path().join("h.ply"), huge).unwrap();
        let mut text = material("m", "vertex_heat") + &object(0.0, "m");
        text = text.replace("s.ply", "h.ply");
        let e = build(&text).err().unwrap().to_string();
        assert!(e.contains("the attribute `vertex_heat` of the mesh file"), "{e}");
        assert!(e.contains("h.ply holds values that are not finite"), "{e}");
        let e = build(&material("m", "color")).err().unwrap().to_string();
        assert!(e.contains("must start with `vertex_` or `face_`"), "{e}");
        let e = build(
            "[materials.m]\ntype = \"diffuse\"\nreflectance = { type = \"checkerboard\", color0 = { type = \"mesh_attribute\", name = \"vertex_color\" } }\n",
        )
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains("not inside a checkerboard"), "{e}");
    }
}
