//! What the stopping comparison measured, and the figures drawn from it.

use serde::Serialize;

use super::coverage::Coverage;
use super::equal::{median, range, rays_at, targets};

/// One step of a sweep.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Run {
    /// The threshold (or rays per pixel, for `uniform`).
    pub value: f64,
    /// Rays traced, of every kind, and camera rays among them.
    pub rays: u64,
    pub primary: u64,
    /// RMSE against the reference with its noise taken out, and as measured.
    pub rmse: f64,
    pub raw_rmse: f64,
    pub seconds: f64,
    /// For the calibrated rule: its intervals against the reference.
    pub coverage: Option<Coverage>,
}

/// A variant's sweep on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct VariantResult {
    pub name: String,
    /// What the sweep's values are.
    pub measure: String,
    /// Whether the calibrated rule is compared with it.
    pub anchor: bool,
    pub runs: Vec<Run>,
}

impl VariantResult {
    /// (rays, RMSE) of each step.
    pub fn sweep(&self) -> Vec<(f64, f64)> {
        self.runs.iter().map(|r| (r.rays as f64, r.rmse)).collect()
    }
}

/// The rays each variant needs for one target RMSE.
#[derive(Clone, Debug, Serialize)]
pub struct EqualRow {
    pub target: f64,
    /// In the order of the variants; `None` outside a variant's sweep.
    pub rays: Vec<Option<f64>>,
    /// The anchor that needs the fewest, and the calibrated rule's rays
    /// over its.
    pub best_anchor: Option<String>,
    pub ratio: Option<f64>,
}

/// One scene.
#[derive(Clone, Debug, Serialize)]
pub struct SceneResult {
    pub name: String,
    pub description: String,
    /// The reference's own RMSE.
    pub reference_rmse: f64,
    pub variants: Vec<VariantResult>,
    pub equal: Vec<EqualRow>,
    /// Median over the targets of the calibrated rule's rays over the best
    /// anchor's.
    pub ratio: Option<f64>,
    /// The calibrated rule's pixels over every step of its sweep.
    pub coverage: Coverage,
    pub plot: String,
}

impl SceneResult {
    /// The figures of scene `name` from its sweeps; the first variant is the
    /// calibrated rule. Targets are spaced over the RMSEs both it and an
    /// anchor reach, and above twice the reference's noise.
    pub fn new(
        (name, description): (&str, &str),
        reference_rmse: f64,
        variants: Vec<VariantResult>,
        count: usize,
    ) -> SceneResult {
        let equal = equal_rows(&variants, reference_rmse, count);
        let ratio = median(&equal.iter().filter_map(|e| e.ratio).collect::<Vec<_>>());
        let mut coverage = Coverage::default();
        for c in variants
            .iter()
            .flat_map(|v| &v.runs)
            .filter_map(|r| r.coverage)
        {
            coverage.add(&c);
        }
        SceneResult {
            name: name.to_string(),
            description: description.to_string(),
            reference_rmse,
            equal,
            ratio,
            coverage,
            plot: format!("plots/stopping-{}.svg", name.replace(' ', "-")),
            variants,
        }
    }
}

/// The rows of equal RMSE (see [`SceneResult::new`]).
pub fn equal_rows(variants: &[VariantResult], floor: f64, count: usize) -> Vec<EqualRow> {
    let Some(calibrated) = variants.first().and_then(|v| range(&v.sweep())) else {
        return Vec::new();
    };
    let anchors: Vec<(f64, f64)> = variants
        .iter()
        .filter(|v| v.anchor)
        .filter_map(|v| range(&v.sweep()))
        .collect();
    let lo = anchors.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
    let hi = anchors.iter().map(|r| r.1).fold(0.0, f64::max);
    let lo = calibrated.0.max(lo).max(2.0 * floor);
    let hi = calibrated.1.min(hi);
    targets(lo, hi, count)
        .into_iter()
        .map(|target| {
            let rays: Vec<Option<f64>> = variants
                .iter()
                .map(|v| rays_at(&v.sweep(), target))
                .collect();
            let best = variants
                .iter()
                .zip(&rays)
                .filter(|(v, _)| v.anchor)
                .filter_map(|(v, r)| r.map(|r| (v.name.clone(), r)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let ratio = rays[0].zip(best.as_ref()).map(|(c, b)| c / b.1);
            EqualRow {
                target,
                rays,
                best_anchor: best.map(|b| b.0),
                ratio,
            }
        })
        .collect()
}

/// The comparison in a few numbers.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Median over the scenes of `1 − ratio`: the share of the best
    /// anchor's rays the calibrated rule saves at equal RMSE.
    pub median_saving: Option<f64>,
    /// The largest ratio over the scenes, and its scene.
    pub worst_ratio: Option<f64>,
    pub worst_scene: Option<String>,
    /// Scenes with at least one target.
    pub scenes_compared: usize,
    /// Every calibrated pixel of every scene and step together.
    pub coverage: Coverage,
    /// The smallest coverage and largest false-stop rate of one render.
    pub coverage_min: Option<f64>,
    pub false_stops_max: Option<f64>,
}

impl Summary {
    pub fn of(scenes: &[SceneResult]) -> Summary {
        let ratios: Vec<(f64, &str)> = scenes
            .iter()
            .filter_map(|s| s.ratio.map(|r| (r, s.name.as_str())))
            .collect();
        let savings: Vec<f64> = ratios.iter().map(|r| 1.0 - r.0).collect();
        let worst = ratios.iter().max_by(|a, b| a.0.total_cmp(&b.0));
        let mut coverage = Coverage::default();
        for s in scenes {
            coverage.add(&s.coverage);
        }
        let renders: Vec<Coverage> = scenes
            .iter()
            .flat_map(|s| &s.variants)
            .flat_map(|v| &v.runs)
            .filter_map(|r| r.coverage)
            .filter(|c| c.pixels > 0)
            .collect();
        Summary {
            median_saving: median(&savings),
            worst_ratio: worst.map(|w| w.0),
            worst_scene: worst.map(|w| w.1.to_string()),
            scenes_compared: ratios.len(),
            coverage,
            coverage_min: renders.iter().map(Coverage::rate).reduce(f64::min),
            false_stops_max: renders
                .iter()
                .map(Coverage::false_stop_rate)
                .reduce(f64::max),
        }
    }
}

/// The whole comparison.
#[derive(Clone, Debug, Serialize)]
pub struct StoppingStudy {
    pub frame: (u32, u32),
    pub spp: u32,
    pub reference_spp: u32,
    pub confidence: f32,
    pub replicas: u32,
    pub elapsed_s: f64,
    pub scenes: Vec<SceneResult>,
    pub summary: Summary,
    /// Every plot's path and SVG text (not written into the JSON).
    #[serde(skip)]
    pub svgs: Vec<(String, String)>,
}

impl StoppingStudy {
    /// The SVG text of the plot at `path`.
    pub fn svg(&self, path: &str) -> &str {
        crate::loglog::svg_at(&self.svgs, path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn variant(name: &str, anchor: bool, c: f64) -> VariantResult {
        VariantResult {
            name: name.into(),
            measure: String::new(),
            anchor,
            runs: [1e3, 1e4, 1e5, 1e6]
                .iter()
                .map(|&n| Run {
                    value: 0.0,
                    rays: n as u64,
                    primary: 0,
                    rmse: c * f64::powf(n, -0.5),
                    raw_rmse: 0.0,
                    seconds: 0.0,
                    coverage: None,
                })
                .collect(),
        }
    }

    /// Power laws of one slope whose constants differ by 2 and by 1.5: at
    /// every common RMSE the calibrated rule needs (1/1.5)² of the best
    /// anchor's rays; a worse anchor and `uniform` do not change that.
    #[test]
    fn the_best_anchor_at_equal_rmse_on_power_laws() {
        let vs = vec![
            variant("calibrated", false, 1.0),
            variant("cycles", true, 2.0),
            variant("povray", true, 1.5),
            variant("uniform", false, 0.5),
        ];
        let rows = equal_rows(&vs, 0.0, 4);
        assert_eq!(rows.len(), 4);
        for r in &rows {
            assert_eq!(r.best_anchor.as_deref(), Some("povray"));
            let ratio = r.ratio.unwrap_or(f64::NAN);
            assert!((ratio - 1.0 / 2.25).abs() < 1e-9, "{ratio}");
            assert!(r.target >= 1.5e-3 && r.target <= 1.0 / 1e3f64.sqrt());
        }
        // Twice the reference's noise bounds the targets from below.
        let floored = equal_rows(&vs, 0.01, 3);
        assert!(floored.iter().all(|r| r.target >= 0.02));
    }
}
