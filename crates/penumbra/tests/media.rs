//! The volumetric path tracer (`volpath`) against closed-form answers,
//! through its own tracking: transmittance through a slab, a volumetric
//! furnace, single scattering against a quadrature; and its determinism.

mod common;

use common::*;
use penumbra::math::Rgb;
use penumbra::render::Image;

/// An orthographic camera at z = 2 looking down −z at a slab of
/// `medium` (a `null` box, z from −1 to 0, wide in x and y), `behind`
/// under it, rendered by `volpath` with `render` keys.
fn slab(medium: &str, behind: &str, render: &str) -> String {
    format!(
        "[render]\nwidth = 24\nheight = 24\nintegrator = \"volpath\"\nseed = 5\n{render}\n\
         [camera]\nprojection = \"orthographic\"\nview_width = 1\nposition = [0, 0, 2]\n\
         look_at = [0, 0, 0]\n\n\
         [materials.boundary]\ntype = \"null\"\n\n\
         [materials.black]\ntype = \"diffuse\"\nreflectance = [0, 0, 0]\n\n\
         [media.slab]\n{medium}\n\n\
         [[objects]]\ntype = \"cube\"\nmaterial = \"boundary\"\ninterior = \"slab\"\n\
         transform = {{ scale = [50, 50, 0.5], translate = [0, 0, -0.5] }}\n\n{behind}"
    )
}

/// A slab of thickness 1 in front of a surface emitting radiance 1
/// toward the camera, absorbing only (albedo 0), with an extinction that
/// differs by channel: each channel keeps `exp(−σt)`, the distances drawn
/// by one channel and weighed by all (and without spectral extinction,
/// channel by channel too). Every collision in a homogeneous medium is
/// real.
#[test]
fn an_absorbing_slab_transmits_exp_of_minus_its_optical_depth() {
    let light = "[[objects]]\ntype = \"quad\"\nmaterial = \"black\"\n\
                 origin = [-5, -5, -2]\nedge_u = [10, 0, 0]\nedge_v = [0, 10, 0]\n\
                 emitter = { radiance = [1, 1, 1] }\n";
    let sigma = [0.5f32, 1.0, 2.0];
    let want = Rgb::from_array(sigma.map(|s| (-s).exp()));
    for spectral in [true, false] {
        let medium = format!(
            "type = \"homogeneous\"\nsigma_t = [0.5, 1.0, 2.0]\nalbedo = 0\n\
             has_spectral_extinction = {spectral}"
        );
        let (img, rays) = render_toml(&slab(&medium, light, "spp = 64"));
        let (got, err) = mean_and_error(&img);
        if spectral {
            assert_within(got, err, want, "spectral extinction");
        } else {
            // Distances drawn by one channel and taken as grey: each
            // channel's estimate is the chosen channel's, a third of the
            // time each.
            let grey = Rgb::splat(want.element_sum() / 3.0);
            assert_within(got, err, grey, "grey extinction");
        }
        assert!(rays.media.scatterings > 1000, "{:?}", rays.media);
        assert_eq!(rays.media.null_collisions, 0);
    }
}

/// A sphere of a medium that scatters all it stops (albedo 1, a
/// Henyey–Greenstein phase, an extinction that differs by channel), behind
/// a `null` boundary, in an environment of radiance 1, 16 × 16 pixels,
/// rendered with `render` keys.
fn furnace_sphere(render: &str) -> String {
    format!(
        "[render]\nwidth = 16\nheight = 16\nseed = 9\nbackground = [1, 1, 1]\n{render}\n\n\
         [camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 30\n\n\
         [materials.boundary]\ntype = \"null\"\n\n\
         [media.fog]\ntype = \"homogeneous\"\nsigma_t = [1, 2, 4]\nalbedo = 1\n\
         phase = {{ type = \"hg\", g = 0.6 }}\n\n\
         [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
         interior = \"fog\"\n"
    )
}

/// A sphere of a medium that scatters all it stops (albedo 1, a
/// Henyey–Greenstein phase, an extinction that differs by channel),
/// behind a `null` boundary, in an environment of radiance 1: it can
/// neither add nor remove light, so every pixel is 1 within noise.
#[test]
fn a_scattering_sphere_in_a_uniform_environment_is_invisible() {
    let toml = &furnace_sphere("integrator = \"volpath\"\nspp = 256");
    let (img, rays) = render_toml(toml);
    let (got, err) = mean_and_error(&img);
    assert_within(got, err, Rgb::ONE, "volumetric furnace");
    // The sphere fills most of the view and scatters many times.
    assert!(rays.media.scatterings > 20_000, "{:?}", rays.media);
    assert!(err.max_element() < 0.04, "noise {err:?}");
}

/// Single scattering (`max_depth = 2`: one scattering event) of a
/// directional light through a slab of thickness 1, seen from above: at
/// depth `s` the light has crossed `s / cos α` of the medium and the view
/// `s`, so the radiance is `σs E p(θ) ∫₀¹ exp(−σt s (1 + 1/cos α)) ds`,
/// θ the scattering angle; the integral by a midpoint rule.
#[test]
fn single_scattering_from_a_directional_light_matches_a_quadrature() {
    let (sigma_t, albedo, g) = (1.5f64, 0.8f64, 0.3f64);
    let alpha = 40f64.to_radians();
    let (sa, ca) = alpha.sin_cos();
    let light = format!(
        "[[lights]]\ntype = \"directional\"\ndirection = [{sa}, 0, {}]\nirradiance = [2, 2, 2]\n",
        -ca
    );
    let medium = format!(
        "type = \"homogeneous\"\nsigma_t = {sigma_t}\nalbedo = {albedo}\n\
         phase = {{ type = \"hg\", g = {g} }}"
    );
    let (img, _) = render_toml(&slab(&medium, &light, "spp = 64\nmax_depth = 2"));
    let (got, err) = mean_and_error(&img);
    // Light travels along (sin α, 0, −cos α) and leaves toward +z.
    let cos_theta = -ca;
    let hg = (1.0 - g * g)
        / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * cos_theta).powf(1.5));
    let n = 10_000;
    let integral: f64 = (0..n)
        .map(|i| {
            let s = (i as f64 + 0.5) / n as f64;
            (-sigma_t * s * (1.0 + 1.0 / ca)).exp() / n as f64
        })
        .sum();
    let want = (sigma_t * albedo * 2.0 * hg * integral) as f32;
    assert_within(got, err, Rgb::splat(want), "single scattering");
    assert!(
        want > 0.01 && err.max_element() < 0.05 * want,
        "{want} ± {err:?}"
    );
}

/// Single scattering as above for the phase functions beyond `hg`, each
/// against its closed form at the scattering angle: `rayleigh`, an
/// asymmetric `tabphase` (whose last value is straight on: read the other
/// way round its value here would be 5 times larger) and a `blendphase`
/// of the two.
#[test]
fn single_scattering_follows_each_phase_function() {
    let (sigma_t, albedo) = (1.5f64, 0.8f64);
    let alpha = 40f64.to_radians();
    let (sa, ca) = alpha.sin_cos();
    let light = format!(
        "[[lights]]\ntype = \"directional\"\ndirection = [{sa}, 0, {}]\nirradiance = [2, 2, 2]\n",
        -ca
    );
    let pi = std::f64::consts::PI;
    let cos_theta = -ca;
    let rayleigh = 3.0 / (16.0 * pi) * (1.0 + cos_theta * cos_theta);
    // Values 0.5, 1, 4 at cos θ = −1, 0, 1: an integral of 3.25 over cos θ.
    let table = (0.5 + 0.5 * (cos_theta + 1.0)) / 3.25 / (2.0 * pi);
    let n = 10_000;
    let integral: f64 = (0..n)
        .map(|i| {
            let s = (i as f64 + 0.5) / n as f64;
            (-sigma_t * s * (1.0 + 1.0 / ca)).exp() / n as f64
        })
        .sum();
    for (phase, value) in [
        ("{ type = \"rayleigh\" }", rayleigh),
        ("{ type = \"tabphase\", values = \"0.5, 1, 4\" }", table),
        (
            "{ type = \"blendphase\", weight = 0.25, phase_0 = { type = \"rayleigh\" }, \
             phase_1 = { type = \"tabphase\", values = \"0.5, 1, 4\" } }",
            0.75 * rayleigh + 0.25 * table,
        ),
    ] {
        let medium = format!(
            "type = \"homogeneous\"\nsigma_t = {sigma_t}\nalbedo = {albedo}\nphase = {phase}"
        );
        let (img, _) = render_toml(&slab(&medium, &light, "spp = 64\nmax_depth = 2"));
        let (got, err) = mean_and_error(&img);
        let want = (sigma_t * albedo * 2.0 * value * integral) as f32;
        assert_within(got, err, Rgb::splat(want), phase);
        assert!(
            want > 0.005 && err.max_element() < 0.05 * want,
            "{phase}: {want} ± {err:?}"
        );
    }
}

/// A sphere that scatters all it stops, in an environment of radiance 1,
/// is invisible whatever its phase function: each new one, and a blend
/// whose weight is a volume varying through the sphere. (A grey
/// extinction: the test is of the phase functions, not of the weights
/// of spectral tracking.)
#[test]
fn a_scattering_sphere_is_invisible_with_each_phase_function() {
    let dir = tempfile::tempdir().unwrap();
    // A 2×1×1 grid over the unit cube, clamped beyond it: weight 0.1 in
    // the sphere's left half and a little more, 0.9 beyond x = 0.5.
    write_vol(dir.path(), "weight.vol", [2, 1, 1], 1, |x, _, _, _| {
        [0.1, 0.9][x as usize]
    });
    for phase in [
        "{ type = \"rayleigh\" }",
        "{ type = \"tabphase\", values = \"4, 0, 0.5, 1, 8\" }",
        "{ type = \"blendphase\", weight = { type = \"gridvolume\", filename = \"weight.vol\", \
         filter_type = \"nearest\" }, phase_0 = { type = \"hg\", g = -0.7 }, \
         phase_1 = { type = \"rayleigh\" } }",
    ] {
        let toml = format!(
            "[render]\nwidth = 12\nheight = 12\nintegrator = \"volpath\"\nspp = 128\n\
             seed = 9\nbackground = [1, 1, 1]\n\n\
             [camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 30\n\n\
             [materials.boundary]\ntype = \"null\"\n\n\
             [media.fog]\ntype = \"homogeneous\"\nsigma_t = 3\nalbedo = 1\n\
             phase = {phase}\n\n\
             [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
             interior = \"fog\"\n"
        );
        let s = scene_in(dir.path(), &toml);
        let (img, rays) = render_scene(&s, 2);
        let (got, err) = mean_and_error(&img);
        assert_within(got, err, Rgb::ONE, phase);
        assert!(rays.media.scatterings > 5_000, "{phase}: {:?}", rays.media);
        assert!(err.max_element() < 0.05, "{phase}: noise {err:?}");
    }
}

/// A homogeneous medium's albedo as a constant volume (a table, or a
/// volume of the scene by name) renders the same bits as the same albedo
/// written as a number or 3 numbers.
#[test]
fn a_constant_albedo_volume_renders_the_plain_albedo_s_bits() {
    let toml = |albedo: &str| {
        format!(
            "[render]\nwidth = 16\nheight = 10\nintegrator = \"volpath\"\nspp = 8\n\
             seed = 3\nbackground = [0.5, 0.7, 1]\n\n\
             [camera]\nposition = [0, 0.5, 4]\nlook_at = [0, 0, 0]\nfov = 40\n\n\
             [volumes.haze]\ntype = \"constvolume\"\nvalue = [0.9, 0.5, 0.2]\n\n\
             [materials.boundary]\ntype = \"null\"\n\n\
             [materials.floor]\ntype = \"diffuse\"\n\n\
             [media.fog]\ntype = \"homogeneous\"\nsigma_t = [1, 2, 3]\nalbedo = {albedo}\n\n\
             [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
             interior = \"fog\"\n\n\
             [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-3, -1, 3]\n\
             edge_u = [6, 0, 0]\nedge_v = [0, 0, -6]\n"
        )
    };
    for (plain, volumes) in [
        ("0.6", &["{ type = \"constvolume\", value = 0.6 }"][..]),
        (
            "[0.9, 0.5, 0.2]",
            &[
                "{ type = \"constvolume\", value = [0.9, 0.5, 0.2] }",
                "\"haze\"",
            ][..],
        ),
    ] {
        let (want, rays) = render_scene(&scene(&toml(plain)), 2);
        assert!(rays.media.scatterings > 0);
        for v in volumes {
            let (got, r) = render_scene(&scene(&toml(v)), 2);
            assert_eq!(r, rays, "{v}");
            for y in 0..want.height {
                for x in 0..want.width {
                    let bits = |i: &Image| i.get(x, y).to_array().map(f32::to_bits);
                    assert_eq!(bits(&got), bits(&want), "pixel ({x}, {y}): {v} vs {plain}");
                }
            }
        }
    }
}

/// Every pixel's samples are a function of the seed, the pixel and the
/// sample alone: the same bits on 1 and 3 threads and in 3 passes.
#[test]
fn volumetric_paths_are_the_same_on_any_threads_and_passes() {
    let toml = "[render]\nwidth = 20\nheight = 12\nintegrator = \"volpath\"\nspp = 6\n\
                seed = 2\nrr_depth = 2\nbackground = [0.5, 0.7, 1]\n\n\
                [camera]\nposition = [0, 0.5, 4]\nlook_at = [0, 0, 0]\nfov = 40\n\n\
                [materials.boundary]\ntype = \"null\"\n\n\
                [materials.floor]\ntype = \"diffuse\"\n\n\
                [media.fog]\ntype = \"homogeneous\"\nsigma_t = [1, 2, 3]\nalbedo = 0.9\n\
                phase = { type = \"hg\", g = -0.3 }\n\n\
                [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
                interior = \"fog\"\n\n\
                [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-3, -1, 3]\n\
                edge_u = [6, 0, 0]\nedge_v = [0, 0, -6]\n";
    let a = same_bits_on_threads_and_passes(toml, "spp = 6\n");
    assert!(a.media.scatterings > 0 && a.shadow > 0);
}

/// `path` ignores media, as Mitsuba's does: a scene with a medium behind
/// a `null` boundary renders under `path` as without the medium.
#[test]
fn path_ignores_media() {
    let light = "[[objects]]\ntype = \"quad\"\nmaterial = \"black\"\n\
                 origin = [-5, -5, -2]\nedge_u = [10, 0, 0]\nedge_v = [0, 10, 0]\n\
                 emitter = { radiance = [1, 1, 1] }\n";
    let medium = "type = \"homogeneous\"\nsigma_t = 3\nalbedo = 0";
    let with = slab(medium, light, "spp = 4").replace("\"volpath\"", "\"path\"");
    let without = with.replace("interior = \"slab\"\n", "");
    let (a, ra) = render_toml(&with);
    let (b, rb) = render_toml(&without);
    assert_eq!(ra, rb);
    for y in 0..a.height {
        for x in 0..a.width {
            assert_eq!(a.get(x, y).to_array(), b.get(x, y).to_array());
        }
    }
    assert_eq!(mean_and_error(&a).0, Rgb::ONE);
}

/// Without media `volpath` is the path tracer on surfaces, counting depth
/// as Mitsuba's volpath does: in a closed box whose walls emit 1 and
/// reflect ρ diffusely, a path of at most `d` scatterings gathers
/// `1 + ρ + … + ρ^(d−1)`, unbounded `1 / (1 − ρ)`; a `null` wall inside
/// the box (a crossing, not a scattering) changes nothing.
#[test]
fn without_media_volpath_holds_the_closed_box_radiance_of_each_depth() {
    let rho = 0.5f32;
    let walls = [
        ([-1, -1, -1], [0, 0, 2], [2, 0, 0]),
        ([-1, 1, -1], [2, 0, 0], [0, 0, 2]),
        ([-1, -1, -1], [0, 2, 0], [0, 0, 2]),
        ([1, -1, -1], [0, 0, 2], [0, 2, 0]),
        ([-1, -1, -1], [2, 0, 0], [0, 2, 0]),
        ([-1, -1, 1], [0, 2, 0], [2, 0, 0]),
    ];
    let scene = |render: &str| {
        let mut s = format!(
            "[render]\nwidth = 16\nheight = 16\nintegrator = \"volpath\"\nseed = 3\n{render}\n\
             [camera]\nposition = [0.1, 0.2, 0.5]\nlook_at = [0.0, 0.0, -1.0]\nfov = 70\n\n\
             [materials.wall]\ntype = \"diffuse\"\nreflectance = [{rho}, {rho}, {rho}]\n\n\
             [materials.boundary]\ntype = \"null\"\n\n\
             [[objects]]\ntype = \"quad\"\nmaterial = \"boundary\"\norigin = [-1, -1, -0.3]\n\
             edge_u = [2, 0, 0]\nedge_v = [0, 2, 0]\n"
        );
        for (o, u, v) in walls {
            s += &format!(
                "\n[[objects]]\ntype = \"quad\"\nmaterial = \"wall\"\norigin = {o:?}\n\
                 edge_u = {u:?}\nedge_v = {v:?}\nemitter = {{ radiance = [1, 1, 1] }}\n"
            );
        }
        s
    };
    for (d, spp) in [(1, 1), (2, 64), (3, 64)] {
        let (img, _) = render_toml(&scene(&format!("spp = {spp}\nmax_depth = {d}")));
        let (got, err) = mean_and_error(&img);
        let want = (1.0 - rho.powi(d)) / (1.0 - rho);
        assert_within(got, err, Rgb::splat(want), &format!("max_depth = {d}"));
    }
    let (img, _) = render_toml(&scene("spp = 128"));
    let (got, err) = mean_and_error(&img);
    assert_within(got, err, Rgb::splat(1.0 / (1.0 - rho)), "unbounded");
}

/// A camera sitting in a medium (its `medium`) sees through it from its
/// near clip plane on, as Mitsuba's camera rays start there: an emitter 4
/// away behind an absorbing medium filling space, the near plane at 1,
/// keeps `exp(−3 σt)`.
#[test]
fn a_camera_in_a_medium_sees_through_it_from_its_near_plane() {
    let toml = "[render]\nwidth = 8\nheight = 8\nintegrator = \"volpath\"\nspp = 256\nseed = 4\n\n\
                [camera]\nprojection = \"orthographic\"\nview_width = 1\nposition = [0, 0, 2]\n\
                look_at = [0, 0, 0]\nnear_clip = 1\nmedium = \"air\"\n\n\
                [materials.black]\ntype = \"diffuse\"\nreflectance = [0, 0, 0]\n\n\
                [media.air]\ntype = \"homogeneous\"\nsigma_t = [0.2, 0.4, 0.6]\nalbedo = 0\n\n\
                [[objects]]\ntype = \"quad\"\nmaterial = \"black\"\norigin = [-5, -5, -2]\n\
                edge_u = [10, 0, 0]\nedge_v = [0, 10, 0]\nemitter = { radiance = [1, 1, 1] }\n";
    let (img, _) = render_toml(toml);
    let (got, err) = mean_and_error(&img);
    let want = Rgb::from_array([0.2f32, 0.4, 0.6].map(|s| (-3.0 * s).exp()));
    assert_within(got, err, want, "camera in a medium");
}

/// Writes a `.vol` grid of `resolution` voxels and `channels` values each,
/// `f(x, y, z, channel)`, as `name` in `dir`.
fn write_vol(
    dir: &std::path::Path,
    name: &str,
    resolution: [u32; 3],
    channels: u32,
    f: impl Fn(u32, u32, u32, u32) -> f32,
) {
    let [nx, ny, nz] = resolution;
    let mut data = Vec::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                data.extend((0..channels).map(|c| f(x, y, z, c)));
            }
        }
    }
    let grid = penumbra::volume::vol_file::VolGrid {
        resolution,
        channels,
        bbox: penumbra::math::Aabb::new(penumbra::math::Vec3::ZERO, penumbra::math::Vec3::ONE),
        data,
    };
    std::fs::write(dir.join(name), grid.to_bytes()).unwrap();
}

/// The scene `toml` built with its files relative to `dir`.
fn scene_in(dir: &std::path::Path, toml: &str) -> penumbra::scene::Scene {
    use penumbra::scene::{LoadOptions, SceneSource};
    SceneSource::from_toml(toml, &dir.join("test.toml"), dir, &LoadOptions::default())
        .and_then(|s| s.build())
        .unwrap_or_else(|e| panic!("scene should be valid: {e}"))
}

/// A heterogeneous slab (the `slab` box, z from −1 to 0) whose extinction
/// rises linearly with depth, `0.2 + 2.8 s` at depth `s` (a 1-channel grid
/// of voxels along z, looked up nearest: the midpoint rule, exact for a
/// linear density), absorbing only, in front of a surface emitting 1:
/// every pixel keeps `exp(−∫σt) = exp(−1.6)`, tracked through the grid of
/// majorants and through Mitsuba's one majorant alike; the grid takes
/// fewer null collisions.
#[test]
fn a_heterogeneous_slab_transmits_exp_of_minus_its_optical_depth() {
    let d = tempfile::tempdir().unwrap();
    let n = 64;
    // Voxel z = 0 is the bottom of the slab (depth 1).
    write_vol(d.path(), "ramp.vol", [1, 1, n], 1, |_, _, z, _| {
        let depth = 1.0 - (z as f32 + 0.5) / n as f32;
        0.2 + 2.8 * depth
    });
    let light = "[[objects]]\ntype = \"quad\"\nmaterial = \"black\"\n\
                 origin = [-5, -5, -2]\nedge_u = [10, 0, 0]\nedge_v = [0, 10, 0]\n\
                 emitter = { radiance = [1, 1, 1] }\n";
    let want = Rgb::splat((-1.6f32).exp());
    let mut nulls = Vec::new();
    for resolution in [16, 1] {
        let medium = format!(
            "type = \"heterogeneous\"\nalbedo = 0\nmajorant_resolution = {resolution}\n\
             sigma_t = {{ type = \"gridvolume\", filename = \"ramp.vol\", \
             filter_type = \"nearest\", \
             transform = {{ scale = [100, 100, 1], translate = [-50, -50, -1] }} }}"
        );
        let s = scene_in(d.path(), &slab(&medium, light, "spp = 64"));
        let (img, rays) = render_scene(&s, 2);
        let (got, err) = mean_and_error(&img);
        assert_within(
            got,
            err,
            want,
            &format!("majorant_resolution = {resolution}"),
        );
        assert!(err.max_element() < 0.01, "noise {err:?}");
        nulls.push(rays.media.null_collisions);
    }
    // Against the one majorant (3) about half the collisions are null;
    // against each cell's, a few.
    assert!(
        nulls[0] * 3 < nulls[1],
        "null collisions, grid vs one: {nulls:?}"
    );
}

/// A cube of heterogeneous medium that scatters all it stops (albedo 1),
/// its extinction a 3-channel grid that differs by channel and from voxel
/// to voxel, behind a `null` boundary larger than the volume, in an
/// environment of radiance 1: every pixel is 1 within noise, with the grid
/// of majorants and with the one majorant.
#[test]
fn a_scattering_heterogeneous_cube_in_a_uniform_environment_is_invisible() {
    let d = tempfile::tempdir().unwrap();
    write_vol(d.path(), "smoke.vol", [8, 8, 8], 3, |x, y, z, c| {
        let v = ((x * 7 + y * 3 + z * 5) % 11) as f32 / 10.0;
        (c + 1) as f32 * 2.0 * v * v
    });
    for resolution in [1, 16] {
        let toml = format!(
            "[render]\nwidth = 16\nheight = 16\nintegrator = \"volpath\"\nspp = 1024\n\
             seed = 19\nbackground = [1, 1, 1]\n\n\
             [camera]\nposition = [0.3, 0.2, 4]\nlook_at = [0, 0, 0]\nfov = 30\n\n\
             [materials.boundary]\ntype = \"null\"\n\n\
             [volumes.smoke]\ntype = \"gridvolume\"\nfilename = \"smoke.vol\"\n\
             transform = {{ scale = 1.6, translate = [-0.8, -0.8, -0.8] }}\n\n\
             [media.fog]\ntype = \"heterogeneous\"\nsigma_t = \"smoke\"\nalbedo = 1\nscale = 2\n\
             majorant_resolution = {resolution}\nphase = {{ type = \"hg\", g = 0.5 }}\n\n\
             [[objects]]\ntype = \"cube\"\nmaterial = \"boundary\"\ninterior = \"fog\"\n"
        );
        let (img, rays) = render_scene(&scene_in(d.path(), &toml), 2);
        let (got, err) = mean_and_error(&img);
        assert_within(
            got,
            err,
            Rgb::ONE,
            &format!("furnace, resolution {resolution}"),
        );
        assert!(rays.media.scatterings > 10_000, "{:?}", rays.media);
        assert!(rays.media.null_collisions > 0, "{:?}", rays.media);
        assert!(err.max_element() < 0.03, "noise {err:?}");
    }
}

/// A heterogeneous medium's paths are a function of the seed, the pixel
/// and the sample alone: the same bits on 1 and 3 threads.
#[test]
fn heterogeneous_paths_are_the_same_on_any_threads() {
    let d = tempfile::tempdir().unwrap();
    write_vol(d.path(), "smoke.vol", [5, 4, 3], 1, |x, y, z, _| {
        ((x + 2 * y + 3 * z) % 4) as f32
    });
    let toml = "[render]\nwidth = 20\nheight = 12\nintegrator = \"volpath\"\nspp = 6\n\
                seed = 2\nrr_depth = 2\nbackground = [0.5, 0.7, 1]\n\n\
                [camera]\nposition = [0, 0.5, 4]\nlook_at = [0, 0, 0]\nfov = 40\n\n\
                [materials.boundary]\ntype = \"null\"\n\n\
                [materials.floor]\ntype = \"diffuse\"\n\n\
                [media.fog]\ntype = \"heterogeneous\"\nalbedo = [0.9, 0.5, 0.7]\nscale = 3\n\
                sigma_t = { type = \"gridvolume\", filename = \"smoke.vol\", \
                transform = { scale = 2, translate = [-1, -1, -1] } }\n\n\
                [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
                interior = \"fog\"\n\n\
                [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-3, -1, 3]\n\
                edge_u = [6, 0, 0]\nedge_v = [0, 0, -6]\n";
    let s = scene_in(d.path(), toml);
    let (one, a) = render_scene(&s, 1);
    let (three, b) = render_scene(&s, 3);
    assert_eq!(a, b);
    for y in 0..one.height {
        for x in 0..one.width {
            let bits = |i: &Image| i.get(x, y).to_array().map(f32::to_bits);
            assert_eq!(bits(&one), bits(&three), "pixel ({x}, {y}), 1 vs 3 threads");
        }
    }
    assert!(a.media.scatterings > 0 && a.media.null_collisions > 0 && a.shadow > 0);
}

/// `distributed` tracks its paths through media, drawing the thesis's
/// sets at surface and medium vertices alike: the volumetric furnace holds
/// with sets of phase directions at the first two vertices.
#[test]
fn distributed_sets_in_a_scattering_sphere_leave_a_uniform_environment_unchanged() {
    let toml = furnace_sphere(
        "integrator = \"distributed\"\nspp = 32\nsets_depth = 2\nreflection_rays = 4\n\
         shadow_rays = 3\ndistribution = \"jitter\"",
    );
    let (img, rays) = render_toml(&toml);
    let (got, err) = mean_and_error(&img);
    assert_within(got, err, Rgb::ONE, "volumetric furnace under distributed");
    // Every collision sends one direction on, those below sets_depth a
    // set of 4.
    assert!(
        rays.media.scattered > rays.media.scatterings,
        "{:?}",
        rays.media
    );
    assert!(rays.shadow > 0);
    assert!(err.max_element() < 0.04, "noise {err:?}");
    // The reflection metric, judging the first collision's set of phase
    // directions on its members' paths, stops sets and keeps the furnace.
    let judged = toml.replace(
        "reflection_rays = 4\n",
        "reflection_rays = 8\nmetric = true\nshadow_metric = false\nmetric_threshold = 0.1\n",
    );
    let (img, rays) = render_toml(&judged);
    let (got, err) = mean_and_error(&img);
    assert_within(
        got,
        err,
        Rgb::ONE,
        "volumetric furnace under the reflection metric",
    );
    assert!(rays.media.saved > 0, "{:?}", rays.media);
}

/// A lit fog sphere over a floor: `distributed`'s sets (at surface and
/// medium vertices, each of its shadow and phase sets weighed against the
/// other by the power heuristic) converge to `volpath`'s image. Each is
/// rendered with two seeds, whose difference gives each pixel's variance;
/// blocks of 4 × 4 pixels are compared, each block's z within 4.
#[test]
fn distributed_sets_in_media_agree_with_volpath() {
    let scene_of = |render: &str, seed: u32| {
        format!(
            "[render]\nwidth = 24\nheight = 16\nseed = {seed}\n{render}\n\n\
             [camera]\nposition = [0, 0.6, 4]\nlook_at = [0, -0.2, 0]\nfov = 45\n\n\
             [materials.boundary]\ntype = \"null\"\n\n\
             [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.6, 0.5, 0.4]\n\n\
             [materials.black]\ntype = \"diffuse\"\nreflectance = [0, 0, 0]\n\n\
             [media.fog]\ntype = \"homogeneous\"\nsigma_t = [1.5, 2, 3]\nalbedo = [0.9, 0.7, 0.8]\n\
             phase = {{ type = \"hg\", g = 0.4 }}\n\n\
             [[objects]]\ntype = \"sphere\"\nradius = 0.8\nmaterial = \"boundary\"\n\
             interior = \"fog\"\n\n\
             [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-4, -0.8, 4]\n\
             edge_u = [8, 0, 0]\nedge_v = [0, 0, -8]\n\n\
             [[objects]]\ntype = \"quad\"\nmaterial = \"black\"\norigin = [-1, 2.5, -1]\n\
             edge_u = [2, 0, 0]\nedge_v = [0, 0, 2]\nemitter = {{ radiance = [4, 4, 4] }}\n"
        )
    };
    // Per pixel, the mean of two seeds' renders and its variance.
    let pair = |render: &str| {
        let (one, rays) = render_toml(&scene_of(render, 11));
        let (two, _) = render_toml(&scene_of(render, 12));
        let at = move |x: u32, y: u32| {
            let (a, b) = (one.get(x, y), two.get(x, y));
            ((a + b) * 0.5, (a - b) * (a - b) * 0.25)
        };
        (at, rays)
    };
    let (a, _) = pair("integrator = \"volpath\"\nspp = 512\nmax_depth = 6");
    let (b, rays) = pair(
        "integrator = \"distributed\"\nspp = 32\nmax_depth = 6\nsets_depth = 2\n\
         reflection_rays = 4\nshadow_rays = 4\ndistribution = \"jitter\"",
    );
    assert!(rays.media.scattered > rays.media.scatterings && rays.shadow > 0);
    let (block, mut worst, mut lit) = (4, 0f32, 0f32);
    for by in 0..16 / block {
        for bx in 0..24 / block {
            let mut sum = [(Rgb::ZERO, Rgb::ZERO); 2];
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    for (s, f) in sum.iter_mut().zip([&a, &b]) {
                        let (m, v) = f(x, y);
                        s.0 += m;
                        s.1 += v;
                    }
                }
            }
            let n = (block * block) as f32;
            let d = (sum[0].0 - sum[1].0) / n;
            let s = ((sum[0].1 + sum[1].1) / (n * n)).map(f32::sqrt);
            lit = lit.max(sum[0].0.min_element() / n);
            for c in 0..3 {
                worst = worst.max(d.to_array()[c].abs() / (s.to_array()[c] + 1e-5));
            }
        }
    }
    assert!(lit > 0.05, "the scene is lit: {lit}");
    assert!(worst < 4.0, "largest block z {worst}");
}

/// `distributed` through media is a function of the seed, the pixel and
/// the sample alone: the same bits on 1 and 3 threads and in 3 passes,
/// with the thesis's metrics judging its sets. The shadow metric stops
/// sets whose first rays all let light through (here most: the fog only
/// dims them); the reflection metric judges the first vertex's set of
/// BSDF samples or phase directions on its members' whole paths.
#[test]
fn distributed_paths_in_media_are_the_same_on_any_threads_and_passes() {
    let toml = "[render]\nwidth = 20\nheight = 12\nintegrator = \"distributed\"\nspp = 3\n\
                seed = 2\nrr_depth = 2\nsets_depth = 2\nreflection_rays = 6\nshadow_rays = 8\n\
                metric = true\nmetric_min_rays = 2\nmetric_threshold = 0.2\nshadow_metric_rays = 2\n\n\
                [camera]\nposition = [0, 0.5, 4]\nlook_at = [0, 0, 0]\nfov = 40\n\n\
                [materials.boundary]\ntype = \"null\"\n\n\
                [materials.floor]\ntype = \"diffuse\"\n\n\
                [media.fog]\ntype = \"homogeneous\"\nsigma_t = [1, 2, 3]\nalbedo = 0.9\n\
                phase = { type = \"hg\", g = -0.3 }\n\n\
                [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
                interior = \"fog\"\n\n\
                [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-3, -1, 3]\n\
                edge_u = [6, 0, 0]\nedge_v = [0, 0, -6]\n\n\
                [[lights]]\ntype = \"point\"\nposition = [0.5, 2.5, 0.5]\nintensity = [5, 5, 5]\n\n\
                [[lights]]\ntype = \"rect\"\norigin = [-1.5, 2.5, 0]\nedge_u = [0.5, 0, 0]\n\
                edge_v = [0, 0, 0.5]\nradiance = [3, 3, 3]\n";
    let a = same_bits_on_threads_and_passes(toml, "spp = 3\n");
    assert!(a.media.scatterings > 0 && a.media.scattered > 0);
    // Both metrics stop sets: shadow sets, the floor's BSDF sets and the
    // fog's sets of phase directions.
    assert!(a.saved.shadow > 0 && a.shadow > 0, "{a:?}");
    assert!(a.saved.reflection > 0 && a.media.saved > 0, "{a:?}");
}

/// The mean of the pixels in [x0, x1) × [y0, y1), over the channels.
fn grey_mean(img: &Image, (x0, y0, x1, y1): (u32, u32, u32, u32)) -> f32 {
    let mut sum = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let v = img.get(x, y);
            assert!(v.is_finite(), "pixel ({x}, {y}) is {v:?}");
            sum += v.to_array().iter().sum::<f32>() / 3.0;
        }
    }
    sum / ((x1 - x0) * (y1 - y0)) as f32
}

/// The built-in `fog` needs no file, is rendered by `volpath`, and shows
/// its spot light's beam in the fog: at 64 × 48 pixels, the top of the
/// image where the beam crosses it (above the spheres, the unlit back wall
/// behind) is more than 3 times as bright as the top-left corner beside it,
/// which sees the same wall through unlit fog; with the fog emptied
/// (`sigma_t = 0`) the two are within a factor 2, the wall alone.
#[test]
fn the_fog_scene_shows_the_spot_lights_beam() {
    let fog = penumbra::scene::builtin::find("fog").expect("built-in fog");
    assert!(!fog.needs_bunny);
    let render = |toml: &str| {
        let mut src = penumbra::scene::SceneSource::from_toml(
            toml,
            std::path::Path::new("fog.toml"),
            std::path::Path::new("."),
            &penumbra::scene::LoadOptions::default(),
        )
        .expect("the fog scene reads");
        set(
            &mut src,
            penumbra::scene::Overrides {
                width: Some(64),
                height: Some(48),
                spp: Some(32),
                ..Default::default()
            },
        );
        let s = src.build().expect("the fog scene builds");
        assert_eq!(
            penumbra::integrator::Config::of(&s).unwrap().choice(),
            penumbra::scene::IntegratorChoice::Volpath
        );
        render_scene(&s, 2).0
    };
    let (beam, beside) = ((32, 0, 48, 8), (0, 0, 8, 8));
    let img = render(fog.toml);
    let (b, s) = (grey_mean(&img, beam), grey_mean(&img, beside));
    assert!(b > 3.0 * s, "in the beam {b}, beside it {s}");
    let empty = fog.toml.replace("sigma_t = 0.07", "sigma_t = 0.0");
    assert_ne!(empty, fog.toml);
    let img = render(&empty);
    let (b, s) = (grey_mean(&img, beam), grey_mean(&img, beside));
    assert!(b < 2.0 * s, "without fog: {b} and {s}");
}
