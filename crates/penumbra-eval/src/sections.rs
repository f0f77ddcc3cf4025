//! The report's content: tables next to the thesis, figures with captions,
//! plots, the convergence study and a summary of what the numbers show.

use crate::convergence::Study;
use crate::doc::{Block, Table};
use crate::figures::Figure;
use crate::format::{approx, count, pct, ratio, seconds, signed};
use crate::growth::{Plot, SweepPoint};
use crate::measure::Measurement;
use crate::report::Report;
use crate::tables::{CountRow, CountTable, MetricRow, MetricTable};

fn h(level: u8, s: impl Into<String>) -> Block {
    Block::Heading(level, s.into())
}

fn p(s: impl Into<String>) -> Block {
    Block::Paragraph(s.into())
}

/// Ratio of the largest to the smallest budget's total in one mode.
pub fn growth(t: &CountTable, mode: &str) -> Option<(u32, u32, f64)> {
    let rows: Vec<_> = t.rows.iter().filter(|r| r.mode == mode).collect();
    let (first, last) = (rows.first()?, rows.last()?);
    let r = last.measured.total as f64 / first.measured.total.max(1) as f64;
    Some((first.rays, last.rays, r))
}

/// The opening: what was run and how to read it.
pub fn intro(r: &Report) -> Vec<Block> {
    let mode = if r.quick { "quick" } else { "full" };
    let mut out =
        vec![
        h(1, "Penumbra: the thesis's evaluation, reproduced"),
        p(format!(
            "This report re-runs the evaluation chapter of the thesis “Stochastic Ray Tracing” (chapter 4: \
             Tables 4.1–4.6, Figures 4.1–4.10) with Penumbra, and adds a measured comparison of \
             the six ray distributions. It was produced by `penumbra reproduce` in {mode} mode: \
             {} renders in {} s on {} worker threads.",
            r.renders,
            seconds(r.elapsed_s),
            r.threads
        )),
        p("How to read it: ray counts are exact (counted by the renderer, never estimated) and \
           are independent of the machine; times and Mrays/s depend on it and on its load. The \
           thesis's numbers come from its own renderer, scene and camera, so they are expected \
           to agree in order of magnitude and, above all, in how counts grow with the budget, \
           not digit for digit. All scenes use recursion depth 3, as the thesis did, and the \
           grid distribution unless a row or panel names another."),
    ];
    if !r.deviations.is_empty() {
        out.push(p("Differences from the thesis's setup in this run:"));
        out.push(Block::List(r.deviations.clone()));
    }
    out
}

/// The measured trends in a few sentences, computed from the tables.
pub fn summary(r: &Report) -> Vec<Block> {
    let mut items = linear_items(r);
    items.extend(reflection_item(r));
    let ranges: Vec<String> = r.tables.counts.iter().filter_map(thesis_range).collect();
    if !ranges.is_empty() {
        let ranges = ranges.join("; ");
        items.push(format!(
            "Measured against published totals (at 800×600): {ranges}."
        ));
    }
    items.extend(scaling_check(r));
    items.extend(metric_items(r));
    items.extend(convergence_items(r));
    vec![h(2, "Summary of the measurements"), Block::List(items)]
}

/// Growth of supersampling, depth of field and penumbra from the smallest
/// to the largest budget.
fn linear_items(r: &Report) -> Vec<String> {
    let linear = [
        ("S", "supersampling", "Supersampling"),
        ("4.1", "depth of field", "Depth of field"),
        ("4.5", "standard", "Penumbra"),
    ];
    linear
        .into_iter()
        .filter_map(|(id, mode, name)| {
            let (a, b, g) = r.tables.count(id).and_then(|t| growth(t, mode))?;
            Some(format!(
                "{name}: {b} rays per effect trace {} the rays of {a} (linear growth would be at most {}×).",
                ratio(g),
                b / a.max(1)
            ))
        })
        .collect()
}

fn reflection_item(r: &Report) -> Option<String> {
    let (a, b, gf) = r.tables.count("4.2").and_then(|t| growth(t, "standard"))?;
    let (_, bm, gm) = r.tables.count("4.3").and_then(|t| growth(t, "standard"))?;
    Some(format!(
        "Reflection: with only the floor reflective, {b} rays trace {} the rays of {a}; with the \
         bunny reflective too, {bm} rays trace {} — mutual reflection multiplies sets at every \
         level of the recursion, as Table 4.3 shows.",
        ratio(gf),
        ratio(gm)
    ))
}

fn metric_items(r: &Report) -> Vec<String> {
    r.tables
        .metrics
        .iter()
        .map(|t| {
            let parts: Vec<String> = t
                .rows
                .iter()
                .map(|row| format!("{} saves {}", row.setting, pct(row.reduction_pct)))
                .collect();
            let title = t.title.to_lowercase();
            format!("Table {} ({title}): {}.", t.id, parts.join("; "))
        })
        .collect()
}

fn convergence_items(r: &Report) -> Vec<String> {
    r.convergence
        .iter()
        .map(|s| {
            let slopes: Vec<String> = s
                .curves
                .iter()
                .map(|c| format!("{} {}", c.distribution, signed(c.slope)))
                .collect();
            format!("Convergence slopes, {}: {}.", s.effect, slopes.join(", "))
        })
        .collect()
}

/// "Table 4.1 0.73–0.83×": the spread of measured/published over a table.
fn thesis_range(t: &CountTable) -> Option<String> {
    let ratios: Vec<f64> = t
        .rows
        .iter()
        .filter_map(|r| r.thesis.map(|v| r.measured.total_at_thesis_size / v))
        .collect();
    let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ratios.iter().copied().fold(0.0, f64::max);
    (!ratios.is_empty()).then(|| format!("Table {} {}–{}", t.id, ratio(lo), ratio(hi)))
}

/// When Table 4.3 is rendered smaller than the others, its 4-ray standard
/// row is the same setting as the second row of Table 4.4 without metric:
/// comparing them checks that scaling by pixel count is sound.
fn scaling_check(r: &Report) -> Option<String> {
    let mirror = r.tables.count("4.3")?;
    let row = mirror
        .rows
        .iter()
        .find(|x| x.mode == "standard" && x.rays == 4)?;
    if !row.measured.is_scaled() {
        return None;
    }
    let full = r.tables.metric("4.4")?.rows.get(1)?.without.as_ref()?;
    if full.width == row.measured.width {
        return None;
    }
    let diff = 100.0 * (row.measured.total_at_thesis_size / full.total as f64 - 1.0);
    Some(format!(
        "Scaling by pixel count is sound: Table 4.3's 4-ray standard row, rendered at {}×{} and scaled, \
         gives {} rays; the same setting rendered at {}×{} (Table 4.4, second row, without metric) traced {} ({:+.2}%).",
        row.measured.width,
        row.measured.height,
        count(row.measured.total_at_thesis_size.round() as u64),
        full.width,
        full.height,
        count(full.total),
        diff
    ))
}

fn scaled(rows: &[&Measurement]) -> bool {
    rows.iter().any(|m| m.is_scaled())
}

/// A count table (4.1, 4.2, 4.3, 4.5 and the supersampling table).
pub fn count_table(t: &CountTable) -> Vec<Block> {
    let is_scaled = scaled(&t.rows.iter().map(|r| &r.measured).collect::<Vec<_>>());
    let mut head = vec![
        "mode",
        t.budget.as_str(),
        "primary",
        "shadow",
        "reflection",
        "total",
    ];
    if is_scaled {
        head.push("total at 800×600");
    }
    head.extend([
        "thesis",
        "measured / thesis",
        "× the 1-ray count",
        "time (s)",
        "Mrays/s",
    ]);
    let mut table = Table::new(&head);
    table.numeric[0] = false;
    for row in &t.rows {
        // The first row of a mode has the smallest budget, one ray.
        let first = t.rows.iter().find(|r| r.mode == row.mode);
        let base = first.map_or(1, |r| r.measured.total.max(1));
        table.row(count_cells(row, base, is_scaled));
    }
    let (w, h3) = t
        .rows
        .first()
        .map_or((0, 0), |r| (r.measured.width, r.measured.height));
    let title = match t.id.as_str() {
        "S" => t.title.clone(),
        id => format!("Table {id}: {}", t.title),
    };
    let mut out = vec![h(3, title), p(format!("Scene `{}` at {w}×{h3}.", t.scene))];
    out.extend(count_note(&t.id).map(p));
    out.push(Block::Table(table));
    out
}

fn count_cells(row: &CountRow, base: u64, is_scaled: bool) -> Vec<String> {
    let m = &row.measured;
    let mut cells = vec![
        row.mode.clone(),
        row.rays.to_string(),
        count(m.primary),
        count(m.shadow),
        count(m.reflection),
        count(m.total),
    ];
    if is_scaled {
        cells.push(approx(m.total_at_thesis_size));
    }
    cells.push(row.thesis_text.clone().unwrap_or_else(|| "–".into()));
    let vs_thesis = row.thesis.map(|v| ratio(m.total_at_thesis_size / v));
    cells.push(vs_thesis.unwrap_or_else(|| "–".into()));
    cells.push(ratio(m.total as f64 / base as f64));
    cells.push(seconds(m.time_s));
    cells.push(format!("{:.2}", m.mrays_per_s));
    cells
}

/// What to keep in mind when reading a count table.
fn count_note(id: &str) -> Option<&'static str> {
    match id {
        "S" => Some(
            "The thesis has no table of its own for supersampling; it refers to the 4x rows of \
             Tables 4.2, 4.3 and 4.5. This table measures it on the plain bunny scene.",
        ),
        "4.2" => Some(
            "The thesis's 1-ray counts here (0.5·10⁶ standard, 1·10⁶ with 4x supersampling) are \
             below the 480,000 and 1,920,000 primary rays those settings trace at 800×600, so that \
             table cannot have counted every kind of ray; its growth with the budget is the \
             comparable part.",
        ),
        _ => None,
    }
}

/// A metric table (4.4 or 4.6).
pub fn metric_table(t: &MetricTable) -> Vec<Block> {
    let is_scaled = scaled(&t.rows.iter().map(|r| &r.with).collect::<Vec<_>>());
    let mut head = vec!["setting", "scene", "+metric", "−metric", "reduction"];
    if is_scaled {
        head.extend(["+metric at 800×600", "−metric at 800×600"]);
    }
    head.extend(["thesis +metric", "thesis −metric", "thesis reduction"]);
    head.extend(["time +/− (s)", "Mrays/s +metric"]);
    let mut table = Table::new(&head);
    table.numeric[0] = false;
    table.numeric[1] = false;
    for row in &t.rows {
        table.row(metric_cells(row, is_scaled));
    }
    let mut out =
        vec![
        h(3, format!("Table {}: {}", t.id, t.title)),
        Block::Table(table),
        p("Per kind (primary / shadow / reflection rays; \"saved\" counts the set members the \
           metric skipped, not their descendants):"),
        Block::List(t.rows.iter().map(breakdown).collect()),
    ];
    if t.rows.iter().any(|r| r.without_estimate.is_some()) {
        out.push(p(
            "Values marked * were not rendered: without the metric this setting traces on \
                    the order of 10¹² rays (weeks on two cores). The count is the thesis's own \
                    estimate r³ · s · width · height · spp (r reflection and s shadow rays, every \
                    reflection ray with its shadow rays), and the reduction is computed against \
                    it, as the thesis did.",
        ));
    }
    out
}

fn metric_cells(row: &MetricRow, is_scaled: bool) -> Vec<String> {
    let w = &row.with;
    let (without, without_scaled) = match (&row.without, row.without_estimate) {
        (Some(m), _) => (count(m.total), approx(m.total_at_thesis_size)),
        (None, Some((here, thesis))) => {
            (format!("{}*", approx(here)), format!("{}*", approx(thesis)))
        }
        (None, None) => ("–".into(), "–".into()),
    };
    let mut cells = vec![
        row.setting.clone(),
        format!("`{}`", row.scene),
        count(w.total),
        without,
        pct(row.reduction_pct),
    ];
    if is_scaled {
        cells.extend([approx(w.total_at_thesis_size), without_scaled]);
    }
    let th = &row.thesis;
    let star = if th.theoretical { "*" } else { "" };
    cells.extend([
        th.with.text.to_string(),
        th.without.text.to_string(),
        format!("{}{star}", pct(th.reduction)),
    ]);
    let t_without = row
        .without
        .as_ref()
        .map_or("–".into(), |m| seconds(m.time_s));
    cells.push(format!("{} / {t_without}", seconds(w.time_s)));
    cells.push(format!("{:.2}", w.mrays_per_s));
    cells
}

fn breakdown(row: &MetricRow) -> String {
    let kinds = |m: &Measurement| {
        format!(
            "{} / {} / {}",
            count(m.primary),
            count(m.shadow),
            count(m.reflection)
        )
    };
    let without = row.without.as_ref().map_or("not rendered".into(), kinds);
    format!(
        "{}: with {} ({} saved), without {}; metric: {}.",
        row.setting,
        kinds(&row.with),
        count(row.with.saved),
        without,
        row.metric
    )
}

pub fn figures(figs: &[Figure]) -> Vec<Block> {
    let mut out = vec![h(2, "Figures")];
    for f in figs {
        out.push(h(3, format!("Figure {}: {}", f.id, f.title)));
        out.push(Block::Image {
            src: f.file.clone(),
            alt: format!("Figure {}: {}", f.id, f.title),
            caption: format!("{} Panels: {}.", f.caption, f.panels.join("; ")),
        });
    }
    out
}

pub fn plot(pl: &Plot) -> Block {
    Block::Image {
        src: pl.file.clone(),
        alt: pl.title.clone(),
        caption: pl.caption.clone(),
    }
}

pub fn sweep(points: &[SweepPoint]) -> Block {
    let mut t = Table::new(&[
        "metric",
        "budget",
        "+metric",
        "−metric",
        "reduction",
        "parameters",
    ]);
    t.numeric[0] = false;
    t.numeric[5] = false;
    for s in points {
        t.row(vec![
            s.metric.clone(),
            s.budget.to_string(),
            count(s.with.total),
            count(s.without.total),
            pct(s.reduction_pct),
            s.parameters.clone(),
        ]);
    }
    Block::Table(t)
}

/// The convergence study: a slope table over all effects, then per effect
/// its plot and errors.
pub fn convergence(studies: &[Study]) -> Vec<Block> {
    let mut out = vec![
        h(2, "Beyond the thesis: convergence of the six distributions"),
        p("For each effect a crop is rendered with a converged reference (the average of two jittered renders with many rays and different seeds), then with every distribution at each ray count; the error is the RMSE of linear radiance over the crop's pixels and channels, averaged over seeds (as mean squared error), and the relative MSE is the mean of (x − r)² / (r² + 0.01). The slope is the least-squares fit of ln RMSE against ln rays: −0.5 is the rate of independent random samples, stratified samples do better on smooth integrands, and a curve that flattens converges to something other than the reference (bias) or has reached the reference's own noise."),
    ];
    let mut head = vec!["distribution".to_string()];
    head.extend(studies.iter().map(|s| format!("slope, {}", s.effect)));
    let head_ref: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut slopes = Table::new(&head_ref);
    slopes.numeric[0] = false;
    let names: Vec<String> = studies
        .first()
        .map(|s| s.curves.iter().map(|c| c.distribution.clone()).collect())
        .unwrap_or_default();
    for (i, name) in names.iter().enumerate() {
        let mut row = vec![name.clone()];
        row.extend(
            studies
                .iter()
                .map(|s| s.curves.get(i).map_or("–".into(), |c| signed(c.slope))),
        );
        slopes.row(row);
    }
    out.push(Block::Table(slopes));
    for s in studies {
        out.extend(study(s));
    }
    out
}

fn study(s: &Study) -> Vec<Block> {
    let counts: Vec<u32> = s
        .curves
        .first()
        .map(|c| c.points.iter().map(|p| p.0).collect())
        .unwrap_or_default();
    let mut head = vec!["distribution".to_string()];
    head.extend(counts.iter().map(|n| format!("RMSE, {n}")));
    head.push(format!("relMSE, {}", counts.last().copied().unwrap_or(0)));
    head.push("slope".into());
    head.push(format!("RMSE, {} (limit)", s.reference_rays));
    head.push("bias (est.)".into());
    let head_ref: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut t = Table::new(&head_ref);
    t.numeric[0] = false;
    for c in &s.curves {
        let mut row = vec![c.distribution.clone()];
        row.extend(c.points.iter().map(|p| format!("{:.4}", p.1)));
        row.push(
            c.points
                .last()
                .map_or("–".into(), |p| format!("{:.4}", p.2)),
        );
        row.push(signed(c.slope));
        row.push(c.limit_rmse.map_or("–".into(), |v| format!("{v:.4}")));
        row.push(c.bias_estimate.map_or("–".into(), |v| format!("{v:.4}")));
        t.row(row);
    }
    vec![
        h(3, format!("Convergence: {}", s.effect)),
        p(format!(
            "Scene `{}`, a {}×{} crop; the count is in {}. Reference: two jittered renders of {} rays each, averaged; its own RMSE ≈ {:.4}. The last column is one render with the reference's count, for the distributions that do not fill the reference's square (random: a disk, fast-random: a cube): its noise part is known (independent samples: the RMSE at the largest count times √(count / reference count)), and what remains, √(limit² − noise²), estimates how far the image it converges to is from the reference (bias). A bias well above the reference's own RMSE flattens the curve.",
            s.scene, s.pixels.0, s.pixels.1, s.unit, s.reference_rays, s.reference_rmse
        )),
        plot(&s.plot),
        Block::Table(t),
    ]
}

/// Library warnings, listed once.
pub fn warnings(w: &[String]) -> Vec<Block> {
    if w.is_empty() {
        return Vec::new();
    }
    vec![h(2, "Renderer warnings"), Block::List(w.to_vec())]
}
