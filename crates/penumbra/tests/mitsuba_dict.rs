//! Mitsuba 3's dict form: a dict saying what an XML file says lowers to
//! the same tree and renders the same pixels; what is wrong in it is named
//! by its key path, also when the plugins' mapping finds it.

mod common;

use std::path::Path;

use penumbra::description::mitsuba::dict::DictValue;
use penumbra::scene::{LoadOptions, SceneSource};

const XML_SCENE: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world">
            <lookat origin="0, 1, 5" target="0, 1, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="40"/>
            <integer name="height" value="30"/>
            <rfilter type="box"/>
        </film>
        <sampler type="independent">
            <integer name="sample_count" value="4"/>
            <integer name="seed" value="7"/>
        </sampler>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
    <bsdf type="diffuse" id="red">
        <rgb name="reflectance" value="0.7, 0.2, 0.2"/>
    </bsdf>
    <shape type="sphere">
        <point name="center" value="0, 1, 0"/>
        <float name="radius" value="0.8"/>
        <ref id="red"/>
    </shape>
    <shape type="obj">
        <string name="filename" value="meshes/tri.obj"/>
        <transform name="to_world">
            <matrix value="5 0 0 0  0 0 5 0  0 -5 0 0  0 0 0 1"/>
        </transform>
        <bsdf type="roughconductor">
            <string name="material" value="Au"/>
            <float name="alpha" value="0.2"/>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <matrix value="0.5 0 0 0  0 0 -0.5 3  0 0.5 0 0  0 0 0 1"/>
        </transform>
        <emitter type="area"><rgb name="radiance" value="10, 10, 10"/></emitter>
    </shape>
    <emitter type="point">
        <point name="position" value="2, 4, 2"/>
        <spectrum name="intensity" value="20"/>
    </emitter>
</scene>
"#;

/// The XML scene in Mitsuba's dict form.
const DICT_SCENE: &str = r#"{
    "type": "scene",
    "integrator": {"type": "path", "max_depth": 3},
    "sensor": {
        "type": "perspective", "fov": 40, "fov_axis": "y",
        "to_world": [[-1, 0, 0, 0], [0, 1, 0, 1], [0, 0, -1, 5], [0, 0, 0, 1]],
        "film": {"type": "hdrfilm", "width": 40, "height": 30, "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": 4, "seed": 7}
    },
    "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 0.1}},
    "red": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.7, 0.2, 0.2]}},
    "ball": {"type": "sphere", "center": [0, 1, 0], "radius": 0.8,
             "bsdf": {"type": "ref", "id": "red"}},
    "floor": {"type": "obj", "filename": "meshes/tri.obj",
              "to_world": [[5, 0, 0, 0], [0, 0, 5, 0], [0, -5, 0, 0], [0, 0, 0, 1]],
              "bsdf": {"type": "roughconductor", "material": "Au", "alpha": 0.2}},
    "lamp": {"type": "rectangle",
             "to_world": [[0.5, 0, 0, 0], [0, 0, -0.5, 3], [0, 0.5, 0, 0], [0, 0, 0, 1]],
             "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [10, 10, 10]}}},
    "light": {"type": "point", "position": [2, 4, 2],
              "intensity": {"type": "spectrum", "value": 20}}
}"#;

const TRIANGLES: &[u8] = b"v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";

fn folder() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("scene.xml"), XML_SCENE).unwrap();
    std::fs::create_dir(d.path().join("meshes")).unwrap();
    std::fs::write(d.path().join("meshes/tri.obj"), TRIANGLES).unwrap();
    d
}

fn dict_source(json: &str, base: &Path) -> Result<SceneSource, String> {
    let d = DictValue::from_json(json).expect("valid JSON");
    SceneSource::from_mitsuba_dict(&d, base, &LoadOptions::default()).map_err(|e| e.to_string())
}

#[test]
fn a_dict_and_the_xml_saying_the_same_make_one_tree_and_the_same_pixels() {
    let d = folder();
    let opts = LoadOptions::default();
    let xml = SceneSource::open(d.path().join("scene.xml").to_str().unwrap(), &opts).unwrap();
    let dict = dict_source(DICT_SCENE, d.path()).unwrap();
    assert!(
        xml.root.same_as(&dict.root),
        "XML:\n{}\ndict:\n{}",
        xml.root.fingerprint(),
        dict.root.fingerprint()
    );
    let (a, _) = common::render_scene(&xml.build().unwrap(), 2);
    let (b, _) = common::render_scene(&dict.build().unwrap(), 2);
    assert_eq!((a.width, a.height), (40, 30));
    assert!(a.pixels == b.pixels, "the dict renders other pixels");
    assert!(a.pixels.iter().any(|p| p.g > 0.0), "a black image");
}

#[test]
fn what_the_mapping_refuses_is_named_by_its_key_path() {
    let d = folder();
    let cases = [
        (
            DICT_SCENE.replace(r#""radius": 0.8"#, r#""radius": "big""#),
            "ball.radius: `radius` must be a float, got a string",
        ),
        (
            DICT_SCENE.replace(r#""id": "red""#, r#""id": "blue""#),
            "ball.bsdf: <ref>: no object has the id `blue`",
        ),
        (
            DICT_SCENE.replace(r#""type": "roughconductor""#, r#""type": "hair""#),
            "floor.bsdf.type: `hair` is not a plugin Penumbra reads",
        ),
        (
            DICT_SCENE.replace(r#""fov_axis": "y""#, r#""fov_axis": "y", "shutter": 1"#),
            "sensor.shutter: `shutter` is not a parameter of the sensor `perspective`",
        ),
        (
            DICT_SCENE.replace(r#""material": "Au""#, r#""material": "Au", "id": "ball""#),
            "floor.bsdf.id: the id `ball` is given twice",
        ),
    ];
    for (json, expected) in cases {
        let e = match dict_source(&json, d.path()) {
            Ok(_) => panic!("should be refused: {expected}"),
            Err(e) => e,
        };
        assert!(e.starts_with(expected), "{e}\n  is not {expected}");
    }
}

/// A scene of participating media in XML: a homogeneous medium with a
/// Henyey–Greenstein phase function inside a sphere (declared at the
/// scene's level and referred to by id), a heterogeneous one of a grid
/// file inside a cube, and the camera in a medium of its own.
const XML_MEDIA: &str = r#"<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="6"/></integrator>
    <medium type="homogeneous" id="fog">
        <rgb name="sigma_t" value="0.5, 1, 1.5"/>
        <float name="albedo" value="0.8"/>
        <phase type="hg"><float name="g" value="0.5"/></phase>
    </medium>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0, 0, 6" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <medium type="homogeneous">
            <float name="sigma_t" value="0.02"/>
            <float name="albedo" value="0.5"/>
        </medium>
        <film type="hdrfilm">
            <integer name="width" value="24"/>
            <integer name="height" value="18"/>
            <rfilter type="box"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere">
        <point name="center" value="-1, 0, 0"/>
        <float name="radius" value="0.9"/>
        <bsdf type="null"/>
        <ref name="interior" id="fog"/>
    </shape>
    <shape type="cube">
        <transform name="to_world">
            <scale value="0.7"/>
            <translate value="1.2, 0, 0"/>
        </transform>
        <bsdf type="null"/>
        <medium type="heterogeneous" name="interior">
            <volume type="gridvolume" name="sigma_t">
                <string name="filename" value="smoke.vol"/>
                <transform name="to_world">
                    <scale value="1.4"/>
                    <translate value="0.5, -0.7, -0.7"/>
                </transform>
            </volume>
            <float name="scale" value="2"/>
            <rgb name="albedo" value="0.9, 0.6, 0.3"/>
            <phase type="isotropic"/>
        </medium>
    </shape>
</scene>
"#;

/// The XML media scene in Mitsuba's dict form.
const DICT_MEDIA: &str = r#"{
    "type": "scene",
    "integrator": {"type": "volpath", "max_depth": 6},
    "fog": {"type": "homogeneous", "sigma_t": {"type": "rgb", "value": [0.5, 1, 1.5]},
            "albedo": 0.8, "phase": {"type": "hg", "g": 0.5}},
    "sensor": {
        "type": "perspective", "fov": 40,
        "to_world": [[-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 6], [0, 0, 0, 1]],
        "medium": {"type": "homogeneous", "sigma_t": 0.02, "albedo": 0.5},
        "film": {"type": "hdrfilm", "width": 24, "height": 18, "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": 4}
    },
    "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 1}},
    "ball": {"type": "sphere", "center": [-1, 0, 0], "radius": 0.9,
             "bsdf": {"type": "null"}, "interior": {"type": "ref", "id": "fog"}},
    "box": {"type": "cube",
            "to_world": [[0.7, 0, 0, 1.2], [0, 0.7, 0, 0], [0, 0, 0.7, 0], [0, 0, 0, 1]],
            "bsdf": {"type": "null"},
            "interior": {"type": "heterogeneous",
                         "sigma_t": {"type": "gridvolume", "filename": "smoke.vol",
                                     "to_world": [[1.4, 0, 0, 0.5], [0, 1.4, 0, -0.7],
                                                  [0, 0, 1.4, -0.7], [0, 0, 0, 1]]},
                         "scale": 2,
                         "albedo": {"type": "rgb", "value": [0.9, 0.6, 0.3]},
                         "phase": {"type": "isotropic"}}}
}"#;

/// A 4³ grid of one channel rising along x.
fn write_smoke(dir: &Path) {
    let grid = penumbra::volume::vol_file::VolGrid {
        resolution: [4, 4, 4],
        channels: 1,
        bbox: penumbra::math::Aabb::new(penumbra::math::Vec3::ZERO, penumbra::math::Vec3::ONE),
        data: (0..64).map(|i| 0.25 * (i % 4) as f32 + 0.1).collect(),
    };
    std::fs::write(dir.join("smoke.vol"), grid.to_bytes()).unwrap();
}

/// Media, phase functions and volumes in a dict (a medium at the scene's
/// level referred to by id, one nested as a shape's `interior`, the
/// sensor's `medium`, a `gridvolume` of a file) read as the XML saying the
/// same: one tree, the same pixels.
#[test]
fn media_in_a_dict_read_as_in_the_xml() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("media.xml"), XML_MEDIA).unwrap();
    write_smoke(d.path());
    let opts = LoadOptions::default();
    let xml = SceneSource::open(d.path().join("media.xml").to_str().unwrap(), &opts).unwrap();
    let dict = dict_source(DICT_MEDIA, d.path()).unwrap();
    assert!(
        xml.root.same_as(&dict.root),
        "XML:\n{}\ndict:\n{}",
        xml.root.fingerprint(),
        dict.root.fingerprint()
    );
    let (a, _) = common::render_scene(&xml.build().unwrap(), 2);
    let (b, _) = common::render_scene(&dict.build().unwrap(), 2);
    assert!(a.pixels == b.pixels, "the dict renders other pixels");
    // The media are seen: the fog's red is thinner than its blue, so the
    // ball's pixel is redder than the sky behind nothing.
    let ball = a.pixels[9 * 24 + 8];
    assert!(ball.r > ball.b, "{ball:?}");
    // A medium's misplaced phase, or a phase outside a medium, is named by
    // its key path.
    let wrong = DICT_MEDIA.replace(
        r#""phase": {"type": "hg", "g": 0.5}"#,
        r#""phase": {"type": "hgx"}"#,
    );
    let e = dict_source(&wrong, d.path())
        .err()
        .expect("an unknown phase");
    assert!(e.contains("fog.phase.type"), "{e}");
}
