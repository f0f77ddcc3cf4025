use super::*;

/// Mitsuba's syntax: pairs separated by commas or spaces, each type's
/// channels in order under Mitsuba's suffixes.
#[test]
fn aovs_read_as_mitsuba_reads_them() {
    let spec = AovSpec::parse("dd.y:depth,nn:sh_normal  uv:uv,, a:albedo,i:prim_index").unwrap();
    let kinds: Vec<AovType> = spec.items.iter().map(|(_, t)| *t).collect();
    assert_eq!(
        kinds,
        [
            AovType::Depth,
            AovType::ShNormal,
            AovType::Uv,
            AovType::Albedo,
            AovType::PrimIndex
        ]
    );
    assert_eq!(
        spec.channel_names().join(" "),
        "dd.y.T nn.X nn.Y nn.Z uv.U uv.V a.R a.G a.B i.I"
    );
    assert!(!spec.differentials());
    assert!(AovSpec::parse("d:duv_dy").unwrap().differentials());
    assert_eq!(AovSpec::parse("").unwrap(), AovSpec::default());
    for t in AovType::ALL {
        assert_eq!(AovType::from_name(t.name()), Some(t));
    }
    let e = AovSpec::parse("dd:depth,nn").unwrap_err();
    assert!(e.contains("`nn` is not a `name:type` pair"), "{e}");
    let e = AovSpec::parse("a:b:c").unwrap_err();
    assert!(e.contains("`a:b:c`"), "{e}");
    let e = AovSpec::parse(":depth").unwrap_err();
    assert!(e.contains("`:depth`"), "{e}");
    let e = AovSpec::parse("n:normal").unwrap_err();
    assert!(
        e.contains("unknown AOV type `normal`") && e.contains("geo_normal"),
        "{e}"
    );
}

/// The channels of `aov` holding an integrator: its image and alpha first.
#[test]
fn a_held_integrators_channels_come_first() {
    let spec = AovSpec::parse("dd:depth").unwrap();
    assert_eq!(
        channel_names(Some("img"), &spec).join(" "),
        "img.R img.G img.B img.A dd.T"
    );
    assert_eq!(channel_names(None, &spec).join(" "), "dd.T");
    assert_eq!(
        moment::channel_names("_arg_0").join(" "),
        "_arg_0.X _arg_0.Y _arg_0.Z m2__arg_0.X m2__arg_0.Y m2__arg_0.Z"
    );
}

/// On a plane `p = (u, v, 0)` seen along −z, rays one unit apart in x
/// and y meet it one unit apart: `duv/dx = (1, 0)`, `duv/dy = (0, 1)`;
/// with `dp/du` twice as long, half as much `u`.
#[test]
fn uv_partials_solve_for_the_neighbouring_rays() {
    let si = Hit {
        t: 2.0,
        p: Vec3::new(0.5, 0.25, 0.0),
        time: 0.0,
        ng: Vec3::Z,
        n: Vec3::Z,
        uv: Vec2::new(0.5, 0.25),
        dpdu: Vec3::X,
        dpdv: Vec3::Y,
        prim: 0,
        bary: Vec2::ZERO,
        object: 0,
        material: 0,
        emitter: None,
    };
    let ray = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 2.0), Vec3::new(0.0, 0.0, -1.0), 0.0);
    let (dx, dy) = uv_partials(&si, &ray(1.5, 0.25), &ray(0.5, 1.25));
    assert!((dx - Vec2::new(1.0, 0.0)).length() < 1e-6, "{dx:?}");
    assert!((dy - Vec2::new(0.0, 1.0)).length() < 1e-6, "{dy:?}");
    let long = Hit {
        dpdu: Vec3::X * 2.0,
        ..si
    };
    let (dx, _) = uv_partials(&long, &ray(1.5, 0.25), &ray(0.5, 1.25));
    assert!((dx - Vec2::new(0.5, 0.0)).length() < 1e-6, "{dx:?}");
    let flat = Hit {
        dpdv: Vec3::X,
        ..si
    };
    assert_eq!(
        uv_partials(&flat, &ray(1.5, 0.25), &ray(0.5, 1.25)),
        (Vec2::ZERO, Vec2::ZERO)
    );
}
