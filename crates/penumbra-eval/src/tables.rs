//! Tables 4.1–4.6 of the thesis, measured: which renders make each row, and
//! the measured counts next to the published ones.

use penumbra::scene::Overrides;
use serde::Serialize;

use crate::error::EvalError;
use crate::format::rays;
use crate::job::Job;
use crate::measure::{reduction, Measurement};
use crate::plan::Plan;
use crate::runner::Runner;
use crate::thesis::{self, Published, TwoModes};

/// Largest relative change of a set's running average that stops it (the
/// library's default; the thesis gives no value).
pub const METRIC_THRESHOLD: f32 = 0.01;

/// A ray-count table: rays per effect against the total.
#[derive(Clone, Debug, Serialize)]
pub struct CountTable {
    pub id: String,
    pub title: String,
    /// What the budget column counts ("primary rays", "shadow rays"…).
    pub budget: String,
    pub scene: String,
    pub rows: Vec<CountRow>,
}

#[derive(Clone, Debug, Serialize)]
pub struct CountRow {
    /// "standard" or "4x supersampling".
    pub mode: String,
    pub rays: u32,
    pub measured: Measurement,
    pub thesis: Option<f64>,
    pub thesis_text: Option<String>,
}

/// A metric table: totals with and without the acceleration metric.
#[derive(Clone, Debug, Serialize)]
pub struct MetricTable {
    pub id: String,
    pub title: String,
    pub rows: Vec<MetricRow>,
}

#[derive(Clone, Debug, Serialize)]
pub struct MetricRow {
    /// The thesis's label, e.g. "Figure 4.8 left 4r 4s 4x".
    pub setting: String,
    pub scene: String,
    /// Which metric was on, with its parameters.
    pub metric: String,
    pub with: Measurement,
    /// Rendered without the metric, when affordable.
    pub without: Option<Measurement>,
    /// Otherwise the thesis's formula for the count without the metric, at
    /// the frame of `with` and at 800×600.
    pub without_estimate: Option<(f64, f64)>,
    pub reduction_pct: f64,
    pub thesis: thesis::MetricRow,
}

/// All measured tables.
#[derive(Clone, Debug, Serialize)]
pub struct Tables {
    pub counts: Vec<CountTable>,
    pub metrics: Vec<MetricTable>,
}

impl Tables {
    pub fn count(&self, id: &str) -> Option<&CountTable> {
        self.counts.iter().find(|t| t.id == id)
    }
    pub fn metric(&self, id: &str) -> Option<&MetricTable> {
        self.metrics.iter().find(|t| t.id == id)
    }
}

/// Width and height overrides for a frame.
pub fn frame(size: (u32, u32)) -> Overrides {
    Overrides {
        width: Some(size.0),
        height: Some(size.1),
        ..Default::default()
    }
}

/// Which metric to switch on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MetricKind {
    Reflection,
    Shadow,
    Both,
}

/// α (and k) for a budget: half of it, between 2 and 4. With α equal to the
/// budget the metric could never act, and the thesis saves rays even at 4.
pub fn alpha(budget: u32) -> u32 {
    (budget / 2).clamp(2, 4)
}

/// Switches the metrics of `kind` on (the thesis measures each alone, then
/// both).
pub fn with_metric(mut o: Overrides, kind: MetricKind, reflection: u32, shadow: u32) -> Overrides {
    o.metric = Some(true);
    o.reflection_metric = Some(kind != MetricKind::Shadow);
    o.shadow_metric = Some(kind != MetricKind::Reflection);
    o.metric_threshold = Some(METRIC_THRESHOLD);
    o.metric_min_rays = Some(alpha(reflection));
    o.shadow_metric_rays = Some(alpha(shadow));
    o
}

/// Describes the metric setting for the report.
pub fn metric_text(kind: MetricKind, reflection: u32, shadow: u32) -> String {
    let r = format!(
        "reflection (threshold {METRIC_THRESHOLD}, α = {})",
        alpha(reflection)
    );
    let s = format!("shadow (k = {})", alpha(shadow));
    match kind {
        MetricKind::Reflection => r,
        MetricKind::Shadow => s,
        MetricKind::Both => format!("{r} and {s}"),
    }
}

/// One render setting: spp, shadow rays, reflection rays.
fn setting(size: (u32, u32), spp: u32, shadow: u32, reflection: u32) -> Overrides {
    Overrides {
        spp: Some(spp),
        shadow_rays: Some(shadow),
        reflection_rays: Some(reflection),
        ..frame(size)
    }
}

/// A row to be measured: its place in a count table and its job.
struct CountSpec {
    table: usize,
    mode: &'static str,
    rays: u32,
    thesis: Option<Published>,
    job: Job,
}

struct MetricSpec {
    table: usize,
    setting: String,
    scene: &'static str,
    metric: String,
    with: Job,
    without: Option<Job>,
    estimate: Option<(u32, u32, u32)>,
    thesis: thesis::MetricRow,
}

fn count_table_heads() -> Vec<CountTable> {
    let head = |id: &str, title: &str, budget: &str, scene: &str| CountTable {
        id: id.into(),
        title: title.into(),
        budget: budget.into(),
        scene: scene.into(),
        rows: Vec::new(),
    };
    vec![
        head(
            "4.1",
            "Depth of field: rays against primary rays per pixel",
            "primary rays",
            "bunnies-dof",
        ),
        head(
            "S",
            "Supersampling: rays against primary rays per pixel",
            "primary rays",
            "bunny",
        ),
        head(
            "4.2",
            "Blurry reflection, one reflective surface (floor)",
            "reflection rays",
            "bunny-reflect",
        ),
        head(
            "4.3",
            "Mutual reflection (reflective floor and bunny)",
            "reflection rays",
            "bunny-mirror",
        ),
        head(
            "4.5",
            "Penumbra: rays against shadow rays",
            "shadow rays",
            "bunny",
        ),
    ]
}

fn count_specs(plan: &Plan) -> Vec<CountSpec> {
    let mut specs = Vec::new();
    let t = plan.table;
    for (i, &spp) in [1u32, 4, 8, 16].iter().enumerate() {
        let dof = format!("Table 4.1: depth of field, {}", rays(spp, "primary"));
        specs.push(CountSpec {
            table: 0,
            mode: "depth of field",
            rays: spp,
            thesis: Some(thesis::TABLE_4_1[i]),
            job: Job::new(dof, "bunnies-dof", setting(t, spp, 1, 1)),
        });
        let ss = format!("supersampling table: {}", rays(spp, "primary"));
        specs.push(CountSpec {
            table: 1,
            mode: "supersampling",
            rays: spp,
            thesis: None,
            job: Job::new(ss, "bunny", setting(t, spp, 1, 1)),
        });
    }
    let reflection = |n| (1, n);
    let shadow = |n| (n, 1);
    let two = [
        TwoModeTable {
            table: 2,
            id: "4.2",
            scene: "bunny-reflect",
            budgets: [1, 4, 32],
            published: &thesis::TABLE_4_2,
            size: t,
            effect: reflection,
        },
        TwoModeTable {
            table: 3,
            id: "4.3",
            scene: "bunny-mirror",
            budgets: plan.mirror_rays,
            published: &thesis::TABLE_4_3,
            size: plan.mirror_frame,
            effect: reflection,
        },
        TwoModeTable {
            table: 4,
            id: "4.5",
            scene: "bunny",
            budgets: [1, 9, 32],
            published: &thesis::TABLE_4_5,
            size: t,
            effect: shadow,
        },
    ];
    for table in two {
        table.push_specs(&mut specs);
    }
    specs
}

/// A table with a "standard" and a "4x supersampling" row per budget.
struct TwoModeTable {
    table: usize,
    id: &'static str,
    scene: &'static str,
    /// The budgets run (the quick run lowers the thesis's largest one).
    budgets: [u32; 3],
    published: &'static TwoModes,
    size: (u32, u32),
    /// A budget as (shadow rays, reflection rays).
    effect: fn(u32) -> (u32, u32),
}

impl TwoModeTable {
    /// A published value is attached only where the budget is the thesis's.
    fn push_specs(&self, specs: &mut Vec<CountSpec>) {
        let p = self.published;
        for (mode, spp, values) in [
            ("standard", 1, &p.standard),
            ("4x supersampling", 4, &p.supersampled),
        ] {
            for (i, &n) in self.budgets.iter().enumerate() {
                let (shadow, reflection) = (self.effect)(n);
                let label = format!("Table {}: {mode}, {}", self.id, rays(n, ""));
                specs.push(CountSpec {
                    table: self.table,
                    mode,
                    rays: n,
                    thesis: (p.budgets[i] == n).then_some(values[i]),
                    job: Job::new(
                        label,
                        self.scene,
                        setting(self.size, spp, shadow, reflection),
                    ),
                });
            }
        }
    }
}

/// A row of Tables 4.4/4.6 before it is run.
struct MetricCase {
    table: usize,
    figure: &'static str,
    scene: &'static str,
    kind: MetricKind,
    reflection: u32,
    shadow: u32,
    spp: u32,
    thesis: thesis::MetricRow,
}

fn metric_cases(plan: &Plan) -> [MetricCase; 6] {
    let h = plan.heavy_metric_rays;
    let case = |table, figure, scene, kind, reflection, shadow, spp, thesis| MetricCase {
        table,
        figure,
        scene,
        kind,
        reflection,
        shadow,
        spp,
        thesis,
    };
    let (left, right) = ("Figure 4.8 left", "Figure 4.8 right");
    let (reflect, mirror) = ("bunny-reflect", "bunny-mirror");
    use MetricKind::{Both, Reflection, Shadow};
    [
        case(0, left, reflect, Reflection, 4, 4, 4, thesis::TABLE_4_4[0]),
        case(0, right, mirror, Reflection, 4, 1, 1, thesis::TABLE_4_4[1]),
        case(0, right, mirror, Both, h, h, 4, thesis::TABLE_4_4[2]),
        case(1, left, reflect, Shadow, 4, 4, 4, thesis::TABLE_4_6[0]),
        case(1, right, mirror, Shadow, 1, 8, 4, thesis::TABLE_4_6[1]),
        case(1, right, mirror, Shadow, 1, 16, 4, thesis::TABLE_4_6[2]),
    ]
}

fn metric_specs(plan: &Plan) -> Vec<MetricSpec> {
    metric_cases(plan)
        .into_iter()
        .map(|c| {
            let (r, s, spp) = (c.reflection, c.shadow, c.spp);
            let name = format!("{} {r}r {s}s {spp}x", c.figure);
            let plain = setting(plan.table, spp, s, r);
            let heavy = c.thesis.theoretical;
            let id = if c.table == 0 { "4.4" } else { "4.6" };
            let with = with_metric(plain.clone(), c.kind, r, s);
            MetricSpec {
                table: c.table,
                setting: name.clone(),
                scene: c.scene,
                metric: metric_text(c.kind, r, s),
                with: Job::new(format!("Table {id}: {name} with metric"), c.scene, with),
                without: (!heavy).then(|| {
                    Job::new(format!("Table {id}: {name} without metric"), c.scene, plain)
                }),
                estimate: heavy.then_some((r, s, spp)),
                thesis: c.thesis,
            }
        })
        .collect()
}

/// The jobs (with metric, without metric if rendered) of row `row` of Table
/// 4.4 (`table` 0) or 4.6 (`table` 1), for figures that show those renders.
pub fn metric_jobs(plan: &Plan, table: usize, row: usize) -> Option<(Job, Option<Job>)> {
    metric_specs(plan)
        .into_iter()
        .filter(|m| m.table == table)
        .nth(row)
        .map(|m| (m.with, m.without))
}

/// Every job the tables need, for planning.
pub fn jobs(plan: &Plan) -> Vec<Job> {
    let mut out: Vec<Job> = count_specs(plan).into_iter().map(|s| s.job).collect();
    for m in metric_specs(plan) {
        out.push(m.with);
        out.extend(m.without);
    }
    out
}

/// Renders and measures every table.
pub fn run(runner: &mut Runner, plan: &Plan) -> Result<Tables, EvalError> {
    let mut counts = count_table_heads();
    for spec in count_specs(plan) {
        let r = runner.run(&spec.job)?;
        counts[spec.table].rows.push(CountRow {
            mode: spec.mode.into(),
            rays: spec.rays,
            measured: Measurement::of(&r),
            thesis: spec.thesis.map(|p| p.value),
            thesis_text: spec.thesis.map(|p| p.text.to_string()),
        });
    }
    let mut metrics = vec![
        MetricTable {
            id: "4.4".into(),
            title: "Reflection metric: rays with and without it".into(),
            rows: Vec::new(),
        },
        MetricTable {
            id: "4.6".into(),
            title: "Shadow metric: rays with and without it".into(),
            rows: Vec::new(),
        },
    ];
    for spec in metric_specs(plan) {
        let row = metric_row(runner, plan, &spec)?;
        metrics[spec.table].rows.push(row);
    }
    Ok(Tables { counts, metrics })
}

fn metric_row(runner: &mut Runner, plan: &Plan, spec: &MetricSpec) -> Result<MetricRow, EvalError> {
    let with = Measurement::of(&*runner.run(&spec.with)?);
    let without = match &spec.without {
        Some(j) => Some(Measurement::of(&*runner.run(j)?)),
        None => None,
    };
    let (w, h) = plan.table;
    let estimate = spec.estimate.map(|(r, s, spp)| {
        let here = thesis::unaccelerated_estimate(r, s, w, h, spp);
        (here, here * crate::runner::THESIS_PIXELS / f64::from(w * h))
    });
    let base = without
        .as_ref()
        .map(|m| m.total as f64)
        .or(estimate.map(|e| e.0));
    Ok(MetricRow {
        setting: spec.setting.clone(),
        scene: spec.scene.into(),
        metric: spec.metric.clone(),
        reduction_pct: reduction(with.total as f64, base.unwrap_or(0.0)),
        with,
        without,
        without_estimate: estimate,
        thesis: spec.thesis,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alpha_is_half_the_budget_within_two_and_four() {
        assert_eq!(alpha(1), 2);
        assert_eq!(alpha(4), 2);
        assert_eq!(alpha(8), 4);
        assert_eq!(alpha(32), 4);
    }

    #[test]
    fn metrics_can_be_switched_on_one_at_a_time() {
        let r = with_metric(Overrides::default(), MetricKind::Reflection, 4, 4);
        assert_eq!(r.metric, Some(true));
        assert_eq!(
            (r.reflection_metric, r.shadow_metric),
            (Some(true), Some(false))
        );
        assert_eq!(r.metric_threshold, Some(METRIC_THRESHOLD));
        let s = with_metric(Overrides::default(), MetricKind::Shadow, 1, 16);
        assert_eq!(
            (s.reflection_metric, s.shadow_metric),
            (Some(false), Some(true))
        );
        assert_eq!(s.shadow_metric_rays, Some(4));
        let b = with_metric(Overrides::default(), MetricKind::Both, 4, 4);
        assert_eq!(
            (b.reflection_metric, b.shadow_metric),
            (Some(true), Some(true))
        );
    }

    #[test]
    fn every_table_row_has_a_job_and_quick_budgets_are_marked() {
        let full = Plan::new(false);
        let specs = count_specs(&full);
        assert_eq!(specs.len(), 4 + 4 + 6 + 6 + 6);
        assert!(specs.iter().all(|s| s.table != 3 || s.thesis.is_some()));
        let quick = count_specs(&Plan::new(true));
        let mirror_32 = quick.iter().filter(|s| s.table == 3 && s.rays == 8);
        assert!(mirror_32.into_iter().all(|s| s.thesis.is_none()));
        assert_eq!(metric_specs(&full).len(), 6);
        assert!(
            metric_specs(&full)
                .iter()
                .filter(|m| m.without.is_none())
                .count()
                == 1
        );
    }
}
