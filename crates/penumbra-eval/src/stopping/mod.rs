//! The stopping rules compared: for each rule of adaptive sampling
//! (`calibrated`, `cycles`, `povray`, `dammertz`), the thesis's α/threshold
//! metric applied to a pixel's camera rays, and a uniform budget, on five
//! scenes: a sweep of the rule's threshold, the rays traced and the RMSE
//! against a reference at each step, and the rays each needs for common
//! target RMSEs (`equal.rs`); and for the calibrated rule, pixel by pixel,
//! how often its interval holds the reference and how often it stops a
//! pixel far from it (`coverage.rs`).
//!
//! The five scenes are settings of the built-in `showcase` (no external
//! file), each with a different integrand per pixel: the film alone
//! (edges, and the ball's motion), one shadow ray per camera ray (soft
//! shadows), one reflection and one refraction ray per camera ray (glossy
//! surfaces), a lens (depth of field), and all of them at once. Each is the
//! whole frame, so the rays counted are the pixels' own. Every rule draws
//! its camera rays from [`PIXELS`] (film, lens, time), at most `spp` per pixel,
//! with the rule's own minimum; the one-ray sets below a camera ray are
//! `jitter` (a uniform point) where an effect is on and the perfect `grid`
//! ray where it is off.
//!
//! **The reference** is the mean of two renders of `reference_spp` camera
//! rays per pixel of `jitter`, with seeds no trial uses: an independent
//! estimate of the same image, whose own mean squared error (a quarter of
//! its halves' mean squared difference) is subtracted from each trial's, as
//! in the render level.

mod coverage;
mod equal;
mod results;
mod section;

use std::path::Path;
use std::time::Instant;

use penumbra::render::Image;
use penumbra::sampling::Distribution;
use penumbra::scene::{Overrides, StopRule};

use crate::convergence::{average, mse};
use crate::error::EvalError;
use crate::job::Job;
use crate::loglog::{LogLog, LogSeries, XAxis};
use crate::runner::{Rendered, Runner};

pub use coverage::Coverage;
pub use equal::{median, rays_at};
pub use results::{EqualRow, Run, SceneResult, StoppingStudy, Summary, VariantResult};
pub use section::blocks;

/// The distribution of every rule's camera rays (film, lens, time):
/// `pmj02`, progressive (every power-of-two prefix of a set in trace
/// order is a net, as the rules' passes need) and stratified in 1D and 2D.
pub const PIXELS: Distribution = Distribution::Pmj02;

/// Seeds of the reference's halves (trials use seed 1).
const REFERENCE_SEED: u32 = 9000;

/// Confidence, replicas and floor of the calibrated rule (its defaults).
pub const CONFIDENCE: f32 = 0.9;
pub const REPLICAS: u32 = 8;
pub const FLOOR: f32 = 1.0;

/// The targets set for the calibrated rule, reported against the
/// measured figures (never asserted).
pub const TARGET_SAVING: f64 = 0.25;
pub const TARGET_WORST: f64 = 1.05;
pub const TARGET_COVERAGE: f64 = 0.9;
pub const TARGET_FALSE_STOPS: f64 = 0.01;

/// What is compared: a rule of adaptive sampling, the pixel metric, or a
/// fixed number of rays per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    Rule(StopRule),
    /// The thesis's α/threshold metric on a pixel's camera rays.
    PixelMetric,
    /// Every pixel `spp` rays: the sweep is over `spp`.
    Uniform,
}

impl Variant {
    pub const ALL: [Variant; 6] = [
        Variant::Rule(StopRule::Calibrated),
        Variant::Rule(StopRule::Cycles),
        Variant::Rule(StopRule::Povray),
        Variant::Rule(StopRule::Dammertz),
        Variant::PixelMetric,
        Variant::Uniform,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Variant::Rule(r) => r.name(),
            Variant::PixelMetric => "pixel metric",
            Variant::Uniform => "uniform",
        }
    }

    /// Whether it is an anchor the calibrated rule is compared with.
    pub fn is_anchor(self) -> bool {
        !matches!(self, Variant::Rule(StopRule::Calibrated) | Variant::Uniform)
    }

    /// What its sweep's values are.
    pub fn measure(self) -> &'static str {
        match self {
            Variant::Rule(StopRule::Calibrated) => {
                "T: the interval's half-width relative to the pixel's largest channel"
            }
            Variant::Rule(StopRule::Cycles) => "T: Cycles' noise threshold",
            Variant::Rule(StopRule::Povray) => {
                "T: POV-Ray's antialias threshold (sum of the channels' half-widths, gamma 2.5)"
            }
            Variant::Rule(StopRule::Dammertz) => "e_t: Dammertz's block error threshold",
            Variant::PixelMetric => "the metric's threshold on the change of the running mean",
            Variant::Uniform => "rays per pixel",
        }
    }

    /// The settings of one step of the sweep.
    fn apply(self, o: &mut Overrides, value: f64, spp: u32) {
        match self {
            Variant::Rule(rule) => {
                o.spp = Some(spp);
                o.noise_threshold = Some(value as f32);
                o.stop_rule = Some(rule);
                o.confidence = Some(CONFIDENCE);
                o.replicas = Some(REPLICAS);
                o.noise_floor = Some(FLOOR);
            }
            Variant::PixelMetric => {
                o.spp = Some(spp);
                o.metric = Some(true);
                o.pixel_metric = Some(true);
                o.reflection_metric = Some(false);
                o.shadow_metric = Some(false);
                o.metric_threshold = Some(value as f32);
            }
            Variant::Uniform => o.spp = Some(value as u32),
        }
    }
}

/// One scene of the comparison: a setting of the showcase.
#[derive(Clone, Copy, Debug)]
pub struct StopScene {
    pub name: &'static str,
    pub description: &'static str,
    apply: fn(&mut Overrides),
}

fn film_only(_: &mut Overrides) {}

fn soft_shadows(o: &mut Overrides) {
    o.shadow_distribution = Some(Distribution::Jitter);
}

fn glossy(o: &mut Overrides) {
    o.reflection_distribution = Some(Distribution::Jitter);
    o.refraction_distribution = Some(Distribution::Jitter);
}

fn depth_of_field(o: &mut Overrides) {
    o.aperture = Some(0.15);
    o.focal_distance = Some(5.0);
}

fn everything(o: &mut Overrides) {
    soft_shadows(o);
    glossy(o);
    o.aperture = Some(0.06);
}

/// The five scenes.
pub const SCENES: [StopScene; 5] = [
    StopScene {
        name: "film",
        description: "film positions alone: edges, reflections in the mirror, the ball's motion",
        apply: film_only,
    },
    StopScene {
        name: "soft shadows",
        description: "one shadow ray per camera ray to the area light",
        apply: soft_shadows,
    },
    StopScene {
        name: "glossy",
        description: "one reflection and one refraction ray per camera ray (glossy sphere, \
                      frosted glass)",
        apply: glossy,
    },
    StopScene {
        name: "depth of field",
        description: "a lens of radius 0.15 focused at 5",
        apply: depth_of_field,
    },
    StopScene {
        name: "everything",
        description: "soft shadows, glossy surfaces and the scene's own lens (0.06) at once",
        apply: everything,
    },
];

/// How big the comparison is.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    pub frame: (u32, u32),
    /// Most camera rays a pixel may take.
    pub spp: u32,
    /// Camera rays per pixel of each half of the reference.
    pub reference_spp: u32,
    /// The sweep of each variant, in the order of [`Variant::ALL`].
    pub sweeps: [Vec<f64>; 6],
    /// Target RMSEs per scene.
    pub targets: usize,
}

impl Config {
    /// A 96×64 frame, at most 1024 rays a pixel, references of 2 × 2304.
    pub fn full() -> Config {
        Config {
            frame: (96, 64),
            spp: 1024,
            reference_spp: 2304,
            sweeps: [
                vec![0.4, 0.2, 0.1, 0.05, 0.025, 0.0125],
                vec![0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625],
                vec![1.0, 0.5, 0.25, 0.125, 0.0625],
                vec![0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125],
                vec![0.03, 0.01, 0.003, 0.001, 0.0003],
                vec![16.0, 32.0, 64.0, 128.0, 256.0, 512.0, 1024.0],
            ],
            targets: 5,
        }
    }

    /// A 64×32 frame, at most 256 rays a pixel, references of 2 × 576.
    pub fn quick() -> Config {
        Config {
            frame: (64, 32),
            spp: 256,
            reference_spp: 576,
            sweeps: [
                vec![0.4, 0.1, 0.025],
                vec![0.2, 0.05, 0.0125],
                vec![1.0, 0.25, 0.0625],
                vec![0.04, 0.01, 0.0025],
                vec![0.03, 0.003, 0.0003],
                vec![16.0, 64.0, 256.0],
            ],
            targets: 3,
        }
    }

    fn base(&self, scene: &StopScene, pixels: Distribution, seed: u32) -> Overrides {
        let mut o = Overrides {
            width: Some(self.frame.0),
            height: Some(self.frame.1),
            seed: Some(seed),
            distribution: Some(Distribution::Grid),
            pixel_distribution: Some(pixels),
            lens_distribution: Some(pixels),
            time_distribution: Some(pixels),
            shadow_rays: Some(1),
            reflection_rays: Some(1),
            refraction_rays: Some(1),
            aperture: Some(0.0),
            ..Default::default()
        };
        (scene.apply)(&mut o);
        o
    }
}

fn trial(config: &Config, scene: &StopScene, v: Variant, value: f64) -> Job {
    let mut o = config.base(scene, PIXELS, 1);
    v.apply(&mut o, value, config.spp);
    Job::new(
        format!("stopping, {}: {} at {value}", scene.name, v.name()),
        "showcase",
        o,
    )
}

fn references(config: &Config, scene: &StopScene) -> [Job; 2] {
    [0, 1].map(|k| {
        let mut o = config.base(scene, Distribution::Jitter, REFERENCE_SEED + k);
        o.spp = Some(config.reference_spp);
        Job::new(
            format!("stopping, {}: reference {}", scene.name, k + 1),
            "showcase",
            o,
        )
    })
}

/// Every render of the comparison, for planning.
pub fn jobs(config: &Config) -> Vec<Job> {
    let mut out = Vec::new();
    for s in &SCENES {
        out.extend(references(config, s));
        for (v, sweep) in Variant::ALL.iter().zip(&config.sweeps) {
            out.extend(sweep.iter().map(|&x| trial(config, s, *v, x)));
        }
    }
    out
}

/// Runs the comparison and writes its plots (`plots/stopping-*.svg`) into
/// `out`.
pub fn run(runner: &mut Runner, config: &Config, out: &Path) -> Result<StoppingStudy, EvalError> {
    let started = Instant::now();
    runner.plan(&jobs(config));
    let mut scenes = Vec::new();
    let mut svgs = Vec::new();
    for s in &SCENES {
        let r = scene(runner, config, s)?;
        svgs.push((r.plot.clone(), plot(&r, out)?));
        scenes.push(r);
    }
    let summary = Summary::of(&scenes);
    Ok(StoppingStudy {
        frame: config.frame,
        spp: config.spp,
        reference_spp: config.reference_spp,
        confidence: CONFIDENCE,
        replicas: REPLICAS,
        elapsed_s: started.elapsed().as_secs_f64(),
        scenes,
        summary,
        svgs,
    })
}

fn scene(runner: &mut Runner, config: &Config, s: &StopScene) -> Result<SceneResult, EvalError> {
    let [a, b] = references(config, s);
    let (a, b) = (runner.run(&a)?, runner.run(&b)?);
    let reference = average(&a.image, &b.image);
    let reference_mse = mse(&a.image, &b.image) / 4.0;
    let mut variants = Vec::new();
    for (v, sweep) in Variant::ALL.iter().zip(&config.sweeps) {
        let mut runs = Vec::new();
        for &value in sweep {
            let r = runner.run(&trial(config, s, *v, value))?;
            runs.push(measure(
                &r,
                &reference,
                reference_mse,
                *v,
                value,
                config.spp,
            ));
        }
        variants.push(VariantResult {
            name: v.name().to_string(),
            measure: v.measure().to_string(),
            anchor: v.is_anchor(),
            runs,
        });
    }
    Ok(SceneResult::new(
        (s.name, s.description),
        reference_mse.sqrt(),
        variants,
        config.targets,
    ))
}

fn measure(
    r: &Rendered,
    reference: &Image,
    reference_mse: f64,
    v: Variant,
    value: f64,
    spp: u32,
) -> Run {
    let m = mse(&r.image, reference);
    let coverage = (v == Variant::Rule(StopRule::Calibrated)).then(|| {
        coverage::check(
            &r.image.pixels,
            &reference.pixels,
            &r.stats.pixel_samples,
            spp,
            (value as f32, FLOOR),
        )
    });
    Run {
        value,
        rays: r.stats.rays.total(),
        primary: r.stats.rays.primary,
        rmse: (m - reference_mse).max(0.0).sqrt(),
        raw_rmse: m.sqrt(),
        seconds: r.time().as_secs_f64(),
        coverage,
    }
}

/// RMSE against rays traced, one line per variant, the targets as grey
/// lines.
fn plot(r: &SceneResult, out: &Path) -> Result<String, EvalError> {
    let series = r
        .variants
        .iter()
        .map(|v| {
            let mut points: Vec<(f64, f64)> =
                v.runs.iter().map(|x| (x.rays as f64, x.rmse)).collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            LogSeries {
                label: v.name.clone(),
                points,
                ..Default::default()
            }
        })
        .collect::<Vec<_>>();
    let xs: Vec<f64> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .collect();
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(0.0, f64::max);
    let mut lines = Vec::new();
    if lo < hi {
        for (k, e) in r.equal.iter().enumerate() {
            let label = if k == 0 {
                "target RMSEs".to_string()
            } else {
                String::new()
            };
            lines.push((label, vec![(lo, e.target), (hi, e.target)]));
        }
    }
    LogLog {
        title: format!("Stopping rules, {}: RMSE against rays", r.name),
        x_desc: "rays traced (every kind)".into(),
        y_desc: "RMSE against the reference".into(),
        x_axis: XAxis::Values,
        series,
        lines,
    }
    .write(&out.join(&r.plot))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scene_and_step_is_planned_once() {
        for c in [Config::quick(), Config::full()] {
            let jobs = jobs(&c);
            let keys: std::collections::HashSet<String> = jobs.iter().map(Job::key).collect();
            assert_eq!(keys.len(), jobs.len());
            let steps: usize = c.sweeps.iter().map(Vec::len).sum();
            assert_eq!(jobs.len(), SCENES.len() * (2 + steps));
        }
        assert!(SCENES.len() >= 5);
        assert_eq!(
            Variant::ALL.iter().filter(|v| v.is_anchor()).count(),
            4,
            "cycles, povray, dammertz, the pixel metric"
        );
    }
}
