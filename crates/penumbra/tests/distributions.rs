//! The distributions through the renderer: what a set's place in the frame
//! does to an image.

mod common;

use common::*;

/// A floor under a large square light, half shadowed by a bar at height 1,
/// seen from below the light: a penumbra across the whole 64×64 image, one
/// camera ray and `shadow` shadow rays per pixel from `distribution`.
fn penumbra(distribution: &str, shadow: u32, seed: u32) -> penumbra::render::Image {
    let (image, _) = render_toml(&format!(
        r#"
[render]
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
