//! The result of a run: the numbers, and the names of the files that
//! present it (`report.md`, `report.html` and `report.json`, written by
//! `document`).

use std::path::PathBuf;

use serde::Serialize;

use crate::convergence::Study;
use crate::figures::Figure;
use crate::growth::{Plot, SweepPoint};
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
}
