//! Reading textures from a scene: the three ways of writing one, `to_uv`,
//! named textures and their errors.

use std::path::Path;

use super::checkerboard::Checkerboard;
use super::*;
use crate::description::{from_toml, SceneError};

/// The scene's textures and its first material's node.
fn scene(text: &str) -> Result<(Textures, Node), SceneError> {
    let root = from_toml(text, Path::new("t.toml"))?;
    crate::scene::schemas::check(&root)?;
    let textures = Textures::of_scene(&root, Path::new("."))?;
    let node = root.child(Kind::Bsdf).cloned().expect("a material");
    Ok((textures, node))
}

fn colour(text: &str) -> Result<Texture, SceneError> {
    let (t, node) = scene(text)?;
    Ok(t.colour(&Props::new(&node), "reflectance", Rgb::splat(0.5))?)
}

fn err(text: &str) -> String {
    colour(text).unwrap_err().to_string()
}

#[test]
fn a_parameter_is_a_colour_a_table_or_a_name() {
    let m = "[materials.m]\ntype = \"diffuse\"\n";
    assert_eq!(
        colour(&format!("{m}reflectance = [0.1, 0.2, 0.3]")).unwrap(),
        Texture::Constant(Rgb::new(0.1, 0.2, 0.3))
    );
    assert_eq!(colour(m).unwrap(), Texture::Constant(Rgb::splat(0.5)));
    let inline = colour(&format!(
        "{m}reflectance = {{ type = \"checkerboard\", color0 = [1, 1, 1] }}"
    ))
    .unwrap();
    let want = Texture::Checkerboard(Checkerboard {
        color0: Box::new(Texture::Constant(Rgb::ONE)),
        color1: Box::new(Texture::Constant(Rgb::splat(0.2))),
        to_uv: UvTransform::IDENTITY,
    });
    assert_eq!(inline, want);
    let named = colour(&format!(
        "[textures.board]\ntype = \"checkerboard\"\ncolor0 = [1, 1, 1]\n{m}reflectance = \"board\""
    ))
    .unwrap();
    assert_eq!(named, want);
}

#[test]
fn to_uv_is_scale_then_rotation_then_translation() {
    let m = "[materials.m]\ntype = \"diffuse\"\n";
    let board = |to_uv: &str| match colour(&format!(
        "{m}reflectance = {{ type = \"checkerboard\", to_uv = {to_uv} }}"
    ))
    .unwrap()
    {
        Texture::Checkerboard(c) => c.to_uv,
        t => panic!("{t:?}"),
    };
    let t = board("{ scale = [2, 3], rotate_degrees = 90, translate = [0.5, -1] }");
    // (1, 0) ↦ (2, 0) ↦ (0, 2) ↦ (0.5, 1); (0, 1) ↦ (0, 3) ↦ (−3, 0) ↦ (−2.5, −1).
    let close = |a: Vec2, b: Vec2| (a - b).length() < 1e-5;
    assert!(close(t.apply(Vec2::new(1.0, 0.0)), Vec2::new(0.5, 1.0)));
    assert!(close(t.apply(Vec2::new(0.0, 1.0)), Vec2::new(-2.5, -1.0)));
    assert_eq!(
        board("{ scale = 2 }").apply(Vec2::new(1.0, 1.0)),
        Vec2::new(2.0, 2.0)
    );
    let m3 = board("{ matrix = [[1, 2, 3], [4, 5, 6], [0, 0, 1]] }");
    assert_eq!(m3.apply(Vec2::new(1.0, 1.0)), Vec2::new(6.0, 15.0));
    assert_eq!(board("{}"), UvTransform::IDENTITY);
}

#[test]
fn bad_textures_are_refused_at_their_place() {
    let m = "[materials.m]\ntype = \"diffuse\"\n";
    for (keys, want) in [
        (
            "reflectance = { type = \"checkerboard\", to_uv = { matrix = [[1, 0, 0], [0, 1, 0], [1, 0, 1]] } }",
            "t.toml:3:59: materials.m.reflectance.to_uv.matrix: must be affine",
        ),
        (
            "reflectance = { type = \"checkerboard\", to_uv = { scale = [1, 2, 3] } }",
            "t.toml:3:58: materials.m.reflectance.to_uv.scale: expected 2 numbers, got 3",
        ),
        (
            "reflectance = { type = \"checkerboard\", to_uv = { scale = 2, matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]] } }",
            "materials.m.reflectance.to_uv.matrix: give either `matrix` or the other keys",
        ),
        (
            "reflectance = { type = \"checkerboard\", to_uv = { translate = [nan, 0] } }",
            "t.toml:3:48: materials.m.reflectance.to_uv: expected finite numbers",
        ),
        (
            "reflectance = true",
            "t.toml:3:15: materials.m.reflectance: invalid type: boolean `true`, expected 3 numbers, a texture table or a texture's name",
        ),
        (
            "reflectance = [1, 1]",
            "t.toml:3:15: materials.m.reflectance: expected 3 numbers, got 2",
        ),
    ] {
        let e = err(&format!("{m}{keys}"));
        assert!(e.contains(want), "{keys}:\n{e}\n{want}");
    }
    // A named texture's errors are at its table; a name no texture has
    // lists the scene's.
    let e = err(&format!(
        "[textures.a]\ntype = \"checkerboard\"\ncolor1 = 3\n{m}reflectance = \"a\""
    ));
    assert!(
        e.starts_with("t.toml:3:10: textures.a.color1: invalid type: integer `3`, expected 3 numbers, a texture table or a texture's name"),
        "{e}"
    );
    let e = err("[textures.a]\ncolor1 = [1, 1, 1]\n");
    assert!(
        e.starts_with("t.toml:1:1: textures.a: missing field `type`"),
        "{e}"
    );
    let e = err(&format!(
        "[textures.b]\ntype = \"checkerboard\"\n[textures.a]\ntype = \"checkerboard\"\n{m}reflectance = \"c\""
    ));
    assert!(
        e.starts_with("t.toml:7:15: materials.m.reflectance: no texture named `c`; the scene's textures are: a, b"),
        "{e}"
    );
    let e = err("[textures.a]\ntype = \"bricks\"\n");
    assert!(
        e.starts_with("t.toml:2:8: textures.a.type: unknown texture `bricks`; valid choices are: checkerboard, bitmap, rawconstant"),
        "{e}"
    );
}

#[test]
fn one_value_of_a_colour_is_its_grey_or_its_luminance() {
    assert_eq!(one(Rgb::splat(0.3)), 0.3);
    let c = Rgb::new(1.0, 0.0, 0.0);
    assert!((one(c) - c.luminance()).abs() < 1e-7);
    assert_eq!(Texture::Constant(Rgb::splat(0.7)).bounds_1(), (0.7, 0.7));
}

/// The batch forms give, lane by lane, the bits of the scalar ones, for
/// the constant and every texture model.
#[test]
fn a_batch_gives_the_bits_of_each_lane() {
    use std::sync::Arc;

    use super::bitmap::{Bitmap, Filter, Wrap};
    use crate::input::image::Image;
    use crate::sampling::Rng;

    let image = Image {
        width: 3,
        height: 2,
        channels: 3,
        pixels: (0..18).map(|i| (i * 7 % 11) as f32 / 10.0).collect(),
    };
    let to_uv = UvTransform::IDENTITY;
    let textures = [
        Texture::Constant(Rgb::new(0.1, 0.4, 0.2)),
        Texture::Checkerboard(Checkerboard {
            color0: Box::new(Texture::Constant(Rgb::new(0.9, 0.1, 0.3))),
            color1: Box::new(Texture::Checkerboard(Checkerboard {
                color0: Box::new(Texture::Constant(Rgb::splat(0.2))),
                color1: Box::new(Texture::RawConstant(
                    super::rawconstant::RawConstant::number(-0.5),
                )),
                to_uv: UvTransform {
                    rows: [[3.0, 0.0, 0.0], [0.0, 3.0, 0.0]],
                },
            })),
            to_uv,
        }),
        Texture::RawConstant(super::rawconstant::RawConstant::rgb(Rgb::new(
            2.0, -1.0, 0.5,
        ))),
        Texture::Bitmap(Bitmap::new(
            Arc::new(image.clone()),
            Filter::Bilinear,
            Wrap::Mirror,
            to_uv,
        )),
        Texture::Bitmap(Bitmap::new(
            Arc::new(image),
            Filter::Nearest,
            Wrap::Repeat,
            to_uv,
        )),
    ];
    let mut rng = Rng::new(3);
    let uvs: Vec<Vec2> = (0..37)
        .map(|_| Vec2::new(rng.range(-2.0, 3.0), rng.range(-2.0, 3.0)))
        .collect();
    let (mut colours, mut values) = (vec![Rgb::ONE; 5], Vec::new());
    for t in &textures {
        t.eval_all(&uvs, &mut colours);
        t.eval_1_all(&uvs, &mut values);
        let bits = |c: Rgb| c.to_array().map(f32::to_bits);
        let want: Vec<_> = uvs.iter().map(|&uv| bits(t.eval_uv(uv))).collect();
        assert_eq!(
            colours.iter().map(|&c| bits(c)).collect::<Vec<_>>(),
            want,
            "{t:?}"
        );
        let want: Vec<_> = uvs.iter().map(|&uv| t.eval_1_uv(uv).to_bits()).collect();
        assert_eq!(
            values.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            want,
            "{t:?}"
        );
    }
    // Not vacuous: the lanes differ.
    assert!(colours.windows(2).any(|w| w[0] != w[1]));
}

/// `rawconstant` keeps its value as written, one number or 3, negative
/// and above 1 included; read as one value, one number is itself.
#[test]
fn a_raw_constant_is_its_value() {
    let m = "[materials.m]\ntype = \"diffuse\"\n";
    let one_number = colour(&format!(
        "{m}reflectance = {{ type = \"rawconstant\", value = -2.5 }}"
    ))
    .unwrap();
    assert_eq!(one_number.eval_uv(Vec2::new(0.3, 7.0)), Rgb::splat(-2.5));
    assert_eq!(one_number.eval_1_uv(Vec2::ZERO), -2.5);
    let three = colour(&format!(
        "{m}reflectance = {{ type = \"rawconstant\", value = [0.25, 3, -1] }}"
    ))
    .unwrap();
    assert_eq!(
        three.eval_uv(Vec2::new(0.3, 7.0)),
        Rgb::new(0.25, 3.0, -1.0)
    );
    assert_eq!(
        three.bounds(),
        (Rgb::new(0.25, 3.0, -1.0), Rgb::new(0.25, 3.0, -1.0))
    );
    for (keys, want) in [
        ("{ type = \"rawconstant\" }", "missing field `value`"),
        (
            "{ type = \"rawconstant\", value = [1, 2] }",
            "expected 3 numbers, got 2",
        ),
        (
            "{ type = \"rawconstant\", value = nan }",
            "expected finite numbers",
        ),
    ] {
        let e = err(&format!("{m}reflectance = {keys}"));
        assert!(e.contains(want), "{keys}:\n{e}");
    }
}

/// A checkerboard of two constant textures is, bit for bit, the
/// checkerboard of the two colours; a texture as a colour is looked up at
/// the surface's own (u, v), not the checkerboard's mapped ones.
#[test]
fn a_checkerboard_takes_textures_as_its_colours() {
    let m = "[materials.m]\ntype = \"diffuse\"\n";
    let plain = colour(&format!(
        "{m}reflectance = {{ type = \"checkerboard\", color0 = [0.1, 0.7, 0.3], color1 = [0.9, 0.2, 0.05] }}"
    ))
    .unwrap();
    let textured = colour(&format!(
        "[textures.a]\ntype = \"rawconstant\"\nvalue = [0.1, 0.7, 0.3]\n{m}reflectance = {{ type = \"checkerboard\", color0 = \"a\", color1 = {{ type = \"rawconstant\", value = [0.9, 0.2, 0.05] }} }}"
    ))
    .unwrap();
    let mut rng = crate::sampling::Rng::new(11);
    for _ in 0..200 {
        let uv = Vec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        let bits = |c: Rgb| c.to_array().map(f32::to_bits);
        assert_eq!(bits(plain.eval_uv(uv)), bits(textured.eval_uv(uv)));
        assert_eq!(
            plain.eval_1_uv(uv).to_bits(),
            textured.eval_1_uv(uv).to_bits()
        );
    }
    assert_eq!(plain.bounds(), textured.bounds());
    // An inner board of squares 1/4 (scaled twice) inside the outer board's
    // squares of 1/2 mapped by a scale of 1/2 (squares of 1): the inner one
    // reads the unmapped (u, v).
    let nested = colour(&format!(
        "{m}reflectance = {{ type = \"checkerboard\", to_uv = {{ scale = 0.5 }}, color0 = {{ type = \"checkerboard\", color0 = [1, 0, 0], color1 = [0, 1, 0], to_uv = {{ scale = 2 }} }}, color1 = [0, 0, 1] }}"
    ))
    .unwrap();
    // (0.1, 0.1): outer (0.05, 0.05), color0; inner (0.2, 0.2): red.
    assert_eq!(nested.eval_uv(Vec2::new(0.1, 0.1)), Rgb::new(1.0, 0.0, 0.0));
    // (0.35, 0.1): outer (0.175, 0.05), color0; inner (0.7, 0.2): green.
    assert_eq!(
        nested.eval_uv(Vec2::new(0.35, 0.1)),
        Rgb::new(0.0, 1.0, 0.0)
    );
    // (1.1, 0.1): outer (0.55, 0.05), color1: blue.
    assert_eq!(nested.eval_uv(Vec2::new(1.1, 0.1)), Rgb::new(0.0, 0.0, 1.0));
    assert_eq!(nested.bounds(), (Rgb::ZERO, Rgb::ONE));
    // A negative constant as a colour is refused where it is written.
    let e = err(&format!(
        "{m}reflectance = {{ type = \"checkerboard\", color0 = [0, -1, 0] }}"
    ));
    assert!(
        e.contains("reflectance.color0: must not be negative"),
        "{e}"
    );
}
