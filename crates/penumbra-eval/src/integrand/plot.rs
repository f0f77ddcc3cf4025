//! One log–log plot per integrand ([`LogLog`]): RMSE against N, one colour
//! per distribution (filled dots on the fitted counts, hollow ones on the
//! counts left out of the fit), and for each distribution with a target a
//! dashed line of the theoretical slope through the centre of gravity of
//! its fitted points (in log–log space), so that only the slopes are
//! compared.

use std::path::Path;

use super::results::IntegrandResult;
use crate::error::EvalError;
use crate::loglog::{slope_line, LogLog, LogSeries, XAxis};

/// Draws the plot of `r`, writes it to `path` and returns its SVG text.
pub fn write(r: &IntegrandResult, path: &Path) -> Result<String, EvalError> {
    let series = r
        .curves
        .iter()
        .map(|c| {
            let (fitted, hollow): (Vec<_>, Vec<_>) = c.points.iter().partition(|p| p.fitted);
            let xy = |p: &&super::results::Point| (p.n as f64, p.rmse);
            let points: Vec<(f64, f64)> = fitted.iter().map(xy).collect();
            let slope = c.fit.map_or(String::new(), |f| format!(" {:+.2}", f.slope));
            let guide = c.theory.and_then(|t| {
                let (first, last) = (points.first()?, points.last()?);
                slope_line(t, &points, first.0, last.0)
            });
            LogSeries {
                label: format!("{}{slope}", c.distribution),
                hollow: hollow.iter().map(xy).collect(),
                points,
                guide,
            }
        })
        .collect();
    LogLog {
        title: format!("{} ({}): RMSE against N", r.name, r.class.name()),
        x_desc: "N (points per set)".into(),
        y_desc: "RMSE of the estimate".into(),
        x_axis: XAxis::Counts,
        series,
        lines: Vec::new(),
    }
    .write(path)
}
