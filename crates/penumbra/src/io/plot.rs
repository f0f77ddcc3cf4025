//! Pictures of ray distributions, like Figure 2.18 of the thesis: to check a
//! distribution by eye and to document it.
//!
//! Deliberately minimal: plain pixels in an [`RgbImage`], the 5×7 bitmap
//! [`font`](super::font) for the titles, no dependency beyond `image`.

use image::{Rgb, RgbImage};

use super::font::{draw_text, put, text_width};
use crate::math::Vec3;
use crate::sampling::{Distribution, Rng};

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
const OUTLINE: Rgb<u8> = Rgb([150, 150, 150]);
const GUIDE: Rgb<u8> = Rgb([200, 200, 215]);
const DOT: Rgb<u8> = Rgb([25, 55, 150]);
const TEXT: Rgb<u8> = Rgb([20, 20, 20]);

/// Draws `points` (their x and y; z is ignored, so fast-random shows its
/// cube from above) on a `size x size` white image: the `[-r, r]^2` square
/// outline, a small cross at the centre (the original ray), the radius-`r`
/// circle when `title` names the `random` distribution (its domain), each
/// point as a filled dot, and `title` at the top. Points that are not finite
/// are skipped; a zero or non-finite radius is drawn as if it were 1.
pub fn draw_points(points: &[Vec3], radius: f32, size: u32, title: &str) -> RgbImage {
    let mut img = RgbImage::from_pixel(size, size, WHITE);
    let layout = Layout::new(size, radius);
    layout.draw_frame(
        &mut img,
        Distribution::from_name(title) == Some(Distribution::Random),
    );
    for p in points {
        if let Some((x, y)) = layout.to_pixel(p.x, p.y) {
            fill_disk(&mut img, x, y, layout.dot, DOT);
        }
    }
    let scale = layout.scale;
    let x = (i64::from(size) - text_width(title, scale)) / 2;
    draw_text(&mut img, x, 3 * scale, title, scale, TEXT);
    img
}

/// Panels per row of [`draw_all`].
const COLUMNS: u32 = 6;

/// Every distribution side by side (rows of six panels of `size x
/// size`, in the order of [`Distribution::ALL`]: the thesis's six, then the
/// low-discrepancy sets), each with `count` points of radius `radius` and
/// titled with its name. Panel `i` uses the stream
/// `Rng::new(seed).derive(i)`, so the picture is reproducible.
pub fn draw_all(count: usize, radius: f32, seed: u64, size: u32) -> RgbImage {
    let rows = (Distribution::ALL.len() as u32).div_ceil(COLUMNS);
    let mut img = RgbImage::from_pixel(COLUMNS * size, rows * size, WHITE);
    let root = Rng::new(seed);
    let mut points = Vec::new();
    for (i, d) in Distribution::ALL.into_iter().enumerate() {
        d.generate(count, radius, &mut root.derive(i as u64), &mut points);
        let panel = draw_points(&points, radius, size, d.name());
        let (col, row) = (i as u32 % COLUMNS, i as u32 / COLUMNS);
        blit(&mut img, &panel, col * size, row * size);
    }
    img
}

/// Where things go in a panel: a title band on top, the square below it.
struct Layout {
    /// Pixel size of one font pixel, and the unit of margins.
    scale: i64,
    /// Top-left corner and side of the square, in pixels.
    x0: f32,
    y0: f32,
    side: f32,
    radius: f32,
    dot: i64,
}

impl Layout {
    fn new(size: u32, radius: f32) -> Self {
        let size = i64::from(size);
        let scale = (size / 120).max(1);
        let band = 13 * scale;
        let side = (size - band - 6 * scale).min(size - 12 * scale).max(1) as f32;
        let usable = radius.is_finite() && radius != 0.0;
        Layout {
            scale,
            x0: (size as f32 - side) / 2.0,
            y0: band as f32,
            side,
            radius: if usable { radius.abs() } else { 1.0 },
            dot: ((side / 60.0) as i64).max(2),
        }
    }

    /// Pixel of the point `(x, y)` (y up), `None` if not finite.
    fn to_pixel(&self, x: f32, y: f32) -> Option<(i64, i64)> {
        let u = self.x0 + (x / self.radius + 1.0) * 0.5 * self.side;
        let v = self.y0 + (1.0 - y / self.radius) * 0.5 * self.side;
        (u.is_finite() && v.is_finite()).then(|| (u.round() as i64, v.round() as i64))
    }

    /// The outline, the centre cross and (under the outline) the circle.
    fn draw_frame(&self, img: &mut RgbImage, circle: bool) {
        let r = self.radius;
        if circle {
            let steps = (4.0 * self.side) as usize;
            for k in 0..steps {
                let (s, c) = (std::f32::consts::TAU * k as f32 / steps as f32).sin_cos();
                if let Some((x, y)) = self.to_pixel(r * c, r * s) {
                    put(img, x, y, GUIDE);
                }
            }
        }
        let corners = [(-r, -r), (r, -r), (r, r), (-r, r), (-r, -r)];
        for w in corners.windows(2) {
            self.line(img, w[0], w[1], OUTLINE);
        }
        let arm = 0.04 * r;
        self.line(img, (-arm, 0.0), (arm, 0.0), GUIDE);
        self.line(img, (0.0, -arm), (0.0, arm), GUIDE);
    }

    /// A straight line between two points in world units.
    fn line(&self, img: &mut RgbImage, a: (f32, f32), b: (f32, f32), color: Rgb<u8>) {
        let (Some(p), Some(q)) = (self.to_pixel(a.0, a.1), self.to_pixel(b.0, b.1)) else {
            return;
        };
        let steps = (q.0 - p.0).abs().max((q.1 - p.1).abs()).max(1);
        for k in 0..=steps {
            let x = p.0 + (q.0 - p.0) * k / steps;
            put(img, x, p.1 + (q.1 - p.1) * k / steps, color);
        }
    }
}

fn fill_disk(img: &mut RgbImage, cx: i64, cy: i64, r: i64, color: Rgb<u8>) {
    for dy in -r..=r {
        for dx in -r..=r {
            if dx * dx + dy * dy <= r * r + r {
                put(img, cx + dx, cy + dy, color);
            }
        }
    }
}

fn blit(dst: &mut RgbImage, src: &RgbImage, x0: u32, y0: u32) {
    for (x, y, &p) in src.enumerate_pixels() {
        put(dst, i64::from(x0 + x), i64::from(y0 + y), p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn is_white(p: &Rgb<u8>) -> bool {
        *p == WHITE
    }

    #[test]
    fn points_land_where_they_should() {
        let size = 200;
        let img = draw_points(&[Vec3::ZERO, Vec3::new(0.5, 0.5, 0.0)], 1.0, size, "grid");
        let layout = Layout::new(size, 1.0);
        for (x, y) in [(0.0, 0.0), (0.5, 0.5)] {
            let (px, py) = layout.to_pixel(x, y).unwrap_or((-1, -1));
            assert_eq!(img.get_pixel(px as u32, py as u32), &DOT, "({x}, {y})");
        }
        // Empty quadrant interior stays white; the title band has ink.
        let (qx, qy) = layout.to_pixel(-0.5, -0.5).unwrap_or((0, 0));
        assert!(is_white(img.get_pixel(qx as u32, qy as u32)));
        let band = (0..size).flat_map(|x| (0..12).map(move |y| (x, y)));
        assert!(band.into_iter().any(|(x, y)| img.get_pixel(x, y) == &TEXT));
    }

    #[test]
    fn circle_only_for_random() {
        let size = 200;
        let layout = Layout::new(size, 1.0);
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let on_circle = |img: &RgbImage| {
            let (x, y) = layout.to_pixel(h, h).unwrap_or((0, 0));
            let near = (-1..=1).flat_map(|dx| (-1..=1).map(move |dy| (x + dx, y + dy)));
            near.into_iter()
                .any(|(x, y)| img.get_pixel(x as u32, y as u32) == &GUIDE)
        };
        assert!(on_circle(&draw_points(&[], 1.0, size, "random")));
        assert!(!on_circle(&draw_points(&[], 1.0, size, "jitter")));
    }

    #[test]
    fn draw_all_has_a_panel_each_and_odd_inputs_are_safe() {
        let img = draw_all(16, 1.0, 7, 120);
        assert_eq!((img.width(), img.height()), (720, 240));
        for i in 0..Distribution::ALL.len() as u32 {
            let (col, row) = (i % COLUMNS, i / COLUMNS);
            let ink = (0..120)
                .flat_map(|x| (20..120).map(move |y| (x, y)))
                .filter(|&(x, y)| img.get_pixel(col * 120 + x, row * 120 + y) == &DOT)
                .count();
            assert!(ink > 16 * 4, "panel ({col}, {row}) has {ink} dot pixels");
        }
        for size in [0, 1, 5, 13] {
            let small = draw_points(&[Vec3::splat(f32::NAN), Vec3::ONE], f32::NAN, size, "x?");
            assert_eq!(small.width(), size);
        }
        let _ = draw_all(0, -2.0, 0, 3);
    }
}
