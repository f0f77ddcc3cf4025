//! Line and scatter charts drawn with `plotters` into SVG, for every plot
//! the studies write: linear or logarithmic axes, series with markers and
//! solid or dashed lines, and a legend of the labelled series. Text is
//! written as SVG `<text>`: no font files are read, so a chart is the same
//! file on every machine.

use std::ops::Range;
use std::path::Path;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};

use crate::error::EvalError;
use crate::output::write_file;

/// Colours for the series, cycled past their number (Tableau 10, then two
/// more).
pub const COLOURS: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 0),
    RGBColor(170, 110, 0),
];

/// The `i`-th colour of [`COLOURS`], cycled.
pub fn colour(i: usize) -> RGBColor {
    COLOURS[i % COLOURS.len()]
}

/// Markers given by [`Series::styled`], cycled, so that series can be told
/// apart in grey-scale print.
const MARKERS: [Marker; 6] = [
    Marker::Dot,
    Marker::Square,
    Marker::Triangle,
    Marker::Ring,
    Marker::Cross,
    Marker::Plus,
];

/// How values map onto an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear, labelled with as many decimals as the tick step needs.
    Linear,
    /// Base-10 logarithmic; values ≤ 0 are left out.
    Log,
    /// Base-2 logarithmic, labelled as integers (counts); values ≤ 0 are
    /// left out.
    Log2,
}

/// The symbol drawn at each point of a series.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    /// A filled circle.
    Dot,
    /// A hollow circle.
    Ring,
    Square,
    Triangle,
    /// A diagonal cross.
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

/// Where the legend goes inside the plot area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Legend {
    UpperRight,
    LowerLeft,
    LowerRight,
}

/// One set of points.
#[derive(Clone, Debug)]
pub struct Series {
    /// The legend entry; a series with an empty label has none.
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub colour: RGBColor,
    pub marker: Marker,
    pub line: Line,
    /// Stroke width of the line, in pixels.
    pub width: u32,
}

impl Series {
    /// A solid line with markers, in the `i`-th colour and marker.
    pub fn styled(i: usize, label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            points,
            colour: colour(i),
            marker: MARKERS[i % MARKERS.len()],
            line: Line::Solid,
            width: 2,
        }
    }

    /// A dashed line without markers.
    pub fn dashed(label: impl Into<String>, points: Vec<(f64, f64)>, colour: RGBColor) -> Series {
        Series {
            label: label.into(),
            points,
            colour,
            marker: Marker::None,
            line: Line::Dashed,
            width: 1,
        }
    }
}

/// A chart: title, axis descriptions and scales, its series and where their
/// legend goes.
#[derive(Clone, Debug)]
pub struct Chart {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    pub series: Vec<Series>,
    pub legend: Legend,
    /// Width and height in pixels.
    pub size: (u32, u32),
}

/// The plot area of a drawn chart, in pixels of the SVG.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlotArea {
    pub x: Range<i32>,
    pub y: Range<i32>,
}

type DrawResult<T> = Result<T, Box<dyn std::error::Error>>;

impl Chart {
    pub fn new(title: &str, x_desc: &str, y_desc: &str, x: Scale, y: Scale) -> Chart {
        Chart {
            title: title.into(),
            x_desc: x_desc.into(),
            y_desc: y_desc.into(),
            x_scale: x,
            y_scale: y,
            series: Vec::new(),
            legend: Legend::LowerLeft,
            size: (960, 640),
        }
    }

    /// Draws the chart, writes it to `path` and returns its SVG text.
    pub fn write(&self, path: &Path) -> Result<String, EvalError> {
        let (svg, _) = self.svg().map_err(|message| EvalError::Write {
            path: path.to_path_buf(),
            message,
        })?;
        write_file(path, svg.as_bytes())?;
        Ok(svg)
    }

    /// The SVG text of the chart and where its plot area lies. Points that
    /// an axis cannot show (not finite, or ≤ 0 on a logarithmic one) are
    /// left out; a chart without any is drawn on default ranges.
    pub fn svg(&self) -> Result<(String, PlotArea), String> {
        let mut svg = String::new();
        let area = {
            let root = SVGBackend::with_string(&mut svg, self.size).into_drawing_area();
            let area = self.draw(&root).map_err(|e| e.to_string())?;
            root.present().map_err(|e| e.to_string())?;
            area
        };
        Ok((svg, area))
    }

    fn draw(&self, root: &DrawingArea<SVGBackend<'_>, Shift>) -> DrawResult<PlotArea> {
        root.fill(&WHITE)?;
        let x = self.range(|p| p.0, self.x_scale);
        let y = self.range(|p| p.1, self.y_scale);
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(80);
        let x_step = nice_step((x.end - x.start) / 6.0);
        let y_step = nice_step((y.end - y.start) / 6.0);
        let labels = (
            move |v: &f64| axis_label(*v, self.x_scale, x_step),
            move |v: &f64| axis_label(*v, self.y_scale, y_step),
        );
        use Scale::{Linear, Log, Log2};
        match (self.x_scale, self.y_scale) {
            (Linear, Linear) => self.finish(builder.build_cartesian_2d(x, y)?, labels),
            (Linear, Log) => self.finish(builder.build_cartesian_2d(x, y.log_scale())?, labels),
            (Linear, Log2) => {
                let y = y.log_scale().base(2.0);
                self.finish(builder.build_cartesian_2d(x, y)?, labels)
            }
            (Log, Linear) => self.finish(builder.build_cartesian_2d(x.log_scale(), y)?, labels),
            (Log, Log) => {
                let chart = builder.build_cartesian_2d(x.log_scale(), y.log_scale())?;
                self.finish(chart, labels)
            }
            (Log, Log2) => {
                let y = y.log_scale().base(2.0);
                self.finish(builder.build_cartesian_2d(x.log_scale(), y)?, labels)
            }
            (Log2, Linear) => {
                let x = x.log_scale().base(2.0);
                self.finish(builder.build_cartesian_2d(x, y)?, labels)
            }
            (Log2, Log) => {
                let x = x.log_scale().base(2.0);
                self.finish(builder.build_cartesian_2d(x, y.log_scale())?, labels)
            }
            (Log2, Log2) => {
                let (x, y) = (x.log_scale().base(2.0), y.log_scale().base(2.0));
                self.finish(builder.build_cartesian_2d(x, y)?, labels)
            }
        }
    }

    /// The mesh, the series and the legend on built axes.
    fn finish<'a, 'b: 'a, X, Y>(
        &self,
        mut chart: ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
        (x_label, y_label): (impl Fn(&f64) -> String, impl Fn(&f64) -> String),
    ) -> DrawResult<PlotArea>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let mut mesh = chart.configure_mesh();
        mesh.x_desc(self.x_desc.as_str())
            .y_desc(self.y_desc.as_str())
            .x_label_formatter(&x_label)
            .y_label_formatter(&y_label)
            .label_style(("sans-serif", 14))
            .light_line_style(RGBColor(235, 235, 235));
        if self.x_scale == Scale::Log2 {
            mesh.x_max_light_lines(0);
        }
        mesh.draw()?;
        let (x_range, y_range) = (self.x_scale.shown(), self.y_scale.shown());
        for s in &self.series {
            let points: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| x_range(p.0) && y_range(p.1))
                .collect();
            let (colour, line, mark, width) = (s.colour, s.line, s.marker, s.width);
            let style = colour.stroke_width(width);
            let key = move |at| Glyph {
                at,
                marker: mark,
                colour,
                line: Some((line, width)),
            };
            let labelled = !s.label.is_empty();
            match s.line {
                Line::Solid => {
                    let drawn = chart.draw_series(LineSeries::new(points.clone(), style))?;
                    if labelled {
                        drawn.label(s.label.as_str()).legend(key);
                    }
                }
                Line::Dashed => {
                    let series = DashedLineSeries::new(points.clone(), 7, 5, style);
                    let drawn = chart.draw_series(series)?;
                    if labelled {
                        drawn.label(s.label.as_str()).legend(key);
                    }
                }
                Line::None => {}
            }
            let drawn =
                chart.draw_series(points.iter().map(|&p| Glyph::marker(p, mark, colour)))?;
            if labelled && line == Line::None {
                drawn.label(s.label.as_str()).legend(key);
            }
        }
        if self.series.iter().any(|s| !s.label.is_empty()) {
            chart
                .configure_series_labels()
                .position(match self.legend {
                    Legend::UpperRight => SeriesLabelPosition::UpperRight,
                    Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
                    Legend::LowerRight => SeriesLabelPosition::LowerRight,
                })
                .label_font(("sans-serif", 13))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(160, 160, 160))
                .draw()?;
        }
        let (x, y) = chart.plotting_area().get_pixel_range();
        Ok(PlotArea { x, y })
    }

    /// The range an axis shows over every point it can show: padded by a
    /// little on a logarithmic axis; on a linear one, padded by 5 % and
    /// starting at 0 when every value is positive and the smallest is under
    /// half the largest (so that growth reads honestly).
    fn range(&self, f: impl Fn(&(f64, f64)) -> f64, scale: Scale) -> Range<f64> {
        let shown = scale.shown();
        let values: Vec<f64> = self
            .series
            .iter()
            .flat_map(|s| {
                s.points
                    .iter()
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
            })
            .map(&f)
            .filter(|v| shown(*v))
            .collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        match scale {
            Scale::Linear => {
                let (mut lo, mut hi) = if lo <= hi { (lo, hi) } else { (0.0, 1.0) };
                if lo > 0.0 && lo < 0.5 * hi {
                    lo = 0.0;
                }
                if hi - lo <= f64::EPSILON * hi.abs().max(1.0) {
                    (lo, hi) = (lo - 1.0, hi + 1.0);
                }
                let pad = 0.05 * (hi - lo);
                let lo = if lo == 0.0 { 0.0 } else { lo - pad };
                lo..hi + pad
            }
            Scale::Log | Scale::Log2 => {
                let (lo, hi) = if lo <= hi { (lo, hi) } else { (1.0, 10.0) };
                let pad = if scale == Scale::Log2 { 1.2 } else { 1.6 };
                lo / pad..hi * pad
            }
        }
    }
}

impl Scale {
    /// Whether a value can be shown on the axis.
    fn shown(self) -> impl Fn(f64) -> bool {
        move |v: f64| v.is_finite() && (self == Scale::Linear || v > 0.0)
    }
}

/// A marker at a point, or (as a legend key, `line` set) a short line
/// (22 pixels, of a style and width) starting at the point with the marker
/// at its middle. Drawn on the backend directly, so that one type serves
/// every marker and line.
struct Glyph<C> {
    at: C,
    marker: Marker,
    colour: RGBColor,
    line: Option<(Line, u32)>,
}

impl<C> Glyph<C> {
    fn marker(at: C, marker: Marker, colour: RGBColor) -> Glyph<C> {
        Glyph {
            at,
            marker,
            colour,
            line: None,
        }
    }
}

impl<'p, C> PointCollection<'p, C> for &'p Glyph<C> {
    type Point = &'p C;
    type IntoIter = std::iter::Once<&'p C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Glyph<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        b: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = pos.next() else {
            return Ok(());
        };
        let c = self.colour;
        let (mx, my) = match self.line {
            None => (x, y),
            Some((line, width)) => {
                let style = c.stroke_width(width);
                match line {
                    Line::Solid => b.draw_path([(x, y), (x + 22, y)], &style)?,
                    Line::Dashed => {
                        for (from, to) in [(0, 6), (10, 16), (20, 22)] {
                            b.draw_line((x + from, y), (x + to, y), &style)?;
                        }
                    }
                    Line::None => {}
                }
                (x + 11, y)
            }
        };
        let stroke = c.stroke_width(2);
        match self.marker {
            Marker::Dot => b.draw_circle((mx, my), 3, &c.filled(), true),
            Marker::Ring => b.draw_circle((mx, my), 3, &c.stroke_width(1), false),
            Marker::Square => b.draw_rect((mx - 3, my - 3), (mx + 3, my + 3), &c.filled(), true),
            Marker::Triangle => b.fill_polygon(
                [(mx, my - 4), (mx + 4, my + 3), (mx - 4, my + 3)],
                &c.filled(),
            ),
            Marker::Cross => {
                b.draw_line((mx - 4, my - 4), (mx + 4, my + 4), &stroke)?;
                b.draw_line((mx - 4, my + 4), (mx + 4, my - 4), &stroke)
            }
            Marker::Plus => {
                b.draw_line((mx - 5, my), (mx + 5, my), &stroke)?;
                b.draw_line((mx, my - 5), (mx, my + 5), &stroke)
            }
            Marker::None => Ok(()),
        }
    }
}

/// A tick label: as many decimals as the step needs on a linear axis,
/// integers on a base-2 one, plain numbers from 0.01 to 9999 and `3e-5`
/// beyond on a base-10 one.
pub fn axis_label(v: f64, scale: Scale, step: f64) -> String {
    match scale {
        Scale::Linear => number_label(v, step),
        Scale::Log2 => format!("{}", v.round()),
        Scale::Log => {
            if (0.01..1e4).contains(&v) {
                let digits = (-v.log10().floor()).max(0.0) as usize;
                format!("{v:.digits$}")
            } else {
                format!("{v:.0e}")
            }
        }
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

/// The elements of an SVG text, for tests: each `<name …>` tag's
/// attributes, in document order.
#[cfg(test)]
pub fn elements(svg: &str, name: &str) -> Vec<Vec<(String, String)>> {
    let doc = roxmltree::Document::parse(svg).unwrap_or_else(|e| panic!("{e}: {svg}"));
    doc.descendants()
        .filter(|n| n.tag_name().name() == name)
        .map(|n| {
            n.attributes()
                .map(|a| (a.name().to_string(), a.value().to_string()))
                .collect()
        })
        .collect()
}

/// The texts of every `<text>` element of an SVG text, for tests.
#[cfg(test)]
pub fn texts(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).unwrap_or_else(|e| panic!("{e}: {svg}"));
    doc.descendants()
        .filter(|n| n.tag_name().name() == "text")
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect()
}

/// An attribute's value as a number, for tests.
#[cfg(test)]
pub fn number(attrs: &[(String, String)], name: &str) -> f64 {
    attrs
        .iter()
        .find(|a| a.0 == name)
        .and_then(|a| a.1.parse().ok())
        .unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attr<'a>(attrs: &'a [(String, String)], name: &str) -> &'a str {
        attrs
            .iter()
            .find(|a| a.0 == name)
            .map_or("", |a| a.1.as_str())
    }

    fn hex(c: RGBColor) -> String {
        format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
    }

    #[test]
    fn nice_steps_and_labels() {
        assert_eq!(nice_step(0.9), 1.0);
        assert_eq!(nice_step(1.1), 2.0);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert!((nice_step(0.03) - 0.05).abs() < 1e-12);
        assert_eq!(nice_step(f64::NAN), 1.0);
        assert_eq!(number_label(0.25, 0.05), "0.25");
        assert_eq!(number_label(2.0e7, 5.0e6), "2e7");
        assert_eq!(axis_label(100.0, Scale::Log, 0.0), "100");
        assert_eq!(axis_label(0.05, Scale::Log, 0.0), "0.05");
        assert_eq!(axis_label(3e-5, Scale::Log, 0.0), "3e-5");
        assert_eq!(axis_label(1e6, Scale::Log, 0.0), "1e6");
        assert_eq!(axis_label(64.0, Scale::Log2, 0.0), "64");
    }

    /// A known chart: one series of three dots joined by a line on a
    /// linear x and a log y axis, one dashed line and one series of
    /// markers only; every element is counted and every dot lies in the
    /// plot area, ordered as its values.
    #[test]
    fn a_known_chart_has_its_elements_where_its_values_say() {
        let mut chart = Chart::new("Known", "along", "up", Scale::Linear, Scale::Log);
        let mut a = Series::styled(0, "alpha", vec![(0.0, 1.0), (5.0, 10.0), (10.0, 1000.0)]);
        a.marker = Marker::Dot;
        chart.series.push(a);
        chart.series.push(Series::dashed(
            "guide",
            vec![(0.0, 2.0), (10.0, 2.0)],
            RGBColor(90, 90, 90),
        ));
        let mut b = Series::styled(1, "beta", vec![(2.0, 5.0), (4.0, -1.0), (f64::NAN, 3.0)]);
        b.line = Line::None;
        b.marker = Marker::Ring;
        chart.series.push(b);
        let Ok((svg, area)) = chart.svg() else {
            panic!("not drawn")
        };
        let blue = hex(colour(0));
        let orange = hex(colour(1));
        let circles = elements(&svg, "circle");
        let dots: Vec<_> = circles.iter().filter(|c| attr(c, "fill") == blue).collect();
        // Three on the plot, one in the legend.
        assert_eq!(dots.len(), 4, "{svg}");
        let rings: Vec<_> = circles
            .iter()
            .filter(|c| attr(c, "stroke") == orange && attr(c, "fill") == "none")
            .collect();
        // (4, -1) and (NaN, 3) cannot be shown.
        assert_eq!(rings.len(), 2, "{svg}");
        let lines = elements(&svg, "polyline");
        let solid = lines
            .iter()
            .filter(|l| attr(l, "stroke") == blue && attr(l, "stroke-width") == "2")
            .count();
        assert_eq!(solid, 2, "the series and its legend key");
        let grey = ["line", "polyline"]
            .into_iter()
            .flat_map(|name| elements(&svg, name))
            .filter(|l| attr(l, "stroke") == "#5A5A5A")
            .count();
        assert!(grey > 10, "dashes of the guide and its key: {grey}");
        let texts = texts(&svg);
        for t in ["Known", "along", "up", "alpha", "guide", "beta", "1000"] {
            assert!(texts.iter().any(|s| s == t), "no text {t}: {texts:?}");
        }
        let at = |c: &&Vec<(String, String)>| (number(c, "cx"), number(c, "cy"));
        let plotted: Vec<(f64, f64)> = dots.iter().take(3).map(at).collect();
        let (x, y) = (area.x.clone(), area.y.clone());
        for p in &plotted {
            assert!(
                p.0 >= f64::from(x.start) - 1.0 && p.0 <= f64::from(x.end) + 1.0,
                "{p:?} {area:?}"
            );
            assert!(
                p.1 >= f64::from(y.start) - 1.0 && p.1 <= f64::from(y.end) + 1.0,
                "{p:?} {area:?}"
            );
        }
        // x grows to the right, y up; 10 lies halfway between 1 and 1000's
        // thirds: one third of the way up on a log axis.
        assert!(plotted[0].0 < plotted[1].0 && plotted[1].0 < plotted[2].0);
        assert!(plotted[0].1 > plotted[1].1 && plotted[1].1 > plotted[2].1);
        let third = (plotted[0].1 - plotted[1].1) / (plotted[0].1 - plotted[2].1);
        assert!((third - 1.0 / 3.0).abs() < 0.02, "{third}");
        let half = (plotted[1].0 - plotted[0].0) / (plotted[2].0 - plotted[0].0);
        assert!((half - 0.5).abs() < 0.02, "{half}");
    }

    #[test]
    fn every_scale_and_marker_draws_and_empty_charts_do_not_fail() {
        let scales = [Scale::Linear, Scale::Log, Scale::Log2];
        for (i, x) in scales.into_iter().enumerate() {
            for y in scales {
                let mut chart = Chart::new("t", "x", "y", x, y);
                for k in 0..7 {
                    let mut s = Series::styled(k, format!("s{k}"), vec![(1.0, 2.0), (4.0, 8.0)]);
                    s.marker = [
                        Marker::Dot,
                        Marker::Ring,
                        Marker::Square,
                        Marker::Triangle,
                        Marker::Cross,
                        Marker::Plus,
                        Marker::None,
                    ][k];
                    chart.series.push(s);
                }
                chart.legend = [Legend::LowerLeft, Legend::UpperRight, Legend::LowerRight][i];
                let svg = chart.svg().map(|s| s.0).unwrap_or_default();
                assert_eq!(
                    texts(&svg).iter().filter(|t| t.starts_with('s')).count(),
                    7,
                    "{x:?} {y:?}"
                );
                // Two triangles and the legend's.
                assert_eq!(elements(&svg, "polygon").len(), 3, "triangles");
            }
        }
        let empty = Chart::new("", "", "", Scale::Log, Scale::Linear);
        assert!(empty.svg().is_ok());
        let mut flat = Chart::new("f", "x", "y", Scale::Linear, Scale::Linear);
        flat.series
            .push(Series::styled(0, "flat", vec![(1.0, 5.0), (1.0, 5.0)]));
        assert!(flat.svg().is_ok());
    }
}
