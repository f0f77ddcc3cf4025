//! The `aov`, `depth` and `moment` integrators: their channels against
//! analytic answers and an independent computation, and their bits on any
//! number of threads, passes and regions.

mod common;

use common::{scene, try_scene};
use penumbra::integrator::{Config, FilmTile, Integrator, PixelWorker, TileJob};
use penumbra::math::{Rgb, Vec3};
use penumbra::render::{render, Image, Region, RenderOptions};
use penumbra::scene::{LoadOptions, Scene, SceneSource};

fn run(s: &Scene, threads: usize, region: Option<Region>) -> Image {
    let opts = RenderOptions {
        threads: Some(threads),
        region,
    };
    render(s, &opts, &|_, _| {}, None).expect("render").0
}

/// The values of channel `name` of `img`, pixel by pixel.
fn channel(img: &Image, name: &str) -> Vec<f32> {
    let extra = img.extra.as_ref().expect("channels beside the image");
    let c = extra
        .index(name)
        .unwrap_or_else(|| panic!("no channel {name} among {:?}", extra.names));
    extra.channel(c).collect()
}

const W: u32 = 40;
const H: u32 = 30;
const FOV: f32 = 40.0;

/// A camera at the origin looking down −z, one camera ray per pixel
/// through its centre (one grid point), the box filter.
fn frame(integrator: &str) -> String {
    format!(
        "[render]\nwidth = {W}\nheight = {H}\nspp = 1\npixel_distribution = \"grid\"\n\
         filter = \"box\"\n{integrator}\n\n\
         [camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = {FOV}\n\n\
         [materials.white]\nalbedo = [0.5, 0.25, 0.125]\n\n"
    )
}

/// The direction of the camera ray through the centre of pixel (x, y)
/// (`fov` vertical), not normalised: its z is −1.
fn centre_ray(x: u32, y: u32) -> Vec3 {
    let t = (FOV.to_radians() * 0.5).tan();
    let sx = ((x as f32 + 0.5) / W as f32 * 2.0 - 1.0) * t * W as f32 / H as f32;
    let sy = (1.0 - (y as f32 + 0.5) / H as f32 * 2.0) * t;
    Vec3::new(sx, sy, -1.0)
}

/// A plane at distance 3 facing the camera: `depth`'s image and the `aov`
/// variable `depth` are the distance along each pixel's ray, 3·|d|/|d_z|;
/// `position` its point, `uv` and the normals those of the quad.
#[test]
fn depth_position_uv_and_normal_of_a_plane_are_analytic() {
    let quad = "[[objects]]\ntype = \"quad\"\nmaterial = \"white\"\norigin = [-10, -8, -3]\n\
                edge_u = [20, 0, 0]\nedge_v = [0, 16, 0]\n";
    let depth = scene(&(frame("integrator = \"depth\"") + quad));
    let img = run(&depth, 2, None);
    assert!(img.extra.is_none());
    let aov = scene(
        &(frame(
            "integrator = \"aov\"\naovs = \"dd:depth,pp:position,uv:uv,ng:geo_normal,nn:sh_normal,al:albedo,dx:duv_dx,dy:duv_dy\"",
        ) + quad),
    );
    let a = run(&aov, 2, None);
    let names = &a.extra.as_ref().unwrap().names;
    assert_eq!(
        names.join(" "),
        "dd.T pp.X pp.Y pp.Z uv.U uv.V ng.X ng.Y ng.Z nn.X nn.Y nn.Z al.R al.G al.B \
         dx.U dx.V dy.U dy.V"
    );
    // A pixel's step on the plane at distance 3 (one camera ray per pixel,
    // so unscaled), over the quad's edges.
    let step = 2.0 * 3.0 * (FOV.to_radians() * 0.5).tan() / H as f32;
    for (name, want) in [
        ("dx.U", step / 20.0),
        ("dx.V", 0.0),
        ("dy.U", 0.0),
        ("dy.V", -step / 16.0),
    ] {
        for got in channel(&a, name) {
            assert!((got - want).abs() < 1e-5, "{name}: {got} vs {want}");
        }
    }
    let dd = channel(&a, "dd.T");
    let (u, v) = (channel(&a, "uv.U"), channel(&a, "uv.V"));
    let (px, py, pz) = (
        channel(&a, "pp.X"),
        channel(&a, "pp.Y"),
        channel(&a, "pp.Z"),
    );
    for y in 0..H {
        for x in 0..W {
            let k = (y * W + x) as usize;
            let d = centre_ray(x, y);
            let want = 3.0 * d.length();
            let close = |got: f32, want: f32, what: &str| {
                assert!(
                    (got - want).abs() <= 2e-5 * want.abs().max(1.0),
                    "{what} at ({x}, {y}): {got} vs {want}"
                );
            };
            close(img.get(x, y).r, want, "depth integrator");
            assert_eq!(img.get(x, y).r, img.get(x, y).b);
            close(dd[k], want, "depth variable");
            let p = d * 3.0;
            close(px[k], p.x, "position x");
            close(py[k], p.y, "position y");
            close(pz[k], -3.0, "position z");
            close(u[k], (p.x + 10.0) / 20.0, "u");
            close(v[k], (p.y + 8.0) / 16.0, "v");
            // The image is black without a held integrator.
            assert_eq!(a.get(x, y), Rgb::ZERO);
        }
    }
    for (name, want) in [
        ("ng.Z", 1.0),
        ("nn.Z", 1.0),
        ("ng.X", 0.0),
        ("al.R", 0.5),
        ("al.G", 0.25),
        ("al.B", 0.125),
    ] {
        assert!(channel(&a, name).iter().all(|&c| c == want), "{name}");
    }
}

/// A sphere's normals at each pixel's centre are the analytic normal of
/// the ray's hit; pixels whose ray misses it have zeros in every variable.
#[test]
fn normals_of_a_sphere_are_analytic_at_pixel_centres() {
    let (c, r) = (Vec3::new(0.3, -0.2, -5.0), 1.5f32);
    let s = scene(
        &(frame("integrator = \"aov\"\naovs = \"ng:geo_normal,nn:sh_normal,dd:depth,si:shape_index\"")
            + &format!(
                "[[objects]]\ntype = \"sphere\"\nmaterial = \"white\"\ncenter = [{}, {}, {}]\nradius = {r}\n",
                c.x, c.y, c.z
            )),
    );
    let img = run(&s, 2, None);
    let (mut hits, mut misses) = (0, 0);
    let ch = |n: &str| channel(&img, n);
    let (ng, nn) = (
        [ch("ng.X"), ch("ng.Y"), ch("ng.Z")],
        [ch("nn.X"), ch("nn.Y"), ch("nn.Z")],
    );
    let (dd, si) = (ch("dd.T"), ch("si.I"));
    for y in 0..H {
        for x in 0..W {
            let k = (y * W + x) as usize;
            let d = centre_ray(x, y).normalize();
            // |t d − c|² = r²: t² − 2 t (d·c) + |c|² − r² = 0.
            let b = d.dot(c);
            let disc = b * b - (c.dot(c) - r * r);
            // Rays grazing the outline are left out: sub-ulp differences
            // decide whether they hit.
            if disc.abs() < 1e-2 {
                continue;
            }
            if disc < 0.0 {
                misses += 1;
                for n in ng.iter().chain(&nn) {
                    assert_eq!(n[k], 0.0, "miss at ({x}, {y})");
                }
                assert_eq!((dd[k], si[k]), (0.0, 0.0));
                continue;
            }
            hits += 1;
            let t = b - disc.sqrt();
            let n = (d * t - c) / r;
            for (got, what) in [(&ng, "geometric"), (&nn, "shading")] {
                let g = Vec3::new(got[0][k], got[1][k], got[2][k]);
                assert!(
                    (g - n).length() < 1e-4,
                    "{what} normal at ({x}, {y}): {g:?} vs {n:?}"
                );
            }
            assert!((dd[k] - t).abs() < 1e-4 * t, "depth at ({x}, {y})");
            assert_eq!(si[k], 1.0);
        }
    }
    assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
}

/// `moment`'s second moment minus the square of its first is each
/// pixel's variance of its samples' CIE Y (and X, Z), computed here from
/// the samples rendered one at a time by the held integrator.
#[test]
fn moment_variance_equals_the_variance_of_the_samples() {
    let body = "[camera]\nposition = [0, 1, 4]\nlook_at = [0, 0.5, 0]\nfov = 40\n\n\
                [materials.white]\nalbedo = [0.7, 0.6, 0.5]\n\n\
                [[objects]]\ntype = \"quad\"\nmaterial = \"white\"\norigin = [-3, 0, -3]\n\
                edge_u = [6, 0, 0]\nedge_v = [0, 0, 6]\n\n\
                [[objects]]\ntype = \"sphere\"\nmaterial = \"white\"\ncenter = [0, 0.6, 0]\nradius = 0.6\n\n\
                [[lights]]\ntype = \"rect\"\norigin = [0.5, 3, 0.5]\nedge_u = [1, 0, 0]\n\
         edge_v = [0, 0, 1]\nradiance = [20, 20, 20]\n";
    let head = |integrator: &str| {
        format!("[render]\nwidth = 12\nheight = 10\nspp = 16\nfilter = \"box\"\n{integrator}\n\n")
    };
    let m = scene(
        &(head(
            "integrator = \"moment\"\nnested = { type = \"path\", max_depth = 3, name = \"img\" }",
        ) + body),
    );
    let img = run(&m, 2, None);
    let names = &img.extra.as_ref().unwrap().names;
    assert_eq!(
        names.join(" "),
        "img.X img.Y img.Z m2_img.X m2_img.Y m2_img.Z"
    );
    let p = scene(&(head("integrator = \"path\"\nmax_depth = 3") + body));
    let Config::Path(settings) = Config::of(&p).unwrap() else {
        panic!("a path integrator")
    };
    let path = penumbra::integrator::Path::new(&p, settings);
    let plain = run(&p, 2, None);
    let mut worker = path.worker(&p);
    let never = || false;
    let mut varied = 0;
    for y in 0..10 {
        for x in 0..12 {
            // The 16 samples of the pixel, one at a time.
            let mut xyz = Vec::new();
            for i in 0..16 {
                let mut film = FilmTile::new(x..x + 1, y..y + 1);
                let job = TileJob {
                    xs: x..x + 1,
                    ys: y..y + 1,
                    samples: i..i + 1,
                    cancelled: &never,
                };
                assert!(worker.render(job, &mut (), &mut film, &mut Vec::new()));
                xyz.push(penumbra::integrator::srgb_to_xyz(film.value(0)).map(f64::from));
            }
            let k = (y * 12 + x) as usize;
            // The image is the held integrator's.
            assert_eq!(img.pixels[k], plain.pixels[k]);
            for (c, axis) in ["X", "Y", "Z"].iter().enumerate() {
                let mean = xyz.iter().map(|v| v[c]).sum::<f64>() / 16.0;
                let var = xyz.iter().map(|v| (v[c] - mean).powi(2)).sum::<f64>() / 16.0;
                let m1 = f64::from(channel(&img, &format!("img.{axis}"))[k]);
                let m2 = f64::from(channel(&img, &format!("m2_img.{axis}"))[k]);
                assert!(
                    (m1 - mean).abs() <= 1e-5 * mean.abs().max(1e-3),
                    "mean {axis} at ({x}, {y}): {m1} vs {mean}"
                );
                let got = m2 - m1 * m1;
                assert!(
                    (got - var).abs() <= 1e-4 * (m2.abs() + 1e-6),
                    "variance {axis} at ({x}, {y}): {got} vs {var}"
                );
                varied += usize::from(var > 1e-4);
            }
        }
    }
    assert!(varied > 50, "{varied} channels with noise");
}

/// A scene of an `aov` over a path tracer, splatted by a Gaussian filter,
/// in `passes` passes.
fn splatted(integrator: &str, passes: u32) -> Scene {
    let toml = format!(
        "[render]\nwidth = 37\nheight = 29\nspp = 6\nfilter = \"gaussian\"\nsplat = true\n\
         {integrator}\n\n\
         [camera]\nposition = [0, 1, 4]\nlook_at = [0, 0.5, 0]\nfov = 40\n\n\
         [materials.white]\nalbedo = [0.7, 0.6, 0.5]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"white\"\norigin = [-3, 0, -3]\n\
         edge_u = [6, 0, 0]\nedge_v = [0, 0, 6]\n\n\
         [[objects]]\ntype = \"sphere\"\nmaterial = \"white\"\ncenter = [0, 0.6, 0]\nradius = 0.6\n\n\
         [[lights]]\ntype = \"rect\"\norigin = [0.5, 3, 0.5]\nedge_u = [1, 0, 0]\n\
         edge_v = [0, 0, 1]\nradiance = [20, 20, 20]\n"
    )
    .replace("PASSES", &passes.to_string());
    scene(&toml)
}

fn bits(img: &Image) -> (Vec<[u32; 3]>, Vec<u32>) {
    (
        img.pixels
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect(),
        img.extra
            .as_ref()
            .map(|e| e.values.iter().map(|v| v.to_bits()).collect())
            .unwrap_or_default(),
    )
}

/// Channels splatted by a Gaussian filter have the same bits on 1 and 3
/// threads, in 1 and 3 passes, and in a region as in the whole frame.
#[test]
fn splatted_channels_keep_their_bits_on_threads_passes_and_regions() {
    for integrator in [
        "integrator = \"aov\"\naovs = \"dd:depth,nn:sh_normal,uv:uv\"\n\
         nested = { type = \"path\", passes = PASSES }",
        "integrator = \"moment\"\nnested = { type = \"path\", passes = PASSES }",
    ] {
        let one = splatted(integrator, 1);
        let three = splatted(integrator, 3);
        let base = run(&one, 1, None);
        let extra = base.extra.as_ref().unwrap();
        assert!(extra.values.iter().any(|v| *v != 0.0));
        assert_eq!(
            bits(&base),
            bits(&run(&one, 3, None)),
            "{integrator}: threads"
        );
        assert_eq!(
            bits(&base),
            bits(&run(&three, 1, None)),
            "{integrator}: passes"
        );
        assert_eq!(
            bits(&base),
            bits(&run(&three, 3, None)),
            "{integrator}: both"
        );
        let region = Region {
            x0: 5,
            y0: 7,
            x1: 23,
            y1: 20,
        };
        let part = run(&one, 3, Some(region));
        let c = extra.names.len();
        let part_extra = part.extra.as_ref().unwrap();
        for y in region.y0..region.y1 {
            for x in region.x0..region.x1 {
                let (i, j) = (
                    (y * 37 + x) as usize,
                    ((y - region.y0) * region.width() + x - region.x0) as usize,
                );
                assert_eq!(base.pixels[i], part.pixels[j], "{integrator}: ({x}, {y})");
                assert_eq!(
                    extra.values[i * c..(i + 1) * c],
                    part_extra.values[j * c..(j + 1) * c],
                    "{integrator}: ({x}, {y})"
                );
            }
        }
    }
}

/// With a held integrator, `aov`'s image is that integrator's, bit for
/// bit, and so are its `N.R`, `N.G`, `N.B` channels; `N.A` is 1 on the
/// surfaces.
#[test]
fn the_held_image_is_the_integrators_own() {
    let with = splatted(
        "integrator = \"aov\"\naovs = \"dd:depth\"\nnested = { type = \"path\", name = \"img\" }",
        1,
    );
    let alone = splatted("integrator = \"path\"", 1);
    let (a, b) = (run(&with, 2, None), run(&alone, 2, None));
    assert_eq!(bits(&a).0, bits(&b).0);
    let names = &a.extra.as_ref().unwrap().names;
    assert_eq!(names.join(" "), "img.R img.G img.B img.A dd.T");
    let red: Vec<f32> = b.pixels.iter().map(|p| p.r).collect();
    assert_eq!(channel(&a, "img.R"), red);
    let alpha = channel(&a, "img.A");
    assert!(alpha.iter().all(|&v| (0.0..=1.0).contains(&v)));
    let covered = alpha.iter().filter(|&&v| v > 0.999).count();
    assert!(
        covered > 300 && covered < alpha.len(),
        "{covered} pixels covered"
    );
}

/// Mistakes in the description are refused at their place.
#[test]
fn bad_descriptions_are_refused_with_their_place() {
    let err = |integrator: &str| {
        try_scene(&frame(integrator))
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = err("integrator = \"aov\"\naovs = \"dd:deep\"");
    assert!(
        e.contains("test.toml:") && e.contains("unknown AOV type `deep`"),
        "{e}"
    );
    assert!(e.contains("shape_index"), "{e}");
    let e = err("integrator = \"aov\"\naovs = \"dd\"");
    assert!(e.contains("`dd` is not a `name:type` pair"), "{e}");
    // Without anything to write, black and no channel (Mitsuba warns).
    for bare in ["integrator = \"aov\"", "integrator = \"moment\""] {
        let img = run(&scene(&frame(bare)), 1, None);
        assert!(img.extra.is_none() && img.pixels.iter().all(|p| *p == Rgb::ZERO));
    }
    let e = err("integrator = \"path\"\nnested = { type = \"path\" }");
    assert!(
        e.contains("the `path` integrator holds no integrator"),
        "{e}"
    );
    let e = err("integrator = \"moment\"\nnested = { type = \"aov\", aovs = \"d:depth\" }");
    assert!(e.contains("`aov` cannot be held"), "{e}");
    let e = err("integrator = \"path\"\naovs = \"d:depth\"");
    assert!(e.contains("aovs"), "{e}");
}

/// Mitsuba's XML scenes name the channels as Mitsuba does: a named child's
/// name, `_arg_0` for an unnamed one.
#[test]
fn mitsuba_scenes_name_the_channels_as_mitsuba() {
    let dir = tempfile::tempdir().unwrap();
    let xml = |integrator: &str| {
        format!(
            "<scene version=\"3.0.0\">{integrator}\
             <sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\
             <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/>\
             <integer name=\"height\" value=\"6\"/></film>\
             <sampler type=\"independent\"><integer name=\"sample_count\" value=\"2\"/></sampler>\
             </sensor>\
             <shape type=\"sphere\"><point name=\"center\" value=\"0, 0, 4\"/></shape></scene>"
        )
    };
    let channels = |integrator: &str| {
        let path = dir.path().join("s.xml");
        std::fs::write(&path, xml(integrator)).unwrap();
        let src = SceneSource::open(path.to_str().unwrap(), &LoadOptions::default()).unwrap();
        let s = src.build().unwrap();
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        let img = run(&s, 1, None);
        assert_eq!(
            Config::of(&s).unwrap().channels(),
            img.extra.as_ref().unwrap().names
        );
        img.extra.unwrap().names.join(" ")
    };
    assert_eq!(
        channels(
            "<integrator type=\"aov\"><string name=\"aovs\" value=\"dd.y:depth,nn:sh_normal\"/>\
             <integrator type=\"path\" name=\"my_image\"/></integrator>"
        ),
        "my_image.R my_image.G my_image.B my_image.A dd.y.T nn.X nn.Y nn.Z"
    );
    assert_eq!(
        channels("<integrator type=\"moment\"><integrator type=\"direct\"/></integrator>"),
        "_arg_0.X _arg_0.Y _arg_0.Z m2__arg_0.X m2__arg_0.Y m2__arg_0.Z"
    );
}

/// `sh_normal` is the normal the material shades by, as Mitsuba's
/// `BSDF::sh_frame`: a normal map tilts it (here by a constant map, the
/// same tilt everywhere on a plane facing the camera), `geo_normal` stays.
#[test]
fn the_shading_normal_is_the_one_a_normal_map_gives() {
    let quad = "[materials.tilted]\ntype = \"normalmap\"\nnormalmap = [0.75, 0.5, 1.0]\n\
                bsdf = \"white\"\n\n\
                [[objects]]\ntype = \"quad\"\nmaterial = \"tilted\"\norigin = [-10, -8, -3]\n\
                edge_u = [20, 0, 0]\nedge_v = [0, 16, 0]\n";
    let aov = scene(&(frame("integrator = \"aov\"\naovs = \"ng:geo_normal,nn:sh_normal\"") + quad));
    let a = run(&aov, 2, None);
    // (2·0.75 − 1, 0, 1) in the frame of tangent +x and normal +z.
    let want = Vec3::new(0.5, 0.0, 1.0).normalize();
    for (name, w) in [
        ("nn.X", want.x),
        ("nn.Y", want.y),
        ("nn.Z", want.z),
        ("ng.Z", 1.0),
    ] {
        for got in channel(&a, name) {
            assert!((got - w).abs() < 1e-5, "{name}: {got} vs {w}");
        }
    }
}
