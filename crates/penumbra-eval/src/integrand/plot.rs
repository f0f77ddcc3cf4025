//! One log–log plot per integrand, drawn with `plotters` into SVG: RMSE
//! against N, one colour per distribution (filled dots on the fitted counts,
//! hollow ones on the counts left out of the fit), and for each distribution
//! with a target a dashed line of the theoretical slope through the centre
//! of gravity of its fitted points (in log–log space), so that only the
//! slopes are compared. Text is written as SVG `<text>`: no font files are
//! read.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::results::{Curve, IntegrandResult};
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

/// Draws the plot of `r`, writes it to `path` and returns its SVG text.
pub fn write(r: &IntegrandResult, path: &Path) -> Result<String, EvalError> {
    let err = |message: String| EvalError::Write {
        path: path.to_path_buf(),
        message,
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(r, &root).map_err(|e| err(e.to_string()))?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    write_file(path, svg.as_bytes())?;
    Ok(svg)
}

type DrawResult = Result<(), Box<dyn std::error::Error>>;

fn draw(r: &IntegrandResult, root: &DrawingArea<SVGBackend<'_>, Shift>) -> DrawResult {
    root.fill(&WHITE)?;
    let (x, y) = ranges(&r.curves);
    let mut chart = ChartBuilder::on(root)
        .caption(
            format!("{} ({}): RMSE against N", r.name, r.class.name()),
            ("sans-serif", 22),
        )
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(x.log_scale().base(2.0), y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc("N (points per set)")
        .y_desc("RMSE of the estimate")
        .x_label_formatter(&|v| format!("{}", v.round()))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 14))
        .light_line_style(RGBColor(235, 235, 235))
        .x_max_light_lines(0)
        .draw()?;
    for (i, c) in r.curves.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let fitted: Vec<(f64, f64)> = c
            .points
            .iter()
            .filter(|p| p.fitted && p.rmse > 0.0)
            .map(|p| (p.n as f64, p.rmse))
            .collect();
        let slope = c.fit.map_or(String::new(), |f| format!(" {:+.2}", f.slope));
        chart
            .draw_series(LineSeries::new(fitted.clone(), colour.stroke_width(2)))?
            .label(format!("{}{slope}", c.distribution))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 22, y)], colour.stroke_width(2)));
        chart.draw_series(fitted.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
        chart.draw_series(
            c.points
                .iter()
                .filter(|p| !p.fitted && p.rmse > 0.0)
                .map(|p| Circle::new((p.n as f64, p.rmse), 3, colour.stroke_width(1))),
        )?;
        if let Some(line) = theory_line(c, &fitted) {
            chart.draw_series(DashedLineSeries::new(line, 7, 5, colour.stroke_width(1)))?;
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

/// The axes' ranges: N over the counts, RMSE over every positive value,
/// padded by a little on the log scale.
fn ranges(curves: &[Curve]) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
    let points = || curves.iter().flat_map(|c| &c.points);
    let n_min = points().map(|p| p.n).min().unwrap_or(1) as f64;
    let n_max = points().map(|p| p.n).max().unwrap_or(2) as f64;
    let positive = || {
        points()
            .map(|p| p.rmse)
            .filter(|&v| v > 0.0 && v.is_finite())
    };
    let lo = positive().fold(f64::INFINITY, f64::min);
    let hi = positive().fold(0.0, f64::max);
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (1e-3, 1.0) };
    (n_min / 1.2..n_max * 1.2, lo / 1.6..hi * 1.6)
}

/// The theoretical slope's line over the fitted counts, through the centre
/// of gravity of the fitted points in log–log space.
fn theory_line(c: &Curve, fitted: &[(f64, f64)]) -> Option<Vec<(f64, f64)>> {
    let slope = c.theory?;
    let (first, last) = (fitted.first()?, fitted.last()?);
    let k = fitted.len() as f64;
    let mx = fitted.iter().map(|p| p.0.ln()).sum::<f64>() / k;
    let my = fitted.iter().map(|p| p.1.ln()).sum::<f64>() / k;
    let at = |n: f64| (n, (my + slope * (n.ln() - mx)).exp());
    Some(vec![at(first.0), at(last.0)])
}
