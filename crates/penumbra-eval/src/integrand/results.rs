//! What the study measured: every RMSE, fit and target, and where the
//! files went.

use std::path::PathBuf;

use serde::Serialize;

use super::functions::Class;
use crate::fit::Fit;
use crate::render_level::RenderLevel;
use crate::stopping::StoppingStudy;

/// Largest distance of a measured slope from its target that counts as
/// agreeing with theory.
pub const TOLERANCE: f64 = 0.05;

/// Smallest count of the second, large-N fit ([`Curve::tail_fit`]).
pub const TAIL_FROM: usize = 64;

/// The error of one distribution at one count.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Point {
    /// Points per set.
    pub n: usize,
    /// Root mean square of (estimate − exact) over the sets.
    pub rmse: f64,
    /// Mean of (estimate − exact): the bias, up to noise of RMSE / √seeds.
    pub mean_error: f64,
    /// Whether the slope fit uses this point (see the module docs).
    pub fitted: bool,
}

/// One distribution on one integrand.
#[derive(Clone, Debug, Serialize)]
pub struct Curve {
    pub distribution: String,
    pub points: Vec<Point>,
    /// The power law fitted to the fitted points; `None` when fewer than two
    /// have a positive RMSE.
    pub fit: Option<Fit>,
    /// The same fit over the counts from [`TAIL_FROM`] on: theory's rates
    /// are asymptotic, and the smallest sets can sit before the asymptote.
    /// Shown beside the main fit; the verdict is on the main fit.
    pub tail_fit: Option<Fit>,
    /// The slope theory predicts, if it predicts one.
    pub theory: Option<f64>,
    /// `|slope − theory| <= TOLERANCE`, when both exist.
    pub within: Option<bool>,
}

/// One integrand with its curves.
#[derive(Clone, Debug, Serialize)]
pub struct IntegrandResult {
    pub name: String,
    pub class: Class,
    pub description: String,
    /// The integral over the unit square, in closed form.
    pub exact: f64,
    /// The plot, relative to the output directory.
    pub plot: String,
    pub curves: Vec<Curve>,
}

/// A row of the theory table, as written to the JSON.
#[derive(Clone, Debug, Serialize)]
pub struct TheoryRow {
    pub distributions: Vec<String>,
    pub edge: Option<f64>,
    pub smooth: Option<f64>,
    pub basis: String,
}

/// The whole study: the configuration, every RMSE and fit, the theory.
#[derive(Clone, Debug, Serialize)]
pub struct DistributionStudy {
    pub quick: bool,
    pub seeds: u32,
    pub counts: Vec<usize>,
    pub threads: usize,
    /// The whole study's time, and the integrand level's.
    pub elapsed_s: f64,
    pub integrand_s: f64,
    pub tolerance: f64,
    pub theory: Vec<TheoryRow>,
    pub integrands: Vec<IntegrandResult>,
    /// The render level, when it ran.
    pub render: Option<RenderLevel>,
    /// The stopping comparison, when it ran.
    pub stopping: Option<StoppingStudy>,
    /// The output directory (not written into the JSON).
    #[serde(skip)]
    pub out: PathBuf,
}

impl DistributionStudy {
    pub fn markdown_path(&self) -> PathBuf {
        self.out.join("distributions.md")
    }
    pub fn html_path(&self) -> PathBuf {
        self.out.join("distributions.html")
    }
    pub fn json_path(&self) -> PathBuf {
        self.out.join("distributions.json")
    }

    /// Every file written, relative to the output directory.
    pub fn files(&self) -> Vec<String> {
        let mut f: Vec<String> = [
            "distributions.md",
            "distributions.html",
            "distributions.json",
        ]
        .map(String::from)
        .to_vec();
        f.extend(self.integrands.iter().map(|i| i.plot.clone()));
        if let Some(r) = &self.render {
            f.extend(r.svgs.iter().map(|s| s.0.clone()));
        }
        if let Some(s) = &self.stopping {
            f.extend(s.svgs.iter().map(|s| s.0.clone()));
        }
        f
    }

    /// The curve of `distribution` on `integrand`, by name.
    pub fn curve(&self, integrand: &str, distribution: &str) -> Option<&Curve> {
        self.integrands
            .iter()
            .find(|i| i.name == integrand)?
            .curves
            .iter()
            .find(|c| c.distribution == distribution)
    }
}
