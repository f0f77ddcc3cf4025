//! The volumetric path tracer with spectral MIS (`volpathmis`) against
//! closed-form answers (transmittance through a slab, a volumetric
//! furnace), against `volpath` on the same scene, block by block, and its
//! determinism; and how much spectral MIS lowers the noise of a strongly
//! chromatic medium.

mod common;

use common::*;
use penumbra::math::Rgb;

/// An orthographic camera at z = 2 looking down −z at a slab of `medium`
/// (a `null` box, z from −1 to 0, wide in x and y) in front of a surface
/// emitting radiance 1, rendered by `integrator` with `render` keys.
fn slab(integrator: &str, medium: &str, render: &str) -> String {
    format!(
        "[render]\nwidth = 24\nheight = 24\nintegrator = \"{integrator}\"\nseed = 5\n{render}\n\
         [camera]\nprojection = \"orthographic\"\nview_width = 1\nposition = [0, 0, 2]\n\
         look_at = [0, 0, 0]\n\n\
         [materials.boundary]\ntype = \"null\"\n\n\
         [materials.black]\ntype = \"diffuse\"\nreflectance = [0, 0, 0]\n\n\
         [media.slab]\n{medium}\n\n\
         [[objects]]\ntype = \"cube\"\nmaterial = \"boundary\"\ninterior = \"slab\"\n\
         transform = {{ scale = [50, 50, 0.5], translate = [0, 0, -0.5] }}\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"black\"\n\
         origin = [-5, -5, -2]\nedge_u = [10, 0, 0]\nedge_v = [0, 10, 0]\n\
         emitter = {{ radiance = [1, 1, 1] }}\n"
    )
}

/// An absorbing slab of thickness 1 whose extinction differs by channel
/// keeps `exp(−σt)` in each channel, with spectral MIS and without (the
/// distances drawn by the path's channel, weighed by it alone); and
/// emission seen through it from a scattering slab agrees under both.
#[test]
fn an_absorbing_slab_transmits_exp_of_minus_its_optical_depth() {
    let sigma = [0.5f32, 1.0, 2.0];
    let want = Rgb::from_array(sigma.map(|s| (-s).exp()));
    let medium = "type = \"homogeneous\"\nsigma_t = [0.5, 1.0, 2.0]\nalbedo = 0";
    for mis in [true, false] {
        let render = format!("spp = 64\nuse_spectral_mis = {mis}");
        let (img, rays) = render_toml(&slab("volpathmis", medium, &render));
        let (got, err) = mean_and_error(&img);
        assert_within(got, err, want, &format!("use_spectral_mis = {mis}"));
        assert!(rays.media.scatterings > 1000, "{:?}", rays.media);
        assert_eq!(rays.media.null_collisions, 0);
    }
}

/// `hide_emitters` hides the emitter seen through the `null` boundary and
/// the medium (the camera ray has not scattered) but not the light it
/// scatters toward the camera: through a scattering slab the image less
/// the hidden image is the transmitted `exp(−σt)`.
#[test]
fn hidden_emitters_still_light_the_medium() {
    let medium = "type = \"homogeneous\"\nsigma_t = [0.5, 1.0, 2.0]\nalbedo = 0.7";
    let (seen, _) = render_toml(&slab("volpathmis", medium, "spp = 256"));
    let (hidden, _) = render_toml(&slab(
        "volpathmis",
        medium,
        "spp = 256\nhide_emitters = true",
    ));
    let ((a, ea), (b, eb)) = (mean_and_error(&seen), mean_and_error(&hidden));
    let want = Rgb::from_array([0.5f32, 1.0, 2.0].map(|s| (-s).exp()));
    assert!(b.min_element() > 0.05, "hidden {b:?}");
    assert_within(
        a - b,
        (ea * ea + eb * eb).map(f32::sqrt),
        want,
        "seen − hidden",
    );
}

/// A sphere of a medium that scatters all it stops (albedo 1, a
/// Henyey–Greenstein phase, an extinction that differs by channel)
/// behind a `null` boundary, in an environment of radiance 1, is `fog`.
fn furnace(integrator: &str, sigma_t: &str, spp: u32) -> String {
    format!(
        "[render]\nwidth = 16\nheight = 16\nintegrator = \"{integrator}\"\nspp = {spp}\n\
         seed = 9\nbackground = [1, 1, 1]\n\n\
         [camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 30\n\n\
         [materials.boundary]\ntype = \"null\"\n\n\
         [media.fog]\ntype = \"homogeneous\"\nsigma_t = {sigma_t}\nalbedo = 1\n\
         phase = {{ type = \"hg\", g = 0.6 }}\n\n\
         [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
         interior = \"fog\"\n"
    )
}

/// The volumetric furnace: the sphere can neither add nor remove light,
/// so every pixel is 1 within noise, its emission met after scatterings
/// weighed against next-event estimation through the medium.
#[test]
fn a_scattering_sphere_in_a_uniform_environment_is_invisible() {
    let (img, rays) = render_toml(&furnace("volpathmis", "[1, 2, 4]", 256));
    let (got, err) = mean_and_error(&img);
    assert_within(got, err, Rgb::ONE, "volumetric furnace");
    assert!(rays.media.scatterings > 20_000, "{:?}", rays.media);
    assert!(err.max_element() < 0.04, "noise {err:?}");
}

/// The furnace again with a heterogeneous medium whose extinction differs
/// by channel (a colour filling the unit cube, tracked against a majorant
/// the same in every channel, so that most tentative collisions of the red
/// and green channels are null ones), with spectral MIS and without: every
/// pixel is 1 within noise. (A far more chromatic extinction under a grey
/// majorant makes the blue channel's weights heavy-tailed, under `volpath`
/// as here, and its mean at a few hundred samples falls short.)
#[test]
fn a_chromatic_heterogeneous_cube_in_a_uniform_environment_is_invisible() {
    for mis in [true, false] {
        let toml = format!(
            "[render]\nwidth = 16\nheight = 16\nintegrator = \"volpathmis\"\nspp = 128\n\
             seed = 7\nbackground = [1, 1, 1]\nuse_spectral_mis = {mis}\n\n\
             [camera]\nposition = [0.5, 0.8, 3.5]\nlook_at = [0.5, 0.5, 0.5]\nfov = 24\n\n\
             [materials.boundary]\ntype = \"null\"\n\n\
             [media.smoke]\ntype = \"heterogeneous\"\nsigma_t = [1, 1.5, 2]\nscale = 1.5\n\
             albedo = 1\nphase = {{ type = \"hg\", g = -0.3 }}\n\n\
             [[objects]]\ntype = \"cube\"\nmaterial = \"boundary\"\ninterior = \"smoke\"\n\
             transform = {{ scale = 0.5, translate = [0.5, 0.5, 0.5] }}\n"
        );
        let (img, rays) = render_toml(&toml);
        let (got, err) = mean_and_error(&img);
        assert_within(got, err, Rgb::ONE, &format!("use_spectral_mis = {mis}"));
        assert!(rays.media.null_collisions > 10_000, "{:?}", rays.media);
        assert!(err.max_element() < 0.04, "noise {err:?}");
    }
}

/// Spectral MIS on a strongly chromatic medium: distances drawn by the
/// red channel's small extinction are rarely where the blue channel's
/// large one would put them, and `volpath` weighs them by the one channel
/// alone; `volpathmis` weighs them by the mean of the three. Both hold
/// the furnace's 1; the variance of `volpathmis`'s pixels is well below
/// `volpath`'s at the same samples.
#[test]
fn spectral_mis_lowers_the_noise_of_a_chromatic_medium() {
    let sigma = "[0.25, 2, 16]";
    let (plain, _) = render_toml(&furnace("volpath", sigma, 64));
    let (mis, _) = render_toml(&furnace("volpathmis", sigma, 64));
    let (a, ea) = mean_and_error(&plain);
    let (b, eb) = mean_and_error(&mis);
    // `volpath`'s weights are heavy-tailed here (a distance drawn by the
    // blue channel weighs the red one by up to `exp(σ_b t) / σ_b`), so its
    // mean at these samples is not held to 1.
    assert_within(b, eb, Rgb::ONE, "volpathmis");
    let ratio = (eb * eb) / (ea * ea);
    println!(
        "volpath {a:?} ± {ea:?}, volpathmis {b:?} ± {eb:?}; \
         variance volpathmis / volpath per channel: {ratio:?}"
    );
    assert!(
        ratio.max_element() < 0.5,
        "variance ratio {ratio:?} (volpath ± {ea:?}, volpathmis ± {eb:?})"
    );
}

/// A chromatic scattering sphere behind a `null` boundary over a diffuse
/// floor, lit by a small area light and a dim environment.
fn lit_fog(integrator: &str, render: &str) -> String {
    format!(
        "[render]\nwidth = 24\nheight = 24\nintegrator = \"{integrator}\"\nseed = 3\n\
         background = [0.2, 0.25, 0.3]\n{render}\n\n\
         [camera]\nposition = [0, 0.6, 4]\nlook_at = [0, 0, 0]\nfov = 38\n\n\
         [materials.boundary]\ntype = \"null\"\n\n\
         [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.6, 0.5, 0.4]\n\n\
         [materials.black]\ntype = \"diffuse\"\nreflectance = [0, 0, 0]\n\n\
         [media.fog]\ntype = \"homogeneous\"\nsigma_t = [0.5, 1.5, 4]\n\
         albedo = [0.9, 0.8, 0.6]\nphase = {{ type = \"hg\", g = 0.3 }}\n\n\
         [[objects]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"boundary\"\n\
         interior = \"fog\"\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"floor\"\norigin = [-4, -1, 4]\n\
         edge_u = [8, 0, 0]\nedge_v = [0, 0, -8]\n\n\
         [[objects]]\ntype = \"quad\"\nmaterial = \"black\"\norigin = [-0.5, 2.5, 0.5]\n\
         edge_u = [1, 0, 0]\nedge_v = [0, 0, -1]\nemitter = {{ radiance = [20, 20, 20] }}\n"
    )
}

/// The mean over `replicas` renders of `toml` (its `seed = 3` replaced by
/// seeds 100, 101, …) of each 4 × 4 block of its 24 × 24 pixels, and the
/// standard error of that mean from the replicas' spread.
fn replicated_blocks(toml: &str, replicas: u32) -> Vec<(Rgb, Rgb)> {
    let mut sums = vec![(Rgb::ZERO, Rgb::ZERO); 36];
    for r in 0..replicas {
        let (img, _) = render_toml(&toml.replace("seed = 3\n", &format!("seed = {}\n", 100 + r)));
        for (k, (sum, sq)) in sums.iter_mut().enumerate() {
            let (bx, by) = (k as u32 % 6, k as u32 / 6);
            let (m, _) = block_mean(&img, (4 * bx, 4 * bx + 4), (4 * by, 4 * by + 4));
            *sum += m;
            *sq += m * m;
        }
    }
    let n = replicas as f32;
    sums.into_iter()
        .map(|(sum, sq)| {
            let mean = sum / n;
            let var = (sq / n - mean * mean).map(|v| v.max(0.0)) * (n / (n - 1.0));
            (mean, (var / n).map(f32::sqrt))
        })
        .collect()
}

/// `volpathmis` and `volpath` estimate the same image: on a chromatic
/// medium lit through next-event estimation and emission met, every 4 × 4
/// block of pixels agrees in every channel, each block's mean and error
/// from 16 independent renders (|t| < 5 over the 108 tests, 15 degrees of
/// freedom each).
#[test]
fn volpathmis_agrees_with_volpath_block_by_block() {
    let render = "spp = 64\nrr_depth = 3";
    let (_, rays) = render_toml(&lit_fog("volpathmis", render));
    assert!(
        rays.media.scatterings > 1000 && rays.shadow > 1000,
        "{rays:?}"
    );
    let a = replicated_blocks(&lit_fog("volpath", render), 16);
    let b = replicated_blocks(&lit_fog("volpathmis", render), 16);
    let mut worst = 0.0f32;
    for (k, ((ma, ea), (mb, eb))) in a.iter().zip(&b).enumerate() {
        for c in 0..3 {
            let d = ma.to_array()[c] - mb.to_array()[c];
            let e = (*ea * *ea + *eb * *eb).to_array()[c].sqrt();
            let t = if d == 0.0 { 0.0 } else { d / e };
            worst = worst.max(t.abs());
            assert!(
                t.abs() < 5.0,
                "block {k} channel {c}: volpath {ma:?} ± {ea:?}, volpathmis {mb:?} ± {eb:?}"
            );
        }
    }
    println!("largest |t| over the blocks: {worst}");
}

/// `volpathmis`'s paths are a function of the seed, the pixel and the
/// sample alone: the same bits on 1 and 3 threads and in 3 passes.
#[test]
fn volpathmis_paths_are_the_same_on_any_threads_and_passes() {
    let toml = lit_fog("volpathmis", "spp = 6\nrr_depth = 2");
    let a = same_bits_on_threads_and_passes(&toml, "spp = 6\n");
    assert!(a.media.scatterings > 0 && a.shadow > 0);
}
