//! Putting renders side by side: sRGB conversion, crops, enlargement, a
//! grid of labelled panels, and writing PNGs atomically.

use std::path::Path;

use image::{Rgb, RgbImage};
use penumbra::io::output::to_srgb8;
use penumbra::render::Image;

use crate::error::EvalError;
use penumbra::io::font::{draw_text, text_width, HEIGHT};

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
const INK: Rgb<u8> = Rgb([20, 20, 20]);
/// Pixels between panels and around the grid.
const GAP: u32 = 8;

/// A linear render as 8-bit sRGB, the way `penumbra render` writes PNGs.
pub fn to_rgb8(image: &Image) -> RgbImage {
    let bytes = to_srgb8(image);
    RgbImage::from_raw(image.width, image.height, bytes)
        .unwrap_or_else(|| RgbImage::new(image.width, image.height))
}

/// `|a − b| · gain` per channel, in linear radiance; the smaller size if they differ.
pub fn difference(a: &Image, b: &Image, gain: f32) -> Image {
    let (w, h) = (a.width.min(b.width), a.height.min(b.height));
    let mut out = Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            out.pixels[(y * w + x) as usize] = (a.get(x, y) - b.get(x, y)).abs() * gain;
        }
    }
    out
}

/// Each pixel repeated `k × k` times, so that aliasing and noise stay visible.
pub fn enlarge(img: &RgbImage, k: u32) -> RgbImage {
    let k = k.max(1);
    RgbImage::from_fn(img.width() * k, img.height() * k, |x, y| {
        *img.get_pixel(x / k, y / k)
    })
}

/// The mean of each `k × k` block (for whole frames shown small).
pub fn shrink(img: &RgbImage, k: u32) -> RgbImage {
    let k = k.max(1);
    let (w, h) = ((img.width() / k).max(1), (img.height() / k).max(1));
    RgbImage::from_fn(w, h, |x, y| {
        let mut sum = [0u32; 3];
        let mut n = 0;
        for dy in 0..k {
            for dx in 0..k {
                if let Some(p) = img.get_pixel_checked(x * k + dx, y * k + dy) {
                    for (s, v) in sum.iter_mut().zip(p.0) {
                        *s += u32::from(v);
                    }
                    n += 1;
                }
            }
        }
        Rgb(sum.map(|s| (s / n.max(1)) as u8))
    })
}

/// An image with the label drawn above it.
#[derive(Clone, Debug)]
pub struct Panel {
    pub label: String,
    pub image: RgbImage,
}

/// Panels in rows of `cols`, each under its label, on white. Panels of
/// different sizes get cells of the largest size.
pub fn grid(panels: &[Panel], cols: usize) -> RgbImage {
    let cols = cols.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(cols).max(1);
    let cw = panels.iter().map(|p| p.image.width()).max().unwrap_or(1);
    let ch = panels.iter().map(|p| p.image.height()).max().unwrap_or(1);
    let scale = if cw >= 200 { 2 } else { 1 };
    let band = (HEIGHT * scale) as u32 + 2 * GAP / 2 + 2;
    let (w, h) = (
        GAP + cols as u32 * (cw + GAP),
        GAP + rows as u32 * (band + ch + GAP),
    );
    let mut out = RgbImage::from_pixel(w, h, WHITE);
    for (i, p) in panels.iter().enumerate() {
        let (c, r) = ((i % cols) as u32, (i / cols) as u32);
        let x0 = GAP + c * (cw + GAP);
        let y0 = GAP + r * (band + ch + GAP);
        let label = fit_label(&p.label, cw, scale);
        let tw = text_width(&label, scale);
        let tx = i64::from(x0) + (i64::from(cw) - tw) / 2;
        draw_text(&mut out, tx, i64::from(y0) + 2, &label, scale, INK);
        image::imageops::replace(&mut out, &p.image, i64::from(x0), i64::from(y0 + band));
    }
    out
}

/// The label, shortened with "..." if it would be wider than the cell.
fn fit_label(label: &str, width: u32, scale: i64) -> String {
    if text_width(label, scale) <= i64::from(width) {
        return label.to_string();
    }
    let fits = (i64::from(width) / (6 * scale)).max(4) as usize;
    let mut s: String = label.chars().take(fits - 3).collect();
    s.push_str("...");
    s
}

/// Encodes an image as PNG and writes it atomically.
pub fn save_png(path: &Path, img: &RgbImage) -> Result<(), EvalError> {
    use image::ImageEncoder;
    let err = |message: String| EvalError::Write {
        path: path.to_path_buf(),
        message,
    };
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| err(e.to_string()))?;
    crate::output::write_file(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enlarge_and_shrink_undo_each_other() {
        let img = RgbImage::from_fn(3, 2, |x, y| Rgb([x as u8 * 50, y as u8 * 50, 7]));
        let big = enlarge(&img, 4);
        assert_eq!(big.dimensions(), (12, 8));
        assert_eq!(big.get_pixel(11, 7), img.get_pixel(2, 1));
        assert_eq!(shrink(&big, 4), img);
    }

    #[test]
    fn grid_places_every_panel_below_its_label() {
        let red = RgbImage::from_pixel(40, 30, Rgb([255, 0, 0]));
        let blue = RgbImage::from_pixel(20, 30, Rgb([0, 0, 255]));
        let panels = [
            Panel {
                label: "a".into(),
                image: red,
            },
            Panel {
                label: "a long label that does not fit".into(),
                image: blue.clone(),
            },
            Panel {
                label: "c".into(),
                image: blue,
            },
        ];
        let g = grid(&panels, 2);
        let count = |c: [u8; 3]| g.pixels().filter(|p| p.0 == c).count();
        assert_eq!(count([255, 0, 0]), 40 * 30);
        assert_eq!(count([0, 0, 255]), 2 * 20 * 30);
        assert!(g.pixels().any(|p| p.0 == INK.0));
        assert_eq!(grid(&[], 3).width(), GAP + 1 + GAP);
    }

    #[test]
    fn difference_is_absolute_and_amplified() {
        let mut a = Image::new(2, 1);
        let b = Image::new(2, 1);
        a.pixels[1] = penumbra::math::Rgb::new(0.1, -0.2, 0.0);
        let d = difference(&a, &b, 10.0);
        assert!((d.pixels[1].r - 1.0).abs() < 1e-6 && (d.pixels[1].g - 2.0).abs() < 1e-6);
    }
}
