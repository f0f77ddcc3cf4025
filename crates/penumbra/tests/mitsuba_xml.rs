//! Mitsuba 3 XML scenes: every tag and plugin read, the tree they make
//! against the TOML scene that says the same, the pixels of both, and
//! hostile files refused with their place.

mod common;

use std::path::{Path, PathBuf};

use penumbra::description::mitsuba::{self, spectrum, transform, Loaded};
use penumbra::description::{from_toml, Kind, Node, Value};
use penumbra::integrator::plugins::registry;
use penumbra::scene::convert;
use penumbra::scene::{IntegratorChoice, LoadOptions, Overrides, SceneError, SceneSource};

const LIMIT: u64 = 4 << 20;

/// A folder with files in it.
struct Dir(tempfile::TempDir);

impl Dir {
    fn new(files: &[(&str, &str)]) -> Dir {
        let d = Dir(tempfile::tempdir().unwrap());
        for (name, text) in files {
            d.write(name, text.as_bytes());
        }
        d
    }

    fn write(&self, name: &str, bytes: &[u8]) {
        let p = self.0.path().join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }

    fn load(&self, name: &str, defines: &[(&str, &str)]) -> Result<Loaded, SceneError> {
        let defines: Vec<(String, String)> = defines
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        mitsuba::from_xml_file(&self.path(name), &defines, LIMIT, registry)
    }

    fn tree(&self, name: &str) -> Node {
        self.load(name, &[]).unwrap_or_else(|e| panic!("{e}")).root
    }

    fn err(&self, name: &str) -> String {
        match self.load(name, &[]) {
            Ok(_) => panic!("{name} should be refused"),
            Err(e) => e.to_string(),
        }
    }
}

/// `scene.xml` built with `--integrator whitted`, as the command line does.
fn build_whitted(d: &Dir) -> Result<penumbra::scene::Scene, SceneError> {
    let path = d.path("scene.xml");
    let mut src = SceneSource::open(path.to_str().unwrap(), &LoadOptions::default())?;
    common::set(
        &mut src,
        Overrides {
            integrator: Some(IntegratorChoice::Whitted),
            ..Default::default()
        },
    );
    src.build()
}

/// One file scene `scene.xml` of `body` (inside `<scene version="3.0.0">`).
fn one(body: &str) -> Dir {
    Dir::new(&[("scene.xml", &scene(body))])
}

fn scene(body: &str) -> String {
    format!("<?xml version=\"1.0\"?>\n<scene version=\"3.0.0\">\n{body}\n</scene>\n")
}

/// A minimal sensor, so that a scene is complete.
const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="45"/></sensor>"#;

fn with_sensor(body: &str) -> Dir {
    one(&format!("{SENSOR}\n{body}"))
}

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(|i| numbers(&i.value)).collect(),
        Value::Float(x) => vec![*x],
        Value::Int(i) => vec![*i as f64],
        other => panic!("not numbers: {other:?}"),
    }
}

fn prop<'a>(node: &'a Node, name: &str) -> &'a Value {
    &node
        .prop(name)
        .unwrap_or_else(|| panic!("no `{name}` in {node:?}"))
        .value
        .value
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

fn shapes(root: &Node) -> Vec<&Node> {
    root.children_of(Kind::Shape).collect()
}

fn sensor(root: &Node) -> &Node {
    root.child(Kind::Sensor).unwrap()
}

/// The place an error names, `file:line:column`.
fn place_of(e: &str) -> (&str, u32, u32) {
    let mut parts = e.splitn(4, ':');
    let file = parts.next().unwrap();
    let line = parts.next().and_then(|l| l.parse().ok()).unwrap_or(0);
    let col = parts
        .next()
        .and_then(|c| c.trim().parse().ok())
        .unwrap_or(0);
    (file, line, col)
}

// ---------------------------------------------------------------------------
// The same scene in XML and TOML.

const XML_SCENE: &str = r#"<?xml version="1.0" encoding="utf-8"?>
<!-- a diffuse sphere on a floor, a point light, a lit rectangle -->
<scene version="3.0.0">
    <integrator type="path">
        <integer name="max_depth" value="3"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world">
            <lookat origin="0, 1, 5" target="0, 1, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="64"/>
            <integer name="height" value="48"/>
            <rfilter type="box"/>
        </film>
        <sampler type="independent">
            <integer name="sample_count" value="4"/>
            <integer name="seed" value="7"/>
        </sampler>
    </sensor>
    <emitter type="constant">
        <rgb name="radiance" value="0.1"/>
    </emitter>
    <bsdf type="diffuse" id="red">
        <rgb name="reflectance" value="0.7, 0.2, 0.2"/>
    </bsdf>
    <shape type="sphere">
        <point name="center" x="0" y="1" z="0"/>
        <float name="radius" value="0.8"/>
        <ref id="red"/>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <matrix value="5 0 0 0  0 0 5 0  0 -5 0 0  0 0 0 1"/>
        </transform>
        <bsdf type="diffuse">
            <spectrum name="reflectance" value="0.5"/>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <matrix value="0.5 0 0 0  0 0 -0.5 3  0 0.5 0 0  0 0 0 1"/>
        </transform>
        <emitter type="area">
            <rgb name="radiance" value="10, 10, 10"/>
        </emitter>
    </shape>
    <emitter type="point">
        <point name="position" value="2, 4, 2"/>
        <rgb name="intensity" value="20"/>
    </emitter>
</scene>
"#;

const TOML_SCENE: &str = r#"
[render]
integrator = "path"
max_depth = 3
light_sampler = "uniform"
width = 64
height = 48
filter = "box"
splat = true
filter_steps = 31
spp = 4
seed = 7
distribution = "random"
pixel_distribution = "fast-random"
background = [0.1, 0.1, 0.1]

[camera]
position = [0.0, 1.0, 5.0]
look_at = [0.0, 1.0, 4.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
near_clip = 0.01
far_clip = 10000.0

[materials.red]
type = "diffuse"
reflectance = [0.7, 0.2, 0.2]

[materials.bsdf_1]
type = "diffuse"
reflectance = [0.5, 0.5, 0.5]

[materials.bsdf_2]
type = "diffuse"
reflectance = [0.0, 0.0, 0.0]

[[objects]]
type = "sphere"
center = [0.0, 1.0, 0.0]
radius = 0.8
material = "red"

[[objects]]
type = "quad"
origin = [-5.0, 0.0, 5.0]
edge_u = [10.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -10.0]
material = "bsdf_1"

[[objects]]
type = "quad"
origin = [-0.5, 3.0, -0.5]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 1.0]
material = "bsdf_2"
emitter = { type = "area", radiance = [10.0, 10.0, 10.0] }

[[lights]]
type = "point"
position = [2.0, 4.0, 2.0]
intensity = [20.0, 20.0, 20.0]
"#;

/// The TOML scene's tree, its integrator replaced.
fn toml_tree(integrator: Option<&str>) -> Node {
    let text = match integrator {
        Some(i) => TOML_SCENE.replace(
            "integrator = \"path\"\nmax_depth = 3\nlight_sampler = \"uniform\"\n",
            &format!("integrator = \"{i}\"\n"),
        ),
        None => TOML_SCENE.to_string(),
    };
    from_toml(&text, Path::new("scene.toml")).unwrap()
}

#[test]
fn an_xml_scene_and_its_toml_scene_make_the_same_tree() {
    let d = Dir::new(&[("scene.xml", XML_SCENE)]);
    let xml = d.tree("scene.xml");
    let toml = toml_tree(None);
    assert!(
        xml.same_as(&toml),
        "XML:\n{}\nTOML:\n{}",
        xml.fingerprint(),
        toml.fingerprint()
    );
    // Every value is placed at its XML tag.
    let sphere = shapes(&xml)[0];
    let radius = sphere.prop("radius").unwrap();
    let at = radius.value.origin.at.as_ref().unwrap();
    assert_eq!((at.line, at.column), (31, 9));
    assert_eq!(at.file.as_path(), d.path("scene.xml"));
    assert_eq!(radius.key.path.to_string(), "objects[0].radius");
}

#[test]
fn an_xml_scene_renders_the_pixels_of_its_toml_scene() {
    let d = Dir::new(&[("scene.xml", XML_SCENE)]);
    let opts = LoadOptions::default();
    let mut xml = SceneSource::open(d.path("scene.xml").to_str().unwrap(), &opts).unwrap();
    // Its `path` integrator renders what the TOML scene's does.
    let path = xml.build().expect("the path integrator builds");
    let config = penumbra::integrator::Config::of(&path).unwrap();
    assert_eq!(config.choice(), IntegratorChoice::Path);
    assert_eq!(config.depth(), 3);
    let toml = SceneSource::from_tree(toml_tree(None), d.0.path(), &opts)
        .build()
        .unwrap();
    let (a, _) = common::render_scene(&path, 2);
    let (b, _) = common::render_scene(&toml, 2);
    assert!(a.pixels == b.pixels, "the XML scene's paths differ");
    assert!(a.pixels.iter().any(|p| p.r > 0.0), "a black image");
    // `--integrator whitted` replaces it whole, saying what it drops.
    common::set(
        &mut xml,
        Overrides {
            integrator: Some(IntegratorChoice::Whitted),
            ..Default::default()
        },
    );
    let xml = xml.build().unwrap();
    assert!(
        xml.warnings
            .iter()
            .any(|w| w.contains("replaces the scene's integrator `path`")
                && w.contains("`max_depth`")),
        "{:?}",
        xml.warnings
    );
    let toml = SceneSource::from_tree(toml_tree(Some("whitted")), d.0.path(), &opts)
        .build()
        .unwrap();
    let (a, _) = common::render_scene(&xml, 2);
    let (b, _) = common::render_scene(&toml, 2);
    assert_eq!((a.width, a.height), (64, 48));
    assert!(a.pixels == b.pixels, "the XML scene renders other pixels");
    assert!(a.pixels.iter().any(|p| p.r > 0.0), "a black image");
}

/// `penumbra convert`'s text: the XML scene's tree, written as TOML and
/// read back, is the tree read from the XML; both render the same pixels.
#[test]
fn an_xml_scene_converted_to_toml_reads_back_to_its_tree_and_pixels() {
    let d = Dir::new(&[("scene.xml", XML_SCENE)]);
    d.write("meshes/tri.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let opts = LoadOptions::default();
    let with_mesh = XML_SCENE.replace(
        "    <emitter type=\"point\">",
        "    <shape type=\"obj\"><string name=\"filename\" value=\"meshes/tri.obj\"/>\
         <boolean name=\"face_normals\" value=\"true\"/></shape>\n    <emitter type=\"point\">",
    );
    d.write("mesh.xml", with_mesh.as_bytes());
    let with_group = XML_SCENE.replace(
        "    <emitter type=\"point\">",
        "    <shape type=\"shapegroup\" id=\"g\"><shape type=\"obj\">\
         <string name=\"filename\" value=\"meshes/tri.obj\"/></shape></shape>\
         <shape type=\"instance\"><ref id=\"g\"/><transform name=\"to_world\">\
         <translate x=\"0.5\"/></transform></shape>\n    <emitter type=\"point\">",
    );
    d.write("group.xml", with_group.as_bytes());
    for name in ["scene.xml", "mesh.xml", "group.xml"] {
        let xml = SceneSource::open(d.path(name).to_str().unwrap(), &opts).unwrap();
        let text = convert::to_toml(&xml, d.0.path()).unwrap_or_else(|e| panic!("{e}"));
        d.write("scene.toml", text.as_bytes());
        let toml = SceneSource::open(d.path("scene.toml").to_str().unwrap(), &opts).unwrap();
        assert!(
            xml.root.same_as(&toml.root),
            "{text}\nXML:\n{}\nTOML:\n{}",
            xml.root.fingerprint(),
            toml.root.fingerprint()
        );
        let (a, _) = common::render_scene(&xml.build().unwrap(), 2);
        let (b, _) = common::render_scene(&toml.build().unwrap(), 2);
        assert!(
            a.pixels == b.pixels,
            "{name}: the TOML scene renders other pixels"
        );
        assert!(a.pixels.iter().any(|p| p.r > 0.0), "a black image");
    }
    // The mesh stays where it is: relative beside the XML file, absolute elsewhere.
    let xml = SceneSource::open(d.path("mesh.xml").to_str().unwrap(), &opts).unwrap();
    let here = convert::to_toml(&xml, d.0.path()).unwrap();
    assert!(here.contains("path = \"meshes/tri.obj\""), "{here}");
    let elsewhere = tempfile::tempdir().unwrap();
    let there = convert::to_toml(&xml, elsewhere.path()).unwrap();
    let absolute = std::path::absolute(d.path("meshes/tri.obj")).unwrap();
    let written = from_toml(&there, Path::new("x.toml")).unwrap();
    let mesh = shapes(&written)[3];
    assert_eq!(
        prop(mesh, "path"),
        &Value::String(absolute.to_string_lossy().into_owned())
    );
    // Only keys the scene format documents: the written file passes its checks.
    assert!(
        !here.contains("to_world") && !here.contains("filename"),
        "{here}"
    );
}

/// A `serialized` mesh the test writes itself: mesh `shape_index` of the
/// file renders as the same triangles from an OBJ file do.
#[test]
fn serialized_meshes_are_read_by_shape_index() {
    use penumbra::geometry::mesh_file::serialized::write_serialized;
    use penumbra::geometry::mesh_file::MeshData;
    let quad = |z: f32| MeshData {
        positions: vec![
            [-1.0, -1.0, z],
            [1.0, -1.0, z],
            [1.0, 1.0, z],
            [-1.0, 1.0, z],
        ],
        normals: Some(vec![[0.0, 0.0, -1.0]; 4]),
        uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        triangles: vec![[0, 2, 1], [0, 3, 2]],
        attributes: Vec::new(),
    };
    let body = |shape: &str| {
        scene(&format!(
            r#"<sensor type="perspective"><float name="fov" value="60"/>
            <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/></film></sensor>
            {shape}
            <emitter type="point"><point name="position" value="0, 0, 0"/><rgb name="intensity" value="5"/></emitter>"#
        ))
    };
    let d = Dir::new(&[
        (
            "ser.xml",
            &body(
                r#"<shape type="serialized"><string name="filename" value="m.serialized"/>
                <integer name="shape_index" value="1"/></shape>"#,
            ),
        ),
        (
            "obj.xml",
            &body(r#"<shape type="obj"><string name="filename" value="m.obj"/></shape>"#),
        ),
        (
            "m.obj",
            "v -1 -1 3\nv 1 -1 3\nv 1 1 3\nv -1 1 3\nf 1 3 2\nf 1 4 3\n",
        ),
    ]);
    for (version, double) in [(3, false), (4, true)] {
        d.write(
            "m.serialized",
            &write_serialized(&[quad(9.0), quad(3.0)], version, double),
        );
        let opts = LoadOptions::default();
        let ser = SceneSource::open(d.path("ser.xml").to_str().unwrap(), &opts).unwrap();
        let mesh = shapes(&ser.root)[0];
        assert_eq!(prop(mesh, "shape_index"), &Value::Int(1));
        let obj = SceneSource::open(d.path("obj.xml").to_str().unwrap(), &opts).unwrap();
        let (a, _) = common::render_scene(&ser.build().unwrap(), 2);
        let (b, _) = common::render_scene(&obj.build().unwrap(), 2);
        assert!(a.pixels == b.pixels, "version {version}: other pixels");
        assert!(a.pixels.iter().any(|p| p.r > 0.0), "a black image");
    }
    // An index past the file's meshes is an error naming the file.
    let out_of_range = scene(&format!(
        "{SENSOR}<shape type=\"serialized\"><string name=\"filename\" value=\"m.serialized\"/>\
         <integer name=\"shape_index\" value=\"2\"/></shape>"
    ));
    d.write("scene.xml", out_of_range.as_bytes());
    let e = build_whitted(&d).err().unwrap().to_string();
    assert!(
        e.contains("m.serialized") && e.contains("holds 2 meshes"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------
// Language features.

#[test]
fn defaults_and_defines_substitute_parameters() {
    let body = format!(
        r#"<default name="r" value="0.25"/>
        <default name="ty" value="sphere"/>
        {SENSOR}
        <shape type="$ty"><float name="radius" value="$r"/></shape>"#
    );
    let d = one(&body);
    assert_eq!(
        prop(shapes(&d.tree("scene.xml"))[0], "radius"),
        &Value::Float(0.25)
    );
    let defined = d.load("scene.xml", &[("r", "2")]).unwrap().root;
    assert_eq!(prop(shapes(&defined)[0], "radius"), &Value::Float(2.0));
    let d = with_sensor(r#"<shape type="sphere"><float name="radius" value="$nothing"/></shape>"#);
    let e = d.err("scene.xml");
    assert!(e.contains("undefined parameter `$nothing`"), "{e}");
    assert_eq!(place_of(&e).1, 4);
}

/// An include is looked for as Mitsuba's parser looks: beside the file
/// that names it, then beside each file that includes that one (the
/// nearest first), then in the scene's folder.
#[test]
fn nested_includes_are_found_beside_their_includers() {
    let d = Dir::new(&[
        (
            "scene.xml",
            &scene(&format!(r#"{SENSOR}<include filename="a/b/first.xml"/>"#)),
        ),
        (
            "a/b/first.xml",
            r#"<scene version="3.0.0">
                <include filename="own.xml"/>
                <include filename="top.xml"/>
            </scene>"#,
        ),
        (
            "a/b/own.xml",
            r#"<shape version="3.0.0" type="sphere"><float name="radius" value="2"/></shape>"#,
        ),
        (
            "a/b/c/inner.xml",
            r#"<shape version="3.0.0" type="sphere"><float name="radius" value="3"/></shape>"#,
        ),
        (
            "top.xml",
            r#"<scene version="3.0.0"><include filename="b/c/inner.xml"/></scene>"#,
        ),
    ]);
    // `top.xml`, named in `a/b/first.xml`, lies in the scene's folder only.
    // What it names is looked for beside it, then beside `a/b/first.xml`,
    // which includes it, then beside the scene: `b/c/inner.xml` is nowhere,
    // `c/inner.xml` is beside `a/b/first.xml`.
    let e = d.err("scene.xml");
    assert!(e.contains("b/c/inner.xml"), "{e}");
    d.write(
        "top.xml",
        br#"<scene version="3.0.0"><include filename="c/inner.xml"/></scene>"#,
    );
    let root = d.tree("scene.xml");
    let radii: Vec<_> = shapes(&root)
        .iter()
        .map(|s| prop(s, "radius").clone())
        .collect();
    assert_eq!(radii, [Value::Float(2.0), Value::Float(3.0)]);
}

#[test]
fn includes_defaults_and_refs_work_across_nested_files() {
    let d = Dir::new(&[
        (
            "scene.xml",
            &scene(&format!(
                r#"<default name="radius" value="0.5"/>
                {SENSOR}
                <include filename="parts/materials.xml"/>
                <shape type="sphere"><float name="radius" value="$radius"/><ref id="blue"/></shape>"#
            )),
        ),
        (
            "parts/materials.xml",
            r#"<scene version="3.0.0">
                <default name="radius" value="9"/>
                <bsdf type="diffuse" id="blue"><rgb name="reflectance" value="0.1, 0.2, 0.7"/></bsdf>
                <include filename="shapes.xml"/>
            </scene>"#,
        ),
        (
            "parts/shapes.xml",
            r#"<shape version="3.0.0" type="sphere"><float name="radius" value="$radius"/><ref id="blue"/></shape>"#,
        ),
    ]);
    let root = d.tree("scene.xml");
    let s = shapes(&root);
    assert_eq!(s.len(), 2);
    // The first default of a name holds.
    for shape in &s {
        assert_eq!(prop(shape, "radius"), &Value::Float(0.5));
        assert_eq!(prop(shape, "material"), &Value::String("blue".into()));
    }
    let bsdf = root.child(Kind::Bsdf).unwrap();
    assert_eq!(bsdf.id.as_deref(), Some("blue"));
    assert_eq!(numbers(prop(bsdf, "reflectance")), [0.1, 0.2, 0.7]);
    // Places name the file each value is written in.
    let inner = s[0]
        .prop("radius")
        .unwrap()
        .value
        .origin
        .at
        .clone()
        .unwrap();
    assert_eq!(inner.file.as_path(), d.path("parts/shapes.xml"));

    // An error in an included file names that file's line and column.
    d.write(
        "parts/shapes.xml",
        b"<shape version=\"3.0.0\" type=\"sphere\">\n  <float name=\"radius\" value=\"abc\"/>\n</shape>",
    );
    let e = d.err("scene.xml");
    assert!(
        e.starts_with(&format!("{}:2:31:", d.path("parts/shapes.xml").display())),
        "{e}"
    );
    assert!(e.contains("`abc` is not a finite number"), "{e}");
}

/// Laid out as Mitsuba's own Cornell box (`cbox-rgb.xml`): an included
/// fragment names meshes relative to the scene's folder, as Mitsuba
/// resolves a plugin's file, and refers to an `area` emitter that the
/// scene declares after the include; the pinhole reads `focus_distance`.
/// A `<path>` folder comes before the scene's folder, and a file found in
/// neither is still found beside the fragment that names it.
#[test]
fn files_and_forward_references_resolve_as_mitsuba_resolves_them() {
    let tri = |z: f32| format!("v -1 -1 {z}\nv 1 -1 {z}\nv 0 1 {z}\nf 1 2 3\n");
    let fragment = scene(
        r#"<shape type="obj"><string name="filename" value="meshes/light.obj"/>
             <ref id="area-emitter"/></shape>
           <shape type="obj"><string name="filename" value="meshes/wall.obj"/></shape>
           <shape type="obj"><string name="filename" value="beside.obj"/></shape>"#,
    );
    let main = scene(
        r#"<sensor type="perspective"><float name="fov" value="45"/>
             <float name="focus_distance" value="1000"/></sensor>
           <include filename="fragments/shapes.xml"/>
           <emitter type="area" id="area-emitter"><rgb name="radiance" value="2"/></emitter>"#,
    );
    let d = Dir::new(&[
        ("scene.xml", &main),
        ("fragments/shapes.xml", &fragment),
        ("meshes/light.obj", &tri(-1.0)),
        ("meshes/wall.obj", &tri(-2.0)),
        // Mitsuba would not look here: the scene's folder comes first.
        ("fragments/meshes/wall.obj", &tri(-9.0)),
        ("fragments/beside.obj", &tri(-3.0)),
    ]);
    let root = d.tree("scene.xml");
    let paths: Vec<String> = shapes(&root)
        .iter()
        .map(|s| match prop(s, "path") {
            Value::String(p) => p.clone(),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        paths,
        [
            "meshes/light.obj",
            "meshes/wall.obj",
            "fragments/beside.obj"
        ]
    );
    let light = shapes(&root)[0];
    let emitter = light.child(Kind::Emitter).expect("the declared emitter");
    assert_eq!(numbers(prop(emitter, "radiance")), [2.0; 3]);
    assert!(shapes(&root)[1].child(Kind::Emitter).is_none());
    let scene = build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.emitters.len(), 1);

    // A `<path>` folder is searched before the scene's.
    let with_path = main.replace("<include", "<path value=\"other\"/>\n<include");
    d.write("scene.xml", with_path.as_bytes());
    d.write("other/meshes/wall.obj", tri(-5.0).as_bytes());
    let root = d.tree("scene.xml");
    let Value::String(wall) = prop(shapes(&root)[1], "path") else {
        panic!()
    };
    assert_eq!(wall, "other/meshes/wall.obj");

    // Declared and referred to by nothing, an `area` emitter is refused.
    let lonely =
        with_sensor(r#"<emitter type="area" id="e"><rgb name="radiance" value="1"/></emitter>"#);
    let e = lonely.err("scene.xml");
    assert!(e.contains("give it an id that a <shape> refers to"), "{e}");
}

/// A scene of several sensors renders the first, or the one asked for
/// (Mitsuba's `--sensor`); one past the last is refused at the scene.
/// Folders given as Mitsuba's `-a` are searched after the `<path>` folders
/// and before the scene's own.
#[test]
fn sensors_are_chosen_and_search_folders_given_as_mitsuba_s_command_line() {
    let sensor = |x: f32| {
        format!(
            r#"<sensor type="perspective"><float name="fov" value="45"/>
                 <transform name="to_world"><translate x="{x}"/></transform></sensor>"#
        )
    };
    let body = format!(
        "{}\n{}\n<shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/></shape>",
        sensor(1.0),
        sensor(2.0)
    );
    let tri = |z: f32| format!("v -1 -1 {z}\nv 1 -1 {z}\nv 0 1 {z}\nf 1 2 3\n");
    let d = Dir::new(&[
        ("scene.xml", &scene(&body)),
        ("tri.obj", &tri(-1.0)),
        ("extra/tri.obj", &tri(-2.0)),
    ]);
    let read = |sensor: usize, search: &[PathBuf]| {
        let read = mitsuba::Read {
            sensor,
            search,
            ..mitsuba::Read::default()
        };
        mitsuba::from_xml_file_read(&d.path("scene.xml"), &read, LIMIT, registry)
    };
    let x = |root: &Node| numbers(prop(root.child(Kind::Sensor).unwrap(), "position"))[0];
    assert_eq!(x(&read(0, &[]).unwrap().root), 1.0);
    assert_eq!(x(&read(1, &[]).unwrap().root), 2.0);
    let e = read(2, &[]).unwrap_err().to_string();
    assert!(
        e.contains("sensor 2 was asked for; the scene has 2, 0 to 1") && place_of(&e).1 == 2,
        "{e}"
    );
    let path = |root: &Node| match prop(shapes(root)[0], "path") {
        Value::String(p) => p.clone(),
        other => panic!("{other:?}"),
    };
    // The scene's own folder holds `tri.obj`, but the search folder comes first.
    let extra = [d.path("extra")];
    assert!(path(&read(0, &extra).unwrap().root).ends_with("extra/tri.obj"));
    assert_eq!(path(&read(0, &[]).unwrap().root), "tri.obj");
}

#[test]
fn include_loops_directories_devices_and_deep_chains_are_refused() {
    let d = Dir::new(&[
        ("scene.xml", &scene(r#"<include filename="a.xml"/>"#)),
        ("a.xml", &scene(r#"<include filename="b.xml"/>"#)),
        ("b.xml", &scene(r#"<include filename="a.xml"/>"#)),
    ]);
    let e = d.err("scene.xml");
    // Named at the `<include>` that closes the loop: `b.xml`'s, line 3.
    let (file, line, _) = place_of(&e);
    assert!(
        e.contains("`a.xml`") && e.contains("include loop") && file.ends_with("b.xml") && line == 3,
        "{e}"
    );
    // A file including itself.
    let d = Dir::new(&[("scene.xml", &scene(r#"<include filename="scene.xml"/>"#))]);
    let e = d.err("scene.xml");
    assert!(
        e.contains("include loop") && place_of(&e).0.ends_with("scene.xml") && place_of(&e).1 == 3,
        "{e}"
    );

    let e = one(r#"<include filename="gone.xml"/>"#).err("scene.xml");
    assert!(
        e.contains("no file") && e.contains("gone.xml") && place_of(&e).1 == 3,
        "{e}"
    );

    let d = one(r#"<include filename="sub"/>"#);
    std::fs::create_dir(d.path("sub")).unwrap();
    let e = d.err("scene.xml");
    assert!(e.contains("sub") && e.contains("not a regular file"), "{e}");

    #[cfg(unix)]
    {
        let d = one(r#"<include filename="/dev/zero"/>"#);
        let e = d.err("scene.xml");
        assert!(
            e.starts_with("/dev/zero:") && e.contains("not a regular file"),
            "{e}"
        );
    }

    // A chain of 40 files, each including the next.
    let d = Dir::new(&[]);
    for i in 0..40 {
        d.write(
            &format!("f{i}.xml"),
            scene(&format!(r#"<include filename="f{}.xml"/>"#, i + 1)).as_bytes(),
        );
    }
    d.write("f40.xml", scene("").as_bytes());
    let e = d.err("f0.xml");
    assert!(e.contains("deep"), "{e}");
}

#[test]
fn the_size_limit_covers_each_file_and_all_includes_together() {
    let pad = format!("<!-- {} -->", "x".repeat(3000));
    let d = Dir::new(&[
        (
            "scene.xml",
            &scene(&format!("{pad}<include filename=\"b.xml\"/>")),
        ),
        ("b.xml", &scene(&pad)),
    ]);
    assert!(
        mitsuba::from_xml_file(&d.path("scene.xml"), &[], 10_000, registry).is_err_and(|e| {
            let e = e.to_string();
            e.contains("sensor")
        })
    );
    let e = mitsuba::from_xml_file(&d.path("scene.xml"), &[], 5_000, registry)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!("{}:", d.path("b.xml").display())) && e.contains("limit"),
        "{e}"
    );
}

#[test]
fn paths_aliases_and_refs_resolve_and_unknown_or_duplicate_ids_are_refused() {
    let d = with_sensor(
        r#"<path value="meshes"/>
        <bsdf type="diffuse" id="grey"/>
        <alias id="grey" as="stone"/>
        <emitter type="area" id="glow"><rgb name="radiance" value="3"/></emitter>
        <shape type="obj"><string name="filename" value="tri.obj"/><ref name="bsdf" id="stone"/></shape>"#,
    );
    std::fs::create_dir(d.path("meshes")).unwrap();
    // The top-level area emitter is refused: it lights nothing.
    let e = d.err("scene.xml");
    assert!(e.contains("area") && e.contains("inside a <shape>"), "{e}");

    let d = with_sensor(
        r#"<path value="meshes"/>
        <bsdf type="diffuse" id="grey"/>
        <alias id="grey" as="stone"/>
        <shape type="obj"><string name="filename" value="tri.obj"/><ref name="bsdf" id="stone"/>
            <boolean name="face_normals" value="true"/></shape>
        <shape type="ply"><string name="filename" value="tri.obj"/></shape>"#,
    );
    std::fs::create_dir(d.path("meshes")).unwrap();
    d.write("meshes/tri.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let root = d.tree("scene.xml");
    let s = shapes(&root);
    assert_eq!(s[0].plugin, "mesh");
    assert_eq!(prop(s[0], "path"), &Value::String("meshes/tri.obj".into()));
    assert_eq!(prop(s[0], "smooth"), &Value::Bool(false));
    // The alias names the very material.
    assert_eq!(prop(s[0], "material"), &Value::String("grey".into()));
    // Mitsuba's default: smooth normals, and the default material.
    assert_eq!(prop(s[1], "smooth"), &Value::Bool(true));
    assert_eq!(prop(s[1], "material"), &Value::String("bsdf_1".into()));

    let d = with_sensor(r#"<shape type="sphere"><ref id="nowhere"/></shape>"#);
    let e = d.err("scene.xml");
    assert!(
        e.contains("no object has the id `nowhere`") && place_of(&e).1 == 4,
        "{e}"
    );
    let d = with_sensor(
        r#"<bsdf type="diffuse" id="twice"/>
        <bsdf type="diffuse" id="twice"/>"#,
    );
    let e = d.err("scene.xml");
    assert!(
        e.contains("the id `twice` is given twice") && place_of(&e).1 == 5,
        "{e}"
    );
    let d = with_sensor(r#"<path value="not-there"/>"#);
    assert!(d.err("scene.xml").contains("no folder"));
}

#[test]
fn property_tags_are_read_and_wrong_types_refused() {
    let d = with_sensor(
        r#"<shape type="sphere">
            <point name="center" value="1, 2, 3"/>
            <integer name="radius" value="2"/>
        </shape>
        <shape type="sphere"><vector name="center" x="1" y="2" z="3"/></shape>"#,
    );
    let root = d.tree("scene.xml");
    let s = shapes(&root);
    assert_eq!(numbers(prop(s[0], "center")), [1.0, 2.0, 3.0]);
    assert_eq!(numbers(prop(s[1], "center")), [1.0, 2.0, 3.0]);
    assert_eq!(prop(s[0], "radius"), &Value::Float(2.0));

    for (body, message) in [
        (
            r#"<shape type="sphere"><string name="radius" value="big"/></shape>"#,
            "`radius` must be a float, got a string",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="1" extra="2"/></shape>"#,
            "unexpected attribute `extra`",
        ),
        (
            r#"<shape type="sphere"><float name="radius"/></shape>"#,
            "missing attribute `value`",
        ),
        (
            r#"<shape type="sphere"><boolean name="flip_normals" value="yes"/></shape>"#,
            "is not `true` or `false`",
        ),
        (
            r#"<shape type="sphere"><integer name="radius" value="1.5"/></shape>"#,
            "is not an integer",
        ),
        (
            r#"<shape type="sphere"><point name="center" value="1, 2"/></shape>"#,
            "expected 1 or 3 numbers, got 2",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="1"/><float name="radius" value="2"/></shape>"#,
            "given twice",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="nan"/></shape>"#,
            "`nan` is not a finite number",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="inf"/></shape>"#,
            "`inf` is not a finite number",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="1e999"/></shape>"#,
            "out of range",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="1.2.3"/></shape>"#,
            "is not a finite number",
        ),
        (
            r#"<shape type="sphere"><rgb name="x" value="1, 2"/></shape>"#,
            "<rgb>: expected 1 or 3 numbers",
        ),
        (
            r#"<shape type="sphere"><blob name="x"/></shape>"#,
            "<blob> is not a tag",
        ),
        (
            r#"<shape type="sphere">text</shape>"#,
            "text is not allowed",
        ),
        (
            r#"<shape><float name="radius" value="1"/></shape>"#,
            "missing attribute `type`",
        ),
    ] {
        let e = with_sensor(body).err("scene.xml");
        assert!(e.contains(message), "{body}: {e}");
        let (file, line, col) = place_of(&e);
        assert!(
            file.ends_with("scene.xml") && line == 4 && col > 0,
            "{body}: {e}"
        );
    }
}

#[test]
fn spectra_convert_as_mitsubas_rgb_variants() {
    let d = with_sensor(
        r#"<bsdf type="diffuse" id="flat"><spectrum name="reflectance" value="0.5"/></bsdf>
        <bsdf type="diffuse" id="sampled"><spectrum name="reflectance" value="400:0.2, 500:0.6, 600:0.4, 700:0.3"/></bsdf>
        <bsdf type="diffuse" id="filed"><spectrum name="reflectance" filename="refl.spd"/></bsdf>
        <emitter type="point"><spectrum name="intensity" value="10"/></emitter>
        <emitter type="constant"><spectrum name="radiance" value="360:1, 830:1"/></emitter>"#,
    );
    d.write(
        "refl.spd",
        b"# wavelength value\n400 0.2\n500 0.6\n600 0.4\n700 0.3\n",
    );
    let root = d.tree("scene.xml");
    let bsdf = |id: &str| {
        root.children_of(Kind::Bsdf)
            .find(|b| b.id.as_deref() == Some(id))
            .unwrap()
    };
    assert_eq!(numbers(prop(bsdf("flat"), "reflectance")), [0.5; 3]);
    let sampled = numbers(prop(bsdf("sampled"), "reflectance"));
    let expect = spectrum::to_rgb(
        &spectrum::parse("400:0.2, 500:0.6, 600:0.4, 700:0.3").unwrap(),
        spectrum::Use::Reflectance,
    );
    assert_eq!(sampled, expect);
    assert_eq!(numbers(prop(bsdf("filed"), "reflectance")), expect);
    // A constant emission is the value times sRGB of XYZ (1, 1, 1): the
    // row sums of the XYZ → sRGB matrix.
    let light = root
        .child(Kind::Emitter)
        .filter(|e| e.plugin == "constant")
        .unwrap();
    let point = root
        .children_of(Kind::Emitter)
        .find(|e| e.plugin == "point")
        .unwrap();
    let by_hand = [1.204794, 0.948291, 0.908916];
    assert!(close(
        &numbers(prop(point, "intensity")),
        &by_hand.map(|c| 10.0 * c),
        1e-9
    ));
    // A flat sampled emission over the whole range is the same colour.
    assert!(close(&numbers(prop(light, "radiance")), &by_hand, 5e-3));
    let e = with_sensor(
        r#"<bsdf type="diffuse"><spectrum name="reflectance" value="500:1, 400:1"/></bsdf>"#,
    )
    .err("scene.xml");
    assert!(e.contains("must increase"), "{e}");
    let e = with_sensor(
        r#"<bsdf type="diffuse"><spectrum name="reflectance" filename="none.spd"/></bsdf>"#,
    )
    .err("scene.xml");
    assert!(
        e.contains("cannot read the spectrum") && place_of(&e).1 == 4,
        "{e}"
    );
}

/// Every conductor material of Mitsuba's table builds, on `conductor`
/// and `roughconductor`; a `<spectrum>` file given as `eta` and `k` is
/// weighted by D65 as Mitsuba's unbounded textures are (other numbers than
/// the same files named by `material`); a hostile spectrum file is refused
/// with the scene's place and the file's line.
#[test]
fn conductor_materials_and_index_spectra_as_mitsuba() {
    let body: String = penumbra::bsdf::ior::CONDUCTOR_NAMES
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let plugin = if i % 2 == 0 { "conductor" } else { "roughconductor" };
            format!(
                r#"<shape type="sphere"><bsdf type="{plugin}"><string name="material" value="{name}"/></bsdf></shape>"#
            )
        })
        .collect::<Vec<_>>()
        .join("\n");
    build_whitted(&with_sensor(&body)).unwrap_or_else(|e| panic!("{e}"));
    let e = build_whitted(&with_sensor(
        r#"<shape type="sphere"><bsdf type="conductor"><string name="material" value="gold"/></bsdf></shape>"#,
    ))
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("gold") && e.contains("W"), "{e}");

    let d = with_sensor(
        r#"<bsdf type="roughconductor" id="au"><spectrum name="eta" filename="Au.eta.spd"/><spectrum name="k" filename="Au.k.spd"/></bsdf>"#,
    );
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ior");
    for f in ["Au.eta.spd", "Au.k.spd"] {
        d.write(f, &std::fs::read(data.join(f)).unwrap());
    }
    let root = d.tree("scene.xml");
    let au = root.child(Kind::Bsdf).unwrap();
    // Mitsuba 3.9.1 `scalar_rgb`, `mi.traverse` of the same bsdf.
    let eta = [0.07987049221992493, 0.4046523869037628, 1.5589680671691895];
    let k = [3.3867456912994385, 2.5007057189941406, 1.7689123153686523];
    let f32s = |v: Vec<f64>| v.iter().map(|&c| c as f32 as f64).collect::<Vec<_>>();
    assert_eq!(f32s(numbers(prop(au, "eta"))), eta);
    assert_eq!(f32s(numbers(prop(au, "k"))), k);

    // `eta` and `k` take textures, as Mitsuba's.
    let d = with_sensor(
        r#"<shape type="sphere"><bsdf type="roughconductor"><texture type="checkerboard" name="eta"><rgb name="color0" value="0.2"/><rgb name="color1" value="0.9"/></texture><spectrum name="k" value="400:3, 700:4"/></bsdf></shape>"#,
    );
    let root = d.tree("scene.xml");
    let rough = root.child(Kind::Bsdf).unwrap();
    assert!(matches!(prop(rough, "eta"), Value::Table(_)), "{rough:?}");
    let k = [3.7901742458343506, 3.475724697113037, 3.120769500732422];
    assert_eq!(f32s(numbers(prop(rough, "k"))), k);
    build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));

    for (text, want) in [
        (
            "400 1\n500 2\n450 3\n",
            "bad.spd: line 3: the wavelength 450 does not exceed",
        ),
        (
            "400 1\n500 nan\n",
            "bad.spd: line 2: `nan` is not a finite number",
        ),
        (
            "400 1\n500 1e400\n",
            "bad.spd: line 2: `1e400` is out of range",
        ),
        ("# nothing\n", "bad.spd: the file holds no"),
    ] {
        let d = with_sensor(
            r#"<bsdf type="conductor"><spectrum name="eta" filename="bad.spd"/></bsdf>"#,
        );
        d.write("bad.spd", text.as_bytes());
        let e = d.err("scene.xml");
        let (file, line, col) = place_of(&e);
        assert!(
            e.contains(want) && file.ends_with("scene.xml") && line == 4 && col > 0,
            "{text:?}: {e}"
        );
    }
}

#[test]
fn transforms_compose_each_operation_after_the_last() {
    let d = with_sensor(
        r#"<shape type="sphere">
            <transform name="to_world">
                <translate x="1"/>
                <scale value="2"/>
                <rotate z="1" angle="90"/>
            </transform>
        </shape>
        <shape type="obj">
            <string name="filename" value="m.obj"/>
            <transform name="to_world">
                <scale x="2" y="3" z="4"/>
                <translate value="1, 2, 3"/>
            </transform>
        </shape>"#,
    );
    let root = d.tree("scene.xml");
    let matrix = |shape: &Node| match prop(shape, "transform") {
        Value::Table(props) => numbers(&props[0].value.value),
        other => panic!("{other:?}"),
    };
    // rotate_z(90) · scale(2) · translate(1, 0, 0), by hand.
    let by_hand = [
        0.0, -2.0, 0.0, 0.0, //
        2.0, 0.0, 0.0, 2.0, //
        0.0, 0.0, 2.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    ];
    let s = shapes(&root);
    assert!(close(&matrix(s[0]), &by_hand, 1e-12), "{:?}", matrix(s[0]));
    let by_hand = [
        2.0, 0.0, 0.0, 1.0, //
        0.0, 3.0, 0.0, 2.0, //
        0.0, 0.0, 4.0, 3.0, //
        0.0, 0.0, 0.0, 1.0,
    ];
    assert_eq!(matrix(s[1]), by_hand);
    // The same order as the module's own product.
    let m = transform::mul(
        &transform::translate([1.0, 2.0, 3.0]),
        &transform::scale([2.0, 3.0, 4.0]),
    );
    assert_eq!(m.iter().flatten().copied().collect::<Vec<_>>(), by_hand);

    for (ops, message) in [
        (r#"<scale x="0"/>"#, "singular"),
        (
            r#"<matrix value="1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1"/>"#,
            "affine",
        ),
        (
            r#"<matrix value="1 0 0"/>"#,
            "expected 16 (or 9) numbers, got 3",
        ),
        (r#"<rotate angle="30"/>"#, "the axis is zero"),
        (r#"<rotate x="1"/>"#, "missing attribute `angle`"),
        (r#"<lookat origin="0,0,0" target="0,0,0"/>"#, "coincide"),
        (r#"<translate x="nan"/>"#, "not a finite number"),
        (r#"<shear x="1"/>"#, "not a transform operation"),
    ] {
        let body =
            format!(r#"<shape type="sphere"><transform name="to_world">{ops}</transform></shape>"#);
        let e = with_sensor(&body).err("scene.xml");
        assert!(e.contains(message) && place_of(&e).1 == 4, "{ops}: {e}");
    }
}

#[test]
fn rectangles_become_quads_with_mitsubas_normal() {
    let d = with_sensor(
        r#"<shape type="rectangle"/>
        <shape type="rectangle"><transform name="to_world"><scale z="-1"/></transform></shape>"#,
    );
    let root = d.tree("scene.xml");
    let s = shapes(&root);
    assert_eq!(s[0].plugin, "quad");
    assert_eq!(numbers(prop(s[0], "origin")), [-1.0, -1.0, 0.0]);
    assert_eq!(numbers(prop(s[0], "edge_u")), [2.0, 0.0, 0.0]);
    assert_eq!(numbers(prop(s[0], "edge_v")), [0.0, 2.0, 0.0]);
    // Mirrored: the edges swap, so that u × v is still the transformed +z (-z).
    let (u, v) = (numbers(prop(s[1], "edge_u")), numbers(prop(s[1], "edge_v")));
    let n = transform::cross([u[0], u[1], u[2]], [v[0], v[1], v[2]]);
    assert!(n[2] < 0.0, "{n:?}");
}

/// `cube`, `cylinder` and `disk` keep their names and parameters,
/// `to_world` as the transform, `flip_normals` on every shape, and
/// `face_normals` as the mesh's flat facets; `rectangle` takes
/// `flip_normals` too. The scene builds, and each shape is where Mitsuba
/// puts it.
#[test]
fn cubes_cylinders_disks_and_flipped_normals_map_by_name() {
    let d = with_sensor(
        r#"<shape type="cube"><transform name="to_world"><translate x="10"/></transform>
            <boolean name="flip_normals" value="true"/></shape>
        <shape type="cylinder"><point name="p0" x="0" y="0" z="-5"/>
            <point name="p1" x="0" y="0" z="-3"/><float name="radius" value="0.5"/></shape>
        <shape type="disk"><transform name="to_world"><scale value="2"/><translate y="-10"/></transform></shape>
        <shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>
        <shape type="ply"><string name="filename" value="m.ply"/><boolean name="face_normals" value="true"/></shape>"#,
    );
    let root = d.tree("scene.xml");
    let s = shapes(&root);
    let plugins: Vec<&str> = s.iter().map(|n| n.plugin.as_str()).collect();
    assert_eq!(plugins, ["cube", "cylinder", "disk", "quad", "mesh"]);
    assert_eq!(prop(s[0], "flip_normals"), &Value::Bool(true));
    assert!(s[0].prop("transform").is_some());
    assert_eq!(numbers(prop(s[1], "p0")), [0.0, 0.0, -5.0]);
    assert_eq!(numbers(prop(s[1], "p1")), [0.0, 0.0, -3.0]);
    assert_eq!(numbers(prop(s[1], "radius")), [0.5]);
    assert!(s[2].prop("transform").is_some());
    assert_eq!(prop(s[3], "flip_normals"), &Value::Bool(true));
    assert_eq!(prop(s[4], "smooth"), &Value::Bool(false));
    // Built (without the mesh): each shape where Mitsuba has it.
    let d = with_sensor(
        r#"<shape type="cube"><transform name="to_world"><translate x="10"/></transform>
            <boolean name="flip_normals" value="true"/></shape>
        <shape type="cylinder"><point name="p0" x="0" y="0" z="-5"/>
            <point name="p1" x="0" y="0" z="-3"/><float name="radius" value="0.5"/></shape>
        <shape type="disk"><transform name="to_world"><scale value="2"/><translate y="-10"/></transform></shape>"#,
    );
    let scene = build_whitted(&d).unwrap();
    let hit = |o: [f32; 3], dir: [f32; 3]| {
        let ray = penumbra::math::Ray::new(o.into(), dir.into(), 0.0);
        scene.world.intersect(&ray, 0.0, f32::INFINITY).unwrap()
    };
    // The cube at x = 10, its normals turned in.
    let h = hit([10.0, 0.0, 5.0], [0.0, 0.0, -1.0]);
    assert!((h.t - 4.0).abs() < 1e-5 && h.ng.z < -0.999, "{h:?}");
    // The cylinder of radius 0.5 around z from −5 to −3.
    let h = hit([3.0, 0.0, -4.0], [-1.0, 0.0, 0.0]);
    assert!((h.t - 2.5).abs() < 1e-5 && h.ng.x > 0.999, "{h:?}");
    // The disk of radius 2 at y = −10, facing +z.
    let h = hit([1.5, -10.0, 5.0], [0.0, 0.0, -1.0]);
    assert!((h.t - 5.0).abs() < 1e-5 && h.ng.z > 0.999, "{h:?}");
}

/// An OBJ's texture coordinates are flipped (`v → 1 − v`) as Mitsuba's
/// reader flips them, unless `flip_tex_coords` is false; a PLY's only when
/// `flip_tex_coords` is true (its reader's default is false), a
/// `.serialized` file's never (its reader does not apply it). Built, a
/// point of the square carries the flipped coordinates.
#[test]
fn obj_texture_coordinates_are_flipped_as_mitsuba_flips_them() {
    let d = with_sensor(
        r#"<shape type="obj"><string name="filename" value="s.obj"/></shape>
        <shape type="obj"><string name="filename" value="s.obj"/><boolean name="flip_tex_coords" value="false"/>
            <transform name="to_world"><translate x="3"/></transform></shape>"#,
    );
    std::fs::write(
        d.path("s.obj"),
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
    )
    .unwrap();
    let root = d.tree("scene.xml");
    let s = shapes(&root);
    assert_eq!(prop(s[0], "flip_tex_coords"), &Value::Bool(true));
    assert_eq!(prop(s[1], "flip_tex_coords"), &Value::Bool(false));
    let scene = build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    let uv = |x: f32| {
        let ray =
            penumbra::math::Ray::new([x + 0.3, 0.2, 5.0].into(), [0.0, 0.0, -1.0].into(), 0.0);
        scene.world.intersect(&ray, 0.0, f32::INFINITY).unwrap().uv
    };
    let (a, b) = (uv(0.0), uv(3.0));
    assert!(
        (a.x - 0.3).abs() < 1e-5 && (a.y - 0.8).abs() < 1e-5,
        "{a:?}"
    );
    assert!(
        (b.x - 0.3).abs() < 1e-5 && (b.y - 0.2).abs() < 1e-5,
        "{b:?}"
    );
    let d = with_sensor(r#"<shape type="ply"><string name="filename" value="m.ply"/></shape>"#);
    assert!(shapes(&d.tree("scene.xml"))[0]
        .prop("flip_tex_coords")
        .is_none());
    // A PLY square with `flip_tex_coords`, built: its coordinates flipped.
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
               property float u\nproperty float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n3 0 2 3\n";
    let d = with_sensor(
        r#"<shape type="ply"><string name="filename" value="s.ply"/><boolean name="flip_tex_coords" value="true"/></shape>
        <shape type="serialized"><string name="filename" value="s.serialized"/><boolean name="flip_tex_coords" value="true"/></shape>"#,
    );
    std::fs::write(d.path("s.ply"), ply).unwrap();
    let root = d.tree("scene.xml");
    assert_eq!(
        prop(shapes(&root)[0], "flip_tex_coords"),
        &Value::Bool(true)
    );
    assert!(shapes(&root)[1].prop("flip_tex_coords").is_none());
    let mut only_ply = root.clone();
    only_ply.children.retain(|c| {
        c.kind != Kind::Shape
            || c.prop("path")
                .is_some_and(|p| matches!(&p.value.value, Value::String(s) if s.ends_with(".ply")))
    });
    let src = SceneSource::from_tree(only_ply, &d.path(""), &LoadOptions::default());
    let scene = src.build().unwrap_or_else(|e| panic!("{e}"));
    let ray = penumbra::math::Ray::new([0.3, 0.2, 5.0].into(), [0.0, 0.0, -1.0].into(), 0.0);
    let uv = scene.world.intersect(&ray, 0.0, f32::INFINITY).unwrap().uv;
    assert!(
        (uv.x - 0.3).abs() < 1e-5 && (uv.y - 0.8).abs() < 1e-5,
        "{uv:?}"
    );
}

/// `shapegroup` and `instance` are `[groups.ID]` and objects of type
/// `instance` naming it, `to_world` as the transform; the instances are
/// hit where they are placed. An emitter in a group, a reference to
/// something else than a group, and a group inside a group are refused
/// at their place.
#[test]
fn shapegroups_and_instances_map_onto_groups() {
    let group = r#"<shape type="shapegroup" id="g">
            <shape type="sphere"><float name="radius" value="0.5"/></shape>
            <shape type="cube"><transform name="to_world"><scale value="0.25"/><translate z="2"/></transform></shape>
        </shape>"#;
    let d = with_sensor(&format!(
        r#"{group}
        <shape type="instance"><ref id="g"/></shape>
        <shape type="instance"><ref id="g"/><transform name="to_world"><translate x="5"/></transform></shape>"#
    ));
    let root = d.tree("scene.xml");
    let s = shapes(&root);
    assert_eq!(s[0].plugin, "shapegroup");
    assert_eq!(s[0].id.as_deref(), Some("g"));
    assert_eq!(s[0].children_of(Kind::Shape).count(), 2);
    assert_eq!(s[1].plugin, "instance");
    assert_eq!(prop(s[1], "group"), &Value::String("g".into()));
    assert!(s[2].prop("transform").is_some());
    let scene = build_whitted(&d).unwrap();
    assert_eq!(scene.world.objects.len(), 4);
    for x in [0.0, 5.0] {
        let ray = penumbra::math::Ray::new([x, 0.0, 9.0].into(), [0.0, 0.0, -1.0].into(), 0.0);
        let h = scene.world.intersect(&ray, 0.0, f32::INFINITY).unwrap();
        // The cube's top (z = 2.25) first.
        assert!((h.t - 6.75).abs() < 1e-5, "{x}: {h:?}");
        assert!((h.p.x - x).abs() < 1e-5);
    }
    // Errors, each at the place it is about.
    for (body, message, line) in [
        (
            r#"<shape type="shapegroup" id="g">
            <shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
            </shape><shape type="instance"><ref id="g"/>
            <transform name="to_world"><scale x="2"/></transform></shape>"#,
            "an emitting sphere that moves or is placed by an instance must keep its proportions",
            5,
        ),
        (
            r#"<bsdf type="diffuse" id="m"/><shape type="instance"><ref id="m"/></shape>"#,
            "an instance refers to a shapegroup; `m` is a <bsdf>",
            4,
        ),
        (
            r#"<shape type="shapegroup" id="g">
            <shape type="shapegroup" id="h"/></shape>"#,
            "groups do not nest",
            5,
        ),
        (
            r#"<shape type="instance"><ref id="g"/><transform name="to_world"><scale x="0"/></transform></shape>
            <shape type="shapegroup" id="g"><shape type="sphere"/></shape>"#,
            "",
            4,
        ),
    ] {
        let d = with_sensor(body);
        let e = match d.load("scene.xml", &[]) {
            Err(e) => e.to_string(),
            Ok(_) => match build_whitted(&d) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("{body} should be refused"),
            },
        };
        assert!(e.contains(message), "{body}: {e}");
        assert_eq!(place_of(&e).1, line, "{body}: {e}");
    }
}

#[test]
fn sensors_films_and_samplers_map_onto_the_camera_and_render_settings() {
    let fov_of = |body: &str| {
        let d = one(body);
        let root = d.tree("scene.xml");
        match prop(sensor(&root), "fov") {
            Value::Float(f) => *f,
            other => panic!("{other:?}"),
        }
    };
    let film = r#"<film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film>"#;
    let half_tan = |deg: f64| (deg.to_radians() / 2.0).tan();
    let deg = |t: f64| 2.0 * t.atan().to_degrees();
    let cases = [
        ("x", deg(half_tan(60.0) / 2.0)),
        ("y", 60.0),
        ("diagonal", deg(half_tan(60.0) / 5f64.sqrt())),
        ("smaller", 60.0),
        ("larger", deg(half_tan(60.0) / 2.0)),
    ];
    for (axis, expect) in cases {
        let body = format!(
            r#"<sensor type="perspective"><float name="fov" value="60"/><string name="fov_axis" value="{axis}"/>{film}</sensor>"#
        );
        assert!((fov_of(&body) - expect).abs() < 1e-12, "{axis}");
    }
    // No fov: a 50 mm lens on 36 × 24 mm film, along the diagonal; 768 × 576.
    let d = one(r#"<sensor type="perspective"/>"#);
    let root = d.tree("scene.xml");
    let f = root.child(Kind::Sensor).unwrap().child(Kind::Film).unwrap();
    assert_eq!(
        (prop(f, "width"), prop(f, "height")),
        (&Value::Int(768), &Value::Int(576))
    );
    assert_eq!(prop(f, "filter"), &Value::String("gaussian".into()));
    let diagonal = 2.0 * (43.266615305567875f64 / 100.0).atan().to_degrees();
    let expect = deg(half_tan(diagonal) / (1.0 + (4.0f64 / 3.0).powi(2)).sqrt());
    let Value::Float(v) = prop(sensor(&root), "fov") else {
        panic!()
    };
    assert!((v - expect).abs() < 1e-9, "{v} {expect}");
    let s = sensor(&root).child(Kind::Sampler).unwrap();
    assert_eq!(prop(s, "spp"), &Value::Int(4));
    assert_eq!(prop(s, "distribution"), &Value::String("random".into()));

    // A thin lens, looking down -z from (1, 2, 3).
    let d = one(r#"<sensor type="thinlens">
            <float name="aperture_radius" value="0.1"/><float name="focus_distance" value="4"/>
            <float name="fov" value="30"/>
            <transform name="to_world"><translate value="1, 2, 3"/><rotate y="1" angle="180"/></transform>
            <sampler type="ldsampler"><integer name="sample_count" value="16"/></sampler>
            <film type="hdrfilm"><rfilter type="tent"/></film>
        </sensor>"#);
    let loaded = d.load("scene.xml", &[]).unwrap();
    let cam = sensor(&loaded.root);
    assert_eq!(prop(cam, "aperture"), &Value::Float(0.1));
    assert_eq!(prop(cam, "focal_distance"), &Value::Float(4.0));
    assert!(close(
        &numbers(prop(cam, "position")),
        &[-1.0, 2.0, -3.0],
        1e-12
    ));
    assert!(close(
        &numbers(prop(cam, "look_at")),
        &[-1.0, 2.0, -4.0],
        1e-12
    ));
    assert!(close(&numbers(prop(cam, "up")), &[0.0, 1.0, 0.0], 1e-12));
    let s = cam.child(Kind::Sampler).unwrap();
    assert_eq!(prop(s, "distribution"), &Value::String("sobol".into()));
    assert_eq!(prop(s, "spp"), &Value::Int(16));
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].contains("ldsampler"));
    let f = cam.child(Kind::Film).unwrap();
    assert_eq!(prop(f, "filter"), &Value::String("tent".into()));

    // The camera sample's distribution, and the path sampler of the
    // bounces (none: independent numbers).
    for (sampler, dist, path) in [
        ("independent", "random", None),
        ("stratified", "jitter", Some("pmj02")),
        ("multijitter", "jitter", Some("pmj02")),
        ("orthogonal", "pmj02", Some("pmj02")),
        ("ldsampler", "sobol", Some("sobol")),
    ] {
        let d = one(&format!(
            r#"<sensor type="perspective"><sampler type="{sampler}"/></sensor>"#
        ));
        let root = d.tree("scene.xml");
        let s = sensor(&root).child(Kind::Sampler).unwrap();
        assert_eq!(
            prop(s, "distribution"),
            &Value::String(dist.into()),
            "{sampler}"
        );
        // Film positions over the pixel's square, not random's disk.
        assert_eq!(
            s.prop("pixel_distribution").map(|p| &p.value.value),
            (dist == "random")
                .then(|| Value::String("fast-random".into()))
                .as_ref(),
            "{sampler}"
        );
        let i = root.child(Kind::Integrator).unwrap();
        assert_eq!(
            i.prop("path_sampler").map(|p| &p.value.value),
            path.map(|p| Value::String(p.into())).as_ref(),
            "{sampler}"
        );
    }

    for (body, message) in [
        (
            r#"<sensor type="perspective"><transform name="to_world"><scale x="-1"/></transform></sensor>"#,
            "mirrors",
        ),
        (
            r#"<sensor type="perspective"><float name="fov" value="180"/></sensor>"#,
            "between 0 and 180",
        ),
        (
            r#"<sensor type="perspective"><string name="fov_axis" value="z"/><float name="fov" value="30"/></sensor>"#,
            "not one of x, y",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="0"/></film></sensor>"#,
            "at least 1",
        ),
        (
            r#"<sensor type="perspective"><film type="specfilm"/></sensor>"#,
            "film `specfilm` is not supported; supported: hdrfilm",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="sinc"/></film></sensor>"#,
            "rfilter `sinc` is not supported; supported: box, tent, gaussian, mitchell, catmullrom, lanczos",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="box"><float name="radius" value="2"/></rfilter></film></sensor>"#,
            "other values are not supported",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="gaussian"><float name="stddev" value="-1"/></rfilter></film></sensor>"#,
            "the gaussian rfilter's `stddev` must be a positive number, got -1",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="lanczos"><integer name="lobes" value="0"/></rfilter></film></sensor>"#,
            "the lanczos rfilter's `lobes` must be an integer from 1 to 32, got 0",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="mitchell"><float name="B" value="1.5"/></rfilter></film></sensor>"#,
            "the mitchell rfilter's `B` must be between 0 and 1, got 1.5",
        ),
        (
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="catmullrom"><float name="C" value="0.5"/></rfilter></film></sensor>"#,
            "`C` is not a parameter of the rfilter `catmullrom`",
        ),
        (
            r#"<sensor type="spherical"/>"#,
            "sensor `spherical` is not supported; supported: perspective, thinlens, orthographic",
        ),
        (
            r#"<sensor type="perspective"><transform name="to_world"><scale value="2"/></transform></sensor>"#,
            "scales",
        ),
        (
            r#"<sensor type="orthographic"><transform name="to_world"><matrix value="1 0.5 0 0  0 1 0 0  0 0 1 0  0 0 0 1"/></transform></sensor>"#,
            "shears",
        ),
        (
            r#"<sensor type="perspective"><float name="near_clip" value="0"/></sensor>"#,
            "`near_clip` must be greater than 0",
        ),
        (
            r#"<sensor type="thinlens"><float name="near_clip" value="5"/><float name="far_clip" value="5"/></sensor>"#,
            "must be less than `far_clip`",
        ),
        (
            r#"<sensor type="thinlens"><float name="focus_distance" value="1"/></sensor>"#,
            "missing `aperture_radius`",
        ),
        (
            r#"<sensor type="perspective"><sampler type="sobolish"/></sensor>"#,
            "sampler `sobolish` is not supported",
        ),
    ] {
        let e = one(body).err("scene.xml");
        assert!(e.contains(message) && place_of(&e).1 >= 3, "{body}: {e}");
    }
    // Clip planes: Mitsuba's defaults unless given; the principal point.
    let clip_of = |body: &str| {
        let root = one(body).tree("scene.xml");
        let cam = sensor(&root).clone();
        let f = |k: &str| match cam.prop(k).map(|p| &p.value.value) {
            Some(Value::Float(v)) => *v,
            other => panic!("{k}: {other:?}"),
        };
        (f("near_clip"), f("far_clip"), cam)
    };
    let (near, far, cam) = clip_of(r#"<sensor type="perspective"/>"#);
    assert_eq!((near, far), (0.01, 10000.0));
    assert!(cam.prop("principal_point_offset").is_none());
    let (near, far, cam) = clip_of(
        r#"<sensor type="perspective"><float name="near_clip" value="2"/><float name="far_clip" value="7"/>
        <float name="principal_point_offset_y" value="0.25"/></sensor>"#,
    );
    assert_eq!((near, far), (2.0, 7.0));
    assert_eq!(
        numbers(prop(&cam, "principal_point_offset")),
        vec![0.0, 0.25]
    );
    // An orthographic camera: the unit view scaled by `to_world`, the
    // near plane moved by its scale along the axis.
    let (near, far, cam) = clip_of(&format!(
        r#"<sensor type="orthographic"><float name="near_clip" value="1"/><float name="far_clip" value="9"/>
        <transform name="to_world"><scale x="3" y="2" z="4"/><translate value="0, 0, 1"/></transform>{film}</sensor>"#
    ));
    assert_eq!((near, far), (4.0, 12.0));
    assert_eq!(
        prop(&cam, "projection"),
        &Value::String("orthographic".into())
    );
    assert_eq!(prop(&cam, "view_width"), &Value::Float(6.0));
    assert_eq!(prop(&cam, "view_height"), &Value::Float(2.0));
    assert!(close(
        &numbers(prop(&cam, "position")),
        &[0.0, 0.0, 1.0],
        1e-12
    ));
    assert!(close(
        &numbers(prop(&cam, "look_at")),
        &[0.0, 0.0, 2.0],
        1e-12
    ));

    // An absurd size passes the reader and is refused by the builder.
    let d = one(
        r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="1000000"/></film></sensor>"#,
    );
    let e = build_whitted(&d).err().unwrap().to_string();
    assert!(
        e.contains("scene.xml:3:") && e.contains("render.width"),
        "{e}"
    );
}

/// Mitsuba's `independent` sampler draws film positions uniformly over the
/// pixel's square, and so must its reading: an emitter whose edges cover a
/// tenth of a row and of two columns of pixels (seen directly, box filter)
/// gives those pixels a tenth of its radiance, a corner pixel a hundredth.
/// Points drawn over the disk inscribed in the pixel give about half as
/// much on the edges and none in the corner.
#[test]
fn independent_film_positions_cover_the_whole_pixel() {
    // 32 × 32 pixels over a 90° field of view: the plane z = -1 holds 16
    // pixels per unit, film y = 16 (1 - y) and film x = 16 (1 + x). The
    // emitter spans film y < 20.1 and 5.9 < film x < 26.1.
    let (y_edge, x_edge) = (1.0 - 20.1 / 16.0, 1.0 - 5.9 / 16.0);
    let body = format!(
        r#"<integrator type="path"><integer name="max_depth" value="1"/></integrator>
        <sensor type="perspective">
            <float name="fov" value="90"/>
            <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="4096"/></sampler>
            <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film>
        </sensor>
        <shape type="rectangle">
            <transform name="to_world"><scale x="{x_edge}" y="{sy}"/><translate y="{ty}" z="-1"/></transform>
            <emitter type="area"><rgb name="radiance" value="1, 1, 1"/></emitter>
        </shape>"#,
        sy = (2.0 - y_edge) / 2.0,
        ty = (2.0 + y_edge) / 2.0,
    );
    let d = one(&body);
    let scene = SceneSource::open(
        d.path("scene.xml").to_str().unwrap(),
        &LoadOptions::default(),
    )
    .unwrap()
    .build()
    .unwrap();
    let (img, _) = common::render_scene(&scene, 2);
    let at = |x: usize, y: usize| f64::from(img.pixels[y * 32 + x].g);
    let mean =
        |p: Vec<(usize, usize)>| p.iter().map(|&(x, y)| at(x, y)).sum::<f64>() / p.len() as f64;
    // 19 and 17 pixels of 4096 samples each: the standard deviation of a
    // covered fraction of 0.1 is at most 0.0011.
    let row = mean((7..26).map(|x| (x, 20)).collect());
    let columns = mean((2..19).flat_map(|y| [(5, y), (26, y)]).collect());
    assert!((row - 0.1).abs() < 0.006, "bottom edge row: {row}");
    assert!(
        (columns - 0.1).abs() < 0.006,
        "side edge columns: {columns}"
    );
    let corners = (at(5, 20) + at(26, 20)) / 2.0;
    assert!((corners - 0.01).abs() < 0.006, "corners: {corners}");
    assert_eq!(at(15, 10), 1.0);
    assert_eq!(at(15, 21), 0.0);
}

#[test]
fn unsupported_plugins_are_refused_naming_what_is_supported() {
    for (body, message) in [
        (
            r#"<bsdf type="hair"/>"#,
            "bsdf `hair` is not supported; supported: diffuse, conductor, \
             roughconductor, dielectric, roughdielectric, thindielectric, plastic, \
             roughplastic, twosided, mask, blendbsdf, normalmap, bumpmap, principled, \
             principledthin",
        ),
        (
            r#"<bsdf type="conductor"><float name="alpha" value="0.1"/></bsdf>"#,
            "`alpha` is not a parameter of the bsdf `conductor`",
        ),
        (
            r#"<bsdf type="twosided"><bsdf type="diffuse"/><bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf>"#,
            "a `twosided` holds 1 or 2 <bsdf>s, not 3",
        ),
        (
            r#"<bsdf type="blendbsdf"><bsdf type="diffuse"/></bsdf>"#,
            "a `blendbsdf` holds 2 <bsdf>s, not 1",
        ),
        (
            r#"<bsdf type="mask"><texture type="bitmap" name="weight"/><bsdf type="diffuse"/></bsdf>"#,
            "a texture as `weight` of the bsdf `mask` is not supported (textures go to: opacity)",
        ),
        (
            r#"<bsdf type="roughplastic"><float name="alpha_u" value="0.1"/></bsdf>"#,
            "`alpha_u` is not a parameter of the bsdf `roughplastic`",
        ),
        (
            r#"<shape type="heightfield"/>"#,
            "shape `heightfield` is not supported; supported: sphere, rectangle, obj, ply, \
             serialized, disk, cube, cylinder, instance, shapegroup",
        ),
        (
            r#"<emitter type="sunsky"/>"#,
            "emitter `sunsky` is not supported; supported: point, constant, spot, projector, \
             directional, envmap, area",
        ),
        (r#"<emitter type="envmap"/>"#, "envmap: missing `filename`"),
        (
            r#"<emitter type="directional"><vector name="direction" value="0, 0, 1"/><transform name="to_world"><rotate x="1" angle="90"/></transform></emitter>"#,
            "`direction` or `to_world`, not both",
        ),
        (
            r#"<integrator type="prbvolpath"/>"#,
            "integrator `prbvolpath` is not supported; supported: path, volpath, volpathmis, direct, \
             ptracer",
        ),
        (
            r#"<medium type="heterogeneous"><volume type="gridvolume" name="density"/></medium>"#,
            "a <volume> named `density` is not a volume the medium `heterogeneous` reads (it reads sigma_t, albedo)",
        ),
        (
            r#"<medium type="homogeneous"><volume type="gridvolume" name="sigma_t"/></medium>"#,
            "a <volume> named `sigma_t` is not a volume the medium `homogeneous` reads (it reads albedo)",
        ),
        (
            r#"<medium type="rainbow"/>"#,
            "medium `rainbow` is not supported; supported: homogeneous, heterogeneous",
        ),
        (
            r#"<medium type="homogeneous"><phase type="sggx"/></medium>"#,
            "phase `sggx` is not supported; supported: isotropic, hg, rayleigh, tabphase, blendphase",
        ),
        (
            r#"<shape type="sphere"><medium type="homogeneous" name="inside"/></shape>"#,
            "a shape's medium is named `interior` or `exterior`",
        ),
        (
            r#"<texture type="gridtexture"/>"#,
            "texture `gridtexture` is not supported; supported: checkerboard, bitmap",
        ),
        (
            r#"<shape type="sphere"><emitter type="point"/></shape>"#,
            "carries an `area` emitter, not `point`",
        ),
        (
            r#"<shape type="sphere"><float name="weird" value="1"/></shape>"#,
            "`weird` is not a parameter of the shape `sphere`",
        ),
        (
            r#"<shape type="instance"/>"#,
            "an instance needs a <ref id=\"...\"/> to its shapegroup",
        ),
        (
            r#"<shape type="shapegroup"/>"#,
            "a shapegroup needs an `id`",
        ),
        (
            r#"<bsdf type="dielectric"><texture type="bitmap" name="int_ior"/></bsdf>"#,
            "a texture as `int_ior` of the bsdf `dielectric` is not supported",
        ),
        (r#"<shape type="obj"/>"#, "missing `filename`"),
    ] {
        let e = with_sensor(body).err("scene.xml");
        assert!(e.contains(message), "{body}: {e}");
        assert_eq!(place_of(&e).1, 4, "{body}: {e}");
    }
    let e = one("").err("scene.xml");
    assert!(e.contains("no <sensor>"), "{e}");
}

/// Mitsuba's conductors and dielectrics are Penumbra's models of the same
/// names, their parameters as they are: names of materials and indices,
/// numbers, colours, microfacet settings; the scene builds and renders.
#[test]
fn conductors_and_dielectrics_keep_their_names_and_parameters() {
    let d = with_sensor(
        r#"<bsdf type="roughconductor" id="gold">
            <string name="material" value="Au"/>
            <string name="distribution" value="ggx"/>
            <float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/>
            <boolean name="sample_visible" value="false"/>
        </bsdf>
        <bsdf type="conductor" id="mirror">
            <rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 1.6"/>
        </bsdf>
        <bsdf type="dielectric" id="water"><string name="int_ior" value="water"/><float name="ext_ior" value="1.0"/></bsdf>
        <bsdf type="roughdielectric" id="frosted"><float name="alpha" value="0.2"/><rgb name="specular_transmittance" value="0.9"/></bsdf>
        <bsdf type="thindielectric" id="sheet"/>
        <shape type="sphere"><ref id="gold"/></shape>
        <shape type="sphere"><point name="center" x="2" y="0" z="0"/><ref id="mirror"/></shape>
        <shape type="sphere"><point name="center" x="-2" y="0" z="0"/><ref id="water"/></shape>
        <shape type="sphere"><point name="center" x="0" y="2" z="0"/><ref id="frosted"/></shape>
        <shape type="sphere"><point name="center" x="0" y="-2" z="0"/><ref id="sheet"/></shape>"#,
    );
    let root = d.tree("scene.xml");
    let bsdf = |id: &str| {
        root.children_of(Kind::Bsdf)
            .find(|b| b.id.as_deref() == Some(id))
            .unwrap_or_else(|| panic!("{id}"))
    };
    let gold = bsdf("gold");
    assert_eq!(gold.plugin, "roughconductor");
    assert_eq!(prop(gold, "material"), &Value::String("Au".into()));
    assert_eq!(prop(gold, "alpha_v"), &Value::Float(0.3));
    assert_eq!(prop(gold, "sample_visible"), &Value::Bool(false));
    assert_eq!(numbers(prop(bsdf("mirror"), "k")), [3.9, 2.4, 1.6]);
    let water = bsdf("water");
    assert_eq!(prop(water, "int_ior"), &Value::String("water".into()));
    assert_eq!(prop(water, "ext_ior"), &Value::Float(1.0));
    assert_eq!(bsdf("frosted").plugin, "roughdielectric");
    assert_eq!(bsdf("sheet").plugin, "thindielectric");
    let mut src = SceneSource::open(
        d.path("scene.xml").to_str().unwrap(),
        &LoadOptions::default(),
    )
    .unwrap();
    common::set(
        &mut src,
        Overrides {
            width: Some(16),
            height: Some(12),
            spp: Some(2),
            ..Default::default()
        },
    );
    let scene = src.build().unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = scene.bsdfs.iter().map(|b| b.name()).collect();
    for m in [
        "roughconductor",
        "conductor",
        "dielectric",
        "roughdielectric",
        "thindielectric",
    ] {
        assert!(names.contains(&m), "{names:?}");
    }
    common::render_scene(&scene, 2);
}

/// Mitsuba's principled materials map through their schemas: numbers,
/// colours and textures under Mitsuba's names; `eta` beside `specular` is
/// refused at the material; the scene builds and renders.
#[test]
fn the_principled_material_keeps_its_parameters() {
    let d = with_sensor(
        r#"<bsdf type="principled" id="car">
            <rgb name="base_color" value="0.8, 0.1, 0.1"/>
            <float name="metallic" value="0.7"/><float name="specular" value="0.6"/>
            <float name="roughness" value="0.2"/><float name="spec_tint" value="0.4"/>
            <float name="anisotropic" value="0.5"/><float name="sheen" value="0.3"/>
            <float name="sheen_tint" value="0.2"/><float name="clearcoat" value="0.6"/>
            <float name="clearcoat_gloss" value="0.3"/><float name="spec_trans" value="0.4"/>
            <float name="flatness" value="0.1"/>
            <float name="main_specular_sampling_rate" value="2"/>
            <texture type="checkerboard" name="roughness_unused_name_check"/>
        </bsdf>
        <shape type="sphere"><ref id="car"/></shape>"#,
    );
    let e = SceneSource::open(
        d.path("scene.xml").to_str().unwrap(),
        &LoadOptions::default(),
    )
    .map(drop)
    .unwrap_err()
    .to_string();
    assert!(e.contains("roughness_unused_name_check"), "{e}");
    let d = with_sensor(
        r#"<bsdf type="principled" id="car">
            <rgb name="base_color" value="0.8, 0.1, 0.1"/>
            <float name="metallic" value="0.7"/><float name="specular" value="0.6"/>
            <float name="spec_tint" value="0.4"/><float name="anisotropic" value="0.5"/>
            <float name="sheen" value="0.3"/><float name="sheen_tint" value="0.2"/>
            <float name="clearcoat" value="0.6"/><float name="clearcoat_gloss" value="0.3"/>
            <float name="spec_trans" value="0.4"/><float name="flatness" value="0.1"/>
            <float name="main_specular_sampling_rate" value="2"/>
            <texture type="checkerboard" name="roughness"/>
        </bsdf>
        <bsdf type="principled" id="glass"><float name="spec_trans" value="1"/><float name="eta" value="1.33"/></bsdf>
        <bsdf type="principledthin" id="leaf">
            <rgb name="base_color" value="0.2, 0.6, 0.1"/><float name="spec_trans" value="0.4"/>
            <float name="diff_trans" value="1.5"/><texture type="checkerboard" name="eta"/>
            <float name="diffuse_transmittance_sampling_rate" value="0.5"/>
        </bsdf>
        <shape type="sphere"><ref id="car"/></shape>
        <shape type="sphere"><point name="center" x="2" y="0" z="0"/><ref id="glass"/></shape>
        <shape type="sphere"><point name="center" x="-2" y="0" z="0"/><ref id="leaf"/></shape>"#,
    );
    let root = d.tree("scene.xml");
    let bsdf = |id: &str| {
        root.children_of(Kind::Bsdf)
            .find(|b| b.id.as_deref() == Some(id))
            .unwrap_or_else(|| panic!("{id}"))
    };
    let car = bsdf("car");
    assert_eq!(car.plugin, "principled");
    assert!(close(
        &numbers(prop(car, "base_color")),
        &[0.8, 0.1, 0.1],
        1e-6
    ));
    assert_eq!(prop(car, "clearcoat_gloss"), &Value::Float(0.3));
    assert_eq!(prop(car, "main_specular_sampling_rate"), &Value::Float(2.0));
    assert!(
        matches!(prop(car, "roughness"), Value::Table(_)),
        "{:?}",
        prop(car, "roughness")
    );
    assert_eq!(prop(bsdf("glass"), "eta"), &Value::Float(1.33));
    let leaf = bsdf("leaf");
    assert_eq!(leaf.plugin, "principledthin");
    assert_eq!(prop(leaf, "diff_trans"), &Value::Float(1.5));
    assert!(matches!(prop(leaf, "eta"), Value::Table(_)));
    let mut src = SceneSource::open(
        d.path("scene.xml").to_str().unwrap(),
        &LoadOptions::default(),
    )
    .unwrap();
    common::set(
        &mut src,
        Overrides {
            width: Some(16),
            height: Some(12),
            spp: Some(2),
            ..Default::default()
        },
    );
    let scene = src.build().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene
            .bsdfs
            .iter()
            .filter(|b| b.name() == "principled")
            .count(),
        2
    );
    common::render_scene(&scene, 2);
    let d = with_sensor(
        r#"<bsdf type="principled"><float name="eta" value="1.5"/><float name="specular" value="0.5"/></bsdf>"#,
    );
    let e = SceneSource::open(
        d.path("scene.xml").to_str().unwrap(),
        &LoadOptions::default(),
    )
    .and_then(|s| s.build().map(drop))
    .map(drop)
    .unwrap_err()
    .to_string();
    assert!(e.contains("either `eta` or `specular`"), "{e}");
}

#[test]
fn plastics_and_materials_holding_materials_map_onto_their_own() {
    let d = with_sensor(
        r#"<bsdf type="roughplastic" id="paint">
            <rgb name="diffuse_reflectance" value="0.7, 0.1, 0.1"/>
            <string name="distribution" value="ggx"/><float name="alpha" value="0.3"/>
            <boolean name="nonlinear" value="true"/>
        </bsdf>
        <bsdf type="blendbsdf" id="worn">
            <float name="weight" value="0.25"/>
            <ref id="paint"/>
            <bsdf type="roughconductor"><string name="material" value="Au"/></bsdf>
        </bsdf>
        <bsdf type="mask" id="leaf"><float name="opacity" value="0.8"/><ref id="worn"/></bsdf>
        <bsdf type="twosided" id="card">
            <bsdf type="plastic"><float name="int_ior" value="1.6"/></bsdf>
            <bsdf type="conductor"/>
        </bsdf>
        <shape type="sphere"><ref id="leaf"/></shape>
        <shape type="sphere"><point name="center" x="2" y="0" z="0"/><ref id="card"/></shape>
        <shape type="sphere"><point name="center" x="-2" y="0" z="0"/>
            <bsdf type="twosided"><bsdf type="roughconductor"/></bsdf></shape>"#,
    );
    let root = d.tree("scene.xml");
    let bsdf = |id: &str| {
        root.children_of(Kind::Bsdf)
            .find(|b| b.id.as_deref() == Some(id))
            .unwrap_or_else(|| panic!("{id}"))
    };
    let paint = bsdf("paint");
    assert_eq!(paint.plugin, "roughplastic");
    assert_eq!(numbers(prop(paint, "diffuse_reflectance")), [0.7, 0.1, 0.1]);
    assert_eq!(prop(paint, "nonlinear"), &Value::Bool(true));
    let worn = bsdf("worn");
    assert_eq!(prop(worn, "weight"), &Value::Float(0.25));
    assert_eq!(prop(worn, "bsdf_0"), &Value::String("paint".into()));
    let Value::String(gold) = prop(worn, "bsdf_1") else {
        panic!()
    };
    assert_eq!(bsdf(gold).plugin, "roughconductor");
    assert_eq!(prop(bsdf("leaf"), "bsdf"), &Value::String("worn".into()));
    let card = bsdf("card");
    assert_eq!(card.plugin, "twosided");
    let Value::String(front) = prop(card, "bsdf") else {
        panic!()
    };
    let Value::String(back) = prop(card, "back") else {
        panic!()
    };
    assert_eq!(
        (bsdf(front).plugin.as_str(), bsdf(back).plugin.as_str()),
        ("plastic", "conductor")
    );
    assert_eq!(prop(bsdf(front), "int_ior"), &Value::Float(1.6));
    let s = shapes(&root);
    let Value::String(third) = prop(s[2], "material") else {
        panic!()
    };
    assert_eq!(bsdf(third).plugin, "twosided");
    let scene = build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = scene.bsdfs.iter().map(|b| b.name()).collect();
    for m in ["roughplastic", "plastic", "blendbsdf", "mask", "twosided"] {
        assert!(names.contains(&m), "{names:?}");
    }
}

#[test]
fn a_twosided_diffuse_is_a_diffuse_material_reflecting_on_both_sides() {
    let d = with_sensor(
        r#"<bsdf type="twosided" id="walls"><bsdf type="diffuse"><rgb name="reflectance" value="0.4"/></bsdf></bsdf>
        <shape type="rectangle"><ref id="walls"/></shape>
        <shape type="sphere"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>"#,
    );
    let root = d.tree("scene.xml");
    let walls = root
        .children_of(Kind::Bsdf)
        .find(|b| b.id.as_deref() == Some("walls"))
        .unwrap();
    assert_eq!(walls.plugin, "diffuse");
    assert_eq!(prop(walls, "two_sided"), &Value::Bool(true));
    assert_eq!(numbers(prop(walls, "reflectance")), [0.4; 3]);
    let s = shapes(&root);
    assert_eq!(prop(s[0], "material"), &Value::String("walls".into()));
    assert_eq!(prop(s[1], "material"), &Value::String("bsdf_1".into()));
    let inner = root
        .children_of(Kind::Bsdf)
        .find(|b| b.id.as_deref() == Some("bsdf_1"))
        .unwrap();
    assert_eq!(prop(inner, "two_sided"), &Value::Bool(true));
    // It builds: the diffuse material takes `two_sided`.
    let mut src = SceneSource::from_tree(root, d.0.path(), &LoadOptions::default());
    common::set(
        &mut src,
        Overrides {
            integrator: Some(IntegratorChoice::Whitted),
            ..Default::default()
        },
    );
    src.build().unwrap();
}

#[test]
fn integrators_are_lowered_as_themselves_and_absent_is_path() {
    let root = with_sensor("").tree("scene.xml");
    let i = root.child(Kind::Integrator).unwrap();
    assert_eq!((i.plugin.as_str(), i.props.len()), ("path", 0));
    let root = with_sensor(
        r#"<integrator type="direct"><integer name="emitter_samples" value="4"/><boolean name="hide_emitters" value="true"/></integrator>"#,
    )
    .tree("scene.xml");
    let i = root.child(Kind::Integrator).unwrap();
    assert_eq!(i.plugin, "direct");
    assert_eq!(prop(i, "emitter_samples"), &Value::Int(4));
    assert_eq!(prop(i, "hide_emitters"), &Value::Bool(true));
}

#[test]
fn old_scenes_are_upgraded_with_one_warning() {
    let d = Dir::new(&[(
        "scene.xml",
        r#"<scene version="0.6.0">
            <sensor type="perspective">
                <float name="fov" value="30"/>
                <string name="fovAxis" value="y"/>
                <sampler type="independent"><integer name="sampleCount" value="8"/></sampler>
            </sensor>
            <bsdf type="diffuse" id="m"><rgb name="diffuseReflectance" value="0.3"/></bsdf>
            <shape type="sphere"><ref id="m"/></shape>
            <shape type="obj"><string name="filename" value="x.obj"/><boolean name="faceNormals" value="true"/></shape>
        </scene>"#,
    )]);
    let loaded = d.load("scene.xml", &[]).unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(
        loaded.warnings[0].contains("0.6.0"),
        "{}",
        loaded.warnings[0]
    );
    let root = &loaded.root;
    assert_eq!(prop(sensor(root), "fov"), &Value::Float(30.0));
    let s = sensor(root).child(Kind::Sampler).unwrap();
    assert_eq!(prop(s, "spp"), &Value::Int(8));
    let m = root
        .children_of(Kind::Bsdf)
        .find(|b| b.id.as_deref() == Some("m"))
        .unwrap();
    assert_eq!(numbers(prop(m, "reflectance")), [0.3; 3]);
    assert_eq!(prop(shapes(root)[1], "smooth"), &Value::Bool(false));

    // uoffset/uscale become a to_uv transform, which no plugin here takes.
    let d = Dir::new(&[(
        "scene.xml",
        r#"<scene version="0.5.0"><shape type="sphere"><float name="uoffset" value="0.5"/></shape></scene>"#,
    )]);
    let e = d.err("scene.xml");
    assert!(e.contains("`to_uv` is not a parameter"), "{e}");
}

// ---------------------------------------------------------------------------
// Hostile files.

#[test]
fn malformed_xml_is_refused_with_its_place() {
    for (text, message, line) in [
        (
            "<scene version=\"3.0.0\">\n<shape type=\"sphere\" type=\"x\"/>\n</scene>",
            "malformed XML",
            2,
        ),
        (
            "<scene version=\"3.0.0\"/>\n<scene version=\"3.0.0\"/>\n",
            "malformed XML",
            2,
        ),
        (
            "<scene version=\"3.0.0\">\n<shape>\n</scene>",
            "malformed XML",
            3,
        ),
        ("<scene>\n</scene>", "missing attribute `version`", 1),
        ("<scene version=\"three\"/>", "is not a version", 1),
        (
            "<shape version=\"3.0.0\" type=\"sphere\"/>",
            "the root element is <shape>",
            1,
        ),
        ("", "malformed XML", 1),
    ] {
        let d = Dir::new(&[("scene.xml", text)]);
        let e = d.err("scene.xml");
        let (file, l, c) = place_of(&e);
        assert!(
            e.contains(message) && file.ends_with("scene.xml") && l == line && c > 0,
            "{text:?}: {e}"
        );
    }
    let d = Dir::new(&[]);
    d.write(
        "scene.xml",
        b"<scene version=\"3.0.0\">\n<!-- \xff\xfe -->\n</scene>",
    );
    let e = d.err("scene.xml");
    assert!(e.contains("not valid UTF-8") && place_of(&e).1 == 2, "{e}");
}

/// An element of very many attributes is refused at its place before the
/// XML parser compares them pairwise, in an included file too; one of
/// `MAX_ATTRIBUTES` is left to the usual checks.
#[test]
fn an_element_of_too_many_attributes_is_refused_at_its_place() {
    let attrs = |n: usize| (0..n).map(|i| format!(" a{i}=\"1\"")).collect::<String>();
    let crowded = format!(
        "<scene version=\"3.0.0\">\n  <integrator type=\"path\"{}/>\n</scene>",
        attrs(100_000)
    );
    let include = "<scene version=\"3.0.0\">\n<include filename=\"crowded.xml\"/>\n</scene>";
    let d = Dir::new(&[
        ("scene.xml", &crowded),
        ("outer.xml", include),
        ("crowded.xml", &crowded),
    ]);
    for (file, name) in [("scene.xml", "scene.xml"), ("outer.xml", "crowded.xml")] {
        let e = d.err(file);
        let (at, line, column) = place_of(&e);
        assert!(
            e.contains("<integrator> has more than 64 attributes")
                && at.ends_with(name)
                && (line, column) == (2, 3),
            "{e}"
        );
    }
    let many = format!(
        "<scene version=\"3.0.0\">\n  <integrator type=\"path\"{}/>\n</scene>",
        attrs(63)
    );
    let e = Dir::new(&[("scene.xml", &many)]).err("scene.xml");
    assert!(e.contains("unexpected attribute `a0`"), "{e}");
}

#[test]
fn a_billion_laughs_is_refused_at_once() {
    let mut text =
        String::from("<?xml version=\"1.0\"?>\n<!DOCTYPE scene [\n<!ENTITY lol \"lol\">\n");
    for i in 1..10 {
        let prev = if i == 1 {
            "lol".to_string()
        } else {
            format!("lol{}", i - 1)
        };
        text.push_str(&format!(
            "<!ENTITY lol{i} \"{}\">\n",
            format!("&{prev};").repeat(10)
        ));
    }
    text.push_str("]>\n<scene version=\"3.0.0\"><string name=\"x\" value=\"&lol9;\"/></scene>\n");
    let d = Dir::new(&[("scene.xml", &text)]);
    let start = std::time::Instant::now();
    let e = d.err("scene.xml");
    assert!(start.elapsed().as_secs() < 2);
    assert!(
        e.contains("malformed XML") && e.contains("DTD") && place_of(&e).1 >= 1,
        "{e}"
    );
    // An external entity is never fetched either: DTDs are refused whole.
    let ext = "<?xml version=\"1.0\"?>\n<!DOCTYPE scene [<!ENTITY x SYSTEM \"/etc/passwd\">]>\n<scene version=\"3.0.0\"/>";
    let e = Dir::new(&[("scene.xml", ext)]).err("scene.xml");
    assert!(e.contains("DTD"), "{e}");
}

#[test]
fn deep_nesting_is_refused_without_overflowing_the_stack() {
    let n = 100_000;
    let text = format!(
        "<scene version=\"3.0.0\">{}{}</scene>",
        "<shape type=\"sphere\">".repeat(n),
        "</shape>".repeat(n)
    );
    let d = Dir::new(&[("scene.xml", &text)]);
    // A thread with a small stack, as tests and Python callers have.
    let path = d.path("scene.xml");
    let e = std::thread::Builder::new()
        .stack_size(256 << 10)
        .spawn(move || {
            mitsuba::from_xml_file(&path, &[], LIMIT, registry)
                .unwrap_err()
                .to_string()
        })
        .unwrap()
        .join()
        .unwrap();
    assert!(
        e.contains("nest more than 64 deep") && place_of(&e).1 == 1,
        "{e}"
    );
}

#[test]
fn a_missing_mesh_is_named_when_the_scene_is_built() {
    let d = with_sensor(r#"<shape type="ply"><string name="filename" value="gone.ply"/></shape>"#);
    let e = build_whitted(&d).err().unwrap().to_string();
    assert!(e.contains("scene.xml:4:") && e.contains("gone.ply"), "{e}");
}

#[test]
fn defines_are_refused_for_a_toml_scene() {
    let d = Dir::new(&[("scene.toml", "")]);
    let opts = LoadOptions {
        defines: vec![("a".into(), "1".into())],
        ..Default::default()
    };
    let e = SceneSource::open(d.path("scene.toml").to_str().unwrap(), &opts)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("-D"), "{e}");
}

#[test]
fn a_path_is_a_child_of_a_scene_in_any_file() {
    let d = Dir::new(&[
        (
            "scene.xml",
            &scene(&format!(r#"{SENSOR}<include filename="sub/more.xml"/>"#)),
        ),
        (
            "sub/more.xml",
            r#"<scene version="3.0.0"><path value="meshes"/><shape type="obj"><string name="filename" value="m.obj"/></shape></scene>"#,
        ),
        ("sub/meshes/m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ]);
    let root = d.tree("scene.xml");
    assert_eq!(
        prop(shapes(&root)[0], "path"),
        &Value::String("sub/meshes/m.obj".into())
    );
    let e = with_sensor(r#"<shape type="sphere"><path value="."/></shape>"#).err("scene.xml");
    assert!(e.contains("<path> must be a child of <scene>"), "{e}");
}

/// `--lenient`: a parameter Penumbra does not read is a warning naming its
/// place and is left out of the tree; an unsupported plugin stays an error.
#[test]
fn lenient_reading_warns_of_unknown_parameters_and_refuses_unknown_plugins() {
    let d = with_sensor(
        r#"<integrator type="path"><integer name="max_depth" value="4"/><boolean name="foo" value="true"/></integrator>
        <shape type="sphere"><float name="radius" value="2"/><string name="glow" value="yes"/></shape>"#,
    );
    let path = d.path("scene.xml");
    let strict = mitsuba::from_xml_file(&path, &[], LIMIT, registry)
        .unwrap_err()
        .to_string();
    assert!(strict.contains("`foo` is not a parameter"), "{strict}");
    let loaded = mitsuba::from_xml_file_with(&path, &[], LIMIT, true, registry).unwrap();
    assert_eq!(loaded.warnings.len(), 2, "{:?}", loaded.warnings);
    assert!(loaded.warnings[1].contains("scene.xml:5:") && loaded.warnings[1].contains("`glow`"));
    assert!(loaded.warnings[1].ends_with("ignored (--lenient)"));
    // `max_depth`, and the light sampler of Mitsuba's integrators.
    let integrator = loaded.root.child(Kind::Integrator).unwrap();
    assert_eq!(integrator.props.len(), 2);
    assert_eq!(prop(shapes(&loaded.root)[0], "radius"), &Value::Float(2.0));
    assert!(shapes(&loaded.root)[0].prop("glow").is_none());
    // The lenient tree loads and builds.
    let opts = LoadOptions {
        lenient: true,
        ..Default::default()
    };
    SceneSource::open(path.to_str().unwrap(), &opts)
        .unwrap()
        .build()
        .unwrap();
    let d = with_sensor(r#"<shape type="torus"/>"#);
    let e = mitsuba::from_xml_file_with(&d.path("scene.xml"), &[], LIMIT, true, registry)
        .unwrap_err()
        .to_string();
    assert!(e.contains("shape `torus` is not supported"), "{e}");
}

/// Each `rfilter` of Mitsuba 3 lands on the film with its parameters (the
/// film's `filter_*` keys), and the built
/// scene's filter has them.
#[test]
fn rfilters_carry_their_parameters() {
    use penumbra::sampling::{Filter, FilterParams, PixelFilter};
    // The rfilter, its XML parameters, the film's keys they give, and the
    // parameters the built filter has.
    type Case<'a> = (&'a str, &'a str, &'a [(&'a str, Value)], FilterParams);
    let cases: [Case; 6] = [
        ("box", "", &[], FilterParams::default()),
        (
            "tent",
            r#"<float name="radius" value="1.5"/>"#,
            &[("filter_radius", Value::Float(1.5))],
            FilterParams {
                radius: Some(1.5),
                ..Default::default()
            },
        ),
        (
            "gaussian",
            r#"<float name="stddev" value="0.25"/>"#,
            &[("filter_stddev", Value::Float(0.25))],
            FilterParams {
                stddev: Some(0.25),
                ..Default::default()
            },
        ),
        (
            "mitchell",
            r#"<float name="B" value="0.5"/><float name="C" value="0.25"/>"#,
            &[
                ("filter_b", Value::Float(0.5)),
                ("filter_c", Value::Float(0.25)),
            ],
            FilterParams {
                b: Some(0.5),
                c: Some(0.25),
                ..Default::default()
            },
        ),
        ("catmullrom", "", &[], FilterParams::default()),
        (
            "lanczos",
            r#"<integer name="lobes" value="2"/>"#,
            &[("filter_lobes", Value::Int(2))],
            FilterParams {
                lobes: Some(2),
                ..Default::default()
            },
        ),
    ];
    for (name, params, props, expect) in cases {
        let body = format!(
            r#"<sensor type="perspective"><float name="fov" value="45"/><film type="hdrfilm"><rfilter type="{name}">{params}</rfilter></film></sensor>"#
        );
        let d = one(&body);
        let root = d.tree("scene.xml");
        let film = sensor(&root).child(Kind::Film).unwrap();
        assert_eq!(prop(film, "filter"), &Value::String(name.into()));
        for (key, v) in props {
            assert_eq!(prop(film, key), v, "{name}");
        }
        let scene = build_whitted(&d).unwrap();
        let f = Filter::from_name(name).unwrap();
        assert_eq!(
            scene.settings.filter,
            PixelFilter::new(f, &expect).unwrap(),
            "{name}"
        );
    }
}

/// Textures nested in the materials holding others: `mask`'s opacity,
/// `blendbsdf`'s weight, `normalmap`'s map (its `<texture name="normalmap">`)
/// and `bumpmap`'s heights (its one texture, whatever its name), beside
/// their `<bsdf>`s; plastics' colours as textures. The scene builds, and a
/// texture a model does not take is refused at its tag.
#[test]
fn materials_holding_others_take_nested_textures() {
    let d = with_sensor(
        r#"
        <texture type="checkerboard" id="board"/>
        <bsdf type="plastic" id="paint"><ref name="diffuse_reflectance" id="board"/></bsdf>
        <bsdf type="mask" id="leaf">
            <texture type="checkerboard" name="opacity"><float name="color0" value="0.2"/></texture>
            <ref id="paint"/>
        </bsdf>
        <bsdf type="blendbsdf" id="worn">
            <ref name="weight" id="board"/>
            <ref id="paint"/>
            <bsdf type="roughconductor"/>
        </bsdf>
        <bsdf type="normalmap" id="tiles">
            <boolean name="use_shadowing_function" value="false"/>
            <texture type="bitmap" name="normalmap">
                <string name="filename" value="n.png"/><boolean name="raw" value="true"/>
            </texture>
            <bsdf type="roughplastic"/>
        </bsdf>
        <bsdf type="bumpmap" id="bumpy">
            <bsdf type="diffuse"/>
            <texture type="bitmap" name="arbitrary">
                <string name="filename" value="n.png"/><boolean name="raw" value="true"/>
            </texture>
            <float name="scale" value="0.5"/>
        </bsdf>
        <shape type="sphere"><ref id="leaf"/></shape>
        <shape type="sphere"><point name="center" x="2" y="0" z="0"/><ref id="worn"/></shape>
        <shape type="sphere"><point name="center" x="-2" y="0" z="0"/><ref id="tiles"/></shape>
        <shape type="sphere"><point name="center" x="0" y="2" z="0"/><ref id="bumpy"/></shape>"#,
    );
    image::RgbImage::from_fn(2, 2, |x, _| image::Rgb([128 + 60 * x as u8, 128, 255]))
        .save(d.path("n.png"))
        .unwrap();
    let root = d.tree("scene.xml");
    let bsdf = |id: &str| {
        root.children_of(Kind::Bsdf)
            .find(|b| b.id.as_deref() == Some(id))
            .unwrap_or_else(|| panic!("{id}"))
    };
    assert_eq!(
        prop(bsdf("paint"), "diffuse_reflectance"),
        &Value::String("board".into())
    );
    assert!(matches!(prop(bsdf("leaf"), "opacity"), Value::Table(_)));
    assert_eq!(prop(bsdf("leaf"), "bsdf"), &Value::String("paint".into()));
    assert_eq!(prop(bsdf("worn"), "weight"), &Value::String("board".into()));
    assert_eq!(prop(bsdf("worn"), "bsdf_0"), &Value::String("paint".into()));
    assert!(matches!(prop(bsdf("tiles"), "normalmap"), Value::Table(_)));
    assert_eq!(
        prop(bsdf("tiles"), "use_shadowing_function"),
        &Value::Bool(false)
    );
    let bumpy = bsdf("bumpy");
    assert!(matches!(prop(bumpy, "texture"), Value::Table(_)));
    assert_eq!(prop(bumpy, "scale"), &Value::Float(0.5));
    let Value::String(inner) = prop(bumpy, "bsdf") else {
        panic!()
    };
    assert_eq!(bsdf(inner).plugin, "diffuse");
    let scene = build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = scene.bsdfs.iter().map(|b| b.name()).collect();
    for m in ["plastic", "mask", "blendbsdf", "normalmap", "bumpmap"] {
        assert!(names.contains(&m), "{names:?}");
    }
    common::render_scene(&scene, 2);

    for (body, want) in [
        (
            r#"<bsdf type="mask" id="m"><texture type="checkerboard" name="alpha"/><bsdf type="diffuse"/></bsdf>"#,
            "a texture as `alpha` of the bsdf `mask` is not supported (textures go to: opacity)",
        ),
        (
            r#"<bsdf type="bumpmap" id="m"><texture type="checkerboard" name="a"/><texture type="checkerboard" name="b"/><bsdf type="diffuse"/></bsdf>"#,
            "`texture` is given twice",
        ),
        (
            r#"<bsdf type="normalmap" id="m"><texture type="checkerboard" name="normalmap"/></bsdf>"#,
            "holds 1 <bsdf>s, not 0",
        ),
    ] {
        let e = with_sensor(body).err("scene.xml");
        assert!(e.contains(want), "{e}\n{want}");
        assert!(e.contains("scene.xml:"), "{e}");
    }
}

/// Textures nested in a bsdf become the parameter's table, references to a
/// texture of the scene its name; `to_uv` is Mitsuba's 3×3 of the
/// transform; a bitmap's file is relative to the XML file. The scene builds
/// and its textures vary where they should.
#[test]
fn textures_nest_in_bsdfs_or_are_referenced_by_id() {
    let d = with_sensor(
        r#"
        <texture type="checkerboard" id="board">
            <rgb name="color0" value="0.9, 0.9, 0.9"/>
            <float name="color1" value="0.1"/>
            <transform name="to_uv"><scale x="2" y="4"/><translate x="0.5" y="0"/></transform>
        </texture>
        <bsdf type="diffuse" id="floor"><ref name="reflectance" id="board"/></bsdf>
        <bsdf type="roughconductor" id="metal">
            <texture type="bitmap" name="alpha">
                <string name="filename" value="maps/rough.png"/>
                <boolean name="raw" value="true"/>
                <string name="filter_type" value="nearest"/>
                <string name="wrap_mode" value="clamp"/>
            </texture>
        </bsdf>
        <shape type="sphere"><ref id="floor"/></shape>
        <shape type="sphere"><ref id="metal"/></shape>"#,
    );
    std::fs::create_dir_all(d.path("maps")).unwrap();
    image::GrayImage::from_fn(2, 2, |x, _| image::Luma([if x == 0 { 51 } else { 204 }]))
        .save(d.path("maps/rough.png"))
        .unwrap();
    let root = d.tree("scene.xml");
    let board = root.child(Kind::Texture).unwrap();
    assert_eq!(
        (board.plugin.as_str(), board.id.as_deref()),
        ("checkerboard", Some("board"))
    );
    assert_eq!(numbers(prop(board, "color1")), [0.1; 3]);
    let Value::Table(to_uv) = prop(board, "to_uv") else {
        panic!()
    };
    assert!(close(
        &numbers(&to_uv[0].value.value),
        &[2.0, 0.0, 0.5, 0.0, 4.0, 0.0, 0.0, 0.0, 1.0],
        1e-12
    ));
    let bsdfs: Vec<&Node> = root.children_of(Kind::Bsdf).collect();
    assert_eq!(
        prop(bsdfs[0], "reflectance"),
        &Value::String("board".into())
    );
    let Value::Table(alpha) = prop(bsdfs[1], "alpha") else {
        panic!()
    };
    // Relative to the scene's folder, as the scene's meshes are named.
    let file = alpha.iter().find(|p| p.name == "filename").unwrap();
    assert_eq!(file.value.value, Value::String("maps/rough.png".into()));
    assert_eq!(
        file.value.origin.path.to_string(),
        "materials.metal.alpha.filename"
    );
    build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));

    for (body, want) in [
        (
            r#"<bsdf type="diffuse" id="m"><texture type="wood" name="reflectance"/></bsdf>"#,
            "texture `wood` is not supported; supported: checkerboard, bitmap",
        ),
        (
            r#"<bsdf type="dielectric" id="m"><texture type="checkerboard" name="int_ior"/></bsdf>"#,
            "a texture as `int_ior` of the bsdf `dielectric` is not supported (textures go to: specular_reflectance, specular_transmittance)",
        ),
        (
            r#"<bsdf type="diffuse" id="m"><rgb name="reflectance" value="0.5"/><texture type="checkerboard" name="reflectance"/></bsdf>"#,
            "`reflectance` is given twice",
        ),
        (
            r#"<bsdf type="diffuse" id="m"><texture type="checkerboard" name="reflectance"><bsdf type="diffuse"/></texture></bsdf>"#,
            "a <bsdf> inside the texture `checkerboard` is not supported",
        ),
        (
            r#"<bsdf type="diffuse" id="m"><texture type="rawconstant" name="reflectance"><rgb name="value" value="0.5"/></texture></bsdf>"#,
            "`value` must be a float or a 3D vector, got an rgb colour",
        ),
    ] {
        let e = with_sensor(body).err("scene.xml");
        assert!(e.contains(want), "{e}\n{want}");
        assert!(e.contains("scene.xml:"), "{e}");
    }
    // A bitmap whose file is missing is refused when the scene is built,
    // at the filename's tag.
    let d = with_sensor(
        r#"<bsdf type="diffuse" id="m"><texture type="bitmap" name="reflectance">
           <string name="filename" value="nowhere.png"/></texture></bsdf>
           <shape type="sphere"><ref id="m"/></shape>"#,
    );
    let e = build_whitted(&d).err().unwrap().to_string();
    assert!(
        e.contains("scene.xml:5:12: materials.m.reflectance.filename:"),
        "{e}"
    );
    assert!(e.contains("nowhere.png"), "{e}");
}

/// `spot`, `directional` and `envmap` become `[[lights]]` of the same
/// names: `to_world` as the spot's position and the point one unit along
/// its +z, as the directional light's direction, as the map's matrix; the
/// map's file relative to the scene, its `mis_compensation`; and the scene
/// builds and renders.
#[test]
fn spot_directional_and_envmap_emitters_are_lights() {
    let d = with_sensor(
        r#"<emitter type="spot">
            <rgb name="intensity" value="2, 3, 4"/>
            <float name="cutoff_angle" value="40"/>
            <float name="beam_width" value="10"/>
            <transform name="to_world"><lookat origin="1, 2, 3" target="1, 0, 3" up="0, 0, 1"/></transform>
        </emitter>
        <emitter type="directional">
            <transform name="to_world"><rotate x="1" angle="90"/></transform>
            <rgb name="irradiance" value="5"/>
        </emitter>
        <emitter type="envmap">
            <string name="filename" value="sky.hdr"/>
            <float name="scale" value="0.5"/>
            <transform name="to_world"><rotate y="1" angle="90"/></transform>
            <boolean name="mis_compensation" value="true"/>
        </emitter>
        <shape type="sphere"><bsdf type="diffuse"/></shape>"#,
    );
    let sky = image::Rgb32FImage::from_pixel(8, 4, image::Rgb([2.0, 2.0, 2.0]));
    image::DynamicImage::ImageRgb32F(sky)
        .save_with_format(d.path("sky.hdr"), image::ImageFormat::Hdr)
        .unwrap();
    let root = d.tree("scene.xml");
    let lights: Vec<&Node> = root.children_of(Kind::Emitter).collect();
    let find = |name: &str| *lights.iter().find(|e| e.plugin == name).unwrap();
    let spot = find("spot");
    assert_eq!(numbers(prop(spot, "intensity")), [2.0, 3.0, 4.0]);
    assert_eq!(numbers(prop(spot, "cutoff_angle")), [40.0]);
    assert_eq!(numbers(prop(spot, "beam_width")), [10.0]);
    assert!(close(
        &numbers(prop(spot, "position")),
        &[1.0, 2.0, 3.0],
        1e-9
    ));
    assert!(close(
        &numbers(prop(spot, "look_at")),
        &[1.0, 1.0, 3.0],
        1e-9
    ));
    let sun = find("directional");
    // +z turned 90° about x is −y.
    assert!(close(
        &numbers(prop(sun, "direction")),
        &[0.0, -1.0, 0.0],
        1e-9
    ));
    assert_eq!(numbers(prop(sun, "irradiance")), [5.0; 3]);
    let map = find("envmap");
    assert_eq!(prop(map, "filename"), &Value::String("sky.hdr".into()));
    assert_eq!(numbers(prop(map, "scale")), [0.5]);
    assert_eq!(prop(map, "mis_compensation"), &Value::Bool(true));
    assert!(close(
        &numbers(prop(map, "to_world")),
        &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        1e-9
    ));
    let scene = build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.emitters.len(), 3);
    let env = scene.emitters.iter().find(|e| e.is_infinite()).unwrap();
    assert_eq!(
        env.eval_miss(penumbra::math::Vec3::Y).r,
        1.0,
        "scale 0.5 on 2"
    );
}

/// Mitsuba's `projector`: its `to_world` as the light's position, axis and
/// up, its nested texture as `irradiance`; a `to_world` that scales is
/// refused at the transform.
#[test]
fn a_projector_is_placed_by_its_lookat_and_takes_a_nested_texture() {
    let d = with_sensor(
        r#"<emitter type="projector">
            <float name="fov" value="60"/>
            <transform name="to_world"><lookat origin="0, 0, 1" target="0, 0, 0" up="0, 1, 0"/></transform>
            <texture type="checkerboard" name="irradiance"/>
        </emitter>"#,
    );
    let root = d.tree("scene.xml");
    let light = root.child(Kind::Emitter).expect("the projector");
    assert_eq!(light.plugin, "projector");
    let close = |v: &Value, want: [f64; 3]| {
        numbers(v)
            .iter()
            .zip(want)
            .all(|(a, b)| (a - b).abs() < 1e-6)
    };
    assert!(close(prop(light, "position"), [0.0, 0.0, 1.0]));
    assert!(close(prop(light, "look_at"), [0.0, 0.0, 0.0]));
    assert!(close(prop(light, "up"), [0.0, 1.0, 0.0]));
    assert!(light.prop("irradiance").is_some());
    let d = with_sensor(
        r#"<emitter type="projector">
            <transform name="to_world"><scale value="2"/></transform>
        </emitter>"#,
    );
    let e = d.err("scene.xml");
    assert!(e.contains("must be a rotation and a translation"), "{e}");
}

/// A perspective sensor framing a unit emitting sphere on a `width` ×
/// `height` film (Mitsuba's default Gaussian filter, splatting) with
/// `film` inside the film's element.
fn lit_sphere(width: u32, height: u32, film: &str) -> String {
    format!(
        r#"<integrator type="path"/>
        <sensor type="perspective"><float name="fov" value="40"/>
          <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
          <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
          <film type="hdrfilm"><integer name="width" value="{width}"/><integer name="height" value="{height}"/>{film}</film>
        </sensor>
        <shape type="sphere"><emitter type="area"><rgb name="radiance" value="1, 0.5, 0.25"/></emitter></shape>"#
    )
}

fn render_xml(body: &str) -> penumbra::render::Image {
    let d = one(body);
    let scene = build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    let opts = penumbra::render::RenderOptions {
        threads: Some(2),
        region: None,
    };
    penumbra::render::render(&scene, &opts, &|_, _| {}, None)
        .unwrap()
        .0
}

const CROP: &str = r#"<integer name="crop_offset_x" value="7"/><integer name="crop_offset_y" value="11"/>
    <integer name="crop_width" value="20"/><integer name="crop_height" value="9"/>"#;

/// Mitsuba's crop window: the image written is the crop of the film; its
/// samples are its own pixels' (Mitsuba's image block is the crop), so the
/// pixels farther than the filter's reach (2 for the Gaussian) from its
/// edges are the whole film's, and those along its edges miss the samples
/// from beyond it. One that leaves the film is refused at its key.
#[test]
fn a_films_crop_window_is_the_image_written() {
    let full = render_xml(&lit_sphere(40, 30, ""));
    let part = render_xml(&lit_sphere(40, 30, CROP));
    assert_eq!((part.width, part.height), (20, 9));
    let mut edges_differ = 0;
    for y in 0..9 {
        for x in 0..20 {
            let (a, b) = (part.get(x, y), full.get(x + 7, y + 11));
            if (2..18).contains(&x) && (2..7).contains(&y) {
                assert_eq!(a, b, "({x}, {y})");
            } else if a != b {
                edges_differ += 1;
            }
        }
    }
    assert!(edges_differ > 20, "{edges_differ}");
    assert!(part.mean().r > 0.0);
    let d = one(&lit_sphere(
        40,
        30,
        r#"<integer name="crop_offset_y" value="25"/><integer name="crop_height" value="6"/>"#,
    ));
    let e = build_whitted(&d).err().unwrap().to_string();
    assert!(
        e.contains("scene.xml:") && e.contains("leaves the image"),
        "{e}"
    );
}

/// `sample_border`: the pixels within the filter's reach beyond the film
/// or its crop are sampled too, so a crop's pixels are all the whole film's
/// (both with a border), and the image does not move: the sphere's centre
/// stays where it is without a border.
#[test]
fn a_sample_border_samples_beyond_the_film_and_its_crop() {
    let border = r#"<boolean name="sample_border" value="true"/>"#;
    let full = render_xml(&lit_sphere(40, 30, border));
    let part = render_xml(&lit_sphere(40, 30, &format!("{border}{CROP}")));
    assert_eq!((full.width, full.height), (40, 30));
    assert_eq!((part.width, part.height), (20, 9));
    for y in 0..9 {
        for x in 0..20 {
            assert_eq!(part.get(x, y), full.get(x + 7, y + 11), "({x}, {y})");
        }
    }
    // The centroid of the sphere's image, with and without a border, on a
    // film whose centre is at (20.5, 15).
    let centroid = |film: &str| {
        let image = render_xml(&lit_sphere(41, 30, film));
        let (mut m, mut mx, mut my) = (0.0, 0.0, 0.0);
        for y in 0..image.height {
            for x in 0..image.width {
                let v = f64::from(image.get(x, y).r);
                m += v;
                mx += v * (f64::from(x) + 0.5);
                my += v * (f64::from(y) + 0.5);
            }
        }
        (mx / m, my / m)
    };
    let with = centroid(border);
    let without = centroid("");
    for (a, b) in [(with.0, without.0), (with.1, without.1)] {
        assert!((a - b).abs() < 0.05, "{with:?} {without:?}");
    }
    assert!(
        (with.0 - 20.5).abs() < 0.05 && (with.1 - 15.0).abs() < 0.05,
        "{with:?}"
    );
}

/// An orthographic sensor whose `to_world` scales its unit view by 2 sees a
/// sphere of radius 1 at its true size: π of the 4 × 4 square.
#[test]
fn an_orthographic_sensor_sees_its_scaled_unit_view() {
    let d = one(r#"<integrator type="path"/>
        <sensor type="orthographic">
          <transform name="to_world"><scale value="2"/><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
          <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
          <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/>
            <rfilter type="box"/></film>
        </sensor>
        <shape type="sphere"><emitter type="area"><rgb name="radiance" value="1, 1, 1"/></emitter></shape>"#);
    let scene = build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    let opts = penumbra::render::RenderOptions {
        threads: Some(2),
        region: None,
    };
    let image = penumbra::render::render(&scene, &opts, &|_, _| {}, None)
        .unwrap()
        .0;
    let covered = f64::from(image.mean().r) * 16.0;
    let want = std::f64::consts::PI;
    assert!((covered - want).abs() < 0.01 * want, "{covered} {want}");
}

/// A checkerboard's colours may be textures (nested or referenced by id);
/// `rawconstant` takes a float or a vector as it is; a spot projects a
/// texture, its `to_world` giving `up`; `format` is read. The scene builds.
#[test]
fn textures_inside_textures_and_spots() {
    let d = with_sensor(
        r#"
        <texture type="rawconstant" id="raw"><vector name="value" value="0.25, 0.5, 0.75"/></texture>
        <bsdf type="diffuse" id="floor">
            <texture type="checkerboard" name="reflectance">
                <ref name="color0" id="raw"/>
                <texture type="rawconstant" name="color1"><float name="value" value="0.5"/></texture>
            </texture>
        </bsdf>
        <emitter type="spot">
            <transform name="to_world"><lookat origin="0, 2, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
            <texture type="bitmap" name="texture">
                <string name="filename" value="slide.png"/>
                <string name="format" value="uint8"/>
            </texture>
        </emitter>
        <shape type="sphere"><ref id="floor"/></shape>"#,
    );
    image::RgbImage::from_fn(2, 1, |x, _| image::Rgb([200 * x as u8, 40, 90]))
        .save(d.path("slide.png"))
        .unwrap();
    let root = d.tree("scene.xml");
    let raw = root.child(Kind::Texture).unwrap();
    assert_eq!(raw.plugin, "rawconstant");
    assert_eq!(numbers(prop(raw, "value")), [0.25, 0.5, 0.75]);
    let floor = root.child(Kind::Bsdf).unwrap();
    let Value::Table(board) = prop(floor, "reflectance") else {
        panic!()
    };
    let get = |name: &str| &board.iter().find(|p| p.name == name).unwrap().value.value;
    assert_eq!(get("color0"), &Value::String("raw".into()));
    let Value::Table(inner) = get("color1") else {
        panic!()
    };
    assert_eq!(numbers(&inner[1].value.value), [0.5]);
    let spot = root.child(Kind::Emitter).unwrap();
    assert!(close(
        &numbers(prop(spot, "position")),
        &[0.0, 2.0, 0.0],
        1e-12
    ));
    assert!(close(
        &numbers(prop(spot, "look_at")),
        &[0.0, 1.0, 0.0],
        1e-12
    ));
    // Mitsuba's look-at: local +y is `up` made orthogonal to the axis.
    assert!(close(&numbers(prop(spot, "up")), &[0.0, 0.0, 1.0], 1e-12));
    let Value::Table(slide) = prop(spot, "texture") else {
        panic!()
    };
    assert!(slide.iter().any(|p| p.name == "format"));
    build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
}

/// `mesh_attribute` reads a PLY file's vertex colours (`vertex_color` of
/// its `red, green, blue`); an attribute the file does not have is refused
/// naming the file.
#[test]
fn mesh_attributes_are_read_from_ply_files() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\n\
        property float x\nproperty float y\nproperty float z\n\
        property uchar red\nproperty uchar green\nproperty uchar blue\n\
        element face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n";
    let shape = |attribute: &str| {
        format!(
            r#"<shape type="ply"><string name="filename" value="t.ply"/>
                <bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
                    <string name="name" value="{attribute}"/><float name="scale" value="0.5"/>
                </texture></bsdf></shape>"#
        )
    };
    let d = with_sensor(&shape("vertex_color"));
    std::fs::write(d.path("t.ply"), ply).unwrap();
    let root = d.tree("scene.xml");
    let bsdf = root.child(Kind::Bsdf).unwrap();
    let Value::Table(t) = prop(bsdf, "reflectance") else {
        panic!()
    };
    let get = |name: &str| &t.iter().find(|p| p.name == name).unwrap().value.value;
    assert_eq!(get("type"), &Value::String("mesh_attribute".into()));
    assert_eq!(get("name"), &Value::String("vertex_color".into()));
    assert_eq!(numbers(get("scale")), [0.5]);
    build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));
    let d = with_sensor(&shape("vertex_nothing"));
    std::fs::write(d.path("t.ply"), ply).unwrap();
    let e = build_whitted(&d).err().unwrap().to_string();
    assert!(
        e.contains("t.ply has no attribute `vertex_nothing` (it has: vertex_color)"),
        "{e}"
    );
}

/// Media as Mitsuba holds them: declared in the scene with an id and
/// referred to as a shape's `interior`, nested in a shape as its
/// `exterior` (named `medium_1`), referred to by the sensor; a phase
/// function nested in a medium; coefficients as a float or an RGB. The
/// scene converts to TOML and reads back to the same tree, builds with
/// each object's media and the camera's, and renders the same pixels
/// under `volpath` from both files.
#[test]
fn media_map_onto_the_scene_s_media_and_the_shapes_sides() {
    let body = r#"<integrator type="volpath"><integer name="max_depth" value="6"/></integrator>
        <medium type="homogeneous" id="fog">
            <rgb name="sigma_t" value="1, 2, 3"/><float name="albedo" value="0.5"/>
            <boolean name="sample_emitters" value="false"/>
            <phase type="hg"><float name="g" value="0.3"/></phase>
        </medium>
        <sensor type="perspective"><float name="fov" value="45"/><ref id="fog"/>
            <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        </sensor>
        <emitter type="constant"/>
        <shape type="sphere"><bsdf type="null"/><ref name="interior" id="fog"/>
            <medium type="homogeneous" name="exterior"><float name="sigma_t" value="0.1"/></medium>
        </shape>
        <shape type="cube"><ref name="interior" id="fog"/><transform name="to_world"><translate x="3"/></transform></shape>"#;
    let d = one(body);
    let root = d.tree("scene.xml");
    let media: Vec<&Node> = root.children_of(Kind::Medium).collect();
    let ids: Vec<_> = media.iter().map(|m| m.id.as_deref().unwrap()).collect();
    assert_eq!(ids, ["fog", "medium_1"]);
    assert_eq!(numbers(prop(media[0], "sigma_t")), [1.0, 2.0, 3.0]);
    assert_eq!(prop(media[0], "sample_emitters"), &Value::Bool(false));
    let phase = media[0].child(Kind::Phase).unwrap();
    assert_eq!(
        (phase.plugin.as_str(), numbers(prop(phase, "g"))),
        ("hg", vec![0.3])
    );
    assert!(media[1].child(Kind::Phase).is_none());
    let s = shapes(&root);
    assert_eq!(prop(s[0], "interior"), &Value::String("fog".into()));
    assert_eq!(prop(s[0], "exterior"), &Value::String("medium_1".into()));
    assert_eq!(prop(s[1], "interior"), &Value::String("fog".into()));
    assert_eq!(prop(sensor(&root), "medium"), &Value::String("fog".into()));

    let opts = LoadOptions::default();
    let xml = SceneSource::open(d.path("scene.xml").to_str().unwrap(), &opts).unwrap();
    let text = convert::to_toml(&xml, d.0.path()).unwrap_or_else(|e| panic!("{e}"));
    assert!(text.contains("[media.fog]"), "{text}");
    d.write("scene.toml", text.as_bytes());
    let toml = SceneSource::open(d.path("scene.toml").to_str().unwrap(), &opts).unwrap();
    assert!(xml.root.same_as(&toml.root), "{text}");
    let built = xml.build().unwrap();
    assert_eq!(built.media.len(), 2);
    assert_eq!(built.camera_medium, Some(0));
    assert_eq!(
        built.object_media,
        [[0, 1], [0, penumbra::scene::NO_MEDIUM]]
    );
    let (a, rays) = common::render_scene(&built, 2);
    let (b, _) = common::render_scene(&toml.build().unwrap(), 2);
    assert!(a.pixels == b.pixels);
    assert!(rays.media.scatterings > 0);
}

/// Phase functions holding phase functions: a `blendphase`'s nested
/// `<phase>`s are its `phase_0` and `phase_1` in the order written, each a
/// table (a blend nested in a blend too), its `<volume name="weight">` its
/// weight; `tabphase` keeps its `values` string. The scene converts to
/// TOML and reads back to the same tree, and renders the same pixels from
/// both files. A blend of one `<phase>`, a `<phase>` inside an `hg` and a
/// table of one value are refused.
#[test]
fn nested_phase_functions_map_onto_tables() {
    let medium = |phase: &str| {
        format!(
            r#"<integrator type="volpath"/>
        <sensor type="perspective"><float name="fov" value="45"/>
            <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        </sensor>
        <emitter type="constant"/>
        <shape type="sphere"><bsdf type="null"/>
            <medium type="homogeneous" name="interior"><float name="sigma_t" value="2"/>{phase}</medium>
        </shape>"#
        )
    };
    let d = one(&medium(
        r#"<phase type="blendphase">
            <volume name="weight" type="constvolume"><float name="value" value="0.25"/></volume>
            <phase name="b" type="rayleigh"/>
            <phase name="a" type="blendphase">
                <float name="weight" value="0.5"/>
                <phase type="tabphase"><string name="values" value="1, 2, 3"/></phase>
                <phase type="hg"><float name="g" value="0.4"/></phase>
            </phase>
        </phase>"#,
    ));
    let root = d.tree("scene.xml");
    let fog = root.children_of(Kind::Medium).next().unwrap();
    let phase = fog.child(Kind::Phase).unwrap();
    assert_eq!(phase.plugin, "blendphase");
    assert!(
        matches!(prop(phase, "weight"), Value::Table(_)),
        "{phase:?}"
    );
    let table = |v: &Value| match v {
        Value::Table(props) => props.clone(),
        other => panic!("not a table: {other:?}"),
    };
    let field = |props: &[penumbra::description::Prop], name: &str| {
        props
            .iter()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("no `{name}` in {props:?}"))
            .value
            .value
            .clone()
    };
    let first = table(prop(phase, "phase_0"));
    assert_eq!(field(&first, "type"), Value::String("rayleigh".into()));
    let second = table(prop(phase, "phase_1"));
    assert_eq!(field(&second, "type"), Value::String("blendphase".into()));
    let inner = table(&field(&second, "phase_0"));
    assert_eq!(field(&inner, "type"), Value::String("tabphase".into()));
    assert_eq!(field(&inner, "values"), Value::String("1, 2, 3".into()));
    let inner = table(&field(&second, "phase_1"));
    assert_eq!(numbers(&field(&inner, "g")), [0.4]);

    let opts = LoadOptions::default();
    let xml = SceneSource::open(d.path("scene.xml").to_str().unwrap(), &opts).unwrap();
    let text = convert::to_toml(&xml, d.0.path()).unwrap_or_else(|e| panic!("{e}"));
    assert!(text.contains("phase_0"), "{text}");
    d.write("scene.toml", text.as_bytes());
    let toml = SceneSource::open(d.path("scene.toml").to_str().unwrap(), &opts).unwrap();
    assert!(xml.root.same_as(&toml.root), "{text}");
    let built = xml.build().unwrap();
    assert_eq!(built.media[0].phase.name(), "blendphase");
    let (a, rays) = common::render_scene(&built, 2);
    let (b, _) = common::render_scene(&toml.build().unwrap(), 2);
    assert!(a.pixels == b.pixels);
    assert!(rays.media.scatterings > 0);

    let refused = |phase: &str| {
        let d = one(&medium(phase));
        let path = d.path("scene.xml");
        match SceneSource::open(path.to_str().unwrap(), &opts).and_then(|s| s.build()) {
            Ok(_) => panic!("{phase} accepted"),
            Err(e) => e.to_string(),
        }
    };
    let e = refused(r#"<phase type="blendphase"><phase type="hg"/></phase>"#);
    assert!(e.contains("a `blendphase` holds 2 <phase>s, not 1"), "{e}");
    let e = refused(r#"<phase type="hg"><phase type="isotropic"/></phase>"#);
    assert!(
        e.contains("a <phase> inside the phase `hg` is not supported"),
        "{e}"
    );
    let e = refused(r#"<phase type="tabphase"><string name="values" value="2"/></phase>"#);
    assert!(e.contains("values") && e.contains("at least 2"), "{e}");
}

/// An `area` emitter's `radiance` takes a texture, nested or by `<ref>` to
/// one declared in the scene (as Mitsuba's), and not twice.
#[test]
fn an_area_emitter_takes_a_textured_radiance() {
    let checker = r#"<texture type="checkerboard" name="radiance"><rgb name="color0" value="0.2"/><rgb name="color1" value="3"/></texture>"#;
    let d = with_sensor(&format!(
        r#"<shape type="rectangle"><emitter type="area">{checker}</emitter></shape>"#
    ));
    let root = d.tree("scene.xml");
    let shape = shapes(&root)[0];
    let emitter = shape.child(Kind::Emitter).unwrap();
    assert!(
        matches!(prop(emitter, "radiance"), Value::Table(_)),
        "{emitter:?}"
    );
    build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));

    let d = with_sensor(&format!(
        r#"{}
        <shape type="sphere"><emitter type="area"><ref name="radiance" id="board"/></emitter></shape>"#,
        checker.replace(r#"name="radiance""#, r#"id="board""#)
    ));
    let root = d.tree("scene.xml");
    let emitter = shapes(&root)[0].child(Kind::Emitter).unwrap();
    assert!(
        matches!(prop(emitter, "radiance"), Value::String(s) if s == "board"),
        "{emitter:?}"
    );
    build_whitted(&d).unwrap_or_else(|e| panic!("{e}"));

    let d = with_sensor(&format!(
        r#"<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/>{checker}</emitter></shape>"#
    ));
    let e = build_whitted(&d).err().expect("refused");
    assert!(e.to_string().contains("`radiance` is given twice"), "{e}");
}
