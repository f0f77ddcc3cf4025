//! Object types of the scene format beyond spheres, quads and meshes
//! (`rectangle`, `disk`, `cube`, `cylinder`), `flip_normals`, and
//! instancing (`[groups.NAME]` and `type = "instance"`): what they hit
//! and what they refuse.

mod common;

use common::{scene, try_scene};
use penumbra::math::{Ray, Vec3};

fn err(toml: &str) -> String {
    match try_scene(toml) {
        Ok(_) => panic!("scene should be rejected:\n{toml}"),
        Err(e) => e.to_string(),
    }
}

fn hit(s: &penumbra::scene::Scene, o: Vec3, d: Vec3) -> Option<penumbra::accel::Hit> {
    s.world.intersect(&Ray::new(o, d, 0.0), 0.0, f32::INFINITY)
}

/// A ray down the z axis meets each shape where its definition says, with
/// its normal; `flip_normals` turns it.
#[test]
fn new_object_types_are_hit_where_they_are() {
    for (object, t, n) in [
        ("type = \"rectangle\"", 5.0, Vec3::Z),
        ("type = \"disk\"\nradius = 0.5", 5.0, Vec3::Z),
        ("type = \"cube\"", 4.0, Vec3::Z),
        // The cylinder around the x axis: met at its top, z = 1.
        (
            "type = \"cylinder\"\np0 = [-1, 0, 0]\np1 = [1, 0, 0]",
            4.0,
            Vec3::Z,
        ),
        (
            "type = \"cube\"\ntransform = { scale = [1, 1, 2], translate = [0, 0, -1] }",
            4.0,
            Vec3::Z,
        ),
    ] {
        for flip in [false, true] {
            let s = scene(&format!("[[objects]]\n{object}\nflip_normals = {flip}\n"));
            let h = hit(&s, Vec3::new(0.05, 0.02, 5.0), -Vec3::Z).expect(object);
            assert!((h.t - t).abs() < 1e-3, "{object}: t = {}", h.t);
            let n = if flip { -n } else { n };
            assert!((h.ng - n).length() < 0.03, "{object}: {:?}", h.ng);
        }
    }
}

/// Mitsuba's uv on the cube's top face and on the cylinder.
#[test]
fn surface_coordinates_are_mitsubas() {
    let s = scene("[[objects]]\ntype = \"cube\"\n");
    let h = hit(&s, Vec3::new(0.5, -0.5, 5.0), -Vec3::Z).unwrap();
    // Face +z: corners 5 (1,−1,1) uv (0,1), 7 (1,1,1) (1,1), 6 (−1,1,1) (1,0), 4 (−1,−1,1) (0,0).
    assert!(
        (h.uv - penumbra::math::Vec2::new(0.25, 0.75)).length() < 1e-5,
        "{:?}",
        h.uv
    );
    let s = scene("[[objects]]\ntype = \"cylinder\"\nradius = 2\np1 = [0, 0, 4]\n");
    let h = hit(&s, Vec3::new(0.0, 5.0, 1.0), -Vec3::Y).unwrap();
    assert!(
        (h.uv - penumbra::math::Vec2::new(0.25, 0.25)).length() < 1e-5,
        "{:?}",
        h.uv
    );
    assert!((h.ng - Vec3::Y).length() < 1e-5);
}

/// Instances of a group of a mesh and a sphere hit where the group's
/// shapes, placed by hand, are hit; with their own materials.
#[test]
fn instances_place_their_group() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let text = "[materials.red]\nalbedo = [0.8, 0.1, 0.1]\n\
        [materials.blue]\nalbedo = [0.1, 0.1, 0.8]\n\
        [[groups.g.objects]]\ntype = \"mesh\"\npath = \"tri.obj\"\nmaterial = \"red\"\n\
        [[groups.g.objects]]\ntype = \"sphere\"\nradius = 0.25\ncenter = [0, 0, 2]\nmaterial = \"blue\"\n\
        [[objects]]\ntype = \"instance\"\ngroup = \"g\"\n\
        [[objects]]\ntype = \"instance\"\ngroup = \"g\"\n\
        transform = { scale = [2, 1, 1], translate = [10, 0, 0] }\n";
    let src = penumbra::scene::SceneSource::from_toml(
        text,
        std::path::Path::new("test.toml"),
        dir.path(),
        &penumbra::scene::LoadOptions::default(),
    )
    .unwrap();
    let s = src.build().unwrap();
    assert_eq!(s.world.objects.len(), 4);
    let down = -Vec3::Z;
    // Materials in name order after the default: blue, red.
    const BLUE: u32 = 1;
    const RED: u32 = 2;
    // The first instance's sphere, then its triangle beside it.
    let h = hit(&s, Vec3::new(0.0, 0.0, 5.0), down).unwrap();
    assert!((h.t - 2.75).abs() < 1e-5 && h.material == BLUE, "{h:?}");
    let h = hit(&s, Vec3::new(0.5, -0.5, 5.0), down).unwrap();
    assert!((h.t - 5.0).abs() < 1e-5 && h.material == RED, "{h:?}");
    // The second, stretched along x: its triangle reaches x = 10 ± 2.
    let h = hit(&s, Vec3::new(11.5, -0.9, 5.0), down).unwrap();
    assert!((h.t - 5.0).abs() < 1e-5 && h.material == RED, "{h:?}");
    assert!((h.p - Vec3::new(11.5, -0.9, 0.0)).length() < 1e-5);
    assert!(hit(&s, Vec3::new(2.5, -0.9, 5.0), down).is_none());
    // The stretched sphere (an ellipsoid) is met at its top, its normal up.
    let h = hit(&s, Vec3::new(10.0, 0.0, 5.0), down).unwrap();
    assert!(
        (h.t - 2.75).abs() < 1e-5 && (h.ng - Vec3::Z).length() < 1e-5,
        "{h:?}"
    );
}

/// Bad shapes and instances are refused at the key they are about.
#[test]
fn bad_shapes_and_instances_are_located() {
    let cases = [
        ("[[objects]]\ntype = \"cylinder\"\nradius = 0\n", "test.toml:3:10:"),
        (
            "[[objects]]\ntype = \"cylinder\"\np0 = [1, 2, 3]\np1 = [1, 2, 3]\n",
            "test.toml:4:6:",
        ),
        (
            "[[objects]]\ntype = \"cube\"\ntransform = { matrix = [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]] }\n",
            "test.toml:3:",
        ),
        (
            "[[objects]]\ntype = \"instance\"\ngroup = \"nope\"\n",
            "test.toml:3:9:",
        ),
        (
            "[[groups.g.objects]]\ntype = \"instance\"\ngroup = \"g\"\n",
            "test.toml:2:8:",
        ),
        (
            "[materials.hot]\nemission = [1, 1, 1]\n[[groups.g.objects]]\ntype = \"sphere\"\nmaterial = \"hot\"\n\
             [[objects]]\ntype = \"instance\"\ngroup = \"g\"\ntransform = { scale = [1, 2, 1] }\n",
            "test.toml:2:",
        ),
        (
            "[groups.g]\nshapes = 1\n",
            "test.toml:2:1:",
        ),
        (
            "[[objects]]\ntype = \"instance\"\ngroup = \"g\"\ntransform = { scale = [1, 0, 1] }\n[[groups.g.objects]]\ntype = \"sphere\"\n",
            "test.toml:4:",
        ),
        (
            "[[objects]]\ntype = \"cylinder\"\ntransform = { scale = [1, 2, 1] }\n",
            "test.toml:3:",
        ),
    ];
    for (text, at) in cases {
        let e = err(text);
        assert!(e.starts_with(at), "{text}\n→ {e}");
    }
    let e = err("[[objects]]\ntype = \"instance\"\ngroup = \"nope\"\n[[groups.a.objects]]\ntype = \"cube\"\n");
    assert!(
        e.contains("no group named `nope`; defined groups: a"),
        "{e}"
    );
    let e = err("[[objects]]\ntype = \"shapegroup\"\n");
    assert!(
        e.starts_with("test.toml:2:8:") && e.contains("`[groups.NAME]`"),
        "{e}"
    );
    let e = err("[[groups.g.objects]]\ntype = \"shapegroup\"\n");
    assert!(e.contains("groups do not nest"), "{e}");
}
