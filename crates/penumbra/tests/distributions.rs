//! The distributions through the renderer: what a set's place in the frame
//! does to an image.

mod common;

use common::*;

/// A floor under a large square light, half shadowed by a bar at height 1,
/// seen from below the light: a penumbra across the whole 64×64 image, one
/// camera ray and `shadow` shadow rays per pixel from `distribution`.
fn penumbra(distribution: &str, shadow: u32, seed: u32) -> penumbra::render::Image {
    penumbra_with(distribution, shadow, seed, "")
}

/// [`penumbra`] with more `[render]` keys.
fn penumbra_with(
    distribution: &str,
    shadow: u32,
    seed: u32,
    keys: &str,
) -> penumbra::render::Image {
    let (image, _) = render_toml(&format!(
        r#"
[render]
{keys}
width = 64
height = 64
seed = {seed}
shadow_rays = {shadow}
shadow_distribution = "{distribution}"

[camera]
position = [0.35, 2.5, 0.0]
look_at = [0.35, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 12

[[objects]]
type = "quad"
origin = [-50.0, 0.0, -50.0]
edge_u = [0.0, 0.0, 100.0]
edge_v = [100.0, 0.0, 0.0]

[[objects]]
type = "quad"
origin = [-20.0, 1.0, -20.0]
edge_u = [20.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 40.0]

[[lights]]
type = "rect"
origin = [-1.5, 3.0, -1.5]
edge_u = [3.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 3.0]
radiance = [5.0, 5.0, 5.0]
"#
    ));
    image
}

/// RMSE against `reference` of the means of `b`×`b` blocks of pixels.
fn block_rmse(image: &penumbra::render::Image, reference: &penumbra::render::Image, b: u32) -> f64 {
    let mut sum = 0.0;
    let mut blocks = 0;
    for by in (0..image.height).step_by(b as usize) {
        for bx in (0..image.width).step_by(b as usize) {
            let mut e = 0.0;
            for y in by..by + b {
                for x in bx..bx + b {
                    e += f64::from(image.get(x, y).r) - f64::from(reference.get(x, y).r);
                }
            }
            sum += (e / f64::from(b * b)).powi(2);
            blocks += 1;
        }
    }
    (sum / f64::from(blocks)).sqrt()
}

/// With one shadow ray a pixel, `zsobol`'s pixels of a Morton quad share one
/// net, so the error of the mean of a 2×2 or 4×4 block is far smaller than
/// with `sobol`, whose sets are scrambled apart, while single pixels are
/// as noisy: the error is spread as blue noise.
#[test]
fn zsobol_spreads_the_error_over_neighbouring_pixels() {
    let reference = penumbra("jitter", 1024, 1);
    let mut errors = [[0.0; 3]; 2];
    for seed in 1..=3 {
        for (k, d) in ["sobol", "zsobol"].iter().enumerate() {
            let image = penumbra(d, 1, seed);
            for (j, b) in [1, 2, 4].into_iter().enumerate() {
                errors[k][j] += block_rmse(&image, &reference, b) / 3.0;
            }
        }
    }
    let [sobol, zsobol] = errors;
    eprintln!("block RMSE (1, 2, 4): sobol {sobol:?}, zsobol {zsobol:?}");
    assert!(
        zsobol[0] > 0.7 * sobol[0],
        "pixels: {zsobol:?} vs {sobol:?}"
    );
    assert!(zsobol[1] < 0.7 * sobol[1], "2x2: {zsobol:?} vs {sobol:?}");
    assert!(zsobol[2] < 0.5 * sobol[2], "4x4: {zsobol:?} vs {sobol:?}");
}

fn rmse(image: &penumbra::render::Image, reference: &penumbra::render::Image) -> f64 {
    block_rmse(image, reference, 1)
}

/// The mean of the red channel over the image.
fn mean(image: &penumbra::render::Image) -> f64 {
    let mut sum = 0.0;
    for y in 0..image.height {
        for x in 0..image.width {
            sum += f64::from(image.get(x, y).r);
        }
    }
    sum / f64::from(image.width * image.height)
}

/// Writes `sets` as a JSON points file and as a `.npy` of float64 (shape
/// (S, N, 2)) in `dir`.
fn points_files(
    dir: &std::path::Path,
    sets: &[Vec<[f64; 2]>],
) -> (std::path::PathBuf, std::path::PathBuf) {
    let json = dir.join("points.json");
    std::fs::write(&json, serde_json::to_string(sets).unwrap()).unwrap();
    let shape = format!("({}, {}, 2)", sets.len(), sets[0].len());
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    bytes.extend(
        sets.iter()
            .flatten()
            .flatten()
            .flat_map(|v| v.to_le_bytes()),
    );
    let npy = dir.join("points.npy");
    std::fs::write(&npy, bytes).unwrap();
    (json, npy)
}

/// A 16-point Hammersley set, `((i + dx) / 16, (radical_inverse_2(i) + dy /
/// 16))`: a (0,4,2)-net for any `dx`, `dy` in `[0, 1)`.
fn net(dx: f64, dy: f64) -> Vec<[f64; 2]> {
    (0..16u32)
        .map(|i| {
            let y = f64::from(i.reverse_bits() >> 28) / 16.0;
            [(f64::from(i) + dx) / 16.0, y + dy / 16.0]
        })
        .collect()
}

/// `custom` with the user's sets: the same image from a JSON file and from
/// a `.npy` of the same points; unbiased (its image's mean is the
/// reference's); and as good as the points are: a 16-point net, randomly
/// shifted per ray set, is far better than 16 independent random points
/// and, on this penumbra whose edges are parallel to the light's sides,
/// better than `jitter`: a net has 16 strata along each axis, jitter 4
/// columns of 4 random points.
#[test]
fn custom_draws_the_users_sets() {
    let dir = tempfile::tempdir().unwrap();
    let sets = [net(0.5, 0.5), net(0.25, 0.75), net(0.75, 0.25)];
    let (json, npy) = points_files(dir.path(), &sets);
    let keys = |path: &std::path::Path| format!("points = {:?}", path.to_str().unwrap());
    let reference = penumbra("jitter", 1024, 1);
    let (mut custom, mut jitter, mut random, mut bias) = (0.0, 0.0, 0.0, 0.0);
    for seed in 1..=3 {
        let from_json = penumbra_with("custom", 16, seed, &keys(&json));
        let from_npy = penumbra_with("custom", 16, seed, &keys(&npy));
        assert!(from_json.pixels == from_npy.pixels, "seed {seed}");
        custom += rmse(&from_json, &reference) / 3.0;
        bias += (mean(&from_json) - mean(&reference)) / 3.0;
        jitter += rmse(&penumbra("jitter", 16, seed), &reference) / 3.0;
        random += rmse(&penumbra("random", 16, seed), &reference) / 3.0;
    }
    eprintln!("RMSE: custom {custom:.4}, jitter {jitter:.4}, random {random:.4}; bias {bias:.5}");
    assert!(custom < 0.7 * random, "custom {custom} random {random}");
    assert!(custom < 0.7 * jitter, "custom {custom} jitter {jitter}");
    // Pixels' errors are independent: the mean's standard error is about
    // RMSE / sqrt(pixels · seeds); five of them is no bias.
    let standard_error = custom / (64.0 * 3f64.sqrt());
    assert!(
        bias.abs() < 5.0 * standard_error,
        "bias {bias}, standard error {standard_error}"
    );
}

/// A scene's `points` path is taken from the scene file's folder.
#[test]
fn points_files_are_found_beside_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    points_files(dir.path(), &[net(0.5, 0.5)]);
    let scene = dir.path().join("s.toml");
    let text =
        "[render]\nwidth = 8\nheight = 8\ndistribution = \"custom\"\npoints = \"points.json\"\n";
    std::fs::write(&scene, text).unwrap();
    let opts = penumbra::scene::LoadOptions::default();
    let source = penumbra::scene::SceneSource::open(scene.to_str().unwrap(), &opts).unwrap();
    let built = source.build().unwrap();
    assert_eq!(built.custom_set_sizes(), [1]);
    assert!(!built.settings.points.is_none());
}
