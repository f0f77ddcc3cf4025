//! What the render level measured.

use serde::Serialize;

use crate::fit::Fit;

/// The error of one distribution at one count, over the seeds.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct RenderPoint {
    /// Rays of the effect.
    pub n: u32,
    /// `√max(MSE − MSE_ref, 0)`: the RMSE against the reference with the
    /// reference's own noise taken out.
    pub rmse: f64,
    /// `√MSE`, the RMSE against the reference as measured.
    pub raw_rmse: f64,
    /// Mean render time of the crop.
    pub seconds: f64,
    /// Mean rays traced for the crop, of every kind.
    pub rays: f64,
    /// Whether the fits use this point: `MSE ≥ 4 MSE_ref`.
    pub fitted: bool,
}

/// One distribution on one effect.
#[derive(Clone, Debug, Serialize)]
pub struct RenderCurve {
    pub distribution: String,
    /// The distribution of the reference it is measured against.
    pub reference: String,
    pub points: Vec<RenderPoint>,
    /// ln RMSE against ln N over the fitted points.
    pub fit: Option<Fit>,
    /// ln RMSE against ln seconds over the fitted points.
    pub time_fit: Option<Fit>,
}

/// A reference of an effect.
#[derive(Clone, Debug, Serialize)]
pub struct Reference {
    /// The distribution rendered.
    pub distribution: String,
    /// The distributions measured against it.
    pub serves: Vec<String>,
    /// Its own RMSE, from its two halves.
    pub rmse: f64,
}

/// One effect with its curves.
#[derive(Clone, Debug, Serialize)]
pub struct EffectResult {
    pub name: String,
    pub unit: String,
    pub description: String,
    /// Size of the crop.
    pub pixels: (u32, u32),
    pub references: Vec<Reference>,
    pub curves: Vec<RenderCurve>,
    /// The plots, relative to the output directory.
    pub plot_rays: String,
    pub plot_time: String,
}

/// The render level of the distribution study.
#[derive(Clone, Debug, Serialize)]
pub struct RenderLevel {
    pub frame: (u32, u32),
    pub counts: Vec<u32>,
    pub poisson_max: u32,
    pub seeds: u32,
    pub reference_rays: u32,
    pub elapsed_s: f64,
    pub effects: Vec<EffectResult>,
    /// Every plot's path and SVG text (not written into the JSON).
    #[serde(skip)]
    pub svgs: Vec<(String, String)>,
}

impl RenderLevel {
    /// The curve of `distribution` on `effect`, by name.
    pub fn curve(&self, effect: &str, distribution: &str) -> Option<&RenderCurve> {
        self.effects
            .iter()
            .find(|e| e.name == effect)?
            .curves
            .iter()
            .find(|c| c.distribution == distribution)
    }

    /// The SVG text of the plot at `path`.
    pub fn svg(&self, path: &str) -> &str {
        crate::loglog::svg_at(&self.svgs, path)
    }
}
