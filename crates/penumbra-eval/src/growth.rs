//! How the ray count grows with the rays per effect (linear for
//! supersampling, depth of field and penumbra; a power of the budget for
//! mutual reflection), and how much the metrics save as budgets grow.

use std::path::Path;

use plotters::style::RGBColor;
use serde::Serialize;

use crate::chart::{Chart, Legend, Line, Marker, Scale, Series};
use crate::error::EvalError;
use crate::job::Job;
use crate::measure::{reduction, Measurement};
use crate::plan::Plan;
use crate::runner::Runner;
use crate::tables::{frame, metric_text, with_metric, MetricKind, Tables};
use crate::thesis;

/// A chart written to the output directory.
#[derive(Clone, Debug, Serialize)]
pub struct Plot {
    pub id: String,
    pub title: String,
    pub caption: String,
    /// Path relative to the output directory.
    pub file: String,
}

/// One budget of the metric sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepPoint {
    /// "shadow" or "reflection".
    pub metric: String,
    pub parameters: String,
    pub budget: u32,
    pub with: Measurement,
    pub without: Measurement,
    pub reduction_pct: f64,
}

/// The scene of the sweep: the thesis's "Figure 4.8 right", many reflections.
const SWEEP_SCENE: &str = "bunny-mirror";

fn sweep_pairs(plan: &Plan) -> Vec<(MetricKind, u32, Job, Job)> {
    let mut out = Vec::new();
    let cases = [
        (MetricKind::Shadow, &plan.sweep_shadow),
        (MetricKind::Reflection, &plan.sweep_reflection),
    ];
    for (kind, budgets) in cases {
        for &n in budgets {
            let (s, r) = if kind == MetricKind::Shadow {
                (n, 1)
            } else {
                (1, n)
            };
            let plain = penumbra::scene::Overrides {
                shadow_rays: Some(s),
                reflection_rays: Some(r),
                ..frame(plan.sweep)
            };
            let name = format!("metric sweep: {r}r {s}s 1x");
            let with = Job::new(
                format!("{name} with metric"),
                SWEEP_SCENE,
                with_metric(plain.clone(), kind, r, s),
            );
            let without = Job::new(format!("{name} without metric"), SWEEP_SCENE, plain);
            out.push((kind, n, with, without));
        }
    }
    out
}

/// Every job of the sweep, for planning.
pub fn sweep_jobs(plan: &Plan) -> Vec<Job> {
    sweep_pairs(plan)
        .into_iter()
        .flat_map(|(_, _, a, b)| [a, b])
        .collect()
}

/// Renders the sweep: each budget with and without its metric.
pub fn run_sweep(runner: &mut Runner, plan: &Plan) -> Result<Vec<SweepPoint>, EvalError> {
    let mut out = Vec::new();
    for (kind, n, with, without) in sweep_pairs(plan) {
        let with = Measurement::of(&*runner.run(&with)?);
        let without = Measurement::of(&*runner.run(&without)?);
        let (r, s) = if kind == MetricKind::Shadow {
            (1, n)
        } else {
            (n, 1)
        };
        out.push(SweepPoint {
            metric: if kind == MetricKind::Shadow {
                "shadow"
            } else {
                "reflection"
            }
            .into(),
            parameters: metric_text(kind, r, s),
            budget: n,
            reduction_pct: reduction(with.total as f64, without.total as f64),
            with,
            without,
        });
    }
    Ok(out)
}

/// (rays per effect, total at 800×600) of one mode of a count table.
fn curve(tables: &Tables, id: &str, mode: &str) -> Vec<(f64, f64)> {
    tables
        .count(id)
        .map(|t| {
            t.rows
                .iter()
                .filter(|r| r.mode == mode)
                .map(|r| (f64::from(r.rays), r.measured.total_at_thesis_size))
                .collect()
        })
        .unwrap_or_default()
}

fn growth_curves(tables: &Tables) -> Vec<(&'static str, Vec<(f64, f64)>)> {
    vec![
        ("supersampling", curve(tables, "S", "supersampling")),
        ("depth of field", curve(tables, "4.1", "depth of field")),
        ("penumbra", curve(tables, "4.5", "standard")),
        ("reflection, floor only", curve(tables, "4.2", "standard")),
        ("mutual reflection", curve(tables, "4.3", "standard")),
        (
            "mutual reflection, 4x",
            curve(tables, "4.3", "4x supersampling"),
        ),
    ]
}

/// Writes the growth and metric plots into `dir/plots/`.
pub fn plots(tables: &Tables, sweep: &[SweepPoint], dir: &Path) -> Result<Vec<Plot>, EvalError> {
    let curves = growth_curves(tables);
    let mut absolute = Chart::new(
        "Rays traced against rays per effect",
        "rays per effect (per pixel, shading point or reflection)",
        "rays traced at 800x600",
        Scale::Linear,
        Scale::Log,
    );
    let mut relative = Chart::new(
        "Growth relative to one ray per effect",
        "rays per effect",
        "rays traced / rays with 1 ray",
        Scale::Log,
        Scale::Log,
    );
    for (i, (name, points)) in curves.iter().enumerate() {
        absolute
            .series
            .push(Series::styled(i, *name, points.clone()));
        let base = points.first().map_or(1.0, |p| p.1);
        let rel = points.iter().map(|p| (p.0, p.1 / base)).collect();
        relative.series.push(Series::styled(i, *name, rel));
    }
    absolute.legend = Legend::LowerRight;
    relative.legend = Legend::LowerRight;
    relative.series.push(guide("n (linear)", 1, 32.0, 185));
    relative.series.push(guide("n^3", 3, 32.0, 90));
    let mut out = vec![
        write(dir, "ray-growth", &absolute, "Total rays (scaled to 800×600) against the rays per effect, log y axis. Supersampling, depth of field and penumbra grow linearly; reflection between the floor and the bunny grows with a power of the budget (up to n + n² + n³ with depth 3).")?,
        write(dir, "ray-growth-relative", &relative, "The same counts divided by the count with one ray, on log–log axes: linear growth has slope 1 (the light dashed n line; supersampling and depth of field lie on it and can hide each other), mutual reflection bends up toward the dark n³ line.")?,
    ];
    out.push(write(dir, "metric-reduction", &metric_chart(sweep), "Rays saved by the metric against the ray budget, on the mutual-reflection scene without supersampling, next to the thesis's reductions on its corresponding scene (the \"Figure 4.8 right\" rows of Tables 4.4 and 4.6, markers only: 4r 1s 1x and 32r 32s 4x for reflection, the latter against a computed count, and 1r 8s 4x and 1r 16s 4x for shadows). The saving grows with the budget.")?);
    Ok(out)
}

/// A dashed grey reference line y = x^power from 1 to `to`, `grey` light
/// or dark so that two guides can be told apart.
fn guide(name: &str, power: i32, to: f64, grey: u8) -> Series {
    let points = (0..=10)
        .map(|i| {
            let x = to.powf(f64::from(i) / 10.0);
            (x, x.powi(power))
        })
        .collect();
    Series::dashed(name, points, RGBColor(grey, grey, grey))
}

fn metric_chart(sweep: &[SweepPoint]) -> Chart {
    let mut chart = Chart::new(
        "Metric savings against ray budget",
        "rays per effect (budget)",
        "rays saved, % of total",
        Scale::Log,
        Scale::Linear,
    );
    for (i, kind) in ["shadow", "reflection"].into_iter().enumerate() {
        let points = sweep
            .iter()
            .filter(|p| p.metric == kind)
            .map(|p| (f64::from(p.budget), p.reduction_pct))
            .collect();
        chart.series.push(Series::styled(
            i,
            format!("{kind} metric (measured)"),
            points,
        ));
    }
    // The thesis's rows on the same scene ("Figure 4.8 right"): 4r 1s 1x and
    // 32r 32s 4x for the reflection metric, 1r 8s 4x and 1r 16s 4x for the
    // shadow metric. Their first rows are on another scene and are left out.
    let published = |rows: &[thesis::MetricRow], budgets: [f64; 2]| -> Vec<(f64, f64)> {
        rows[1..]
            .iter()
            .zip(budgets)
            .map(|(r, b)| (b, r.reduction))
            .collect()
    };
    let mut t6 = Series::styled(
        0,
        "shadow, thesis Table 4.6",
        published(&thesis::TABLE_4_6, [8.0, 16.0]),
    );
    t6.line = Line::None;
    t6.marker = Marker::Cross;
    let mut t4 = Series::styled(
        1,
        "reflection, thesis Table 4.4",
        published(&thesis::TABLE_4_4, [4.0, 32.0]),
    );
    t4.line = Line::None;
    t4.marker = Marker::Plus;
    chart.series.extend([t6, t4]);
    chart.legend = Legend::LowerRight;
    chart
}

fn write(dir: &Path, id: &str, chart: &Chart, caption: &str) -> Result<Plot, EvalError> {
    let file = format!("plots/{id}.svg");
    chart.write(&dir.join(&file))?;
    Ok(Plot {
        id: id.into(),
        title: chart.title.clone(),
        caption: caption.into(),
        file,
    })
}
