//! The `penumbra` binary as a user meets it: exit codes, messages, outputs.

use std::path::Path;
use std::process::{Command, Output};

fn penumbra(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(args)
        .current_dir(dir)
        .env_remove("PENUMBRA_BUNNY")
        .output()
        .expect("run penumbra")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const SMALL: &[&str] = &["--width", "32", "--height", "24", "--quiet"];

#[test]
fn renders_the_default_scene_with_stats() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec!["render", "-o", "out.png", "--stats", "stats.json"];
    args.extend_from_slice(SMALL);
    let o = penumbra(&args, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(dir.path().join("out.png")).unwrap();
    assert_eq!((img.width(), img.height()), (32, 24));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("stats.json")).unwrap()).unwrap();
    for key in ["primary", "shadow", "reflection", "refraction", "total"] {
        assert!(stats["rays"][key].is_u64(), "rays.{key} missing: {stats}");
    }
    let rays = &stats["rays"];
    let sum: u64 = ["primary", "shadow", "reflection", "refraction"]
        .iter()
        .map(|k| rays[k].as_u64().unwrap())
        .sum();
    assert_eq!(sum, rays["total"].as_u64().unwrap());
    assert_eq!(
        rays["primary"].as_u64().unwrap(),
        32 * 24 * stats["spp"].as_u64().unwrap()
    );
    assert!(stats["time"]["build_s"].is_f64() && stats["time"]["render_s"].is_f64());
    assert!(stats["mrays_per_s"].as_f64().unwrap() > 0.0);
    assert_eq!(
        (stats["width"].as_u64(), stats["height"].as_u64()),
        (Some(32), Some(24))
    );
    assert!(stats["threads"].as_u64().unwrap() >= 1);
}

#[test]
fn exr_output_and_thread_counts_agree_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    for (t, name) in [("1", "a.exr"), ("2", "b.exr")] {
        let mut args = vec!["render", "-o", name, "--threads", t];
        args.extend_from_slice(SMALL);
        let o = penumbra(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let a = std::fs::read(dir.path().join("a.exr")).unwrap();
    let b = std::fs::read(dir.path().join("b.exr")).unwrap();
    assert!(a == b, "1 and 2 threads wrote different files");
}

#[test]
fn every_kernel_set_writes_the_same_file_and_names_itself() {
    let dir = tempfile::tempdir().unwrap();
    let version = penumbra(&["--version"], dir.path());
    let version = String::from_utf8_lossy(&version.stdout).into_owned();
    // "penumbra 0.1.0 (kernels: avx2; supported: avx2, portable)"
    let supported = version
        .split("supported: ")
        .nth(1)
        .unwrap_or_else(|| panic!("no kernel sets in {version}"))
        .trim()
        .trim_end_matches(')');
    let sets: Vec<&str> = supported.split(", ").collect();
    println!("kernel sets run: {}", sets.join(", "));
    assert!(sets.contains(&"portable"), "{version}");
    assert!(
        version.contains(&format!("kernels: {}", sets[0])),
        "{version}"
    );
    let mut files = Vec::new();
    for set in &sets {
        let out = format!("{set}.exr");
        let stats = format!("{set}.json");
        let mut args = vec![
            "--simd",
            set,
            "render",
            "cornell-box",
            "-o",
            &out,
            "--stats",
            &stats,
        ];
        args.extend_from_slice(SMALL);
        let o = penumbra(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let doc: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.path().join(&stats)).unwrap()).unwrap();
        assert_eq!(doc["kernels"], *set);
        files.push(std::fs::read(dir.path().join(&out)).unwrap());
    }
    assert!(
        files.iter().all(|f| *f == files[0]),
        "kernel sets wrote different files"
    );
    // A set this processor lacks, or none of that name: status 2, named.
    let other = if cfg!(target_arch = "x86_64") {
        "neon"
    } else {
        "avx2"
    };
    for (name, says) in [(other, "not supported"), ("sse9", "unknown kernel set")] {
        let o = penumbra(&["--simd", name, "render", "-o", "x.png"], dir.path());
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains(says), "{}", stderr(&o));
        assert!(!dir.path().join("x.png").exists());
    }
    let o = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args(["scenes"])
        .env("PENUMBRA_SIMD", "sse9")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn a_bad_scene_exits_2_and_leaves_the_old_image_alone() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.toml"),
        "[render]\nwidth = 10\nspp = -3\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("out.png"), b"old image").unwrap();
    let o = penumbra(&["render", "bad.toml", "-o", "out.png"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("bad.toml:3:7:") && e.contains("spp"), "{e}");
    assert_eq!(
        std::fs::read(dir.path().join("out.png")).unwrap(),
        b"old image"
    );
}

/// An `aov` render's channels need an EXR: a PNG output is refused before
/// rendering, and the EXR holds every channel by name.
#[test]
fn aov_channels_are_written_to_exr_and_refused_for_png() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("aov.toml"),
        "[render]\nwidth = 8\nheight = 6\nintegrator = \"aov\"\naovs = \"dd:depth,nn:geo_normal\"\n\
         nested = { type = \"path\", name = \"img\" }\n\n\
         [[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
    )
    .unwrap();
    let o = penumbra(&["render", "aov.toml", "-o", "out.png", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("out.png") && e.contains("img.R, img.G") && e.contains(".exr"),
        "{e}"
    );
    assert!(!dir.path().join("out.png").exists());
    let o = penumbra(&["render", "aov.toml", "-o", "out.exr", "-q"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let exr = exr::prelude::read_all_flat_layers_from_file(dir.path().join("out.exr")).unwrap();
    let mut names: Vec<String> = exr.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    names.sort();
    assert_eq!(
        names.join(" "),
        "B G R dd.T img.A img.B img.G img.R nn.X nn.Y nn.Z"
    );
}

#[test]
fn malformed_meshes_exit_2_with_their_location() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("m.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[[objects]]\ntype = \"mesh\"\npath = \"m.ply\"\n",
    )
    .unwrap();
    let o = penumbra(&["render", "s.toml", "-o", "x.png"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("s.toml:3:8:") && e.contains("m.ply"), "{e}");
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn bad_arguments_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["render", "--width", "0"],
        vec!["render", "-o", "out.jpg"],
        vec!["render", "-o", "no/such/dir/out.png"],
        vec!["render", "no-such-scene"],
        vec!["render", "--distribution", "sobel"],
        vec!["render", "--bogus"],
        vec!["samples", "--distribution", "nope", "--count", "4"],
        vec![
            "reproduce",
            "--bunny",
            "missing.ply",
            "--out",
            "report",
            "--quiet",
        ],
        vec!["reproduce", "--study", "nope", "--out", "report", "--quiet"],
    ] {
        let o = penumbra(&args, dir.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).is_empty());
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing may be written"
    );
}

/// An unknown distribution's message lists every name a user may give,
/// `custom` too, on the command line as in a scene file.
#[test]
fn an_unknown_distribution_names_every_selectable_one() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[render]\ndistribution = \"sobel\"\n",
    )
    .unwrap();
    for args in [
        vec!["render", "--distribution", "sobel", "-o", "x.png"],
        vec!["render", "s.toml", "-o", "x.png"],
    ] {
        let o = penumbra(&args, dir.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = stderr(&o);
        for name in ["grid", "pmj02bn", "r2", "custom"] {
            assert!(e.contains(name), "{args:?}: {e}");
        }
    }
}

#[test]
fn an_unknown_study_names_the_valid_ones() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(&["reproduce", "--study", "distribution"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("'distribution'") && e.contains("distributions"),
        "{e}"
    );
}

/// The distribution study runs on its own, without the bunny (the test
/// removes $PENUMBRA_BUNNY), and writes only its own files.
#[test]
fn the_distribution_study_runs_without_the_bunny() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(
        &[
            "reproduce",
            "--study",
            "distributions",
            "--quick",
            "--out",
            "out",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.path().join("out");
    for f in [
        "distributions.md",
        "distributions.html",
        "distributions.json",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    assert!(out.join("plots/distributions-disk.svg").is_file());
    assert!(out.join("plots/render-penumbra-rays.svg").is_file());
    assert!(out.join("plots/render-anti-aliasing-time.svg").is_file());
    assert!(out.join("plots/stopping-everything.svg").is_file());
    assert!(!out.join("report.md").exists() && !out.join("figures").exists());
    assert!(String::from_utf8_lossy(&o.stdout).contains("distributions.md"));
}

#[test]
fn unknown_scene_names_the_built_ins() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(&["render", "nope"], dir.path());
    assert!(stderr(&o).contains("showcase") && stderr(&o).contains("bunny"));
}

#[test]
fn bunny_scene_without_the_mesh_explains_how_to_supply_it() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(&["render", "bunny"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--bunny"), "{}", stderr(&o));
}

#[test]
fn scenes_lists_every_built_in() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(&["scenes"], dir.path());
    let out = String::from_utf8_lossy(&o.stdout);
    for name in [
        "showcase",
        "bunny",
        "bunny-reflect",
        "bunny-mirror",
        "bunny-glass",
        "bunnies-dof",
        "bunny-gi",
        "bunny-motion",
        "cornell-box",
        "materials",
        "fog",
    ] {
        assert!(out.contains(name), "{name} missing from:\n{out}");
    }
}

#[test]
fn every_subcommand_has_help() {
    let dir = tempfile::tempdir().unwrap();
    for sub in ["render", "convert", "scenes", "samples"] {
        let o = penumbra(&[sub, "--help"], dir.path());
        assert!(o.status.success());
        assert!(String::from_utf8_lossy(&o.stdout).contains("Usage"));
    }
}

/// The low-discrepancy sets print like the others, reproducibly; the 16
/// points of a `sobol`, `zsobol`, `pmj02` or `pmj02bn` set fill the 4 x 4
/// cells one each; an unknown name lists them.
#[test]
fn samples_prints_the_low_discrepancy_sets() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["sobol", "zsobol", "pmj02", "pmj02bn", "halton", "r2"] {
        let o = penumbra(
            &["samples", "-d", name, "-c", "16", "-r", "2", "-s", "5"],
            dir.path(),
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(doc["distribution"], name);
        let pts: Vec<(f64, f64)> = doc["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect();
        assert_eq!(pts.len(), 16);
        assert!(pts.iter().all(|&(x, y)| x.abs() <= 2.0 && y.abs() <= 2.0));
        if ["sobol", "zsobol", "pmj02", "pmj02bn"].contains(&name) {
            let cell = |t: f64| ((t + 2.0) / 4.0 * 4.0).floor() as usize;
            let mut cells: Vec<usize> = pts.iter().map(|&(x, y)| cell(y) * 4 + cell(x)).collect();
            cells.sort_unstable();
            assert_eq!(cells, (0..16).collect::<Vec<_>>(), "{name}");
        }
        let again = penumbra(
            &["samples", "-d", name, "-c", "16", "-r", "2", "-s", "5"],
            dir.path(),
        );
        assert_eq!(o.stdout, again.stdout, "{name} is not reproducible");
    }
    let o = penumbra(&["samples", "-d", "sobel", "-c", "4"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    for name in [
        "sobol", "zsobol", "pmj02", "pmj02bn", "halton", "r2", "grid",
    ] {
        assert!(stderr(&o).contains(name), "{}", stderr(&o));
    }
}

#[test]
fn samples_prints_json_in_trace_order() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(
        &[
            "samples",
            "--distribution",
            "grid",
            "--count",
            "9",
            "--radius",
            "2",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["distribution"], "grid");
    assert_eq!(doc["count"], 9);
    assert_eq!(doc["radius"], 2.0);
    let pts = doc["points"].as_array().unwrap();
    assert_eq!(pts.len(), 9);
    assert!(pts.iter().all(|p| p.as_array().unwrap().len() == 2));
    let o = penumbra(&["samples", "-d", "fast-random", "-c", "5"], dir.path());
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(doc["points"]
        .as_array()
        .unwrap()
        .iter()
        .all(|p| p.as_array().unwrap().len() == 3));
    let o = penumbra(
        &[
            "samples", "-d", "all", "-c", "16", "-f", "svg", "-o", "all.svg",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(dir.path().join("all.svg")).unwrap();
    let panels = penumbra::sampling::Distribution::ALL.len();
    assert_eq!(svg.matches("<circle").count(), 16 * panels);
    for d in penumbra::sampling::Distribution::ALL {
        assert!(
            svg.contains(&format!(">\n{}\n</text>", d.name())),
            "{}",
            d.name()
        );
    }
    // One distribution, by default into samples.svg; a PNG is not offered.
    let o = penumbra(
        &["samples", "-d", "halton", "-c", "9", "-f", "svg"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(dir.path().join("samples.svg")).unwrap();
    assert_eq!(svg.matches("<circle").count(), 9);
    let o = penumbra(
        &["samples", "-d", "all", "-c", "4", "-f", "png"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = penumbra(&["samples", "-d", "all", "-c", "4"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--format svg"), "{}", stderr(&o));
}

/// `custom` renders from a points file given by flag or scene key, and
/// every bad points file exits 2 naming the file, leaving no image.
#[test]
fn custom_points_render_and_bad_ones_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| std::fs::write(dir.path().join(name), text).unwrap();
    write(
        "p.json",
        "[[[0.25, 0.25], [0.75, 0.75]], [[0.25, 0.75], [0.75, 0.25]]]",
    );
    let custom = ["--distribution", "custom", "--shadow-rays", "2"];
    let args = |points: &str, out: &'static str| {
        let mut a = vec!["render", "showcase", "-o", out, "--points", points];
        a.extend(custom);
        a.extend(SMALL);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run = |a: Vec<String>| {
        penumbra(
            &a.iter().map(String::as_str).collect::<Vec<_>>(),
            dir.path(),
        )
    };
    let o = run(args("p.json", "ok.png"));
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    write(
        "s.toml",
        "[render]\ndistribution = \"custom\"\npoints = \"p.json\"\nwidth = 8\nheight = 8\n",
    );
    let o = penumbra(&["render", "s.toml", "-o", "s.png", "--quiet"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    write("nan.json", "[[0.5, NaN]]");
    write("out.json", "[[0.5, 1.0]]");
    write("shape.json", "[[0.5, 0.5, 0.5]]");
    write("empty.json", "[]");
    write("syntax.json", "[[0.5,\n 0.5]");
    for (file, says) in [
        ("nan.json", "nan.json:1:"),
        ("out.json", "set 0, point 0"),
        ("shape.json", "expected [x, y]"),
        ("empty.json", "no point sets"),
        ("syntax.json", "syntax.json:2:"),
        ("none.json", "none.json"),
        (".", "not a regular file"),
    ] {
        let o = run(args(file, "bad.png"));
        assert_eq!(o.status.code(), Some(2), "{file}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("render.points") && e.contains(says),
            "{file}: {e}"
        );
        assert!(!dir.path().join("bad.png").exists(), "{file}");
    }
    let o = penumbra(&["samples", "-d", "custom", "-c", "4"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--points"), "{}", stderr(&o));
}

/// A Mitsuba XML scene: `-D` sets its parameters (a film of width 0 is
/// refused at its tag, leaving no image), its `path` integrator renders,
/// and `--integrator whitted` replaces it with a warning.
#[test]
fn renders_a_mitsuba_scene_with_defines() {
    let dir = tempfile::tempdir().unwrap();
    let scene = r#"<scene version="3.0.0">
    <default name="res" value="16"/>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/></film>
    </sensor>
    <shape type="sphere"><point name="center" value="0, 0, 4"/></shape>
    <emitter type="point"><point name="position" value="0, 2, 0"/><rgb name="intensity" value="5"/></emitter>
</scene>
"#;
    std::fs::write(dir.path().join("scene.xml"), scene).unwrap();
    let render = |defines: &[&str]| {
        let mut args = vec!["render", "scene.xml", "-o", "out.png", "--quiet"];
        args.extend_from_slice(defines);
        penumbra(&args, dir.path())
    };
    let o = render(&["-D", "res=0", "--define", "unused=1"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("scene.xml:5:") && e.contains("width"), "{e}");
    assert!(!dir.path().join("out.png").exists());

    let o = render(&["-D", "res=24"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(dir.path().join("out.png")).unwrap();
    assert_eq!((img.width(), img.height()), (24, 24));
    std::fs::remove_file(dir.path().join("out.png")).unwrap();

    let o = penumbra(
        &[
            "render",
            "scene.xml",
            "-o",
            "out.png",
            "--quiet",
            "-D",
            "res=24",
            "--integrator",
            "whitted",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: --integrator whitted replaces the scene's integrator `path`")
    );
    let img = image::open(dir.path().join("out.png")).unwrap();
    assert_eq!((img.width(), img.height()), (24, 24));

    let o = penumbra(&["render", "scene.xml", "-D", "no-equals"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("NAME=VALUE"), "{}", stderr(&o));
}

/// Mitsuba's command-line flags: `--sensor N` renders sensor N (its film's
/// size shows which), one past the last is refused with exit 2 and no
/// image; `-a` adds search folders, several separated by `;`, for `render`
/// and `convert` alike.
#[test]
fn chooses_a_sensor_and_searches_folders_as_mitsuba() {
    let dir = tempfile::tempdir().unwrap();
    let sensor = |w: u32| {
        format!(
            r#"<sensor type="perspective"><float name="fov" value="45"/>
        <film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="8"/></film></sensor>"#
        )
    };
    let scene = format!(
        r#"<scene version="3.0.0">
    {}
    {}
    <shape type="obj"><string name="filename" value="tri.obj"/></shape>
    <emitter type="point"><point name="position" value="0, 2, 0"/><rgb name="intensity" value="5"/></emitter>
</scene>
"#,
        sensor(8),
        sensor(12)
    );
    std::fs::write(dir.path().join("scene.xml"), scene).unwrap();
    std::fs::create_dir(dir.path().join("meshes")).unwrap();
    let tri = "v -1 -1 4\nv 1 -1 4\nv 0 1 4\nf 1 2 3\n";
    std::fs::write(dir.path().join("meshes/tri.obj"), tri).unwrap();
    let render = |extra: &[&str]| {
        let mut args = vec!["render", "scene.xml", "-o", "out.png", "--quiet"];
        args.extend_from_slice(extra);
        penumbra(&args, dir.path())
    };
    // The mesh is found only along the search folders.
    let o = render(&[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("tri.obj"), "{}", stderr(&o));
    for (extra, width) in [
        (&["-a", "none;meshes"][..], 8),
        (&["-a", "meshes", "--sensor", "1"][..], 12),
    ] {
        let o = render(extra);
        assert!(o.status.success(), "{}", stderr(&o));
        let img = image::open(dir.path().join("out.png")).unwrap();
        assert_eq!(img.width(), width);
        std::fs::remove_file(dir.path().join("out.png")).unwrap();
    }
    let o = render(&["-a", "meshes", "--sensor", "2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("sensor 2 was asked for; the scene has 2"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("out.png").exists());
    let o = penumbra(
        &[
            "convert",
            "scene.xml",
            "-o",
            "out.toml",
            "-a",
            "meshes",
            "--sensor",
            "1",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let toml = std::fs::read_to_string(dir.path().join("out.toml")).unwrap();
    assert!(
        toml.contains("width = 12") && toml.contains("tri.obj"),
        "{toml}"
    );
}

/// `penumbra convert`: the TOML file renders the XML file's pixels; it is
/// never written over the input, and a bad scene leaves an existing output
/// as it was (exit 2).
#[test]
fn converts_a_mitsuba_scene_to_toml() {
    let dir = tempfile::tempdir().unwrap();
    let scene = r#"<scene version="3.0.0">
    <default name="r" value="1"/>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film>
    </sensor>
    <shape type="sphere"><point name="center" value="0, 0, 4"/><float name="radius" value="$r"/></shape>
    <emitter type="point"><point name="position" value="0, 2, 0"/><rgb name="intensity" value="5"/></emitter>
</scene>
"#;
    std::fs::write(dir.path().join("scene.xml"), scene).unwrap();
    let o = penumbra(
        &["convert", "scene.xml", "-o", "scene.toml", "-D", "r=0.5"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let toml = std::fs::read_to_string(dir.path().join("scene.toml")).unwrap();
    assert!(toml.contains("radius = 0.5"), "{toml}");
    // An ordinary file: the mode any new file gets, not a temporary's 0600.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = |name: &str| {
            std::fs::metadata(dir.path().join(name))
                .unwrap()
                .permissions()
                .mode()
                & 0o777
        };
        std::fs::write(dir.path().join("plain"), b"").unwrap();
        assert_eq!(mode("scene.toml"), mode("plain"));
        std::fs::remove_file(dir.path().join("plain")).unwrap();
    }
    for (input, image) in [("scene.xml", "xml.png"), ("scene.toml", "toml.png")] {
        let mut args = vec!["render", input, "-o", image, "--quiet"];
        if input.ends_with("xml") {
            args.extend(["-D", "r=0.5"]);
        }
        let o = penumbra(&args, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let a = std::fs::read(dir.path().join("xml.png")).unwrap();
    let b = std::fs::read(dir.path().join("toml.png")).unwrap();
    assert!(a == b, "the TOML scene renders other pixels");

    // Never over the input, whatever the path says.
    let o = penumbra(&["convert", "scene.xml", "-o", "./scene.xml"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("the output is the input"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("scene.xml")).unwrap(),
        scene
    );

    // A bad scene: exit 2 at its place, the old output untouched, no stray file.
    std::fs::write(
        dir.path().join("bad.xml"),
        "<scene version=\"3.0.0\"><shape type=\"torus\"/></scene>",
    )
    .unwrap();
    let o = penumbra(&["convert", "bad.xml", "-o", "scene.toml"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bad.xml:1:"), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("scene.toml")).unwrap(),
        toml
    );
    let o = penumbra(&["convert", "scene.toml", "-o", "again.toml"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["bad.xml", "scene.toml", "scene.xml", "toml.png", "xml.png"]
    );
}

/// `penumbra convert` into another folder makes a volume's file name
/// absolute, as it does a mesh's, though the `gridvolume` is nested in a
/// medium: the TOML written elsewhere renders the XML file's pixels.
#[test]
fn a_scene_converted_into_another_folder_finds_its_volume() {
    let dir = tempfile::tempdir().unwrap();
    for sub in ["scenes", "out"] {
        std::fs::create_dir(dir.path().join(sub)).unwrap();
    }
    // A 2 × 2 × 2 grid of one channel (Mitsuba's `.vol`, version 3).
    let mut vol = b"VOL\x03".to_vec();
    for v in [1i32, 2, 2, 2, 1] {
        vol.extend(v.to_le_bytes());
    }
    for v in [
        0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0,
    ] {
        vol.extend(v.to_le_bytes());
    }
    std::fs::write(dir.path().join("scenes/smoke.vol"), vol).unwrap();
    let scene = r#"<scene version="3.0.0">
    <integrator type="volpath"/>
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
    <emitter type="constant"/>
    <medium type="heterogeneous" id="smoke">
        <volume name="sigma_t" type="gridvolume">
            <string name="filename" value="smoke.vol"/>
            <transform name="to_world"><scale value="2"/><translate value="-1, -1, -1"/></transform>
        </volume>
        <float name="albedo" value="0.5"/>
    </medium>
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="smoke"/></shape>
</scene>
"#;
    std::fs::write(dir.path().join("scenes/smoke.xml"), scene).unwrap();
    let o = penumbra(
        &["convert", "scenes/smoke.xml", "-o", "out/smoke.toml"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let toml = std::fs::read_to_string(dir.path().join("out/smoke.toml")).unwrap();
    assert!(!toml.contains("filename = \"smoke.vol\""), "{toml}");
    for (input, image) in [
        ("scenes/smoke.xml", "xml.png"),
        ("out/smoke.toml", "toml.png"),
    ] {
        let o = penumbra(&["render", input, "-o", image, "--quiet"], dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let a = std::fs::read(dir.path().join("xml.png")).unwrap();
    let b = std::fs::read(dir.path().join("toml.png")).unwrap();
    assert!(a == b, "the TOML scene renders other pixels");
}

/// A Mitsuba scene in a folder below the working one finds its bitmap
/// beside it, as it finds its meshes, named by a relative path or from
/// inside its folder; the two renders are the same pixels.
#[test]
fn a_mitsuba_scene_in_a_folder_finds_its_textures() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("scenes");
    std::fs::create_dir(&sub).unwrap();
    image::RgbImage::from_pixel(4, 4, image::Rgb([200, 40, 40]))
        .save(sub.join("red.png"))
        .unwrap();
    let scene = r#"<scene version="3.0.0">
    <integrator type="path"/>
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
    </sensor>
    <emitter type="constant"/>
    <shape type="sphere">
        <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="red.png"/></texture></bsdf>
    </shape>
</scene>
"#;
    std::fs::write(sub.join("scene.xml"), scene).unwrap();
    let o = penumbra(
        &["render", "scenes/scene.xml", "-o", "a.exr", "--quiet"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = penumbra(&["render", "scene.xml", "-o", "b.exr", "--quiet"], &sub);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = image::open(dir.path().join("a.exr")).unwrap().into_rgb32f();
    let b = image::open(sub.join("b.exr")).unwrap().into_rgb32f();
    assert_eq!(a.as_raw(), b.as_raw());
    // The sphere's centre is red.
    let c = a.get_pixel(8, 8);
    assert!(c[0] > 2.0 * c[1], "{c:?}");
}

/// `explore` refuses at start what it could not open, before serving.
#[test]
fn explore_refuses_an_unknown_scene_before_serving() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(&["explore", "no-such-scene", "--port", "0"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("no-such-scene: no such file, and not a built-in scene"),
        "{err}"
    );
    assert!(!err.contains("http://"), "{err}");
}
