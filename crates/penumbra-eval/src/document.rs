//! The report as a document: its sections in reading order, written as
//! `report.md` and `report.html` (the same blocks), with the raw numbers
//! beside them in `report.json`.

use crate::doc::{to_html, to_markdown, Block};
use crate::error::EvalError;
use crate::output::write_file;
use crate::report::Report;
use crate::sections;

/// The report as blocks, in reading order.
pub fn blocks(r: &Report) -> Vec<Block> {
    let mut b = sections::intro(r);
    b.extend(sections::summary(r));
    b.push(Block::Heading(2, "Ray counts (Tables 4.1–4.6)".into()));
    let order = ["S", "4.1", "4.2", "4.3"];
    for id in order {
        if let Some(t) = r.tables.count(id) {
            b.extend(sections::count_table(t));
        }
    }
    if let Some(t) = r.tables.metric("4.4") {
        b.extend(sections::metric_table(t));
    }
    if let Some(t) = r.tables.count("4.5") {
        b.extend(sections::count_table(t));
    }
    if let Some(t) = r.tables.metric("4.6") {
        b.extend(sections::metric_table(t));
    }
    b.push(Block::Heading(2, "Plots".into()));
    for pl in &r.plots {
        b.push(Block::Heading(3, pl.title.clone()));
        b.push(sections::plot(pl));
    }
    b.push(Block::Paragraph(
        "The metric sweep behind the last plot:".into(),
    ));
    b.push(sections::sweep(&r.sweep));
    b.extend(sections::figures(&r.figures));
    b.extend(sections::convergence(&r.convergence));
    b.extend(sections::warnings(&r.warnings));
    b
}

/// Writes `report.md`, `report.html` and `report.json` into the report's
/// output directory.
pub fn write(r: &Report) -> Result<(), EvalError> {
    let blocks = blocks(r);
    let md = to_markdown(&blocks);
    let html = to_html("Penumbra: the thesis's evaluation, reproduced", &blocks);
    let json = serde_json::to_string_pretty(r).map_err(|e| EvalError::Write {
        path: r.json_path(),
        message: e.to_string(),
    })?;
    write_file(&r.markdown_path(), md.as_bytes())?;
    write_file(&r.html_path(), html.as_bytes())?;
    write_file(&r.json_path(), json.as_bytes())
}
