//! A corpus of hostile and malformed scenes and meshes, each rendered by the
//! `penumbra` binary at 32×24 and 1 sample per pixel into a path that already
//! holds a file, under a 4 GiB address-space cap (on Linux).
//!
//! Every case must: exit (within 20 s, within 1 s for FIFOs and devices),
//! not panic or die of a signal, peak under 1 GiB of memory (on Linux), exit
//! with status 2 and an error naming the file and line (the file alone for
//! errors about the file itself), or with status 0 and a PNG where the input
//! is valid; leave the existing output byte-identical on error; leave no
//! other file behind; and print a short message.

use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What is in one file of a case's directory.
enum Entry {
    Bytes(Vec<u8>),
    Dir,
    /// A symbolic link to this target.
    Link(&'static str),
    /// A named pipe no one writes to.
    Fifo,
    /// A sparse file of this many zero bytes.
    Sparse(u64),
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Expect {
    /// Status 2, naming the scene file and a line in it.
    SceneLine,
    /// Status 2, naming this file (no line: the file itself is refused).
    File(&'static str),
    /// Status 2, at a line of the scene, naming this mesh or image file.
    Mesh(&'static str),
    /// Status 0 and a 32×24 PNG.
    Valid,
}

struct Case {
    name: String,
    entries: Vec<(&'static str, Entry)>,
    expect: Expect,
    /// Leave the size and sample-count flags out: the scene's values hold.
    bare: bool,
    /// Seconds it may take.
    limit: u64,
}

const OLD_OUTPUT: &[u8] = b"an image rendered earlier, to be kept";

/// The scene around a mesh: a camera looking at it, and a light.
fn mesh_scene(path: &str) -> String {
    format!(
        "[camera]\nposition = [0.5, 0.5, 3]\nlook_at = [0.5, 0.5, 0]\n\n\
         [[objects]]\ntype = \"mesh\"\npath = \"{path}\"\n\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 2, 3]\nintensity = [5, 5, 5]\n"
    )
}

const PLY_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                        property float y\nproperty float z\nelement face 1\n\
                        property list uchar int vertex_indices\nend_header\n";

/// [`PLY_HEAD`] with texture coordinates `u`, `v` after the position.
const PLY_UV_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                           property float y\nproperty float z\nproperty float u\n\
                           property float v\nelement face 1\n\
                           property list uchar int vertex_indices\nend_header\n";

fn binary_ply(vertices: u64, faces: u64, body: &[u8]) -> Vec<u8> {
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\n\
         property float x\nproperty float y\nproperty float z\nelement face {faces}\n\
         property list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    b.extend_from_slice(body);
    b
}

fn valid_binary_ply() -> Vec<u8> {
    binary_ply(3, 1, &binary_body())
}

/// Three vertices and one triangle, little-endian.
fn binary_body() -> Vec<u8> {
    let mut body = Vec::new();
    for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        for x in v {
            body.extend_from_slice(&x.to_le_bytes());
        }
    }
    body.push(3);
    for i in [0i32, 1, 2] {
        body.extend_from_slice(&i.to_le_bytes());
    }
    body
}

fn corpus() -> Vec<Case> {
    let mut cases = Vec::new();
    let mut scene = |name: &str, text: Vec<u8>, expect: Expect| {
        cases.push(Case {
            name: name.to_string(),
            entries: vec![("scene.toml", Entry::Bytes(text))],
            expect,
            bare: false,
            limit: 20,
        });
    };
    use Expect::*;
    let s = |t: &str| t.as_bytes().to_vec();
    let mega = "x".repeat(1 << 20);

    // Text that is not a scene.
    scene("empty", s(""), Valid);
    scene("comment only", s("# nothing here\n"), Valid);
    scene("NUL bytes", vec![0; 4096], SceneLine);
    scene(
        "not UTF-8",
        b"[render]\nwidth = 32\n\xff\xfe\xfd\n".to_vec(),
        SceneLine,
    );
    scene(
        "binary noise",
        (0..65536u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect(),
        SceneLine,
    );
    scene("unclosed header", s("[render\nwidth = 3\n"), SceneLine);
    // Pixel filters' parameters out of range, or of another filter.
    for text in [
        "[render]\nfilter = \"lanczos\"\nfilter_lobes = 0\n",
        "[render]\nfilter = \"lanczos\"\nfilter_lobes = 9223372036854775807\n",
        "[render]\nfilter = \"gaussian\"\nfilter_stddev = -1.0\n",
        "[render]\nfilter = \"gaussian\"\nfilter_stddev = 1e40\n",
        "[render]\nfilter = \"tent\"\nfilter_radius = nan\n",
        "[render]\nfilter = \"mitchell\"\nfilter_b = -0.5\n",
        "[render]\nfilter_c = 0.5\n",
    ] {
        scene(&format!("filter {text:?}"), s(text), SceneLine);
    }
    // Filters far narrower and far wider than a pixel are filters still.
    for text in [
        "[render]\nfilter = \"gaussian\"\nfilter_stddev = 1e-40\n",
        "[render]\nfilter = \"gaussian\"\nfilter_stddev = 1e30\n",
        "[render]\nfilter = \"tent\"\nfilter_radius = 3e38\n",
        "[render]\nfilter = \"lanczos\"\nfilter_lobes = 32\nspp = 4\n",
    ] {
        scene(&format!("filter {text:?}"), s(text), Valid);
    }

    // Shapes and instances.
    let group = "[[groups.g.objects]]\ntype = \"cube\"\n";
    let instance = |t: &str| format!("{group}[[objects]]\ntype = \"instance\"\ngroup = \"g\"\n{t}");
    scene("instances", s(&instance("")), Valid);
    scene(
        "instance with a singular matrix",
        s(&instance(
            "transform = { matrix = [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]] }\n",
        )),
        SceneLine,
    );
    scene(
        "instance of an unknown group",
        s("[[objects]]\ntype = \"instance\"\ngroup = \"none\"\n"),
        SceneLine,
    );
    scene(
        "group holding an instance of itself",
        s("[[groups.g.objects]]\ntype = \"instance\"\ngroup = \"g\"\n\
           [[objects]]\ntype = \"instance\"\ngroup = \"g\"\n"),
        SceneLine,
    );
    scene(
        "cylinder of zero radius",
        s("[[objects]]\ntype = \"cylinder\"\nradius = 0\n"),
        SceneLine,
    );
    scene(
        "cylinder with equal ends",
        s("[[objects]]\ntype = \"cylinder\"\np0 = [1, 1, 1]\np1 = [1, 1, 1]\n"),
        SceneLine,
    );
    scene(
        "unclosed string",
        s("[render]\nfilter = \"box\n"),
        SceneLine,
    );
    scene(
        "duplicate key",
        s("[render]\nwidth = 3\nwidth = 4\n"),
        SceneLine,
    );
    scene("duplicate table", s("[render]\n[render]\n"), SceneLine);

    // Bombs: huge values, huge arrays, deep nesting.
    scene(
        "megabyte string",
        format!("[render]\nfilter = \"{mega}\"\n").into_bytes(),
        SceneLine,
    );
    scene(
        "megabyte key",
        format!("[render]\n{mega} = 1\n").into_bytes(),
        SceneLine,
    );
    scene(
        "megabyte type",
        format!("[[objects]]\ntype = \"{mega}\"\n").into_bytes(),
        SceneLine,
    );
    scene(
        "megabyte material name",
        format!("[[objects]]\ntype = \"sphere\"\nmaterial = \"{mega}\"\n").into_bytes(),
        SceneLine,
    );
    scene(
        "megabyte table name",
        format!("[materials.{mega}]\nior = 0.1\n").into_bytes(),
        SceneLine,
    );
    scene(
        "megabyte bare value",
        format!("[render]\nwidth = {mega}\n").into_bytes(),
        SceneLine,
    );
    scene(
        "megabyte mesh path",
        format!("[[objects]]\ntype = \"mesh\"\npath = \"{mega}.ply\"\n").into_bytes(),
        SceneLine,
    );
    scene(
        "megabyte comment",
        format!("# {mega}\n[render]\nwidth = 8\n").into_bytes(),
        Valid,
    );
    let numbers = vec!["0.5"; 100_000].join(", ");
    scene(
        "background of 100,000 numbers",
        format!("[render]\nbackground = [{numbers}]\n").into_bytes(),
        SceneLine,
    );
    scene(
        "array of 2 million numbers",
        format!("[render]\nbackground = [{}]\n", "1,".repeat(2_000_000)).into_bytes(),
        SceneLine,
    );
    scene(
        "100,000 materials",
        (0..100_000)
            .map(|i| format!("[materials.m{i}]\n"))
            .collect::<String>()
            .into_bytes(),
        Valid,
    );
    scene(
        "materials holding each other in a loop",
        s("[materials.a]\ntype = \"mask\"\nbsdf = \"b\"\n\n[materials.b]\ntype = \"blendbsdf\"\nbsdf_0 = \"a\"\nbsdf_1 = \"a\"\n"),
        SceneLine,
    );
    scene(
        "50,000 materials each holding the next",
        (0..50_000)
            .map(|i| {
                format!(
                    "[materials.m{i}]\ntype = \"twosided\"\nbsdf = \"m{}\"\n",
                    i + 1
                )
            })
            .chain(["[materials.m50000]\ntype = \"diffuse\"\n".to_string()])
            .collect::<String>()
            .into_bytes(),
        SceneLine,
    );
    scene(
        "60,000 spheres",
        "[[objects]]\ntype = \"sphere\"\nradius = 0.1\n"
            .repeat(60_000)
            .into_bytes(),
        Valid,
    );
    scene(
        "scene over 4 MiB",
        format!("# {}\n", "y".repeat(5 << 20)).into_bytes(),
        File("scene.toml"),
    );
    let key = vec!["a"; 5000].join(".");
    scene(
        "dotted key 5000 deep",
        format!("[render]\nwidth = 3\n{key} = 1\n").into_bytes(),
        SceneLine,
    );
    scene(
        "table header 5000 deep",
        format!("[{key}]\n").into_bytes(),
        SceneLine,
    );
    scene(
        "array of tables 5000 deep",
        format!("[[{key}]]\n").into_bytes(),
        SceneLine,
    );
    scene(
        "inline dotted key 5000 deep",
        format!("x = {{ {key} = 1 }}\n").into_bytes(),
        SceneLine,
    );
    scene(
        "arrays 10,000 deep",
        format!("x = {}{}\n", "[".repeat(10_000), "]".repeat(10_000)).into_bytes(),
        SceneLine,
    );
    scene(
        "inline tables 10,000 deep",
        format!("x = {}1{}\n", "{a = ".repeat(10_000), "}".repeat(10_000)).into_bytes(),
        SceneLine,
    );
    scene(
        "unclosed arrays",
        format!("x = {}", "[".repeat(100_000)).into_bytes(),
        SceneLine,
    );

    // Arity.
    for (text, what) in [
        ("[camera]\nposition = [0, 1, 5, 1]\n", "position of 4"),
        ("[camera]\nposition = [0, 1]\n", "position of 2"),
        ("[camera]\nup = []\n", "empty up"),
        ("[camera]\nshutter = [0, 0.5, 1]\n", "shutter of 3"),
        ("[materials.m]\nalbedo = [0.5]\n", "albedo of 1"),
        ("[[objects]]\ntype = \"sphere\"\ncenter = [[0, 0, 0]]\n", "nested center"),
        ("[[objects]]\ntype = \"sphere\"\n[objects.transform]\nscale = [1, 2]\n", "scale of 2"),
        ("[[objects]]\ntype = \"sphere\"\n[objects.transform]\nmatrix = [[1,0,0,0],[0,1,0,0],[0,0,1,0]]\n", "matrix of 3 rows"),
        ("[[objects]]\ntype = \"sphere\"\n[objects.transform]\nmatrix = [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1,0]]\n", "matrix row of 5"),
        ("[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [1, 1, 1, 1, 1, 1]\n", "intensity of 6"),
    ] {
        scene(&format!("arity: {what}"), s(text), SceneLine);
    }

    // Numbers out of their ranges, NaN and infinity, wrong types.
    for (text, what) in [
        ("[camera]\nposition = [nan, 0, 0]\n", "NaN position"),
        ("[camera]\nfov = inf\n", "infinite fov"),
        ("[camera]\nfov = -inf\n", "negative infinite fov"),
        ("[[objects]]\ntype = \"sphere\"\nradius = nan\n", "NaN radius"),
        ("[[objects]]\ntype = \"sphere\"\nradius = 1e40\n", "radius beyond f32"),
        ("[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [inf, 1, 1]\n", "infinite intensity"),
        ("[render]\nbackground = [-1, 0, 0]\n", "negative background"),
        ("[render]\nmetric_threshold = nan\n", "NaN threshold"),
        ("[render]\nwidth = 99999999999999999999\n", "integer overflow"),
        ("[render]\nmax_depth = -1\n", "negative depth"),
        ("[render]\nmax_depth = 1000000\n", "huge depth"),
        ("[render]\nseed = -1\n", "negative seed"),
        ("[render]\nwidth = \"32\"\n", "width as string"),
        ("objects = 3\n", "objects as number"),
        ("materials = []\n", "materials as array"),
        ("[[lights]]\ntype = \"point\"\nshadow_rays = -5\nposition = [0, 1, 0]\nintensity = [1, 1, 1]\n", "negative shadow rays"),
        ("[materials.m]\nreflection_rays = 4294967296\n", "rays beyond u32"),
        ("[[objects]]\ntype = \"sphere\"\n[objects.transform]\nscale = 0\n", "zero scale"),
        ("[[objects]]\ntype = \"sphere\"\n[objects.transform]\nmatrix = [[nan,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n", "NaN matrix"),
        ("[[objects]]\ntype = \"sphere\"\n[objects.transform]\nmatrix = [[0,0,0,0],[0,0,0,0],[0,0,0,0],[0,0,0,1]]\n", "singular matrix"),
    ] {
        scene(&format!("value: {what}"), s(text), SceneLine);
    }
    for (text, what) in [
        (
            "[render]\nwidth = 1000000000\nheight = 1000000000\n",
            "1e9 x 1e9",
        ),
        ("[render]\nwidth = 32768\nheight = 32768\n", "32768 x 32768"),
        ("[render]\nwidth = -32\n", "negative width"),
        ("[render]\nwidth = 0\n", "zero width"),
        ("[render]\nspp = 1000000000\n", "1e9 spp"),
        ("[render]\nspp = -1\n", "negative spp"),
        ("[render]\nshadow_rays = 0\n", "zero shadow rays"),
    ] {
        cases.push(Case {
            name: format!("absurd: {what}"),
            entries: vec![("scene.toml", Entry::Bytes(s(text)))],
            expect: SceneLine,
            bare: true,
            limit: 20,
        });
    }

    // The scene file is not a file.
    let special = |name: &str, entry: Entry, expect: Expect| Case {
        name: name.to_string(),
        entries: vec![("scene.toml", entry)],
        expect,
        bare: false,
        limit: 1,
    };
    cases.push(special("scene is a FIFO", Entry::Fifo, File("scene.toml")));
    cases.push(special(
        "scene is /dev/zero",
        Entry::Link("/dev/zero"),
        File("scene.toml"),
    ));
    cases.push(special(
        "scene is /dev/urandom",
        Entry::Link("/dev/urandom"),
        File("scene.toml"),
    ));
    cases.push(special(
        "scene is a directory",
        Entry::Dir,
        File("scene.toml"),
    ));
    cases.push(special(
        "scene of 3 GiB of zeros",
        Entry::Sparse(3 << 30),
        File("scene.toml"),
    ));
    cases.push(special(
        "scene is a dangling link",
        Entry::Link("/nonexistent/x.toml"),
        File("scene.toml"),
    ));

    // Meshes.
    let mut mesh = |name: &str, file: &'static str, entry: Entry, expect: Expect, limit: u64| {
        cases.push(Case {
            name: name.to_string(),
            entries: vec![
                ("scene.toml", Entry::Bytes(mesh_scene(file).into_bytes())),
                (file, entry),
            ],
            expect,
            bare: false,
            limit,
        });
    };
    let b = |t: &str| Entry::Bytes(t.as_bytes().to_vec());
    mesh("mesh is a FIFO", "m.ply", Entry::Fifo, Mesh("m.ply"), 1);
    mesh(
        "mesh is /dev/zero",
        "m.ply",
        Entry::Link("/dev/zero"),
        Mesh("m.ply"),
        1,
    );
    mesh(
        "OBJ mesh is /dev/urandom",
        "m.obj",
        Entry::Link("/dev/urandom"),
        Mesh("m.obj"),
        1,
    );
    mesh("mesh is a directory", "m.ply", Entry::Dir, Mesh("m.ply"), 1);
    mesh(
        "PLY of 3 GiB of zeros",
        "m.ply",
        Entry::Sparse(3 << 30),
        Mesh("m.ply"),
        1,
    );
    mesh(
        "OBJ of 3 GiB of zeros",
        "m.obj",
        Entry::Sparse(3 << 30),
        Mesh("m.obj"),
        1,
    );
    mesh(
        "PLY of 5 GiB of zeros",
        "m.ply",
        Entry::Sparse(5 << 30),
        Mesh("m.ply"),
        1,
    );
    mesh(
        "mesh is missing",
        "m.ply",
        Entry::Link("/nonexistent/m.ply"),
        Mesh("m.ply"),
        1,
    );
    mesh(
        "mesh is not a mesh format",
        "m.stl",
        b("solid x\n"),
        Mesh("m.stl"),
        20,
    );
    mesh(
        "valid ASCII PLY",
        "m.ply",
        Entry::Bytes(format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes()),
        Valid,
        20,
    );
    mesh(
        "valid binary PLY",
        "m.ply",
        Entry::Bytes(valid_binary_ply()),
        Valid,
        20,
    );
    mesh(
        "valid OBJ",
        "m.obj",
        b("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        Valid,
        20,
    );
    mesh(
        "valid OBJ with texture coordinates",
        "m.obj",
        b("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1\nvt 0 1 0\nf 1/1 2/2 3/-1\n"),
        Valid,
        20,
    );
    mesh(
        "valid PLY with texture coordinates",
        "m.ply",
        Entry::Bytes(
            format!("{PLY_UV_HEAD}0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n").into_bytes(),
        ),
        Valid,
        20,
    );
    let ply_cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty PLY", Vec::new()),
        ("magic only", s("ply\n")),
        (
            "no end_header",
            s("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"),
        ),
        (
            "megabyte header line",
            format!("ply\nformat ascii 1.0\ncomment {mega}\nelement vertex {mega}\nend_header\n")
                .into_bytes(),
        ),
        (
            "a trillion ASCII vertices",
            s(&PLY_HEAD.replace("vertex 3", "vertex 1000000000000")),
        ),
        (
            "negative vertex count",
            s(&PLY_HEAD.replace("vertex 3", "vertex -5")),
        ),
        (
            "4 billion vertices",
            s(&PLY_HEAD.replace("vertex 3", "vertex 4294967296")),
        ),
        (
            "binary: counts beyond the bytes",
            binary_ply(1 << 40, 1 << 40, &[0; 64]),
        ),
        ("binary: body cut short", {
            let mut v = valid_binary_ply();
            v.truncate(v.len() - 3);
            v
        }),
        (
            "binary header, ASCII body",
            binary_ply(3, 1, b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        ),
        ("ASCII header, binary body", {
            let mut v = s(PLY_HEAD);
            v.extend_from_slice(&binary_body());
            v
        }),
        (
            "index out of range",
            format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n").into_bytes(),
        ),
        (
            "negative index",
            format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n").into_bytes(),
        ),
        (
            "face of 255 corners, 3 given",
            format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n255 0 1 2\n").into_bytes(),
        ),
        (
            "face of 2 corners",
            format!("{PLY_HEAD}0 0 0\n1 0 0\n0 1 0\n2 0 1\n").into_bytes(),
        ),
        (
            "NaN vertex",
            format!("{PLY_HEAD}nan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes(),
        ),
        (
            "infinite vertex",
            format!("{PLY_HEAD}inf 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes(),
        ),
        (
            "double beyond f32",
            format!("{PLY_HEAD}1e300 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes(),
        ),
        (
            "list count of 4 billion",
            s(&format!(
                "{}0 0 0\n1 0 0\n0 1 0\n4294967295 0 1 2\n",
                PLY_HEAD.replace("uchar", "uint")
            )),
        ),
        ("unknown format", s(&PLY_HEAD.replace("ascii", "utf16"))),
        (
            "unknown property type",
            s(&PLY_HEAD.replace("property float x", "property quaternion x")),
        ),
        (
            "no faces",
            s(&format!(
                "{}0 0 0\n1 0 0\n0 1 0\n",
                PLY_HEAD.replace("face 1", "face 0")
            )),
        ),
        (
            "non-UTF-8 header",
            b"ply\nformat ascii 1.0\ncomment \xff\xfe\nelement vertex 3\n".to_vec(),
        ),
        (
            "texture coordinates: a trillion ASCII vertices",
            s(&PLY_UV_HEAD.replace("vertex 3", "vertex 1000000000000")),
        ),
        ("texture coordinates: binary counts beyond the bytes", {
            let head = PLY_UV_HEAD
                .replace("ascii", "binary_little_endian")
                .replace("vertex 3", "vertex 1099511627776")
                .replace("face 1", "face 1099511627776");
            let mut v = s(&head);
            v.extend_from_slice(&[0; 64]);
            v
        }),
        (
            "NaN texture coordinate",
            format!("{PLY_UV_HEAD}0 0 0 0 0\n1 0 0 nan 0\n0 1 0 0 1\n3 0 1 2\n").into_bytes(),
        ),
        (
            "texture coordinate missing",
            format!("{PLY_UV_HEAD}0 0 0 0 0\n1 0 0 1\n0 1 0 0 1\n3 0 1 2\n").into_bytes(),
        ),
    ];
    for (what, bytes) in ply_cases {
        mesh(
            &format!("PLY: {what}"),
            "m.ply",
            Entry::Bytes(bytes),
            Mesh("m.ply"),
            20,
        );
    }
    let obj_cases: Vec<(&str, Vec<u8>)> = vec![
        ("empty OBJ", Vec::new()),
        ("index 0", s("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")),
        (
            "index out of range",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"),
        ),
        (
            "relative index out of range",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n"),
        ),
        (
            "index beyond i64",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n"),
        ),
        ("face of 2 corners", s("v 0 0 0\nv 1 0 0\nf 1 2\n")),
        ("NaN vertex", s("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")),
        ("faces without vertices", s("f 1 2 3\n")),
        (
            "megabyte token",
            format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 {mega}\n").into_bytes(),
        ),
        (
            "non-UTF-8",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \xff\n".to_vec(),
        ),
        ("NUL bytes", vec![0; 4096]),
        (
            "vt index 2^40",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1099511627776\n"),
        ),
        (
            "vt index out of range",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n"),
        ),
        (
            "vt index 0",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/0 3/1\n"),
        ),
        (
            "relative vt index out of range",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-1 2/-1 3/-9\n"),
        ),
        (
            "malformed vt",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 x\nf 1/1 2/1 3/1\n"),
        ),
        (
            "NaN vt",
            s("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt nan 0\nf 1/1 2/1 3/1\n"),
        ),
        ("a million vt, a face past them", {
            let mut text = "v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_string();
            text.push_str(&"vt 0 0\n".repeat(1_000_000));
            text.push_str("f 1/1 2/1 3/1000001\n");
            text.into_bytes()
        }),
    ];
    for (what, bytes) in obj_cases {
        mesh(
            &format!("OBJ: {what}"),
            "m.obj",
            Entry::Bytes(bytes),
            Mesh("m.obj"),
            20,
        );
    }

    // One small mesh named thousands of times.
    let mut grid = String::new();
    for i in 0..=100 {
        for j in 0..=100 {
            let _ = writeln!(grid, "v {} {} 0", i as f32 / 100.0, j as f32 / 100.0);
        }
    }
    for i in 0..100 {
        for j in 0..100 {
            let a = i * 101 + j + 1;
            let _ = writeln!(
                grid,
                "f {a} {} {}\nf {a} {} {}",
                a + 1,
                a + 102,
                a + 102,
                a + 101
            );
        }
    }
    texture_cases(&mut cases);
    volume_cases(&mut cases);
    let object = "[[objects]]\ntype = \"mesh\"\npath = \"grid.obj\"\n";
    xml_cases(&mut cases);
    envmap_cases(&mut cases);
    cases.push(Case {
        name: "mesh named 5000 times".into(),
        entries: vec![
            ("scene.toml", Entry::Bytes(object.repeat(5000).into_bytes())),
            ("grid.obj", Entry::Bytes(grid.into_bytes())),
        ],
        expect: SceneLine,
        bare: false,
        limit: 20,
    });
    cases
}

/// A CRC-32 (PNG's), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xEDB8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG whose header, checksum and all, claims `w` × `h` RGB pixels, with
/// no pixel data after it.
fn png_claiming(w: u32, h: u32) -> Vec<u8> {
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend(w.to_be_bytes());
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 2, 0, 0, 0]);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend(13u32.to_be_bytes());
    out.extend(&ihdr);
    out.extend(crc32(&ihdr).to_be_bytes());
    out.extend(0u32.to_be_bytes());
    out.extend(b"IEND");
    out.extend(crc32(b"IEND").to_be_bytes());
    out
}

/// Scenes whose textures are bad: image files missing, lying, truncated or
/// not images, unknown filter and wrap names. A valid bitmap renders.
fn texture_cases(cases: &mut Vec<Case>) {
    use Expect::*;
    let scene = |texture: &str| {
        format!(
            "[camera]\nposition = [0, 0, 3]\n\n[materials.m]\ntype = \"diffuse\"\n\
             reflectance = {{ type = \"bitmap\", {texture} }}\n\n\
             [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n\n\
             [[lights]]\ntype = \"point\"\nposition = [0, 2, 3]\nintensity = [5, 5, 5]\n"
        )
        .into_bytes()
    };
    let mut good = Vec::new();
    image::RgbImage::from_fn(64, 64, |x, y| {
        image::Rgb([(x * 4) as u8, (y * 4) as u8, 128])
    })
    .write_to(
        &mut std::io::Cursor::new(&mut good),
        image::ImageFormat::Png,
    )
    .unwrap();
    let truncated = good[..good.len() / 2].to_vec();
    let mut case = |name: &str, texture: &str, file: Option<Vec<u8>>, expect: Expect| {
        let mut entries = vec![("scene.toml", Entry::Bytes(scene(texture)))];
        if let Some(bytes) = file {
            entries.push(("t.png", Entry::Bytes(bytes)));
        }
        cases.push(Case {
            name: format!("texture: {name}"),
            entries,
            expect,
            bare: false,
            limit: 20,
        });
    };
    let file = "filename = \"t.png\"";
    case("valid bitmap", file, Some(good.clone()), Valid);
    case("missing image file", file, None, SceneLine);
    case(
        "header claiming 65535² pixels",
        file,
        Some(png_claiming(65535, 65535)),
        SceneLine,
    );
    case(
        "header claiming more rows than present",
        file,
        Some(png_claiming(64, 4096)),
        SceneLine,
    );
    case("truncated PNG", file, Some(truncated), SceneLine);
    case(
        "not an image",
        file,
        Some(b"P6 this is no image at all".to_vec()),
        SceneLine,
    );
    case("empty image file", file, Some(Vec::new()), SceneLine);
    case(
        "image file is a directory",
        "filename = \".\"",
        None,
        SceneLine,
    );
    case(
        "unknown filter type",
        &format!("{file}, filter_type = \"trilinear\""),
        Some(good.clone()),
        SceneLine,
    );
    case(
        "unknown wrap mode",
        &format!("{file}, wrap_mode = \"border\""),
        Some(good.clone()),
        SceneLine,
    );
    case("bitmap without a file", "raw = true", None, SceneLine);
    case(
        "singular to_uv",
        "filename = \"t.png\", to_uv = { matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 0]] }",
        Some(good),
        SceneLine,
    );
}

/// A `.vol` file's bytes: a header of `resolution` voxels of `channels`
/// values and a box, then `values`.
fn vol_bytes(resolution: [i32; 3], channels: i32, values: &[f32]) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    b.extend_from_slice(&1i32.to_le_bytes());
    for n in resolution.into_iter().chain([channels]) {
        b.extend_from_slice(&n.to_le_bytes());
    }
    for x in [0f32, 0., 0., 1., 1., 1.]
        .into_iter()
        .chain(values.iter().copied())
    {
        b.extend_from_slice(&x.to_le_bytes());
    }
    b
}

/// Volume files (`[volumes.NAME]`, read when the scene is loaded): headers
/// that lie about the size or the channels, files that end early, values
/// that are not densities, absurd resolutions, and files that are not files.
fn volume_cases(cases: &mut Vec<Case>) {
    use Expect::*;
    let scene = "[camera]\nposition = [0, 0, 3]\n\n[volumes.smoke]\ntype = \"gridvolume\"\n\
                 filename = \"v.vol\"\n\n[[objects]]\ntype = \"sphere\"\nradius = 1\n\n\
                 [[lights]]\ntype = \"point\"\nposition = [0, 2, 3]\nintensity = [5, 5, 5]\n";
    let mut case = |name: &str, entry: Entry, expect: Expect, limit: u64| {
        cases.push(Case {
            name: format!("volume: {name}"),
            entries: vec![
                ("scene.toml", Entry::Bytes(scene.as_bytes().to_vec())),
                ("v.vol", entry),
            ],
            expect,
            bare: false,
            limit,
        });
    };
    let ones = vec![1.0f32; 8];
    let good = vol_bytes([2, 2, 2], 1, &ones);
    case("valid grid", Entry::Bytes(good.clone()), Valid, 20);
    case(
        "valid grid of 3 channels",
        Entry::Bytes(vol_bytes([2, 2, 2], 3, &[0.5; 24])),
        Valid,
        20,
    );
    let v = Mesh("v.vol");
    case(
        "header lies about the size",
        Entry::Bytes(vol_bytes([2, 2, 3], 1, &ones)),
        v,
        20,
    );
    case(
        "header lies about the channels",
        Entry::Bytes(vol_bytes([2, 2, 2], 3, &ones)),
        v,
        20,
    );
    case(
        "6 channels",
        Entry::Bytes(vol_bytes([1, 1, 1], 6, &[0.1; 6])),
        v,
        20,
    );
    case(
        "truncated data",
        Entry::Bytes(good[..good.len() - 5].to_vec()),
        v,
        20,
    );
    case("truncated header", Entry::Bytes(good[..30].to_vec()), v, 20);
    case(
        "trailing bytes",
        Entry::Bytes([good.as_slice(), &[0; 16]].concat()),
        v,
        20,
    );
    let mut nan = ones.clone();
    nan[3] = f32::NAN;
    case(
        "NaN density",
        Entry::Bytes(vol_bytes([2, 2, 2], 1, &nan)),
        v,
        20,
    );
    let mut inf = ones.clone();
    inf[7] = f32::INFINITY;
    case(
        "infinite density",
        Entry::Bytes(vol_bytes([2, 2, 2], 1, &inf)),
        v,
        20,
    );
    let mut negative = ones.clone();
    negative[0] = -0.5;
    case(
        "negative density",
        Entry::Bytes(vol_bytes([2, 2, 2], 1, &negative)),
        v,
        20,
    );
    case(
        "absurd resolution",
        Entry::Bytes(vol_bytes([i32::MAX, i32::MAX, i32::MAX], 3, &ones)),
        v,
        20,
    );
    case(
        "zero resolution",
        Entry::Bytes(vol_bytes([0, 2, 2], 1, &[])),
        v,
        20,
    );
    case(
        "negative resolution",
        Entry::Bytes(vol_bytes([2, -2, 2], 1, &ones)),
        v,
        20,
    );
    case(
        "resolution matching a sparse 3 GiB file",
        Entry::Sparse(3 << 30),
        v,
        20,
    );
    case(
        "not a volume file",
        Entry::Bytes(b"VOX this is no volume".to_vec()),
        v,
        20,
    );
    case("empty file", Entry::Bytes(Vec::new()), v, 20);
    case("a FIFO", Entry::Fifo, v, 1);
    case("/dev/zero", Entry::Link("/dev/zero"), v, 1);
    case("a directory", Entry::Dir, v, 20);
}

/// Environment maps: image files that lie about their size, end early, are
/// not images or not files.
fn envmap_cases(cases: &mut Vec<Case>) {
    let scene = |file: &str| {
        format!(
            "[render]\nintegrator = \"path\"\n\n\
             [[objects]]\ntype = \"sphere\"\ncenter = [0, 0, -3]\nradius = 1\n\n\
             [[lights]]\ntype = \"envmap\"\nfilename = \"{file}\"\n"
        )
        .into_bytes()
    };
    let hdr = |w: u32, h: u32, body: &[u8]| {
        let mut b = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
        b.extend_from_slice(body);
        b
    };
    // Flat RGBE pixels of radiance about 1.
    let pixels = |n: usize| [128u8, 128, 128, 129].repeat(n);
    let mut png = Vec::new();
    image::DynamicImage::ImageRgb8(image::RgbImage::from_fn(64, 32, |x, y| {
        image::Rgb([(x * 4) as u8, (y * 8) as u8, (x ^ y) as u8])
    }))
    .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
    .unwrap();
    let half = png[..png.len() / 2].to_vec();
    let files: Vec<(&str, &'static str, Entry, Expect)> = vec![
        (
            "envmap valid",
            "sky.hdr",
            Entry::Bytes(hdr(8, 4, &pixels(32))),
            Expect::Valid,
        ),
        (
            "envmap header claiming 65535x65535",
            "sky.hdr",
            Entry::Bytes(hdr(65535, 65535, &pixels(16))),
            Expect::Mesh("sky.hdr"),
        ),
        (
            "envmap header claiming more rows than it has",
            "sky.hdr",
            Entry::Bytes(hdr(64, 2048, &pixels(100))),
            Expect::Mesh("sky.hdr"),
        ),
        (
            "envmap truncated PNG",
            "sky.png",
            Entry::Bytes(half),
            Expect::Mesh("sky.png"),
        ),
        (
            "envmap not an image",
            "sky.exr",
            Entry::Bytes(b"v 0 0 0\nf 1 1 1\n".to_vec()),
            Expect::Mesh("sky.exr"),
        ),
        (
            "envmap empty file",
            "sky.hdr",
            Entry::Bytes(Vec::new()),
            Expect::Mesh("sky.hdr"),
        ),
        (
            "envmap a directory",
            "sky.hdr",
            Entry::Dir,
            Expect::Mesh("sky.hdr"),
        ),
        (
            "envmap a FIFO",
            "sky.hdr",
            Entry::Fifo,
            Expect::Mesh("sky.hdr"),
        ),
        (
            "envmap missing",
            "none.hdr",
            Entry::Dir,
            Expect::Mesh("none.hdr"),
        ),
    ];
    for (name, file, entry, expect) in files {
        let on_disk = if name == "envmap missing" {
            "other"
        } else {
            file
        };
        cases.push(Case {
            name: name.into(),
            entries: vec![("scene.toml", Entry::Bytes(scene(file))), (on_disk, entry)],
            expect,
            bare: false,
            limit: 20,
        });
    }
}

/// Mitsuba XML scenes (`scene.xml`), rendered with their own integrator
/// (`path` where they name none).
fn xml_cases(cases: &mut Vec<Case>) {
    use Expect::*;
    let xml = |body: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"45\"/></sensor>\n{body}\n</scene>\n"
        )
        .into_bytes()
    };
    let mut case = |name: &str, entries: Vec<(&'static str, Entry)>, expect: Expect| {
        cases.push(Case {
            name: format!("XML: {name}"),
            entries,
            expect,
            bare: false,
            limit: 20,
        });
    };
    let one = |body: &str| vec![("scene.xml", Entry::Bytes(xml(body)))];
    case(
        "valid",
        one(
            r#"<shape type="sphere"/><emitter type="point"><point name="position" value="0, 0, -3"/></emitter>"#,
        ),
        Valid,
    );
    let mut laughs =
        String::from("<?xml version=\"1.0\"?>\n<!DOCTYPE scene [\n<!ENTITY a \"lol\">\n");
    for i in 1..12 {
        let prev = if i == 1 {
            "a".to_string()
        } else {
            format!("a{}", i - 1)
        };
        laughs.push_str(&format!(
            "<!ENTITY a{i} \"{}\">\n",
            format!("&{prev};").repeat(10)
        ));
    }
    laughs.push_str("]>\n<scene version=\"3.0.0\"><string name=\"x\" value=\"&a11;\"/></scene>\n");
    case(
        "billion laughs",
        vec![("scene.xml", Entry::Bytes(laughs.into_bytes()))],
        SceneLine,
    );
    let deep = format!(
        "<scene version=\"3.0.0\">{}{}</scene>",
        "<shape type=\"sphere\">".repeat(100_000),
        "</shape>".repeat(100_000)
    );
    case(
        "100,000 deep",
        vec![("scene.xml", Entry::Bytes(deep.into_bytes()))],
        SceneLine,
    );
    case(
        "includes itself",
        one(r#"<include filename="scene.xml"/>"#),
        SceneLine,
    );
    let mut dir = one(r#"<include filename="sub"/>"#);
    dir.push(("sub", Entry::Dir));
    case("includes a directory", dir, File("sub"));
    case(
        "includes /dev/zero",
        one(r#"<include filename="/dev/zero"/>"#),
        File("/dev/zero"),
    );
    let mut fifo = one(r#"<include filename="pipe.xml"/>"#);
    fifo.push(("pipe.xml", Entry::Fifo));
    case("includes a FIFO", fifo, File("pipe.xml"));
    case(
        "duplicate attribute",
        one(r#"<shape type="sphere" type="sphere"/>"#),
        SceneLine,
    );
    case(
        "two roots",
        vec![(
            "scene.xml",
            Entry::Bytes(b"<scene version=\"3.0.0\"/>\n<scene version=\"3.0.0\"/>\n".to_vec()),
        )],
        SceneLine,
    );
    case(
        "not UTF-8",
        vec![(
            "scene.xml",
            Entry::Bytes(b"<scene version=\"3.0.0\">\n<!-- \xff -->\n</scene>\n".to_vec()),
        )],
        SceneLine,
    );
    case(
        "NaN",
        one(r#"<shape type="sphere"><float name="radius" value="NaN"/></shape>"#),
        SceneLine,
    );
    case(
        "singular matrix",
        one(
            r#"<shape type="sphere"><transform name="to_world"><scale x="0"/></transform></shape>"#,
        ),
        SceneLine,
    );
    case(
        "zero film width",
        vec![(
            "scene.xml",
            Entry::Bytes(
                b"<scene version=\"3.0.0\"><sensor type=\"perspective\">\n<film type=\"hdrfilm\"><integer name=\"width\" value=\"0\"/></film></sensor></scene>".to_vec(),
            ),
        )],
        SceneLine,
    );
    case(
        "missing mesh",
        one(r#"<shape type="ply"><string name="filename" value="gone.ply"/></shape>"#),
        Mesh("gone.ply"),
    );
    case("unknown bsdf", one(r#"<bsdf type="hair"/>"#), SceneLine);
    let serialized = |bytes: Vec<u8>| {
        let mut entries = one(
            r#"<shape type="serialized"><string name="filename" value="m.serialized"/></shape>"#,
        );
        entries.push(("m.serialized", Entry::Bytes(bytes)));
        entries
    };
    // A zlib stream of these bytes behind a version 3 header.
    let stream = |body: &[u8]| {
        let mut z =
            flate2::write::ZlibEncoder::new(vec![0x1C, 0x04, 3, 0], flate2::Compression::best());
        std::io::Write::write_all(&mut z, body).unwrap();
        z.finish().unwrap()
    };
    let counts = |vertices: u64, faces: u64| {
        let mut b = 0x1000u32.to_le_bytes().to_vec();
        b.extend(vertices.to_le_bytes());
        b.extend(faces.to_le_bytes());
        b
    };
    let mut one_triangle = counts(3, 1);
    for x in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        one_triangle.extend(x.to_le_bytes());
    }
    for i in [0u32, 1, 2] {
        one_triangle.extend(i.to_le_bytes());
    }
    case("serialized mesh", serialized(stream(&one_triangle)), Valid);
    let valid = stream(&one_triangle);
    case(
        "serialized: truncated",
        serialized(valid[..valid.len() - 9].to_vec()),
        Mesh("m.serialized"),
    );
    case(
        "serialized: counts lie",
        serialized(stream(&counts(1 << 40, 1 << 40))),
        Mesh("m.serialized"),
    );
    let mut bomb = counts(1 << 28, 0);
    bomb.resize(64 << 20, 0);
    case(
        "serialized: zip bomb",
        serialized(stream(&bomb)),
        Mesh("m.serialized"),
    );
    let mut index = one_triangle.clone();
    let n = index.len();
    index[n - 4..].copy_from_slice(&7u32.to_le_bytes());
    case(
        "serialized: index past the vertices",
        serialized(stream(&index)),
        Mesh("m.serialized"),
    );
    case(
        "serialized: version 5",
        serialized(vec![0x1C, 0x04, 5, 0, 0, 0]),
        Mesh("m.serialized"),
    );
}

/// Makes a case's files; `false` if this platform cannot (no FIFOs).
fn make(dir: &Path, name: &str, entry: &Entry) -> bool {
    let path = dir.join(name);
    match entry {
        Entry::Bytes(b) => std::fs::write(&path, b).unwrap(),
        Entry::Dir => std::fs::create_dir(&path).unwrap(),
        Entry::Link(target) => {
            #[cfg(unix)]
            std::os::unix::fs::symlink(target, &path).unwrap();
            #[cfg(not(unix))]
            {
                let _ = target;
                return false;
            }
        }
        Entry::Sparse(len) => {
            let file = std::fs::File::create(&path).unwrap();
            if file.set_len(*len).is_err() {
                return false;
            }
        }
        Entry::Fifo => {
            let made = Command::new("mkfifo").arg(&path).status();
            if !matches!(made, Ok(s) if s.success()) {
                return false;
            }
        }
    }
    true
}

fn listing(dir: &Path) -> Vec<(String, Option<Vec<u8>>)> {
    let mut names: Vec<(String, Option<Vec<u8>>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let regular = e.file_type().unwrap().is_file();
            let name = e.file_name().to_string_lossy().into_owned();
            // The contents of the output only: inputs are never written.
            let bytes = (regular && name == "out.png").then(|| std::fs::read(e.path()).unwrap());
            (name, bytes)
        })
        .collect();
    names.sort();
    names
}

/// How a run ended.
struct Run {
    code: Option<i32>,
    signal: Option<i32>,
    stderr: String,
    elapsed: Duration,
    /// Peak resident memory in KiB, where the platform says.
    peak_kib: Option<i64>,
}

/// Runs the binary in `dir`, killing it after `limit`; `None` if it had to be killed.
fn run(dir: &Path, args: &[String], limit: Duration, log: &Path) -> Option<Run> {
    run_with(dir, args, None, limit, log)
}

/// [`run`] with `PENUMBRA_MAX_FILE_SIZE` set to `max_file_size` (else unset).
fn run_with(
    dir: &Path,
    args: &[String],
    max_file_size: Option<&str>,
    limit: Duration,
    log: &Path,
) -> Option<Run> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_penumbra"));
    match max_file_size {
        Some(v) => cmd.env("PENUMBRA_MAX_FILE_SIZE", v),
        None => cmd.env_remove("PENUMBRA_MAX_FILE_SIZE"),
    };
    cmd.args(args)
        .current_dir(dir)
        .env_remove("PENUMBRA_BUNNY")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(log).unwrap());
    cap_address_space(&mut cmd);
    let start = Instant::now();
    let mut child = cmd.spawn().expect("run penumbra");
    let read_log = || {
        let mut text = std::fs::read(log).unwrap();
        text.truncate(1 << 20);
        String::from_utf8_lossy(&text).into_owned()
    };
    loop {
        if let Some((code, signal, peak_kib)) = reap(&mut child) {
            return Some(Run {
                code,
                signal,
                stderr: read_log(),
                elapsed: start.elapsed(),
                peak_kib,
            });
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The address-space cap the cases run under: an allocation past it fails.
#[cfg(target_os = "linux")]
fn cap_address_space(cmd: &mut Command) {
    use std::os::unix::process::CommandExt;
    let cap = libc::rlimit {
        rlim_cur: 4 << 30,
        rlim_max: 4 << 30,
    };
    // SAFETY: setrlimit is async-signal-safe and touches only the child.
    unsafe {
        cmd.pre_exec(move || {
            if libc::setrlimit(libc::RLIMIT_AS, &cap) == 0 {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            }
        });
    }
}

#[cfg(not(target_os = "linux"))]
fn cap_address_space(_: &mut Command) {}

/// The child's exit (code, signal, peak memory) if it has exited.
#[cfg(target_os = "linux")]
fn reap(child: &mut std::process::Child) -> Option<(Option<i32>, Option<i32>, Option<i64>)> {
    let mut status = 0;
    // SAFETY: plain out-parameters; the child is ours and not yet waited for.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = child.id() as libc::pid_t;
    let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
    if r != pid {
        return None;
    }
    let code = libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
    let signal = libc::WIFSIGNALED(status).then(|| libc::WTERMSIG(status));
    Some((code, signal, Some(usage.ru_maxrss)))
}

#[cfg(not(target_os = "linux"))]
fn reap(child: &mut std::process::Child) -> Option<(Option<i32>, Option<i32>, Option<i64>)> {
    let status = child.try_wait().unwrap()?;
    #[cfg(unix)]
    let signal = std::os::unix::process::ExitStatusExt::signal(&status);
    #[cfg(not(unix))]
    let signal = None;
    Some((status.code(), signal, None))
}

/// Checks one case; the problems found, if any, else its time and peak memory.
fn check(case: &Case, logs: &Path) -> Result<(Duration, Option<i64>), String> {
    let dir = tempfile::tempdir().unwrap();
    for (name, entry) in &case.entries {
        if !make(dir.path(), name, entry) {
            println!(
                "skipped `{}`: this platform cannot make its files",
                case.name
            );
            return Ok((Duration::ZERO, None));
        }
    }
    std::fs::write(dir.path().join("out.png"), OLD_OUTPUT).unwrap();
    let before = listing(dir.path());
    let scene_file = case
        .entries
        .iter()
        .map(|(name, _)| *name)
        .find(|name| name.starts_with("scene."))
        .unwrap_or("scene.toml");
    let mut args: Vec<String> = ["render", scene_file, "-o", "out.png", "--quiet"]
        .map(String::from)
        .to_vec();
    if !case.bare {
        args.extend(["--width", "32", "--height", "24", "--spp", "1"].map(String::from));
    }
    let log = logs.join("stderr.txt");
    let limit = Duration::from_secs(case.limit);
    // Generous against a loaded machine, for the cases allowed a second.
    let kill_after = limit.max(Duration::from_secs(20));
    let Some(r) = run(dir.path(), &args, kill_after, &log) else {
        return Err(format!("did not exit within {kill_after:?} (a hang)"));
    };
    let mut problems = Vec::new();
    let e = &r.stderr;
    let shown: String = e.chars().take(400).collect();
    if r.elapsed > limit {
        problems.push(format!("took {:?}, more than {limit:?}", r.elapsed));
    }
    if let Some(sig) = r.signal {
        problems.push(format!("killed by signal {sig}"));
    }
    if e.contains("panicked") || r.code == Some(101) {
        problems.push(format!("panicked: {shown}"));
    }
    if let Some(kib) = r.peak_kib {
        if kib > 1 << 20 {
            problems.push(format!("peak memory {} MiB", kib >> 10));
        }
    }
    if e.len() > 1200 || e.lines().count() > 6 {
        problems.push(format!(
            "a message of {} bytes, {} lines",
            e.len(),
            e.lines().count()
        ));
    }
    let after = listing(dir.path());
    match case.expect {
        Expect::Valid => {
            if r.code != Some(0) {
                problems.push(format!("exit {:?} for a valid input: {shown}", r.code));
            } else {
                match image::open(dir.path().join("out.png")) {
                    Ok(img) if (img.width(), img.height()) == (32, 24) => {}
                    Ok(img) => problems.push(format!("a {}x{} image", img.width(), img.height())),
                    Err(err) => problems.push(format!("no PNG written: {err}")),
                }
                let names = |l: &[(String, Option<Vec<u8>>)]| {
                    l.iter().map(|x| x.0.clone()).collect::<Vec<_>>()
                };
                if names(&before) != names(&after) {
                    problems.push(format!(
                        "files changed: {:?} -> {:?}",
                        names(&before),
                        names(&after)
                    ));
                }
            }
        }
        expect => {
            if r.code != Some(2) {
                problems.push(format!("exit {:?}, not 2: {shown}", r.code));
            }
            if before != after {
                problems.push("the old output or the directory changed".to_string());
            }
            let located = |file: &str| {
                e.match_indices(&format!("{file}:"))
                    .any(|(i, m)| e[i + m.len()..].starts_with(|c: char| c.is_ascii_digit()))
            };
            let ok = match expect {
                Expect::SceneLine => located(scene_file),
                Expect::File(file) => e.starts_with(&format!("error: {file}: ")),
                Expect::Mesh(file) => located(scene_file) && e.contains(file),
                Expect::Valid => unreachable!(),
            };
            if !ok {
                problems.push(format!(
                    "the message does not name the place ({expect:?}): {shown}"
                ));
            }
        }
    }
    if problems.is_empty() {
        Ok((r.elapsed, r.peak_kib))
    } else {
        Err(problems.join("; "))
    }
}

#[test]
fn every_hostile_case_fails_cleanly_or_renders() {
    let logs = tempfile::tempdir().unwrap();
    let cases = corpus();
    let mut failures = Vec::new();
    println!("{} cases", cases.len());
    let (mut slowest, mut largest) = ((Duration::ZERO, ""), (0, ""));
    for case in &cases {
        match check(case, logs.path()) {
            Ok((time, peak)) => {
                slowest = slowest.max((time, &case.name));
                largest = largest.max((peak.unwrap_or(0), &case.name));
            }
            Err(why) => failures.push(format!("{}: {why}", case.name)),
        }
    }
    println!("slowest: {} ({:?})", slowest.1, slowest.0);
    println!("largest: {} ({} MiB)", largest.1, largest.0 >> 10);
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn the_file_size_limit_can_be_raised_and_lowered() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "# {}\n[render]\nwidth = 8\nheight = 6\n",
        "z".repeat(5 << 20)
    );
    std::fs::write(dir.path().join("big.toml"), scene).unwrap();
    let base = ["render", "big.toml", "-o", "out.png", "--quiet"];
    let logs = tempfile::tempdir().unwrap();
    let log = logs.path().join("stderr.txt");
    let args = |extra: &[&str]| -> Vec<String> {
        base.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let r = run(dir.path(), &args(&[]), Duration::from_secs(20), &log).unwrap();
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(r.stderr.contains("--max-file-size"), "{}", r.stderr);
    let r = run(
        dir.path(),
        &args(&["--max-file-size", "8M"]),
        Duration::from_secs(20),
        &log,
    )
    .unwrap();
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let r = run_with(
        dir.path(),
        &args(&[]),
        Some("8MiB"),
        Duration::from_secs(20),
        &log,
    )
    .unwrap();
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    // The flag wins over the variable.
    let r = run_with(
        dir.path(),
        &args(&["--max-file-size", "1M"]),
        Some("8M"),
        Duration::from_secs(20),
        &log,
    )
    .unwrap();
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    // An empty variable is no variable.
    let r = run_with(
        dir.path(),
        &args(&[]),
        Some(""),
        Duration::from_secs(20),
        &log,
    )
    .unwrap();
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(
        r.stderr.contains("more than the limit of 4194304 bytes"),
        "{}",
        r.stderr
    );
    let r = run_with(
        dir.path(),
        &args(&[]),
        Some("lots"),
        Duration::from_secs(20),
        &log,
    )
    .unwrap();
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(
        r.stderr
            .contains("PENUMBRA_MAX_FILE_SIZE=lots is not a size"),
        "{}",
        r.stderr
    );
    // Lowered below a small mesh.
    std::fs::write(dir.path().join("s.toml"), mesh_scene("m.obj")).unwrap();
    let obj = format!(
        "# {}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "-".repeat(1000)
    );
    std::fs::write(dir.path().join("m.obj"), obj).unwrap();
    let small = [
        "render", "s.toml", "-o", "out.png", "--quiet", "--width", "8", "--height", "6",
    ];
    let with = |extra: &[&str]| -> Vec<String> {
        small.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let r = run(
        dir.path(),
        &with(&["--max-file-size", "500"]),
        Duration::from_secs(20),
        &log,
    )
    .unwrap();
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(
        r.stderr
            .contains("m.obj: the file is 1035 bytes, more than the limit of 500 bytes"),
        "{}",
        r.stderr
    );
    let r = run(
        dir.path(),
        &with(&["--max-file-size", "lots"]),
        Duration::from_secs(20),
        &log,
    )
    .unwrap();
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    let r = run(dir.path(), &with(&[]), Duration::from_secs(20), &log).unwrap();
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}
