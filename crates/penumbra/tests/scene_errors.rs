//! Bad scenes give clear errors at file:line:column, never a panic.

mod common;

use common::try_scene;

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
    let e = err("[render]\ndistribution = \"sobol\"\n");
    assert!(e.starts_with("test.toml:2:16:"), "{e}");
    for name in [
        "grid",
        "jitter",
        "semi-jitter",
        "poisson",
        "random",
        "fast-random",
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
}

#[test]
fn closed_sets_list_valid_choices() {
    let e = err("[[objects]]\ntype = \"cube\"\n");
    assert!(e.contains("sphere, quad, mesh"), "{e}");
    let e = err("[[lights]]\ntype = \"spot\"\nposition = [0.0, 1.0, 0.0]\n");
    assert!(e.contains("point, rect, sphere, disk"), "{e}");
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
