//! The result of a run and the files that present it: `report.md`,
//! `report.html` (the same blocks) and `report.json` (the raw numbers).

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::convergence::Study;
use crate::doc::{to_html, to_markdown, Block};
use crate::error::EvalError;
use crate::figures::Figure;
use crate::growth::{Plot, SweepPoint};
use crate::sections;
use crate::tables::Tables;

/// Everything a run measured and wrote.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub quick: bool,
    /// Worker threads the renders used.
    pub threads: usize,
    /// Wall-clock time of the whole run.
    pub elapsed_s: f64,
    /// Distinct renders made.
    pub renders: usize,
    pub tables: Tables,
    pub figures: Vec<Figure>,
    /// Ray growth and metric plots.
    pub plots: Vec<Plot>,
    pub sweep: Vec<SweepPoint>,
    pub convergence: Vec<Study>,
    /// How this run's setup differs from the thesis's.
    pub deviations: Vec<String>,
    /// The renderer's warnings, each once.
    pub warnings: Vec<String>,
    /// The output directory (not written into `report.json`: the files refer
    /// to each other by relative paths only).
    #[serde(skip)]
    pub out: PathBuf,
}

impl Report {
    pub fn markdown_path(&self) -> PathBuf {
        self.out.join("report.md")
    }
    pub fn html_path(&self) -> PathBuf {
        self.out.join("report.html")
    }
    pub fn json_path(&self) -> PathBuf {
        self.out.join("report.json")
    }

    /// Every file of the report, relative to the output directory.
    pub fn files(&self) -> Vec<String> {
        let mut f: Vec<String> = ["report.md", "report.html", "report.json"]
            .map(String::from)
            .to_vec();
        f.extend(self.figures.iter().map(|x| x.file.clone()));
        f.extend(self.plots.iter().map(|x| x.file.clone()));
        f.extend(self.convergence.iter().map(|x| x.plot.file.clone()));
        f
    }

    /// The report as blocks, in reading order.
    pub fn blocks(&self) -> Vec<Block> {
        let mut b = sections::intro(self);
        b.extend(sections::summary(self));
        b.push(Block::Heading(2, "Ray counts (Tables 4.1–4.6)".into()));
        let order = ["S", "4.1", "4.2", "4.3"];
        for id in order {
            if let Some(t) = self.tables.count(id) {
                b.extend(sections::count_table(t));
            }
        }
        if let Some(t) = self.tables.metric("4.4") {
            b.extend(sections::metric_table(t));
        }
        if let Some(t) = self.tables.count("4.5") {
            b.extend(sections::count_table(t));
        }
        if let Some(t) = self.tables.metric("4.6") {
            b.extend(sections::metric_table(t));
        }
        b.push(Block::Heading(2, "Plots".into()));
        for pl in &self.plots {
            b.push(Block::Heading(3, pl.title.clone()));
            b.push(sections::plot(pl));
        }
        b.push(Block::Paragraph(
            "The metric sweep behind the last plot:".into(),
        ));
        b.push(sections::sweep(&self.sweep));
        b.extend(sections::figures(&self.figures));
        b.extend(sections::convergence(&self.convergence));
        b.extend(sections::warnings(&self.warnings));
        b
    }

    /// Writes `report.md`, `report.html` and `report.json` into the output directory.
    pub fn write(&self) -> Result<(), EvalError> {
        let blocks = self.blocks();
        let md = to_markdown(&blocks);
        let html = to_html("Penumbra: the thesis's evaluation, reproduced", &blocks);
        let json = serde_json::to_string_pretty(self).map_err(|e| EvalError::Write {
            path: self.json_path(),
            message: e.to_string(),
        })?;
        write(&self.markdown_path(), md.as_bytes())?;
        write(&self.html_path(), html.as_bytes())?;
        write(&self.json_path(), json.as_bytes())
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), EvalError> {
    crate::output::write_file(path, bytes)
}
