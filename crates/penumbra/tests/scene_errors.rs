//! Bad scenes give clear errors at file:line:column, never a panic.

mod common;

use std::path::Path;

use common::try_scene;
use penumbra::scene::{LoadOptions, SceneSource};

fn err(toml: &str) -> String {
    match try_scene(toml) {
        Ok(_) => panic!("scene should be rejected:\n{toml}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn unknown_key_names_line_and_column() {
    let e = err("[render]\nwidth = 10\nheigth = 5\n");
    assert!(e.starts_with("test.toml:3:1:"), "{e}");
    assert!(e.contains("heigth"), "{e}");
}

#[test]
fn wrong_type_is_located() {
    let e = err("[camera]\nfov = \"wide\"\n");
    assert!(e.starts_with("test.toml:2:7:"), "{e}");
}

#[test]
fn unknown_distribution_lists_the_choices() {
    let e = err("[render]\ndistribution = \"sobel\"\n");
    assert!(e.starts_with("test.toml:2:16:"), "{e}");
    for name in [
        "grid",
        "jitter",
        "semi-jitter",
        "poisson",
        "random",
        "fast-random",
        "sobol",
        "zsobol",
        "pmj02",
        "pmj02bn",
        "halton",
        "r2",
    ] {
        assert!(e.contains(name), "{e}");
    }
}

#[test]
fn out_of_range_values_point_at_the_value() {
    let e = err("[render]\nwidth = 10\nspp = 0\n");
    assert!(e.starts_with("test.toml:3:7:"), "{e}");
    assert!(e.contains("render.spp"), "{e}");
    let e = err("[materials.m]\nreflectivity = 0.7\ntransparency = 0.6\n");
    assert!(e.starts_with("test.toml:3:16:"), "{e}");
    let e = err("[[objects]]\ntype = \"sphere\"\nradius = -1.0\n");
    assert!(e.starts_with("test.toml:3:10:"), "{e}");
    let e = err("[render]\nbackground = [0.0, nan, 0.0]\n");
    assert!(e.starts_with("test.toml:2:14:"), "{e}");
    let e = err("[[lights]]\ntype = \"sky\"\nresolution = 15\n");
    assert!(
        e.starts_with("test.toml:3:14:") && e.contains("even"),
        "{e}"
    );
    let e = err("[[lights]]\ntype = \"sky\"\nsun_radius = 0\n");
    assert!(
        e.starts_with("test.toml:3:14:") && e.contains("sun_radius"),
        "{e}"
    );
}

#[test]
fn closed_sets_list_valid_choices() {
    let e = err("[[objects]]\ntype = \"torus\"\n");
    assert!(
        e.contains("sphere, quad, mesh, rectangle, disk, cube, cylinder, instance, shapegroup"),
        "{e}"
    );
    let e = err("[[lights]]\ntype = \"sunsky\"\nposition = [0.0, 1.0, 0.0]\n");
    assert!(
        e.contains("point, constant, spot, projector, directional, envmap, sky, rect, sphere, quad, mesh, rectangle, disk, cube, cylinder"),
        "{e}"
    );
    let e = err("[[lights]]\ntype = \"rect\"\norigin = [0.0, 1.0, 0.0]\nedge_u = [1.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 1.0]\nradiance = [1.0, 1.0, 1.0]\nmodel = \"exact\"\n");
    assert!(
        e.starts_with("test.toml:7:9:") && e.contains("surface, thesis"),
        "{e}"
    );
}

#[test]
fn keys_of_another_type_are_rejected() {
    let e = err("[[objects]]\ntype = \"quad\"\nradius = 1.0\norigin = [0.0, 0.0, 0.0]\nedge_u = [1.0, 0.0, 0.0]\nedge_v = [0.0, 1.0, 0.0]\n");
    assert!(
        e.starts_with("test.toml:3:10:") && e.contains("origin, edge_u, edge_v"),
        "{e}"
    );
}

#[test]
fn undefined_material_lists_defined_ones() {
    let e = err(
        "[materials.red]\n[materials.blue]\n[[objects]]\ntype = \"sphere\"\nmaterial = \"green\"\n",
    );
    assert!(
        e.starts_with("test.toml:5:12:") && e.contains("blue, red"),
        "{e}"
    );
}

#[test]
fn missing_required_key_points_at_its_table() {
    let e = err("[[lights]]\ntype = \"point\"\nintensity = [1.0, 1.0, 1.0]\n");
    assert!(e.contains("position"), "{e}");
    assert!(e.starts_with("test.toml:"), "{e}");
}

#[test]
fn missing_mesh_file_is_reported_with_the_scene_position() {
    let e = err("[[objects]]\ntype = \"mesh\"\npath = \"no/such/mesh.ply\"\n");
    assert!(
        e.starts_with("test.toml:3:8:") && e.contains("mesh.ply"),
        "{e}"
    );
}

#[test]
fn the_camera_cannot_look_along_up() {
    let e = err("[camera]\nposition = [0.0, 5.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\n");
    assert!(e.contains("up"), "{e}");
}

#[test]
fn syntax_errors_are_located() {
    let e = err("[render]\nwidth = = 3\n");
    assert!(e.starts_with("test.toml:2:"), "{e}");
}

#[test]
fn bunny_scene_without_bunny_says_how_to_supply_it() {
    let src = penumbra::scene::SceneSource::from_toml(
        "[[objects]]\ntype = \"mesh\"\npath = \"@bunny\"\n",
        std::path::Path::new("b.toml"),
        std::path::Path::new("."),
        &Default::default(),
    )
    .unwrap();
    // No bunny in the options: the library looks nowhere else.
    let e = src.build().err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.contains("--bunny") && e.contains("PENUMBRA_BUNNY"), "{e}");
    assert!(
        !e.contains("shared"),
        "no default location may be offered: {e}"
    );
}

/// Every fixed-length array of the format, given one element too few and one
/// too many (and, for one, a hundred thousand), is an error at its line
/// naming the key and both lengths: nothing is cut to size in silence.
#[test]
fn every_fixed_length_array_has_exactly_its_length() {
    // (table header, other keys the table needs, key, length)
    let sphere = "type = \"sphere\"";
    let mesh = "type = \"mesh\"\npath = \"m.ply\"";
    let point = "type = \"point\"";
    let rect = "type = \"rect\"";
    let disk = "type = \"disk\"";
    let cases: [(&str, &str, &str, usize); 20] = [
        ("[render]", "", "background", 3),
        ("[camera]", "", "position", 3),
        ("[camera]", "", "look_at", 3),
        ("[camera]", "", "up", 3),
        ("[camera]", "", "shutter", 2),
        ("[camera]", "", "position_end", 3),
        ("[camera]", "", "look_at_end", 3),
        ("[materials.m]", "", "albedo", 3),
        ("[materials.m]", "", "emission", 3),
        ("[[objects]]", sphere, "center", 3),
        ("[[objects]]", "type = \"quad\"", "origin", 3),
        ("[[objects]]", "type = \"quad\"", "edge_u", 3),
        ("[[objects]]", "type = \"quad\"", "edge_v", 3),
        ("[[lights]]", point, "position", 3),
        ("[[lights]]", point, "intensity", 3),
        ("[[lights]]", rect, "radiance", 3),
        ("[[lights]]", rect, "origin", 3),
        ("[[lights]]", rect, "edge_u", 3),
        ("[[lights]]", disk, "center", 3),
        ("[[lights]]", disk, "normal", 3),
    ];
    let table_key = |header: &str, key: &str| -> String {
        let name = header.trim_matches(['[', ']']);
        match header {
            "[[objects]]" | "[[lights]]" => format!("{name}[0].{key}"),
            _ => format!("{name}.{key}"),
        }
    };
    for (header, needs, key, n) in cases {
        for got in [n - 1, n + 1] {
            let values = vec!["1.0"; got].join(", ");
            let toml = match needs {
                "" => format!("{header}\n{key} = [{values}]\n"),
                _ => format!("{header}\n{needs}\n{key} = [{values}]\n"),
            };
            let line = 2 + needs.lines().count();
            let e = err(&toml);
            let at = format!("test.toml:{line}:{}:", key.len() + 4);
            let what = format!(
                "{}: expected {n} numbers, got {got}",
                table_key(header, key)
            );
            assert!(e.starts_with(&at) && e.contains(&what), "{e}\n{toml}");
        }
    }
    for (key, n) in [("translate", 3), ("rotate_axis", 3), ("scale", 3)] {
        for got in [n - 1, n + 1] {
            let values = vec!["1.0"; got].join(", ");
            let toml = format!("[[objects]]\n{mesh}\n[objects.transform]\n{key} = [{values}]\n");
            let e = err(&toml);
            let what = format!("objects[0].transform.{key}: expected {n} numbers, got {got}");
            assert!(e.starts_with("test.toml:5:") && e.contains(&what), "{e}");
        }
    }
    let rows = |rows: &[&str]| {
        format!(
            "[[objects]]\n{mesh}\ntransform.matrix = [{}]\n",
            rows.join(", ")
        )
    };
    let row = "[1, 0, 0, 0]";
    let e = err(&rows(&[row, row, row]));
    assert!(
        e.starts_with("test.toml:4:") && e.contains("transform.matrix: expected 4 rows, got 3"),
        "{e}"
    );
    let e = err(&rows(&[row, row, row, row, row]));
    assert!(e.contains("expected 4 rows, got 5"), "{e}");
    let e = err(&rows(&[row, row, row, "[0, 0, 1]"]));
    assert!(
        e.contains("transform.matrix[3]: expected 4 numbers, got 3"),
        "{e}"
    );
    let many = vec!["0.5"; 100_000].join(",");
    let e = err(&format!("[render]\nbackground = [{many}]\n"));
    assert!(
        e.starts_with("test.toml:2:14: render.background: expected 3 numbers, got 100000"),
        "{e}"
    );
    assert!(e.len() < 200, "{e}");
}

/// The TOML parser refuses keys and values nested too deeply, some of them
/// without a position: every such error still names its line.
#[test]
fn nesting_too_deep_is_located() {
    let key = vec!["a"; 200].join(".");
    for (toml, line) in [
        (format!("[render]\nwidth = 8\n{key} = 1\n"), 3),
        (format!("[render]\n\n[{key}]\n"), 3),
        (format!("[[objects]]\ntype = \"sphere\"\n[[{key}]]\n"), 3),
        (format!("x = 1\ny = {{ {key} = 1 }}\n"), 2),
    ] {
        let e = err(&toml);
        assert!(e.starts_with(&format!("test.toml:{line}:")), "{e}");
        assert!(e.contains("200 dotted parts"), "{e}");
    }
    let arrays = format!(
        "[render]\nbackground = {}{}\n",
        "[".repeat(500),
        "]".repeat(500)
    );
    let e = err(&arrays);
    assert!(e.starts_with("test.toml:2:"), "{e}");
    let tables = format!(
        "[render]\nwidth = 3\nx = {}1{}\n",
        "{a = ".repeat(300),
        "}".repeat(300)
    );
    let e = err(&tables);
    assert!(e.starts_with("test.toml:3:"), "{e}");
}

/// Values quoted in errors are cut to a few dozen characters, and no message
/// is longer than a few lines, whatever the scene holds.
#[test]
fn messages_stay_short_whatever_the_input() {
    let huge = "x".repeat(1 << 20);
    let cases = [
        format!("[render]\nwidth = \"{huge}\"\n"),
        format!("[render]\n{huge} = 1\n"),
        format!("[[objects]]\ntype = \"{huge}\"\n"),
        format!("[[objects]]\ntype = \"sphere\"\nmaterial = \"{huge}\"\n"),
        format!("[materials.{huge}]\nalbedo = [2, 2, 2]\n"),
        format!("[render]\ndistribution = \"{huge}\"\n"),
        format!("[render]\nwidth = {huge}\n"),
        format!("[[objects]]\ntype = \"mesh\"\npath = \"{huge}.ply\"\n"),
        format!("[[lights]]\ntype = \"rect\"\nmodel = \"{huge}\"\n"),
        format!("# {huge}\n[render]\nwidth = -1\n"),
        format!("x = \"\"\"\n{}\"\"\"\n", "line\n".repeat(100_000)),
    ];
    for toml in &cases {
        let e = err(toml);
        assert!(e.starts_with("test.toml:"), "{}", &e[..e.len().min(200)]);
        assert!(e.len() < 1200, "{} bytes: {}", e.len(), &e[..200]);
        assert!(e.lines().count() <= 5, "{e}");
    }
    // What is cut is marked.
    let e = err(&cases[0]);
    assert!(e.contains("xxx…\""), "{e}");
}

#[test]
fn every_located_error_has_a_line() {
    for toml in [
        "[render]\nwidth = 0\n",
        "[[objects]]\n",
        "[[objects]]\ntype = \"sphere\"\ncenter = [1, 2, 3, 4]\n",
        "objects = 3\n",
        "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 0]\n",
        "[render\n",
        "= 1\n",
        "[materials.m]\nalbedo = [0.9, 0.9, 0.9]\nspecular = 0.5\n",
    ] {
        let e = err(toml);
        let rest = e.strip_prefix("test.toml:").expect(&e);
        let line: String = rest.chars().take_while(char::is_ascii_digit).collect();
        assert!(!line.is_empty(), "{e}");
    }
}

/// A frame too large to hold in memory is refused before anything is
/// allocated, whichever side is large.
#[test]
fn an_image_too_large_for_memory_is_refused() {
    let e = err("[render]\nwidth = 32768\nheight = 32768\n");
    assert!(e.starts_with("test.toml:3:10: render.height:"), "{e}");
    assert!(e.contains("1073741824 pixels"), "{e}");
    for (w, h) in [(16384, 16384), (32768, 8192), (32768, 1)] {
        let toml = format!("[render]\nwidth = {w}\nheight = {h}\n");
        let r = common::try_scene(&toml);
        assert!(r.is_ok(), "{w} x {h}: {:?}", r.err());
    }
}

/// Objects sharing a mesh multiply it: a short scene naming one mesh
/// thousands of times is refused (at the object that passes the bound)
/// before it fills memory.
#[test]
fn a_mesh_used_too_many_times_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // A strip of 40,000 triangles.
    let n = 20_000;
    let mut obj = String::new();
    for i in 0..=n {
        obj.push_str(&format!("v {i} 0 0\nv {i} 1 0\n"));
    }
    for i in 0..n {
        let (a, b) = (2 * i + 1, 2 * i + 2);
        obj.push_str(&format!("f {a} {} {b}\nf {b} {} {}\n", a + 2, a + 2, b + 2));
    }
    std::fs::create_dir(dir.path().join("d")).unwrap();
    std::fs::write(dir.path().join("d/strip.obj"), obj).unwrap();
    // The same file under several names counts as one file.
    let mut names = vec![
        "d/strip.obj",
        "d/./strip.obj",
        "d//strip.obj",
        "d/../d/strip.obj",
    ];
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("d/strip.obj", dir.path().join("link.obj")).unwrap();
        names.push("link.obj");
    }
    let build = |count: usize| {
        let toml: String = (0..count)
            .map(|i| {
                let name = &names[i % names.len()];
                format!("[[objects]]\ntype = \"mesh\"\npath = \"{name}\"\n")
            })
            .collect();
        SceneSource::from_toml(
            &toml,
            Path::new("test.toml"),
            dir.path(),
            &LoadOptions::default(),
        )
        .and_then(|s| s.build())
    };
    assert!(build(3).is_ok());
    // 4,194,304 / 40,000: 104 uses are allowed, the 105th is not.
    let e = build(5000).err().expect("refused").to_string();
    assert!(e.starts_with("test.toml:315:8: objects[104].path:"), "{e}");
    assert!(
        e.contains("4200000 triangles") && e.contains("40000 triangles of its mesh files"),
        "{e}"
    );
}

/// A filter's bad parameter, or the parameter of another filter, is an
/// error at its value.
#[test]
fn bad_filter_parameters_point_at_the_value() {
    for (toml, place, message) in [
        (
            "[render]\nfilter = \"gaussian\"\nfilter_stddev = -0.5\n",
            "test.toml:3:17:",
            "render.filter_stddev: must be a positive number, got -0.5",
        ),
        (
            "[render]\nfilter = \"lanczos\"\nfilter_lobes = 0\n",
            "test.toml:3:16:",
            "render.filter_lobes: must be an integer from 1 to 32, got 0",
        ),
        (
            "[render]\nfilter = \"mitchell\"\nfilter_c = 1.5\n",
            "test.toml:3:12:",
            "render.filter_c: must be between 0 and 1, got 1.5",
        ),
        (
            "[render]\nfilter_stddev = 0.3\n",
            "test.toml:2:17:",
            "the box filter has no parameter `stddev` (it takes: none)",
        ),
        (
            "[render]\nfilter = \"mitchell\"\nfilter_lobes = 2\n",
            "test.toml:3:16:",
            "the mitchell filter has no parameter `lobes` (it takes: B, C)",
        ),
    ] {
        let e = err(toml);
        assert!(e.starts_with(place), "{toml}: {e}");
        assert!(e.contains(message), "{toml}: {e}");
    }
}

/// Materials holding materials name them; a loop, an unknown name and a
/// held material that does not fit are refused at the name.
#[test]
fn held_materials_are_named_and_loops_refused() {
    let ok =
        "[materials.a]\ntype = \"diffuse\"\n\n[materials.b]\ntype = \"mask\"\nbsdf = \"c\"\n\n\
              [materials.c]\ntype = \"blendbsdf\"\nbsdf_0 = \"a\"\nbsdf_1 = \"d\"\n\n\
              [materials.d]\ntype = \"twosided\"\nbsdf = \"a\"\n\n\
              [[objects]]\ntype = \"sphere\"\nmaterial = \"b\"\n";
    let scene = try_scene(ok).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = scene.bsdfs.iter().map(|b| b.name()).collect();
    assert_eq!(names[1..5], ["diffuse", "mask", "blendbsdf", "twosided"]);
    let e = err("[materials.a]\ntype = \"mask\"\nbsdf = \"b\"\n\n[materials.b]\ntype = \"twosided\"\nbsdf = \"a\"\n");
    assert!(e.contains("holds itself"), "{e}");
    assert!(
        e.starts_with("test.toml:3:8:") || e.starts_with("test.toml:7:8:"),
        "{e}"
    );
    let e = err("[materials.a]\ntype = \"mask\"\nbsdf = \"a\"\n");
    assert!(
        e.starts_with("test.toml:3:8:") && e.contains("holds itself"),
        "{e}"
    );
    let e = err("[materials.a]\ntype = \"blendbsdf\"\nbsdf_0 = \"x\"\nbsdf_1 = \"x\"\n");
    assert!(
        e.starts_with("test.toml:3:10:") && e.contains("no material named `x`"),
        "{e}"
    );
    let e = err("[materials.g]\ntype = \"dielectric\"\n\n[materials.t]\ntype = \"twosided\"\nbsdf = \"g\"\n");
    assert!(
        e.starts_with("test.toml:4:1:") && e.contains("transmits light"),
        "{e}"
    );
    let chain = |n: usize| -> String {
        (1..n)
            .map(|i| {
                format!(
                    "[materials.m{i}]\ntype = \"twosided\"\nbsdf = \"m{}\"\n",
                    i + 1
                )
            })
            .chain([format!("[materials.m{n}]\ntype = \"diffuse\"\n")])
            .collect()
    };
    assert!(try_scene(&chain(16)).is_ok());
    let e = err(&chain(17));
    assert!(e.contains("more than 16 deep"), "{e}");
    let e = err("[materials.a]\ntype = \"roughplastic\"\nalpha_u = 0.1\n");
    assert!(
        e.starts_with("test.toml:3:") && e.contains("does not apply"),
        "{e}"
    );
}

/// Media: a name no medium has is refused at the value that names it (an
/// object's side, the camera's medium), listing the media there are; an
/// unknown medium or phase function type at its `type` (a blend's held
/// one too); a table where a coefficient goes (a volume) at the value; a
/// tabulated phase function's bad table at its values.
#[test]
fn media_errors_point_at_the_value() {
    let media = "[media.fog]\ntype = \"homogeneous\"\n";
    let e = err(&format!(
        "{media}\n[[objects]]\ntype = \"sphere\"\nradius = 1\ninterior = \"smoke\"\n"
    ));
    assert!(e.starts_with("test.toml:7:12:"), "{e}");
    assert!(
        e.contains("objects[0].interior")
            && e.contains("no medium named `smoke`; defined media: fog"),
        "{e}"
    );
    let e = err(&format!("[camera]\nmedium = \"mist\"\n\n{media}"));
    assert!(
        e.starts_with("test.toml:2:10:") && e.contains("no medium named `mist`"),
        "{e}"
    );
    let e = err("[media.fog]\ntype = \"inhomogeneous\"\n");
    assert!(
        e.starts_with("test.toml:2:8:") && e.contains("homogeneous, heterogeneous"),
        "{e}"
    );
    let e = err(&format!("{media}phase = {{ type = \"sggx\" }}\n"));
    assert!(
        e.starts_with("test.toml:3:18:")
            && e.contains("isotropic, hg, rayleigh, tabphase, blendphase"),
        "{e}"
    );
    // Inside a blend: the held phase function's type, and a bad table's
    // values, at their own place.
    let blend = |inner: &str| {
        format!(
            "{media}phase = {{ type = \"blendphase\", phase_0 = {{ type = \"isotropic\" }}, \
             phase_1 = {inner} }}\n"
        )
    };
    let e = err(&blend("{ type = \"sggx\" }"));
    assert!(
        e.starts_with("test.toml:3:85:") && e.contains("unknown phase `sggx`"),
        "{e}"
    );
    let e = err(&blend("{ type = \"tabphase\", values = \"1, -1\" }"));
    assert!(
        e.contains("media.fog.phase.phase_1.values") && e.contains("value 2 is -1"),
        "{e}"
    );
    let e = err(&format!(
        "{media}phase = {{ type = \"blendphase\", phase_0 = {{ type = \"hg\" }} }}\n"
    ));
    assert!(e.contains("missing field `phase_1`"), "{e}");
    let e = err(&format!("{media}albedo = {{ type = \"gridvolume\" }}\n"));
    assert!(
        e.starts_with("test.toml:3:10:") && e.contains("media.fog.albedo"),
        "{e}"
    );
    let e = err("[media.fog]\nsigma_t = 1\n");
    assert!(e.starts_with("test.toml:1:1:") && e.contains("type"), "{e}");
}

/// A textured area light's radiance is looked up at surface coordinates:
/// the thesis model, which collapses the light to a point, and a mesh
/// attribute are refused, naming where the radiance is written.
#[test]
fn a_textured_light_refuses_the_thesis_model_and_mesh_attributes() {
    let rect = "[[lights]]\ntype = \"rect\"\norigin = [0.0, 1.0, 0.0]\nedge_u = [1.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 1.0]\n";
    let board = "radiance = { type = \"checkerboard\", color0 = [1, 1, 1], color1 = [2, 2, 2] }\n";
    let e = err(&format!("{rect}{board}model = \"thesis\"\n"));
    assert!(
        e.starts_with("test.toml:6:") && e.contains("takes a constant radiance"),
        "{e}"
    );
    let e = err(&format!(
        "{rect}radiance = {{ type = \"mesh_attribute\", name = \"vertex_color\" }}\n"
    ));
    assert!(
        e.starts_with("test.toml:6:") && e.contains("not a mesh attribute"),
        "{e}"
    );
    // Taken otherwise.
    if let Err(e) = try_scene(&format!("{rect}{board}")) {
        panic!("a textured rect light is refused: {e}");
    }
}
