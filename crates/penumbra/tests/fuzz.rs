//! Random bytes and random mutations of valid scenes, PLY and OBJ files fed
//! to the loaders: none may panic, and each either loads (a valid scene, a
//! mesh whose every index is in range and every position finite) or fails
//! with an error that names the file and stays a few lines long. A thousand
//! cases each, about a second in all.

use std::path::{Path, PathBuf};

use penumbra::geometry::mesh_file::{obj::parse_obj, ply::parse_ply, MeshData};
use penumbra::scene::{LoadOptions, SceneSource};
use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence};

/// Cases per property; no regression files are written into the source tree.
fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..Config::default()
    }
}

const SCENE: &str = r#"# Every kind of table and most keys.
[render]
width = 16
height = 12
max_depth = 2
background = [0.1, 0.2, 0.3]
spp = 4
distribution = "jitter"
filter = "tent"
metric = true

[camera]
position = [0, 1, 5]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov = 40
aperture = 0.05
shutter = [0, 1]

[materials.glass]
albedo = [0.1, 0.1, 0.1]
transparency = 0.8
ior = 1.5
translucency = 0.05

[materials.gold]
albedo = [0.5, 0.4, 0.1]
reflectivity = 0.4
reflection_rays = 4

[[objects]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "glass"
transform_end = { translate = [0.2, 0, 0] }

[[objects]]
type = "quad"
origin = [-5, -1, -5]
edge_u = [10, 0, 0]
edge_v = [0, 0, 10]
material = "gold"

[[objects]]
type = "mesh"
path = "m.obj"
smooth = true
[objects.transform]
scale = [1, 2, 1]
rotate_axis = [0, 1, 0]
rotate_degrees = 30
translate = [1, 0, 0]

[[objects]]
type = "mesh"
path = "m.ply"
transform = { matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]] }

[[lights]]
type = "rect"
origin = [-1, 3, -1]
edge_u = [2, 0, 0]
edge_v = [0, 0, 2]
radiance = [4, 4, 4]
shadow_rays = 4

[[lights]]
type = "point"
position = [0, 4, 0]
intensity = [10, 10, 10]
"#;

const OBJ: &str = "# a square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n\
                   vt 0 0\nf 1//1 2//1 3//1\nf 1/1/1 3/1/1 4/1/1\nf -4 -3 -1\n";

const PLY_ASCII: &str = "ply\nformat ascii 1.0\ncomment a square\nelement vertex 4\n\
                         property float x\nproperty float y\nproperty float z\n\
                         property float nx\nproperty float ny\nproperty float nz\n\
                         element face 2\nproperty list uchar int vertex_indices\n\
                         end_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n\
                         0 1 0 0 0 1\n3 0 1 2\n4 0 1 2 3\n";

/// Texture coordinates on every corner (normals on only some), with every
/// corner form and relative indices.
const OBJ_UV: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1 0\n\
                      vt 0.5\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/4 3/-2 4/-1\n\
                      f -4/-4 -2/-2 -1/1\n";

const PLY_UV_ASCII: &str = "ply\nformat ascii 1.0\nelement vertex 4\n\
                            property float x\nproperty float y\nproperty float z\n\
                            property float u\nproperty float v\nelement face 2\n\
                            property list uchar int vertex_indices\nend_header\n\
                            0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n4 0 1 2 3\n";

/// A square whose vertices carry `s` (uchar) and `t` (double) texture coordinates.
fn ply_uv_binary(big_endian: bool) -> Vec<u8> {
    let order = if big_endian { "big" } else { "little" };
    let mut b = format!(
        "ply\nformat binary_{order}_endian 1.0\nelement vertex 4\nproperty float x\n\
         property float y\nproperty float z\nproperty uchar s\nproperty double t\n\
         element face 1\nproperty list uchar uint vertex_indices\nend_header\n"
    )
    .into_bytes();
    for (i, v) in [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]]
        .into_iter()
        .enumerate()
    {
        for x in v {
            b.extend_from_slice(&if big_endian {
                x.to_be_bytes()
            } else {
                x.to_le_bytes()
            });
        }
        b.push(i as u8);
        let t = i as f64 / 4.0;
        b.extend_from_slice(&if big_endian {
            t.to_be_bytes()
        } else {
            t.to_le_bytes()
        });
    }
    b.push(4);
    for i in 0u32..4 {
        b.extend_from_slice(&if big_endian {
            i.to_be_bytes()
        } else {
            i.to_le_bytes()
        });
    }
    b
}

fn ply_binary(big_endian: bool) -> Vec<u8> {
    let order = if big_endian { "big" } else { "little" };
    let mut b = format!(
        "ply\nformat binary_{order}_endian 1.0\nelement vertex 4\nproperty float x\n\
         property float y\nproperty float z\nelement face 2\n\
         property list uchar uint vertex_indices\nend_header\n"
    )
    .into_bytes();
    let f32b = |x: f32| {
        if big_endian {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    let u32b = |x: u32| {
        if big_endian {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    for v in [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
        for x in v {
            b.extend_from_slice(&f32b(x));
        }
    }
    for face in [&[0u32, 1, 2][..], &[0, 1, 2, 3]] {
        b.push(face.len() as u8);
        for &i in face {
            b.extend_from_slice(&u32b(i));
        }
    }
    b
}

/// One change to a file's bytes; positions are taken modulo its length.
#[derive(Clone, Debug)]
enum Mutation {
    Set(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    /// Repeats a run of bytes many times (a long line, a deep nesting).
    Repeat(usize, usize, usize),
    /// Puts a hostile token in place of a run of bytes.
    Token(usize, usize, &'static str),
}

const TOKENS: &[&str] = &[
    "nan",
    "-nan",
    "inf",
    "-inf",
    "0",
    "-1",
    "-0",
    "1e39",
    "1e-45",
    "4294967295",
    "4294967296",
    "-2147483649",
    "9223372036854775807",
    "99999999999999999999",
    "255",
    "65536",
    "\"\"",
    "[]",
    "[[",
    "]]",
    "{",
    "}",
    ",",
    ".",
    "=",
    "\n",
    "\"",
    "'''",
    "\"\"\"",
    "#",
    "\\",
    "\0",
    "\u{feff}",
    "a.b.c.d.e.f.g.h",
    "@bunny",
    "/dev/zero",
    "m.ply",
    "m.obj",
    "../m.obj",
    "binary_big_endian",
    "ascii",
    "uchar",
    "double",
    "list",
    "end_header",
    "element",
    "vertex",
    "face",
    "f",
    "v",
    "vn",
    "/",
    "//",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Set(i, b)),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(i, b)| Mutation::Insert(i, b)),
        (any::<usize>(), 1usize..64).prop_map(|(i, n)| Mutation::Delete(i, n)),
        (any::<usize>(), 1usize..16, 1usize..2000).prop_map(|(i, n, k)| Mutation::Repeat(i, n, k)),
        (any::<usize>(), 0usize..8, prop::sample::select(TOKENS))
            .prop_map(|(i, n, t)| Mutation::Token(i, n, t)),
    ]
}

fn mutate(original: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let mut b = original.to_vec();
    for m in mutations {
        let at = |i: usize, b: &Vec<u8>| if b.is_empty() { 0 } else { i % (b.len() + 1) };
        match m {
            Mutation::Set(i, x) => {
                if !b.is_empty() {
                    let i = i % b.len();
                    b[i] = *x;
                }
            }
            Mutation::Insert(i, x) => {
                let i = at(*i, &b);
                b.splice(i..i, x.iter().copied());
            }
            Mutation::Delete(i, n) => {
                let i = at(*i, &b);
                let end = (i + n).min(b.len());
                b.drain(i..end);
            }
            Mutation::Repeat(i, n, k) => {
                let i = at(*i, &b);
                let end = (i + n).min(b.len());
                let run = b[i..end].to_vec();
                let copies: Vec<u8> = run.iter().copied().cycle().take(run.len() * k).collect();
                b.splice(end..end, copies);
            }
            Mutation::Token(i, n, t) => {
                let i = at(*i, &b);
                let end = (i + n).min(b.len());
                b.splice(i..end, t.bytes());
            }
        }
    }
    b
}

/// A message that names `file`, stays a few lines long and holds no panic.
fn check_message(message: &str, file: &Path) -> Result<(), TestCaseError> {
    let name = file.display().to_string();
    prop_assert!(
        message.starts_with(&name),
        "does not name {name}: {message}"
    );
    prop_assert!(
        message.len() <= 1200,
        "{} bytes: {}",
        message.len(),
        message
    );
    prop_assert!(message.lines().count() <= 5, "{message}");
    Ok(())
}

/// A directory with the meshes the scene names, and the scene written there.
struct SceneDir {
    dir: tempfile::TempDir,
    scene: PathBuf,
}

impl SceneDir {
    fn new() -> SceneDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m.obj"), OBJ).unwrap();
        std::fs::write(dir.path().join("m.ply"), PLY_ASCII).unwrap();
        let scene = dir.path().join("scene.toml");
        SceneDir { dir, scene }
    }

    /// Loads and builds `bytes` as the scene file, as the command line does.
    fn check(&self, bytes: &[u8]) -> Result<(), TestCaseError> {
        std::fs::write(&self.scene, bytes).unwrap();
        let name = self.scene.to_str().unwrap();
        let result = SceneSource::open(name, &LoadOptions::default()).and_then(|s| s.build());
        match result {
            Ok(scene) => {
                prop_assert!(scene.settings.width >= 1 && scene.settings.height >= 1);
                Ok(())
            }
            Err(e) => {
                let m = e.to_string();
                check_message(&m, &self.scene)?;
                // Every error in a scene file names a line: file:line:column.
                let rest = &m[name.len()..];
                let located =
                    rest.starts_with(':') && rest[1..].starts_with(|c: char| c.is_ascii_digit());
                // Errors about the file itself (its size) name the file alone.
                prop_assert!(located || rest.starts_with(": the file is"), "{m}");
                Ok(())
            }
        }
    }
}

fn check_mesh(
    result: Result<MeshData, penumbra::geometry::mesh_file::MeshError>,
    file: &Path,
) -> Result<(), TestCaseError> {
    match result {
        Ok(mesh) => {
            let n = mesh.positions.len();
            prop_assert!(mesh.positions.iter().flatten().all(|x| x.is_finite()));
            prop_assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
            if let Some(normals) = &mesh.normals {
                prop_assert_eq!(normals.len(), n);
            }
            if let Some(uvs) = &mesh.uvs {
                prop_assert_eq!(uvs.len(), n);
                prop_assert!(uvs.iter().flatten().all(|x| x.is_finite()));
            }
            Ok(())
        }
        Err(e) => check_message(&e.to_string(), file),
    }
}

#[test]
fn the_unmutated_inputs_are_valid() {
    let dir = SceneDir::new();
    std::fs::write(&dir.scene, SCENE).unwrap();
    let name = dir.scene.to_str().unwrap();
    let scene = SceneSource::open(name, &LoadOptions::default()).and_then(|s| s.build());
    assert!(scene.is_ok(), "{:?}", scene.err());
    assert_eq!(
        parse_obj(OBJ.as_bytes(), Path::new("m.obj"))
            .unwrap()
            .triangles
            .len(),
        3
    );
    assert_eq!(
        parse_ply(PLY_ASCII.as_bytes(), Path::new("m.ply"))
            .unwrap()
            .triangles
            .len(),
        3
    );
    for big in [false, true] {
        assert_eq!(
            parse_ply(&ply_binary(big), Path::new("m.ply"))
                .unwrap()
                .triangles
                .len(),
            3
        );
    }
    let uvs = |mesh: MeshData| (mesh.uvs.map(|t| t.len()), mesh.triangles.len());
    let obj = parse_obj(OBJ_UV.as_bytes(), Path::new("m.obj")).unwrap();
    assert_eq!(uvs(obj), (Some(6), 3));
    let ply = parse_ply(PLY_UV_ASCII.as_bytes(), Path::new("m.ply")).unwrap();
    assert_eq!(uvs(ply), (Some(4), 3));
    for big in [false, true] {
        let ply = parse_ply(&ply_uv_binary(big), Path::new("m.ply")).unwrap();
        assert_eq!(uvs(ply), (Some(4), 2));
    }
    drop(dir.dir);
}

proptest! {
    #![proptest_config(config(1000))]

    #[test]
    fn mutated_scenes_load_or_fail_with_their_place(
        mutations in prop::collection::vec(mutation(), 1..6)
    ) {
        thread_local!(static DIR: SceneDir = SceneDir::new());
        DIR.with(|d| d.check(&mutate(SCENE.as_bytes(), &mutations)))?;
    }

    #[test]
    fn random_scene_text_loads_or_fails_with_its_place(
        text in "[\\[\\]{}=.,\"'#a-z_0-9 \\n-]{0,300}"
    ) {
        thread_local!(static DIR: SceneDir = SceneDir::new());
        DIR.with(|d| d.check(text.as_bytes()))?;
    }

    #[test]
    fn random_bytes_as_a_scene_fail_with_its_place(
        bytes in prop::collection::vec(any::<u8>(), 0..1024)
    ) {
        thread_local!(static DIR: SceneDir = SceneDir::new());
        DIR.with(|d| d.check(&bytes))?;
    }

    #[test]
    fn mutated_meshes_load_or_fail_naming_the_file(
        which in 0usize..8,
        mutations in prop::collection::vec(mutation(), 1..6)
    ) {
        let (original, name) = match which {
            0 => (OBJ.as_bytes().to_vec(), "m.obj"),
            1 => (PLY_ASCII.as_bytes().to_vec(), "m.ply"),
            2 => (ply_binary(false), "m.ply"),
            3 => (ply_binary(true), "m.ply"),
            4 => (OBJ_UV.as_bytes().to_vec(), "m.obj"),
            5 => (PLY_UV_ASCII.as_bytes().to_vec(), "m.ply"),
            6 => (ply_uv_binary(false), "m.ply"),
            _ => (ply_uv_binary(true), "m.ply"),
        };
        let bytes = mutate(&original, &mutations);
        let path = Path::new(name);
        let result = if name.ends_with(".obj") {
            parse_obj(&bytes, path)
        } else {
            parse_ply(&bytes, path)
        };
        check_mesh(result, path)?;
    }

    #[test]
    fn random_bytes_as_a_mesh_fail_naming_the_file(
        bytes in prop::collection::vec(any::<u8>(), 0..1024),
        ply_magic in any::<bool>()
    ) {
        let mut b = if ply_magic { b"ply\n".to_vec() } else { Vec::new() };
        b.extend_from_slice(&bytes);
        check_mesh(parse_ply(&b, Path::new("r.ply")), Path::new("r.ply"))?;
        check_mesh(parse_obj(&bytes, Path::new("r.obj")), Path::new("r.obj"))?;
    }
}
