//! Every parameter Mitsuba 3's plugin documentation lists, given to the
//! Mitsuba reader: each one of a plugin Penumbra has is read — neither
//! refused as unknown nor ignored with a warning — unless it is listed
//! below with the reason. The table (`data/mitsuba_params.tsv`) is made by
//! `scripts/mitsuba_params.py` from Mitsuba's sources.

use std::collections::BTreeSet;

use penumbra::description::mitsuba;
use penumbra::description::Kind;
use penumbra::integrator::plugins::registry;

const LIMIT: u64 = 4 << 20;

/// The parameters of plugins Penumbra has that it does not read, with
/// why. Every line must still be unread: reading one fails this test
/// until it is struck from the list.
const NOT_READ: &[(&str, &str, &str)] = &[
    // The output file's extension chooses the format and precision.
    ("hdrfilm", "file_format", "output format from the file name"),
    (
        "hdrfilm",
        "component_format",
        "output precision from the file name",
    ),
    // A spectral response: Mitsuba's RGB variants refuse it too.
    ("perspective", "srf", "spectral variants only"),
    ("thinlens", "srf", "spectral variants only"),
    ("orthographic", "srf", "spectral variants only"),
];

/// Plugins of Mitsuba's documentation that Penumbra does not have.
const MISSING: &[&str] = &[
    "d65",
    "srgb",
    "uniform",
    "regular",
    "irregular",
    "rawconstant",
    "blackbody",
    "bsplinecurve",
    "circular",
    "directionalarea",
    "distant",
    "ellipsoids",
    "ellipsoidsmesh",
    "hair",
    "irradiancemeter",
    "linearcurve",
    "measured",
    "measured_polarized",
    "batch",
    "polarizer",
    "pplastic",
    "radiancemeter",
    "retarder",
    "sdfgrid",
    "sggx",
    "specfilm",
    "stokes",
    "sunsky",
    "timed_sunsky",
    "volume",
];

struct Row {
    kind: String,
    plugin: String,
    param: String,
    ty: String,
}

fn rows() -> Vec<Row> {
    let text = include_str!("data/mitsuba_params.tsv");
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            assert_eq!(f.len(), 4, "{l}");
            Row {
                kind: f[0].into(),
                plugin: f[1].into(),
                param: f[2].into(),
                ty: f[3].into(),
            }
        })
        .collect()
}

/// A value of the documented type for `param` of `plugin`, as an XML
/// element.
fn element(plugin: &str, param: &str, ty: &str) -> String {
    let string = |v: &str| format!(r#"<string name="{param}" value="{v}"/>"#);
    match (plugin, param) {
        ("conductor" | "roughconductor", "material") => return string("Au"),
        (_, "distribution") => return string("beckmann"),
        (_, "filename") => {
            let file = match plugin {
                "obj" => "mesh.obj",
                "ply" => "mesh.ply",
                "gridvolume" => "grid.vol",
                "serialized" => "mesh.serialized",
                _ => "image.pfm",
            };
            return string(file);
        }
        (_, "focal_length") => return string("50mm"),
        (_, "fov_axis") => return string("x"),
        (_, "file_format") => return string("openexr"),
        (_, "pixel_format") => return string("rgb"),
        (_, "component_format") => return string("float32"),
        (_, "aovs") => return string("dd:depth"),
        (_, "normals") => return string("smooth"),
        ("tabphase" | "regular" | "irregular", "values") => return string("1, 1"),
        (_, "wavelengths") => return string("400, 700"),
        (_, "filter_type") => return string("bilinear"),
        (_, "wrap_mode") => return string("repeat"),
        (_, "format") => return string("variant"),
        ("mesh_attribute", "name") => return string("vertex_color"),
        (_, "shell") => return string("ico_sphere"),
        _ => {}
    }
    let first = ty.split(" or ").next().unwrap_or(ty).trim_end_matches(',');
    if first.contains("spectrum") || first.contains("color") {
        format!(r#"<rgb name="{param}" value="0.5, 0.5, 0.5"/>"#)
    } else if first.contains("float") || first.contains("Float") {
        format!(r#"<float name="{param}" value="0.5"/>"#)
    } else if first.contains("int") {
        format!(r#"<integer name="{param}" value="1"/>"#)
    } else if first.contains("bool") {
        format!(r#"<boolean name="{param}" value="false"/>"#)
    } else if first.contains("transform") {
        format!(r#"<transform name="{param}"><translate x="0.25"/></transform>"#)
    } else if first.contains("point") {
        format!(r#"<point name="{param}" x="0" y="0" z="1"/>"#)
    } else if first.contains("vector") {
        format!(r#"<vector name="{param}" x="0" y="0" z="1"/>"#)
    } else if first.contains("texture") {
        format!(r#"<texture type="checkerboard" name="{param}"/>"#)
    } else if first.contains("volume") {
        format!(r#"<float name="{param}" value="0.5"/>"#)
    } else {
        string("0")
    }
}

/// What a plugin needs besides the parameter under test to be read.
fn required(plugin: &str, param: &str) -> String {
    let needs: &[(&str, &str)] = match plugin {
        "envmap" | "bitmap" | "obj" | "ply" | "serialized" | "gridvolume" => {
            &[("filename", "|string|")]
        }
        "mesh_attribute" => &[("name", "|string|")],
        "tabphase" => &[("values", "|string|")],
        "irregular" => &[("wavelengths", "|string|"), ("values", "|string|")],
        "regular" => &[
            ("wavelength_min", "|float|"),
            ("wavelength_max", "|float|"),
            ("values", "|string|"),
        ],
        "projector" => &[("irradiance", "|texture|")],
        "thinlens" => &[("aperture_radius", "|float|")],
        _ => &[],
    };
    let nested = match plugin {
        "blendbsdf" => r#"<bsdf type="diffuse"/><bsdf type="conductor"/>"#,
        "twosided" | "mask" => r#"<bsdf type="diffuse"/>"#,
        "bumpmap" => r#"<texture type="checkerboard"/><bsdf type="diffuse"/>"#,
        "normalmap" => r#"<bsdf type="diffuse"/>"#,
        "blendphase" => r#"<phase type="isotropic"/><phase type="hg"/>"#,
        _ => "",
    };
    let mut xml: String = needs
        .iter()
        .filter(|(n, _)| *n != param)
        .map(|(n, t)| element(plugin, n, t))
        .collect();
    if plugin == "normalmap" && param != "normalmap" {
        xml += &element(plugin, "normalmap", "|texture|");
    }
    xml + nested
}

/// A scene holding `plugin` of Mitsuba's `kind` with `body` inside it.
fn scene(kind: &str, plugin: &str, body: &str) -> String {
    let sphere = |inner: String| format!(r#"<shape type="sphere">{inner}</shape>"#);
    let object = match kind {
        "bsdfs" => sphere(format!(r#"<bsdf type="{plugin}">{body}</bsdf>"#)),
        "emitters" if plugin == "area" => {
            sphere(format!(r#"<emitter type="{plugin}">{body}</emitter>"#))
        }
        "emitters" => format!(r#"<emitter type="{plugin}">{body}</emitter>"#),
        "shapes" if plugin == "instance" => format!(
            r#"<shape type="shapegroup" id="g"><shape type="sphere"/></shape><shape type="instance"><ref id="g"/>{body}</shape>"#
        ),
        "shapes" if plugin == "shapegroup" => {
            format!(r#"<shape type="shapegroup"><shape type="sphere"/>{body}</shape>"#)
        }
        "shapes" => format!(r#"<shape type="{plugin}">{body}</shape>"#),
        "sensors" => format!(r#"<sensor type="{plugin}">{body}<film type="hdrfilm"/></sensor>"#),
        "films" => {
            format!(r#"<sensor type="perspective"><film type="{plugin}">{body}</film></sensor>"#)
        }
        "rfilters" => format!(
            r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="{plugin}">{body}</rfilter></film></sensor>"#
        ),
        "samplers" => format!(
            r#"<sensor type="perspective"><film type="hdrfilm"/><sampler type="{plugin}">{body}</sampler></sensor>"#
        ),
        "integrators" => {
            let nested = match plugin {
                "aov" | "moment" | "stokes" => r#"<integrator type="path"/>"#,
                _ => "",
            };
            format!(r#"<integrator type="{plugin}">{body}{nested}</integrator>"#)
        }
        "textures" => sphere(format!(
            r#"<bsdf type="diffuse"><texture type="{plugin}" name="reflectance">{body}</texture></bsdf>"#
        )),
        "spectra" => sphere(format!(
            r#"<bsdf type="diffuse"><spectrum type="{plugin}" name="reflectance">{body}</spectrum></bsdf>"#
        )),
        "media" => sphere(format!(
            r#"<bsdf type="dielectric"/><medium type="{plugin}" name="interior">{body}</medium>"#
        )),
        "phase" => sphere(format!(
            r#"<bsdf type="dielectric"/><medium type="homogeneous" name="interior"><phase type="{plugin}">{body}</phase></medium>"#
        )),
        "volumes" => format!(r#"<volume type="{plugin}" id="v">{body}</volume>"#),
        other => panic!("a kind of Mitsuba plugin the test does not know: {other}"),
    };
    let sensor = match kind {
        "sensors" | "films" | "rfilters" | "samplers" => "",
        _ => r#"<sensor type="perspective"><film type="hdrfilm"/></sensor>"#,
    };
    format!("<scene version=\"3.0.0\">\n{sensor}{object}\n</scene>\n")
}

/// What reading `text` says of `param`: `None` if it was read, else the
/// message that refused or ignored it.
fn read(dir: &std::path::Path, text: &str, param: Option<&str>) -> Result<Vec<String>, String> {
    let path = dir.join("scene.xml");
    std::fs::write(&path, text).unwrap();
    match mitsuba::from_xml_file(&path, &[], LIMIT, registry) {
        Ok(loaded) => Ok(loaded
            .warnings
            .into_iter()
            .filter(|w| {
                param.is_some_and(|p| w.contains(&format!("`{p}`")) && w.contains("ignored"))
            })
            .collect()),
        Err(e) => Err(e.to_string()),
    }
}

fn files(dir: &std::path::Path) {
    std::fs::write(dir.join("mesh.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        dir.join("mesh.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    std::fs::write(dir.join("image.pfm"), b"PF\n1 1\n-1\n\0\0\0?\0\0\0?\0\0\0?").unwrap();
}

/// Penumbra's kind of plugin for a folder of Mitsuba's sources, where it
/// has one with a registry.
fn kind_of(folder: &str) -> Option<Kind> {
    Some(match folder {
        "bsdfs" => Kind::Bsdf,
        "emitters" => Kind::Emitter,
        "shapes" => Kind::Shape,
        "sensors" => Kind::Sensor,
        "films" => Kind::Film,
        "rfilters" => Kind::Filter,
        "samplers" => Kind::Sampler,
        "integrators" => Kind::Integrator,
        "textures" => Kind::Texture,
        "media" => Kind::Medium,
        "phase" => Kind::Phase,
        "volumes" => Kind::Volume,
        _ => return None,
    })
}

#[test]
fn every_documented_parameter_of_a_plugin_penumbra_has_is_read() {
    let dir = tempfile::tempdir().unwrap();
    files(dir.path());
    let mut unread = BTreeSet::new();
    let mut read_ok = 0;
    for row in rows() {
        let base = scene(&row.kind, &row.plugin, &required(&row.plugin, ""));
        let has = !MISSING.contains(&row.plugin.as_str());
        if let Some(kind) = kind_of(&row.kind) {
            // `moment` is read as the integrator it holds.
            let listed = row.plugin == "moment"
                || registry(kind)
                    .iter()
                    .any(|p| p.names.contains(&row.plugin.as_str()));
            assert_eq!(
                listed, has,
                "the {} `{}`: update MISSING",
                row.kind, row.plugin
            );
        }
        match (has, read(dir.path(), &base, None)) {
            (false, Err(_)) => continue,
            (false, Ok(_)) => panic!(
                "the {} `{}` is read: strike it from MISSING",
                row.kind, row.plugin
            ),
            (true, Err(e)) => panic!(
                "the {} `{}` without parameters is refused: {e}",
                row.kind, row.plugin
            ),
            (true, Ok(_)) => {}
        }
        let body = required(&row.plugin, &row.param) + &element(&row.plugin, &row.param, &row.ty);
        let text = scene(&row.kind, &row.plugin, &body);
        let unknown = format!("`{}` is not a parameter", row.param);
        match read(dir.path(), &text, Some(&row.param)) {
            Err(e) if e.contains(&unknown) || e.contains("is not supported") => {
                unread.insert((row.plugin.clone(), row.param.clone(), e));
            }
            Ok(warnings) if !warnings.is_empty() => {
                unread.insert((row.plugin.clone(), row.param.clone(), warnings.join("; ")));
            }
            // Read: accepted, or refused for its value (the test's values
            // are of the documented type, not always in range).
            _ => read_ok += 1,
        }
    }
    let listed: BTreeSet<(String, String)> = NOT_READ
        .iter()
        .map(|(p, k, _)| (p.to_string(), k.to_string()))
        .collect();
    let found: BTreeSet<(String, String)> = unread
        .iter()
        .map(|(p, k, _)| (p.clone(), k.clone()))
        .collect();
    let new: Vec<_> = unread
        .iter()
        .filter(|(p, k, _)| !listed.contains(&(p.clone(), k.clone())))
        .map(|(p, k, e)| format!("{p}.{k}: {e}"))
        .collect();
    assert!(
        new.is_empty(),
        "parameters Mitsuba reads that Penumbra does not:\n{}",
        new.join("\n")
    );
    let stale: Vec<_> = listed.difference(&found).collect();
    assert!(
        stale.is_empty(),
        "read now, strike from NOT_READ: {stale:?}"
    );
    assert!(read_ok > 150, "only {read_ok} parameters read");
}
