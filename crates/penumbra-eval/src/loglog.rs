//! Log–log plots shared by the studies, drawn as a
//! [`Chart`](crate::chart::Chart): one colour per series, filled dots
//! joined by a line on the points that count, hollow dots on those shown
//! but set aside, and for each series an optional dashed guide (a
//! theoretical slope); grey dashed lines with a legend of their own (a
//! reference's noise).

use std::path::Path;

use plotters::style::RGBColor;

use crate::chart::{colour, Chart, Legend, Line, Marker, Scale, Series};
use crate::error::EvalError;

/// How the x axis is labelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum XAxis {
    /// Counts on a base-2 scale, labelled as integers.
    Counts,
    /// Any positive quantity on a base-10 scale.
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
        self.chart().write(path)
    }

    /// The plot as a [`Chart`]: per series a line with dots (in the
    /// legend), hollow dots and a dashed guide (not in it); then the grey
    /// lines.
    pub fn chart(&self) -> Chart {
        let x = match self.x_axis {
            XAxis::Counts => Scale::Log2,
            XAxis::Values => Scale::Log,
        };
        let mut chart = Chart::new(&self.title, &self.x_desc, &self.y_desc, x, Scale::Log);
        chart.legend = Legend::LowerLeft;
        for (i, s) in self.series.iter().enumerate() {
            let c = colour(i);
            let one = |label: &str, points: &[(f64, f64)], marker, line, width| Series {
                label: label.to_string(),
                points: positive(points),
                colour: c,
                marker,
                line,
                width,
            };
            chart
                .series
                .push(one(&s.label, &s.points, Marker::Dot, Line::Solid, 2));
            chart
                .series
                .push(one("", &s.hollow, Marker::Ring, Line::None, 1));
            if let Some(guide) = &s.guide {
                chart
                    .series
                    .push(one("", guide, Marker::None, Line::Dashed, 1));
            }
        }
        let grey = RGBColor(110, 110, 110);
        for (label, line) in &self.lines {
            chart
                .series
                .push(Series::dashed(label.as_str(), positive(line), grey));
        }
        chart
    }
}

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
        let texts = crate::chart::texts(&svg);
        assert!(texts.iter().any(|t| t == "alpha"), "{texts:?}");
        assert!(texts.iter().any(|t| t == "floor"), "{texts:?}");
        let circles = crate::chart::elements(&svg, "circle");
        let filled = |c: &&Vec<(String, String)>| c.iter().any(|a| a.0 == "fill" && a.1 != "none");
        // Two dots and the legend's; one hollow dot.
        assert_eq!(circles.iter().filter(filled).count(), 3, "{svg}");
        assert_eq!(circles.len(), 4, "{svg}");
        // The series' line and its legend key; the guide is dashed.
        let thick_blue = crate::chart::elements(&svg, "polyline")
            .into_iter()
            .filter(|l| l.contains(&("stroke".into(), "#1F77B4".into())))
            .filter(|l| l.contains(&("stroke-width".into(), "2".into())))
            .count();
        assert_eq!(thick_blue, 2, "{svg}");
        assert_eq!(
            std::fs::read_to_string(dir.path().join("p.svg")).ok(),
            Some(svg)
        );
    }
}
