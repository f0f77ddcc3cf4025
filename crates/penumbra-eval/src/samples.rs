//! Pictures of ray distributions, like Figure 2.18 of the thesis, drawn by
//! `plotters` as SVG (`penumbra samples --format svg`): to check a
//! distribution by eye and to document it. Titles are SVG `<text>`: no font
//! files are read.

use plotters::coord::Shift;
use plotters::prelude::*;

use penumbra::math::Vec3;
use penumbra::sampling::{Distribution, Domain, Rng};

/// Side of the panel of one distribution, in pixels.
pub const PANEL: u32 = 512;
/// Side of each panel of [`draw_all`], in pixels.
pub const SMALL_PANEL: u32 = 320;
/// Panels per row of [`draw_all`].
pub const COLUMNS: u32 = 6;

const OUTLINE: RGBColor = RGBColor(150, 150, 150);
const GUIDE: RGBColor = RGBColor(200, 200, 215);
const DOT: RGBColor = RGBColor(25, 55, 150);
const INK: RGBColor = RGBColor(20, 20, 20);

type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// `points` (their x and y; z is ignored, so fast-random shows its cube
/// from above) as an SVG of [`PANEL`]² pixels: the `[-r, r]²` square
/// outline, a small cross at the centre (the original ray), the radius-`r`
/// circle when `title` names the `random` distribution (its domain), each
/// point as a filled dot, and `title` at the top. Points that are not
/// finite are left out; a zero or non-finite radius is drawn as if it were 1.
pub fn draw_points(points: &[Vec3], radius: f32, title: &str) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (PANEL, PANEL)).into_drawing_area();
        panel(&root, points, radius, title).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Every distribution side by side, in rows of [`COLUMNS`] panels of
/// [`SMALL_PANEL`]² pixels in the order of [`Distribution::ALL`] (the
/// thesis's six, then the low-discrepancy sets), each with `count` points
/// of radius `radius` and titled with its name. Panel `i` uses the stream
/// `Rng::new(seed).derive(i)`, so the picture is reproducible.
pub fn draw_all(count: usize, radius: f32, seed: u64) -> Result<String, String> {
    let n = Distribution::ALL.len() as u32;
    let rows = n.div_ceil(COLUMNS);
    let size = (COLUMNS * SMALL_PANEL, rows * SMALL_PANEL);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let cells = root.split_evenly((rows as usize, COLUMNS as usize));
        let stream = Rng::new(seed);
        let mut points = Vec::new();
        for (i, (d, cell)) in Distribution::ALL.into_iter().zip(&cells).enumerate() {
            d.generate(count, radius, &mut stream.derive(i as u64), &mut points);
            panel(cell, &points, radius, d.name()).map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// One distribution's panel on `area`: the title band on top, the square
/// centred below it.
fn panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    points: &[Vec3],
    radius: f32,
    title: &str,
) -> DrawResult {
    area.fill(&WHITE)?;
    let (w, _) = area.dim_in_pixel();
    let font = (w / 20).max(8);
    let below = area.titled(title, ("sans-serif", font).into_font().color(&INK))?;
    let (bw, bh) = below.dim_in_pixel();
    let pad = font / 2;
    let side = bw.min(bh).saturating_sub(2 * pad).max(1);
    let (dx, dy) = (bw - side.min(bw), bh - side.min(bh));
    let square = below.margin(dy / 2, dy - dy / 2, dx / 2, dx - dx / 2);
    let r = if radius.is_finite() && radius != 0.0 {
        f64::from(radius.abs())
    } else {
        1.0
    };
    let mut chart = ChartBuilder::on(&square).build_cartesian_2d(-r..r, -r..r)?;
    if Distribution::from_name(title).map(Distribution::domain) == Some(Domain::Disk) {
        let circle = (0..=256).map(|k| {
            let (s, c) = (std::f64::consts::TAU * f64::from(k) / 256.0).sin_cos();
            (r * c, r * s)
        });
        chart.draw_series(LineSeries::new(circle, GUIDE.stroke_width(1)))?;
    }
    chart.draw_series(std::iter::once(Rectangle::new(
        [(-r, -r), (r, r)],
        OUTLINE.stroke_width(1),
    )))?;
    let arm = 0.04 * r;
    chart.draw_series([
        PathElement::new([(-arm, 0.0), (arm, 0.0)], GUIDE.stroke_width(1)),
        PathElement::new([(0.0, -arm), (0.0, arm)], GUIDE.stroke_width(1)),
    ])?;
    let dot = (side / 120).max(2);
    chart.draw_series(
        points
            .iter()
            .filter(|p| p.x.is_finite() && p.y.is_finite())
            .map(|p| Circle::new((f64::from(p.x), f64::from(p.y)), dot, DOT.filled())),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chart::{elements, number, texts};

    fn attr<'a>(attrs: &'a [(String, String)], name: &str) -> &'a str {
        attrs
            .iter()
            .find(|a| a.0 == name)
            .map_or("", |a| a.1.as_str())
    }

    /// The outline's rectangle: (left, top, width, height).
    fn outlines(svg: &str) -> Vec<(f64, f64, f64, f64)> {
        elements(svg, "rect")
            .iter()
            .filter(|r| attr(r, "stroke") == "#969696")
            .map(|r| {
                let n = |k| number(r, k);
                (n("x"), n("y"), n("width"), n("height"))
            })
            .collect()
    }

    fn dots(svg: &str) -> Vec<(f64, f64)> {
        elements(svg, "circle")
            .iter()
            .filter(|c| attr(c, "fill") == "#193796")
            .map(|c| (number(c, "cx"), number(c, "cy")))
            .collect()
    }

    #[test]
    fn points_land_where_they_should() {
        let pts = [
            Vec3::ZERO,
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(-1.0, -1.0, 3.0),
            Vec3::splat(f32::NAN),
        ];
        let svg = draw_points(&pts, 1.0, "grid").unwrap_or_default();
        let o = outlines(&svg);
        assert_eq!(o.len(), 1, "{svg}");
        let (x, y, w, h) = o[0];
        assert!((w - h).abs() <= 1.0, "a square: {w} × {h}");
        assert!(w > 0.8 * f64::from(PANEL), "{w}");
        let d = dots(&svg);
        assert_eq!(d.len(), 3, "the NaN point is left out");
        let near =
            |p: (f64, f64), q: (f64, f64)| (p.0 - q.0).abs() <= 1.5 && (p.1 - q.1).abs() <= 1.5;
        assert!(near(d[0], (x + w / 2.0, y + h / 2.0)), "{d:?} {o:?}");
        assert!(
            near(d[1], (x + 0.75 * w, y + 0.25 * h)),
            "y grows up: {d:?}"
        );
        assert!(near(d[2], (x, y + h)), "{d:?}");
        let t = texts(&svg);
        assert_eq!(t, ["grid"]);
        let title = &elements(&svg, "text")[0];
        assert!(number(title, "y") < y, "the title is above the square");
    }

    #[test]
    fn the_circle_is_drawn_for_random_only() {
        let circle = |svg: &str| {
            elements(svg, "polyline").iter().any(|l| {
                attr(l, "stroke") == "#C8C8D7" && attr(l, "points").split(' ').count() > 200
            })
        };
        assert!(circle(&draw_points(&[], 1.0, "random").unwrap_or_default()));
        assert!(!circle(
            &draw_points(&[], 1.0, "jitter").unwrap_or_default()
        ));
        // Odd radii are drawn as 1, and still make a document.
        for r in [0.0, f32::NAN, -2.0] {
            let svg = draw_points(&[Vec3::ONE], r, "x?").unwrap_or_default();
            assert_eq!(dots(&svg).len(), 1, "radius {r}");
        }
    }

    #[test]
    fn draw_all_has_a_titled_panel_of_dots_for_each_distribution() {
        let svg = draw_all(16, 1.0, 7).unwrap_or_default();
        let n = Distribution::ALL.len();
        let names: Vec<&str> = Distribution::ALL.iter().map(|d| d.name()).collect();
        assert_eq!(texts(&svg), names);
        let o = outlines(&svg);
        assert_eq!(o.len(), n);
        let d = dots(&svg);
        // Every distribution gives 16 points (grid and the jitters 4 × 4).
        assert_eq!(d.len(), 16 * n, "{}", d.len());
        for (i, (x, y, w, h)) in o.iter().enumerate() {
            let (col, row) = ((i as u32 % COLUMNS) as f64, (i as u32 / COLUMNS) as f64);
            let cell = f64::from(SMALL_PANEL);
            assert!(*x >= col * cell && x + w <= (col + 1.0) * cell, "panel {i}");
            assert!(*y >= row * cell && y + h <= (row + 1.0) * cell, "panel {i}");
            let inside = d[16 * i..16 * (i + 1)].iter().all(|p| {
                p.0 >= x - 1.0 && p.0 <= x + w + 1.0 && p.1 >= y - 1.0 && p.1 <= y + h + 1.0
            });
            assert!(inside, "the dots of {} lie in its square", names[i]);
        }
        assert!(draw_all(0, -2.0, 0).is_ok());
    }
}
