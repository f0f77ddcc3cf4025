//! Putting renders side by side: sRGB conversion, crops, enlargement, and a
//! grid of labelled panels written as an SVG document.

use std::path::Path;

use image::{Rgb, RgbImage};
use penumbra::io::output::to_srgb8;
use penumbra::render::Image;

use base64::prelude::{Engine, BASE64_STANDARD};

use crate::error::EvalError;

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

/// An image with its label above it.
#[derive(Clone, Debug)]
pub struct Panel {
    pub label: String,
    pub image: RgbImage,
}

/// Label font size in pixels for cells of a given width.
fn font_size(cell_width: u32) -> u32 {
    if cell_width >= 200 {
        16
    } else {
        12
    }
}

/// Panels in rows of `cols`, each under its label, on white, as an SVG
/// document: each panel is a PNG embedded as a data URL (so that the file
/// stands alone, also where it is shown through an `<img>`, which loads no
/// other file) and drawn pixel for pixel; each label is an SVG `<text>`, set
/// by the viewer, so that no font is read here. Panels of different sizes
/// get cells of the largest size.
pub fn grid(panels: &[Panel], cols: usize) -> Result<String, String> {
    let cols = cols.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(cols).max(1);
    let cw = panels.iter().map(|p| p.image.width()).max().unwrap_or(1);
    let ch = panels.iter().map(|p| p.image.height()).max().unwrap_or(1);
    let size = font_size(cw);
    let band = size + GAP;
    let (w, h) = (
        GAP + cols as u32 * (cw + GAP),
        GAP + rows as u32 * (band + ch + GAP),
    );
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"#FFFFFF\"/>\n"
    );
    for (i, p) in panels.iter().enumerate() {
        let (c, r) = ((i % cols) as u32, (i / cols) as u32);
        let x0 = GAP + c * (cw + GAP);
        let y0 = GAP + r * (band + ch + GAP);
        let png = png_bytes(&p.image).map_err(|e| e.to_string())?;
        out.push_str(&format!(
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-family=\"sans-serif\" \
             font-size=\"{size}\" fill=\"#141414\">{}</text>\n",
            x0 + cw / 2,
            y0 + size,
            escape(&fit_label(&p.label, cw, size))
        ));
        out.push_str(&format!(
            "<image x=\"{x0}\" y=\"{}\" width=\"{}\" height=\"{}\" \
             style=\"image-rendering:pixelated\" href=\"data:image/png;base64,{}\"/>\n",
            y0 + band,
            p.image.width(),
            p.image.height(),
            BASE64_STANDARD.encode(png)
        ));
    }
    out.push_str("</svg>\n");
    Ok(out)
}

/// The label, shortened with "…" if it would be wider than the cell
/// (reckoning a character at 0.6 of the font size, a generous width for a
/// sans-serif face).
fn fit_label(label: &str, width: u32, size: u32) -> String {
    let fits = ((f64::from(width) / (0.6 * f64::from(size))) as usize).max(4);
    if label.chars().count() <= fits {
        return label.to_string();
    }
    let mut s: String = label.chars().take(fits - 1).collect();
    s.push('…');
    s
}

/// Text with XML's special characters escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// An image encoded as PNG.
fn png_bytes(img: &RgbImage) -> image::ImageResult<Vec<u8>> {
    use image::ImageEncoder;
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes).write_image(
        img.as_raw(),
        img.width(),
        img.height(),
        image::ExtendedColorType::Rgb8,
    )?;
    Ok(bytes)
}

/// Writes a grid of panels ([`grid`]) as an SVG file, atomically.
pub fn save_grid(path: &Path, panels: &[Panel], cols: usize) -> Result<(), EvalError> {
    let svg = grid(panels, cols).map_err(|message| EvalError::Write {
        path: path.to_path_buf(),
        message,
    })?;
    crate::output::write_file(path, svg.as_bytes())
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

    /// Every panel comes back pixel for pixel from its data URL, in its
    /// cell, under its label.
    #[test]
    fn grid_places_every_panel_below_its_label() {
        let red = RgbImage::from_pixel(40, 30, Rgb([255, 0, 0]));
        let blue = RgbImage::from_fn(20, 30, |x, y| Rgb([0, x as u8, y as u8]));
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
                label: "x<&".into(),
                image: blue,
            },
        ];
        let svg = grid(&panels, 2).unwrap_or_default();
        let images = crate::chart::elements(&svg, "image");
        assert_eq!(images.len(), 3, "{svg}");
        let texts = crate::chart::texts(&svg);
        assert_eq!(texts.len(), 3, "{svg}");
        assert_eq!(texts[0], "a");
        assert_eq!(texts[2], "x<&");
        assert!(
            texts[1].starts_with("a l") && texts[1].ends_with('…'),
            "{texts:?}"
        );
        let labels = crate::chart::elements(&svg, "text");
        let num = crate::chart::number;
        for (i, (p, (img, label))) in panels.iter().zip(images.iter().zip(&labels)).enumerate() {
            let href = img
                .iter()
                .find(|a| a.0 == "href")
                .map_or("", |a| a.1.as_str());
            let data = href.strip_prefix("data:image/png;base64,").unwrap_or("");
            let bytes = BASE64_STANDARD.decode(data).unwrap_or_default();
            let back = image::load_from_memory(&bytes).map(|i| i.to_rgb8());
            assert_eq!(back.ok().as_ref(), Some(&p.image), "panel {i}");
            let (col, row) = ((i % 2) as f64, (i / 2) as f64);
            let cell = (40 + GAP) as f64;
            assert_eq!(num(img, "x"), f64::from(GAP) + col * cell);
            assert_eq!(num(img, "width"), f64::from(p.image.width()));
            // The label is centred over the cell, above the image.
            assert_eq!(num(label, "x"), f64::from(GAP) + col * cell + 20.0);
            assert!(num(label, "y") < num(img, "y"));
            assert!(num(img, "y") > row * 30.0);
        }
        let empty = grid(&[], 3).unwrap_or_default();
        assert!(
            empty.contains(&format!("width=\"{}\"", GAP + 1 + GAP)),
            "{empty}"
        );
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
