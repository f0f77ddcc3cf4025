//! Log–log plots drawn with `plotters` into SVG, shared by the studies:
//! one colour per series, filled dots joined by a line on the points that
//! count, hollow dots on those shown but set aside, and for each series an
//! optional dashed guide (a theoretical slope); grey dashed lines with a
//! legend of their own (a reference's noise). Text is written as SVG
//! `<text>`: no font files are read.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::EvalError;
use crate::output::write_file;

const SIZE: (u32, u32) = (960, 640);

/// Colours for the series, cycled past their number (Tableau 10, then two
/// more).
const COLOURS: [RGBColor; 12] = [
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

/// How the x axis is labelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum XAxis {
    /// Counts on a base-2 scale, labelled as integers.
    Counts,
    /// Any positive quantity on a base-10 scale, labelled like `3e-2`.
    Values,
}

/// One series of a plot.
#[derive(Clone, Debug, Default)]
pub struct LogSeries {
    pub label: String,
    /// Filled dots joined by a line.
    pub points: Vec<(f64, f64)>,
    /// Hollow dots, not joined: measured but set aside.
    pub hollow: Vec<(f64, f64)>,
    /// A dashed line in the series' colour.
    pub guide: Option<Vec<(f64, f64)>>,
}

/// A log–log plot.
#[derive(Clone, Debug)]
pub struct LogLog {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub x_axis: XAxis,
    pub series: Vec<LogSeries>,
    /// Grey dashed lines with their legend labels (none if empty).
    pub lines: Vec<(String, Vec<(f64, f64)>)>,
}

impl LogLog {
    /// Draws the plot, writes it to `path` and returns its SVG text.
    pub fn write(&self, path: &Path) -> Result<String, EvalError> {
        let err = |message: String| EvalError::Write {
            path: path.to_path_buf(),
            message,
        };
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            self.draw(&root).map_err(|e| err(e.to_string()))?;
            root.present().map_err(|e| err(e.to_string()))?;
        }
        write_file(path, svg.as_bytes())?;
        Ok(svg)
    }

    fn draw(&self, root: &DrawingArea<SVGBackend<'_>, Shift>) -> DrawResult {
        root.fill(&WHITE)?;
        let (x, y) = self.ranges();
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(80);
        match self.x_axis {
            XAxis::Counts => {
                let mut chart =
                    builder.build_cartesian_2d(x.log_scale().base(2.0), y.log_scale())?;
                chart
                    .configure_mesh()
                    .x_desc(self.x_desc.as_str())
                    .y_desc(self.y_desc.as_str())
                    .x_label_formatter(&|v| format!("{}", v.round()))
                    .y_label_formatter(&|v| format!("{v:.0e}"))
                    .label_style(("sans-serif", 14))
                    .light_line_style(RGBColor(235, 235, 235))
                    .x_max_light_lines(0)
                    .draw()?;
                self.draw_series(&mut chart)
            }
            XAxis::Values => {
                let mut chart = builder.build_cartesian_2d(x.log_scale(), y.log_scale())?;
                chart
                    .configure_mesh()
                    .x_desc(self.x_desc.as_str())
                    .y_desc(self.y_desc.as_str())
                    .x_label_formatter(&|v| format!("{v:.0e}"))
                    .y_label_formatter(&|v| format!("{v:.0e}"))
                    .label_style(("sans-serif", 14))
                    .light_line_style(RGBColor(235, 235, 235))
                    .draw()?;
                self.draw_series(&mut chart)
            }
        }
    }

    fn draw_series<'a, 'b: 'a, X, Y>(
        &self,
        chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
    ) -> DrawResult
    where
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
    {
        for (i, s) in self.series.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let points = positive(&s.points);
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))?
                .label(s.label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 22, y)], colour.stroke_width(2))
                });
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
            chart.draw_series(
                positive(&s.hollow)
                    .into_iter()
                    .map(|p| Circle::new(p, 3, colour.stroke_width(1))),
            )?;
            if let Some(guide) = &s.guide {
                let guide = positive(guide);
                chart.draw_series(DashedLineSeries::new(guide, 7, 5, colour.stroke_width(1)))?;
            }
        }
        let grey = RGBColor(110, 110, 110);
        for (label, line) in &self.lines {
            let drawn = chart.draw_series(DashedLineSeries::new(
                positive(line),
                4,
                4,
                grey.stroke_width(1),
            ))?;
            if !label.is_empty() {
                drawn.label(label.as_str()).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 22, y)], grey.stroke_width(1))
                });
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .draw()?;
        Ok(())
    }

    /// The axes' ranges over every positive point, padded by a little on
    /// the log scale.
    fn ranges(&self) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
        let all: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().chain(&s.hollow))
            .chain(self.lines.iter().flat_map(|l| &l.1))
            .copied()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
            .collect();
        let span = |f: fn(&(f64, f64)) -> f64, default: (f64, f64)| {
            let lo = all.iter().map(f).fold(f64::INFINITY, f64::min);
            let hi = all.iter().map(f).fold(0.0, f64::max);
            if lo <= hi {
                (lo, hi)
            } else {
                default
            }
        };
        let (x0, x1) = span(|p| p.0, (1.0, 2.0));
        let (y0, y1) = span(|p| p.1, (1e-3, 1.0));
        (x0 / 1.2..x1 * 1.2, y0 / 1.6..y1 * 1.6)
    }
}

type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// The points a log scale can show.
fn positive(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
        .collect()
}

/// The SVG text of the plot at `path` among `(path, text)` pairs; empty if
/// there is none.
pub fn svg_at<'a>(svgs: &'a [(String, String)], path: &str) -> &'a str {
    svgs.iter()
        .find(|(p, _)| p == path)
        .map_or("", |(_, s)| s.as_str())
}

/// The line of slope `slope` on log–log axes from `x0` to `x1` through the
/// centre of gravity of `points` (in log–log space); `None` without points.
pub fn slope_line(slope: f64, points: &[(f64, f64)], x0: f64, x1: f64) -> Option<Vec<(f64, f64)>> {
    let points = positive(points);
    if points.is_empty() {
        return None;
    }
    let k = points.len() as f64;
    let mx = points.iter().map(|p| p.0.ln()).sum::<f64>() / k;
    let my = points.iter().map(|p| p.1.ln()).sum::<f64>() / k;
    let at = |n: f64| (n, (my + slope * (n.ln() - mx)).exp());
    Some(vec![at(x0), at(x1)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slope_line_passes_through_the_centre_of_gravity() {
        let pts = [(4.0, 1.0), (16.0, 0.5), (64.0, 0.25)];
        let line = slope_line(-0.5, &pts, 4.0, 64.0).unwrap_or_default();
        assert_eq!(line.len(), 2);
        assert!((line[0].1 - 1.0).abs() < 1e-12 && (line[1].1 - 0.25).abs() < 1e-12);
        assert!(slope_line(-0.5, &[(0.0, 1.0)], 1.0, 2.0).is_none());
    }

    #[test]
    fn plots_are_written_with_their_labels() {
        let Ok(dir) = tempfile::tempdir() else { return };
        let plot = LogLog {
            title: "t".into(),
            x_desc: "x".into(),
            y_desc: "y".into(),
            x_axis: XAxis::Values,
            series: vec![LogSeries {
                label: "alpha".into(),
                points: vec![(0.01, 1.0), (0.1, 0.3)],
                hollow: vec![(1.0, 0.2)],
                guide: Some(vec![(0.01, 1.0), (1.0, 0.1)]),
            }],
            lines: vec![("floor".into(), vec![(0.01, 0.05), (1.0, 0.05)])],
        };
        let svg = plot.write(&dir.path().join("p.svg"));
        let svg = svg.unwrap_or_default();
        assert!(svg.contains("alpha") && svg.contains("floor"), "{svg}");
        assert!(dir.path().join("p.svg").is_file());
    }
}
