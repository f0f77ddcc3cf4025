//! Line charts with axes, ticks, log scales and a legend, drawn into an
//! [`RgbImage`] with the bitmap [`font`](penumbra::io::font).
//!
//! Written here rather than taken from a plotting crate so that the report
//! needs no system libraries and no font files: the pictures are the same on
//! every machine.

use image::{Rgb, RgbImage};

use penumbra::io::font::{draw_text, draw_text_up, put, text_width, HEIGHT};

/// How values map onto an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    Linear,
    /// Base-10 logarithmic; values ≤ 0 are left out.
    Log,
}

/// The symbol drawn at each data point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
    Plus,
    None,
}

/// How the points of a series are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Line {
    Solid,
    Dashed,
    None,
}

/// One named set of points.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub color: Rgb<u8>,
    pub marker: Marker,
    pub line: Line,
}

impl Series {
    /// A solid line with markers in the `i`-th colour and marker of the palette.
    pub fn styled(i: usize, name: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            name: name.into(),
            points,
            color: PALETTE[i % PALETTE.len()],
            marker: MARKERS[i % MARKERS.len()],
            line: Line::Solid,
        }
    }
}

/// Distinguishable colours (also in grey-scale print, by their markers).
pub const PALETTE: [Rgb<u8>; 8] = [
    Rgb([31, 119, 180]),
    Rgb([214, 39, 40]),
    Rgb([44, 160, 44]),
    Rgb([255, 127, 14]),
    Rgb([148, 103, 189]),
    Rgb([140, 86, 75]),
    Rgb([227, 119, 194]),
    Rgb([23, 190, 207]),
];

const MARKERS: [Marker; 6] = [
    Marker::Circle,
    Marker::Square,
    Marker::Triangle,
    Marker::Diamond,
    Marker::Cross,
    Marker::Plus,
];

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
const BLACK: Rgb<u8> = Rgb([20, 20, 20]);
const GRID: Rgb<u8> = Rgb([228, 228, 228]);
/// Font pixels are drawn as `TEXT × TEXT` blocks.
const TEXT: i64 = 2;

/// A chart: title, axis labels and scales, and its series.
#[derive(Clone, Debug)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    pub series: Vec<Series>,
    pub width: u32,
    pub height: u32,
}

impl Chart {
    pub fn new(title: &str, x_label: &str, y_label: &str, x: Scale, y: Scale) -> Chart {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: x,
            y_scale: y,
            series: Vec::new(),
            width: 960,
            height: 600,
        }
    }

    /// Draws the chart. Points that cannot be shown (non-finite, or ≤ 0 on a
    /// log axis) are skipped; a chart without any is drawn with unit axes.
    pub fn render(&self) -> RgbImage {
        let mut img = RgbImage::from_pixel(self.width, self.height, WHITE);
        let xs = self.values(|p| p.0, self.x_scale);
        let ys = self.values(|p| p.1, self.y_scale);
        let x_axis = Axis::fit(&xs, self.x_scale);
        let y_axis = Axis::fit(&ys, self.y_scale);
        let frame = self.frame(&y_axis);
        let map = Mapping {
            frame,
            x: x_axis,
            y: y_axis,
        };
        map.draw_grid(&mut img);
        for s in &self.series {
            map.draw_series(&mut img, s);
        }
        map.draw_axes(&mut img);
        self.draw_labels(&mut img, &map);
        self.draw_legend(&mut img, &frame);
        img
    }

    fn values(&self, f: impl Fn(&(f64, f64)) -> f64, scale: Scale) -> Vec<f64> {
        self.series
            .iter()
            .flat_map(|s| s.points.iter().map(&f))
            .filter(|v| usable(*v, scale))
            .collect()
    }

    /// The plot area: room on the left for tick labels and the y label, at
    /// the bottom for tick labels and the x label, on the right for the legend.
    fn frame(&self, y: &Axis) -> Frame {
        let tick_chars = y.ticks().iter().map(|t| t.1.chars().count()).max();
        let left = 24 + TEXT * HEIGHT + text_width(&"0".repeat(tick_chars.unwrap_or(1)), TEXT);
        let legend = self
            .series
            .iter()
            .map(|s| text_width(&s.name, TEXT))
            .max()
            .unwrap_or(0);
        let right = if self.series.is_empty() {
            20
        } else {
            legend + 90
        };
        Frame {
            left,
            top: 24 + 2 * TEXT * HEIGHT,
            right: i64::from(self.width) - right,
            bottom: i64::from(self.height) - (28 + 2 * TEXT * HEIGHT),
        }
    }

    fn draw_labels(&self, img: &mut RgbImage, map: &Mapping) {
        let f = &map.frame;
        let w = i64::from(self.width);
        let tw = text_width(&self.title, TEXT);
        draw_text(img, (w - tw) / 2, 12, &self.title, TEXT, BLACK);
        let xw = text_width(&self.x_label, TEXT);
        let xl_y = i64::from(self.height) - 10 - TEXT * HEIGHT;
        draw_text(
            img,
            (f.left + f.right - xw) / 2,
            xl_y,
            &self.x_label,
            TEXT,
            BLACK,
        );
        let yw = text_width(&self.y_label, TEXT);
        draw_text_up(
            img,
            8,
            (f.top + f.bottom + yw) / 2,
            &self.y_label,
            TEXT,
            BLACK,
        );
    }

    fn draw_legend(&self, img: &mut RgbImage, f: &Frame) {
        let x = f.right + 16;
        for (i, s) in self.series.iter().enumerate() {
            let y = f.top + 8 + i as i64 * (TEXT * HEIGHT + 10);
            let mid = y + TEXT * HEIGHT / 2;
            if s.line != Line::None {
                let dashed = s.line == Line::Dashed;
                thick_line(img, (x, mid), (x + 36, mid), s.color, dashed, &mut 0.0);
            }
            marker(img, x + 18, mid, s.marker, s.color);
            draw_text(img, x + 44, y, &s.name, TEXT, BLACK);
        }
    }
}

fn usable(v: f64, scale: Scale) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

/// The plot area in pixels.
#[derive(Clone, Copy, Debug)]
struct Frame {
    left: i64,
    top: i64,
    right: i64,
    bottom: i64,
}

/// The range an axis shows, in axis units (log10 of the value for a log axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub scale: Scale,
    pub lo: f64,
    pub hi: f64,
}

impl Axis {
    /// The range for `values`: whole decades on a log axis, "nice" steps on
    /// a linear one (which starts at 0 when all values are positive and the
    /// smallest is under half the largest, so bars of growth read honestly).
    pub fn fit(values: &[f64], scale: Scale) -> Axis {
        let (mut lo, mut hi) = values
            .iter()
            .map(|&v| to_axis(v, scale))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        if !lo.is_finite() || !hi.is_finite() {
            (lo, hi) = (0.0, 1.0);
        }
        match scale {
            Scale::Log => {
                let (mut a, mut b) = (lo.floor(), hi.ceil());
                if b <= a {
                    (a, b) = (a - 1.0, b + 1.0);
                }
                Axis {
                    scale,
                    lo: a,
                    hi: b,
                }
            }
            Scale::Linear => {
                if lo > 0.0 && lo < 0.5 * hi {
                    lo = 0.0;
                }
                if hi <= lo {
                    (lo, hi) = (lo - 1.0, hi + 1.0);
                }
                let step = nice_step((hi - lo) / 5.0);
                Axis {
                    scale,
                    lo: (lo / step).floor() * step,
                    hi: (hi / step).ceil() * step,
                }
            }
        }
    }

    /// Major ticks: (position in axis units, label).
    pub fn ticks(&self) -> Vec<(f64, String)> {
        match self.scale {
            Scale::Log => {
                let span = (self.hi - self.lo).round() as i64;
                let every = (span / 8 + 1).max(1);
                (self.lo.round() as i64..=self.hi.round() as i64)
                    .filter(|k| (k - self.lo.round() as i64) % every == 0)
                    .map(|k| (k as f64, decade_label(k)))
                    .collect()
            }
            Scale::Linear => {
                let step = nice_step((self.hi - self.lo) / 5.0);
                let n = ((self.hi - self.lo) / step).round() as i64;
                (0..=n)
                    .map(|i| {
                        let v = self.lo + i as f64 * step;
                        (v, number_label(v, step))
                    })
                    .collect()
            }
        }
    }

    /// Minor ticks of a log axis: 2–9 times each decade.
    fn minor(&self) -> Vec<f64> {
        if self.scale != Scale::Log || self.hi - self.lo > 8.0 {
            return Vec::new();
        }
        let (a, b) = (self.lo.round() as i64, self.hi.round() as i64);
        (a..b)
            .flat_map(|k| (2..10).map(move |m| k as f64 + f64::from(m).log10()))
            .collect()
    }

    /// Fraction of the way along the axis of a value (not axis units).
    fn fraction(&self, v: f64) -> f64 {
        (to_axis(v, self.scale) - self.lo) / (self.hi - self.lo)
    }
}

fn to_axis(v: f64, scale: Scale) -> f64 {
    match scale {
        Scale::Linear => v,
        Scale::Log if v > 0.0 => v.log10(),
        Scale::Log => f64::NAN,
    }
}

/// 1, 2 or 5 times a power of ten, at least `raw`.
pub fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * p)
}

/// `1`, `10`, `100`, `1000`, then `1e4`…; `0.1`, `0.01`, then `1e-3`….
pub fn decade_label(k: i64) -> String {
    match k {
        0..=3 => format!("{}", 10i64.pow(k as u32)),
        -2..=-1 => format!("{}", 10f64.powi(k as i32)),
        _ => format!("1e{k}"),
    }
}

/// A linear tick value with as many decimals as its step needs.
pub fn number_label(v: f64, step: f64) -> String {
    let v = if v.abs() < step * 1e-9 { 0.0 } else { v };
    if v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-3) {
        return format!("{v:.0e}");
    }
    let decimals = if step >= 1.0 {
        0
    } else {
        (-step.log10().floor()) as usize
    };
    format!("{v:.decimals$}")
}

/// Axis ranges placed on the frame.
struct Mapping {
    frame: Frame,
    x: Axis,
    y: Axis,
}

impl Mapping {
    fn px(&self, x: f64, y: f64) -> Option<(i64, i64)> {
        let (fx, fy) = (self.x.fraction(x), self.y.fraction(y));
        if !(fx.is_finite() && fy.is_finite()) {
            return None;
        }
        let f = &self.frame;
        let px = f.left as f64 + fx * (f.right - f.left) as f64;
        let py = f.bottom as f64 - fy * (f.bottom - f.top) as f64;
        Some((px.round() as i64, py.round() as i64))
    }

    fn x_px(&self, a: f64) -> i64 {
        let f = &self.frame;
        f.left
            + ((a - self.x.lo) / (self.x.hi - self.x.lo) * (f.right - f.left) as f64).round() as i64
    }

    fn y_px(&self, a: f64) -> i64 {
        let f = &self.frame;
        f.bottom
            - ((a - self.y.lo) / (self.y.hi - self.y.lo) * (f.bottom - f.top) as f64).round() as i64
    }

    fn draw_grid(&self, img: &mut RgbImage) {
        let f = self.frame;
        for (a, _) in self.x.ticks() {
            vline(img, self.x_px(a), f.top, f.bottom, GRID);
        }
        for (a, _) in self.y.ticks() {
            hline(img, f.left, f.right, self.y_px(a), GRID);
        }
    }

    fn draw_axes(&self, img: &mut RgbImage) {
        let f = self.frame;
        hline(img, f.left, f.right, f.bottom, BLACK);
        hline(img, f.left, f.right, f.top, BLACK);
        vline(img, f.left, f.top, f.bottom, BLACK);
        vline(img, f.right, f.top, f.bottom, BLACK);
        for (a, label) in self.x.ticks() {
            let x = self.x_px(a);
            vline(img, x, f.bottom - 6, f.bottom, BLACK);
            let w = text_width(&label, TEXT);
            draw_text(img, x - w / 2, f.bottom + 8, &label, TEXT, BLACK);
        }
        for a in self.x.minor() {
            vline(img, self.x_px(a), f.bottom - 3, f.bottom, BLACK);
        }
        for (a, label) in self.y.ticks() {
            let y = self.y_px(a);
            hline(img, f.left, f.left + 6, y, BLACK);
            let w = text_width(&label, TEXT);
            draw_text(
                img,
                f.left - 8 - w,
                y - TEXT * HEIGHT / 2,
                &label,
                TEXT,
                BLACK,
            );
        }
        for a in self.y.minor() {
            hline(img, f.left, f.left + 3, self.y_px(a), BLACK);
        }
    }

    fn draw_series(&self, img: &mut RgbImage, s: &Series) {
        let pts: Vec<(i64, i64)> = s
            .points
            .iter()
            .filter(|p| usable(p.0, self.x.scale) && usable(p.1, self.y.scale))
            .filter_map(|p| self.px(p.0, p.1))
            .collect();
        if s.line != Line::None {
            let mut phase = 0.0;
            for w in pts.windows(2) {
                let dashed = s.line == Line::Dashed;
                thick_line(img, w[0], w[1], s.color, dashed, &mut phase);
            }
        }
        for &(x, y) in &pts {
            marker(img, x, y, s.marker, s.color);
        }
    }
}

fn hline(img: &mut RgbImage, x0: i64, x1: i64, y: i64, c: Rgb<u8>) {
    for x in x0..=x1 {
        put(img, x, y, c);
    }
}

fn vline(img: &mut RgbImage, x: i64, y0: i64, y1: i64, c: Rgb<u8>) {
    for y in y0..=y1 {
        put(img, x, y, c);
    }
}

/// A 2-pixel-wide line; a dashed one alternates 8 pixels on and 6 off,
/// carrying its phase from segment to segment.
fn thick_line(
    img: &mut RgbImage,
    a: (i64, i64),
    b: (i64, i64),
    c: Rgb<u8>,
    dashed: bool,
    phase: &mut f64,
) {
    let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
    let len = dx.hypot(dy);
    let steps = len.ceil().max(1.0) as i64;
    for k in 0..=steps {
        let t = k as f64 / steps as f64;
        let on = !dashed || (*phase + t * len) % 14.0 < 8.0;
        if on {
            let (x, y) = (a.0 as f64 + t * dx, a.1 as f64 + t * dy);
            let (x, y) = (x.round() as i64, y.round() as i64);
            for (ox, oy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                put(img, x + ox, y + oy, c);
            }
        }
    }
    *phase += len;
}

fn marker(img: &mut RgbImage, x: i64, y: i64, m: Marker, c: Rgb<u8>) {
    const R: i64 = 5;
    for dy in -R..=R {
        for dx in -R..=R {
            let inside = match m {
                Marker::Circle => dx * dx + dy * dy <= R * R,
                Marker::Square => dx.abs() < R && dy.abs() < R,
                Marker::Triangle => dy >= -R && 2 * dx.abs() <= dy + R,
                Marker::Diamond => dx.abs() + dy.abs() <= R,
                Marker::Cross => (dx - dy).abs() <= 1 || (dx + dy).abs() <= 1,
                Marker::Plus => dx.abs() <= 1 || dy.abs() <= 1,
                Marker::None => false,
            };
            if inside {
                put(img, x + dx, y + dy, c);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(0.9), 1.0);
        assert_eq!(nice_step(1.0), 1.0);
        assert_eq!(nice_step(1.1), 2.0);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert!((nice_step(0.03) - 0.05).abs() < 1e-12);
        assert_eq!(nice_step(f64::NAN), 1.0);
    }

    #[test]
    fn log_axis_covers_whole_decades() {
        let a = Axis::fit(&[3.0e5, 2.0e9], Scale::Log);
        assert_eq!((a.lo, a.hi), (5.0, 10.0));
        let labels: Vec<String> = a.ticks().into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["1e5", "1e6", "1e7", "1e8", "1e9", "1e10"]);
        let one = Axis::fit(&[100.0], Scale::Log);
        assert!(one.hi > one.lo);
        assert_eq!(decade_label(0), "1");
        assert_eq!(decade_label(2), "100");
        assert_eq!(decade_label(-1), "0.1");
        assert_eq!(decade_label(-3), "1e-3");
    }

    #[test]
    fn linear_axis_is_nice_and_starts_at_zero_for_growth() {
        let a = Axis::fit(&[1.0, 32.0], Scale::Linear);
        assert_eq!(a.lo, 0.0);
        assert!(a.hi >= 32.0);
        let t = a.ticks();
        assert_eq!(t.first().map(|t| t.1.as_str()), Some("0"));
        let b = Axis::fit(&[90.0, 100.0], Scale::Linear);
        assert!(b.lo >= 80.0 && b.lo <= 90.0, "{b:?}");
        assert_eq!(number_label(0.25, 0.05), "0.25");
        assert_eq!(number_label(2.0e7, 5.0e6), "2e7");
    }

    #[test]
    fn series_are_drawn_where_the_axes_say() {
        let mut chart = Chart::new("T", "x", "y", Scale::Linear, Scale::Log);
        chart
            .series
            .push(Series::styled(0, "a", vec![(0.0, 1.0), (10.0, 1000.0)]));
        chart.series.push(Series::styled(
            1,
            "skip",
            vec![(5.0, -1.0), (f64::NAN, 2.0)],
        ));
        let img = chart.render();
        assert_eq!(img.dimensions(), (960, 600));
        let c = PALETTE[0];
        let count = img.pixels().filter(|p| **p == c).count();
        assert!(count > 200, "the line and its markers: {count}");
        // The first point sits at the bottom-left corner of the plot area.
        let frame = chart.frame(&Axis::fit(&[1.0, 1000.0], Scale::Log));
        let near = (-3..=3).flat_map(|dx| (-3..=3).map(move |dy| (dx, dy)));
        let hit = near.into_iter().any(|(dx, dy)| {
            img.get_pixel((frame.left + dx) as u32, (frame.bottom + dy) as u32) == &c
        });
        assert!(hit);
    }

    #[test]
    fn empty_and_degenerate_charts_do_not_panic() {
        let chart = Chart::new("", "", "", Scale::Log, Scale::Log);
        let _ = chart.render();
        let mut c = Chart::new("t", "x", "y", Scale::Linear, Scale::Linear);
        c.series
            .push(Series::styled(3, "flat", vec![(1.0, 5.0), (1.0, 5.0)]));
        c.width = 50;
        c.height = 40;
        let _ = c.render();
    }
}
