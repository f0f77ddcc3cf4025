//! Volumes in scenes: `[volumes.NAME]` in TOML and `<volume>` in Mitsuba
//! XML are read, checked against their schemas and built when the scene
//! is; a broken `.vol` file is refused naming the file and the scene's
//! line; a Mitsuba scene's volumes convert to TOML and read back.

use std::path::Path;

use penumbra::description::{Kind, Value};
use penumbra::math::{Aabb, Vec3};
use penumbra::scene::{convert, LoadOptions, SceneSource};
use penumbra::volume::vol_file::VolGrid;

fn vol(resolution: [u32; 3], channels: u32) -> Vec<u8> {
    let n = resolution.iter().product::<u32>() * channels;
    VolGrid {
        resolution,
        channels,
        bbox: Aabb {
            min: Vec3::new(-1.0, -1.0, -1.0),
            max: Vec3::new(1.0, 1.0, 1.0),
        },
        data: (0..n).map(|i| (i % 7) as f32).collect(),
    }
    .to_bytes()
}

const CAMERA: &str = "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\n";

fn build(dir: &Path, name: &str) -> Result<(), String> {
    let path = dir.join(name);
    let src = SceneSource::open(path.to_str().unwrap(), &LoadOptions::default())
        .map_err(|e| e.to_string())?;
    src.build().map(drop).map_err(|e| e.to_string())
}

#[test]
fn toml_volumes_are_built_with_the_scene() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("smoke.vol"), vol([4, 3, 2], 1)).unwrap();
    std::fs::write(d.path().join("albedo.vol"), vol([2, 2, 2], 3)).unwrap();
    let good = format!(
        "{CAMERA}\n[volumes.smoke]\ntype = \"gridvolume\"\nfilename = \"smoke.vol\"\n\
         filter_type = \"nearest\"\nwrap_mode = \"repeat\"\nuse_grid_bbox = true\n\
         transform = {{ scale = 2, translate = [0, 1, 0] }}\n\n\
         [volumes.albedo]\ntype = \"gridvolume\"\nfilename = \"albedo.vol\"\nmax_value = 3\n\n\
         [volumes.haze]\ntype = \"constvolume\"\nvalue = [0.5, 0.25, 1]\n"
    );
    std::fs::write(d.path().join("good.toml"), &good).unwrap();
    build(d.path(), "good.toml").unwrap();

    // Each refused at its line, the file named where a file is at fault.
    std::fs::write(d.path().join("short.vol"), &vol([4, 3, 2], 1)[..60]).unwrap();
    std::fs::create_dir(d.path().join("dir.vol")).unwrap();
    for (body, line, want) in [
        (
            "type = \"gridvolume\"\nfilename = \"short.vol\"\n",
            3,
            "short.vol: the header says 4 × 3 × 2 voxels",
        ),
        (
            "type = \"gridvolume\"\nfilename = \"dir.vol\"\n",
            3,
            "dir.vol: is a directory",
        ),
        (
            "type = \"gridvolume\"\nfilename = \"none.vol\"\n",
            3,
            "none.vol",
        ),
        ("type = \"gridvolume\"\n", 1, "missing field `filename`"),
        (
            "type = \"gridvolume\"\nfilename = \"smoke.vol\"\nwrap_mode = \"wrap\"\n",
            4,
            "wrap_mode",
        ),
        (
            "type = \"gridvolume\"\nfilename = \"smoke.vol\"\nmax_value = -1\n",
            4,
            "max_value",
        ),
        (
            "type = \"gridvolume\"\nfilename = \"smoke.vol\"\naccel = true\n",
            4,
            "accel",
        ),
        (
            "type = \"constvolume\"\nvalue = -1\n",
            3,
            "must be finite and ≥ 0",
        ),
        (
            "type = \"smoke\"\n",
            2,
            "unknown volume `smoke`; valid choices are: gridvolume, constvolume",
        ),
    ] {
        let text = format!("{CAMERA}\n[volumes.v]\n{body}");
        std::fs::write(d.path().join("bad.toml"), &text).unwrap();
        let e = build(d.path(), "bad.toml").unwrap_err();
        // The camera's 3 lines and a blank one come first.
        let at = format!("bad.toml:{}:", line + 4);
        assert!(e.contains(&at) && e.contains(want), "{body}: {e}");
    }
}

#[test]
fn mitsuba_volumes_are_read_and_convert_to_toml() {
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir(d.path().join("textures")).unwrap();
    std::fs::write(d.path().join("textures/sigmat.vol"), vol([4, 4, 4], 1)).unwrap();
    let xml = r#"<?xml version="1.0"?>
<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="45"/></sensor>
    <volume id="smoke" type="gridvolume">
        <transform name="to_world">
            <scale x="1.5" y="1.5" z="1.5"/>
            <translate x="-0.5" y="-0.5" z="-0.5"/>
        </transform>
        <boolean name="use_grid_bbox" value="false"/>
        <string name="filter_type" value="nearest"/>
        <string name="filename" value="textures/sigmat.vol"/>
    </volume>
    <volume type="constvolume">
        <rgb name="value" value="0.9, 0.5, 0.25"/>
    </volume>
</scene>
"#;
    std::fs::write(d.path().join("scene.xml"), xml).unwrap();
    let opts = LoadOptions::default();
    let src = SceneSource::open(d.path().join("scene.xml").to_str().unwrap(), &opts).unwrap();
    let volumes: Vec<_> = src.root.children_of(Kind::Volume).collect();
    assert_eq!(volumes.len(), 2);
    assert_eq!(volumes[0].id.as_deref(), Some("smoke"));
    assert_eq!(volumes[0].plugin, "gridvolume");
    assert_eq!(volumes[1].plugin, "constvolume");
    let transform = volumes[0].prop("transform").expect("to_world as transform");
    let Value::Table(t) = &transform.value.value else {
        panic!("{transform:?}")
    };
    assert_eq!(t[0].name, "matrix");
    src.build().unwrap();
    let text = convert::to_toml(&src, d.path()).unwrap();
    assert!(
        text.contains("[volumes]\nsmoke = {")
            && text.contains("filename = \"textures/sigmat.vol\""),
        "{text}"
    );
    std::fs::write(d.path().join("scene.toml"), &text).unwrap();
    let back = SceneSource::open(d.path().join("scene.toml").to_str().unwrap(), &opts).unwrap();
    assert!(back.root.same_as(&src.root), "{text}");
    back.build().unwrap();

    // A parameter gridvolume does not read, at its line.
    let bad = xml.replace(
        r#"<boolean name="use_grid_bbox" value="false"/>"#,
        r#"<boolean name="dx" value="false"/>"#,
    );
    std::fs::write(d.path().join("bad.xml"), bad).unwrap();
    let e = SceneSource::open(d.path().join("bad.xml").to_str().unwrap(), &opts)
        .and_then(|s| s.build())
        .map(drop)
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.xml:9:") && e.contains("`dx`"), "{e}");
}

/// A Python dict's volumes make the tree its XML makes.
#[test]
fn a_dict_s_volumes_are_the_xml_s() {
    use penumbra::description::mitsuba::dict::DictValue;
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("sigmat.vol"), vol([4, 4, 4], 1)).unwrap();
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="45"/></sensor>
    <volume id="smoke" type="gridvolume">
        <transform name="to_world"><scale value="2"/></transform>
        <string name="filename" value="sigmat.vol"/>
        <string name="wrap_mode" value="mirror"/>
    </volume>
    <volume id="haze" type="constvolume"><rgb name="value" value="0.9, 0.5, 0.25"/></volume>
</scene>"#;
    let json = r#"{"type": "scene",
        "sensor": {"type": "perspective", "fov": 45},
        "smoke": {"type": "gridvolume", "filename": "sigmat.vol", "wrap_mode": "mirror",
                  "to_world": [[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]]},
        "haze": {"type": "constvolume", "value": {"type": "rgb", "value": [0.9, 0.5, 0.25]}}}"#;
    std::fs::write(d.path().join("scene.xml"), xml).unwrap();
    let opts = LoadOptions::default();
    let from_xml = SceneSource::open(d.path().join("scene.xml").to_str().unwrap(), &opts).unwrap();
    let dict = DictValue::from_json(json).unwrap();
    let from_dict = SceneSource::from_mitsuba_dict(&dict, d.path(), &opts).unwrap();
    assert!(
        from_xml.root.same_as(&from_dict.root),
        "XML:\n{}\ndict:\n{}",
        from_xml.root.fingerprint(),
        from_dict.root.fingerprint()
    );
    from_dict.build().unwrap();
}

/// A `<float>` or a colour where a volume is expected is a plain value (a
/// constant volume): read through a plugin whose schema takes a volume (a
/// stand-in texture here, until a medium takes one).
#[test]
fn a_float_or_a_colour_where_a_volume_is_expected_is_a_plain_value() {
    use penumbra::description::mitsuba::{self, Mitsuba, Plugin};
    use penumbra::description::{Param, Schema, Type};
    const FOG: Schema = Schema {
        kind: Kind::Texture,
        plugin: "fog",
        what: "stand-in",
        doc: "",
        mitsuba: &["fog"],
        params: &[
            Param::new("sigma_t", Type::Volume, "1", ""),
            Param::new("albedo", Type::Volume, "1", ""),
        ],
    };
    const TEXTURES: &[Plugin] = &[Plugin::new(&FOG, Mitsuba::SAME)];
    fn registry(kind: Kind) -> &'static [Plugin] {
        match kind {
            Kind::Texture => TEXTURES,
            k => penumbra::integrator::plugins::registry(k),
        }
    }
    let d = tempfile::tempdir().unwrap();
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="45"/></sensor>
    <texture id="f" type="fog">
        <float name="sigma_t" value="2.5"/>
        <rgb name="albedo" value="0.9, 0.5, 1.5"/>
    </texture>
</scene>"#;
    let path = d.path().join("scene.xml");
    std::fs::write(&path, xml).unwrap();
    let loaded = mitsuba::from_xml_file(&path, &[], 1 << 20, registry).unwrap();
    let fog = loaded.root.children_of(Kind::Texture).next().unwrap();
    assert_eq!(fog.prop("sigma_t").unwrap().value.value, Value::Float(2.5));
    let Value::Array(c) = &fog.prop("albedo").unwrap().value.value else {
        panic!("{fog:?}")
    };
    let c: Vec<f64> = c
        .iter()
        .map(|x| match x.value {
            Value::Float(f) => f,
            _ => panic!("{x:?}"),
        })
        .collect();
    // Unbounded: the 1.5 is kept.
    assert!(
        (c[0] - 0.9).abs() < 1e-6 && (c[1] - 0.5).abs() < 1e-6 && (c[2] - 1.5).abs() < 1e-6,
        "{c:?}"
    );
}

/// A heterogeneous medium's volumes in Mitsuba XML, nested or referred
/// to: its `sigma_t` the nested volume's table and its `albedo` the
/// declared volume's name; the scene builds. (The dict reader does not
/// read media yet.)
#[test]
fn a_medium_s_volumes_are_read_from_xml() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("sigmat.vol"), vol([4, 4, 4], 1)).unwrap();
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="45"/></sensor>
    <volume id="haze" type="constvolume"><rgb name="value" value="0.9, 0.5, 0.25"/></volume>
    <medium id="fog" type="heterogeneous">
        <volume name="sigma_t" type="gridvolume">
            <string name="filename" value="sigmat.vol"/>
        </volume>
        <ref name="albedo" id="haze"/>
        <float name="scale" value="2"/>
    </medium>
    <shape type="sphere">
        <bsdf type="null"/>
        <ref name="interior" id="fog"/>
    </shape>
</scene>"#;
    std::fs::write(d.path().join("scene.xml"), xml).unwrap();
    let opts = LoadOptions::default();
    let from_xml = SceneSource::open(d.path().join("scene.xml").to_str().unwrap(), &opts).unwrap();
    let fog = from_xml.root.children_of(Kind::Medium).next().unwrap();
    assert!(
        matches!(&fog.prop("sigma_t").unwrap().value.value, Value::Table(_)),
        "{fog:?}"
    );
    assert_eq!(
        fog.prop("albedo").unwrap().value.value,
        Value::String("haze".into())
    );
    from_xml.build().unwrap();
}
