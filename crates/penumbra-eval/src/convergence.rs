//! Beyond the thesis: how fast each distribution converges. For penumbra,
//! glossy reflection, depth of field and anti-aliasing, a crop is rendered
//! with many jittered rays as the reference, then with each distribution at
//! a range of ray counts and seeds; the error against the reference is fitted
//! by a power law whose exponent (the slope on log–log axes) is the
//! convergence rate: −0.5 for independent random samples, steeper for
//! stratified ones, and a flattening curve for a distribution that converges
//! to a biased image.

use std::path::Path;

use penumbra::render::Image;
use penumbra::sampling::Distribution;
use penumbra::scene::Overrides;
use plotters::style::RGBColor;
use serde::Serialize;

use crate::chart::{Chart, Legend, Line, Scale, Series};
use crate::error::EvalError;
use crate::fit;
use crate::growth::Plot;
use crate::job::{Crop, Job, Variant};
use crate::plan::Plan;
use crate::runner::Runner;
use crate::tables::frame;

/// ε of the relative MSE, `(x − r)² / (r² + ε)`: keeps near-black pixels of
/// the reference from dominating (radiance of the lit floor is about 0.3–1).
pub const REL_EPSILON: f64 = 0.01;

/// Seed of the reference renders (the trials use 1, 2, 3…).
const REFERENCE_SEED: u32 = 1000;

/// One effect of a convergence study: which scene, which crop, which knob.
#[derive(Clone, Copy, Debug)]
pub struct Effect {
    pub name: &'static str,
    pub scene: &'static str,
    pub crop: Crop,
    /// What the count means ("shadow rays" …).
    pub unit: &'static str,
    /// Sets the effect's count and distribution.
    pub apply: fn(&mut Overrides, u32, Distribution),
    /// What is changed in the scene beyond its settings.
    pub variant: Variant,
}

impl Effect {
    /// The crop of the effect's scene with `base`'s settings, `n` rays of
    /// `d` for the effect, and `seed`.
    pub fn job(&self, base: Overrides, n: u32, d: Distribution, seed: u32) -> Job {
        let mut o = base;
        (self.apply)(&mut o, n, d);
        o.seed = Some(seed);
        Job::new(
            format!(
                "convergence, {}: {} {n} rays, seed {seed}",
                self.name,
                d.name()
            ),
            self.scene,
            o,
        )
        .with_crop(self.crop)
        .with_variant(self.variant)
    }
}

fn penumbra(o: &mut Overrides, n: u32, d: Distribution) {
    o.shadow_rays = Some(n);
    o.shadow_distribution = Some(d);
}

fn glossy(o: &mut Overrides, n: u32, d: Distribution) {
    o.reflection_rays = Some(n);
    o.reflection_distribution = Some(d);
}

fn depth_of_field(o: &mut Overrides, n: u32, d: Distribution) {
    o.spp = Some(n);
    o.lens_distribution = Some(d);
    o.pixel_distribution = Some(d);
    o.aperture = Some(0.15);
    o.focal_distance = Some(3.0);
}

fn anti_aliasing(o: &mut Overrides, n: u32, d: Distribution) {
    o.spp = Some(n);
    o.pixel_distribution = Some(d);
}

/// The four effects.
pub const EFFECTS: [Effect; 4] = [
    Effect {
        name: "penumbra",
        scene: "bunny",
        crop: Crop::new(0.18, 0.62, 0.48, 0.82),
        unit: "shadow rays",
        apply: penumbra,
        variant: Variant::AsIs,
    },
    Effect {
        name: "glossy reflection",
        scene: "bunny-reflect",
        crop: Crop::new(0.3, 0.78, 0.8, 1.0),
        unit: "reflection rays",
        apply: glossy,
        variant: Variant::AsIs,
    },
    Effect {
        name: "depth of field",
        scene: "bunnies-dof",
        crop: Crop::new(0.55, 0.35, 0.85, 0.6),
        unit: "primary rays (lens and film)",
        apply: depth_of_field,
        variant: Variant::AsIs,
    },
    Effect {
        name: "anti-aliasing",
        scene: "bunny",
        crop: Crop::new(0.3, 0.15, 0.55, 0.4),
        unit: "primary rays (film)",
        apply: anti_aliasing,
        variant: Variant::AsIs,
    },
];

/// The errors of one distribution at each count.
#[derive(Clone, Debug, Serialize)]
pub struct Curve {
    pub distribution: String,
    /// (rays, RMSE, relative MSE), each averaged over the seeds (RMSE as the
    /// root of the mean MSE).
    pub points: Vec<(u32, f64, f64)>,
    /// Least-squares slope of ln RMSE against ln rays.
    pub slope: f64,
    /// RMSE of one render with as many rays as a reference, for the
    /// distributions whose points do not cover the jittered square (see
    /// `LIMIT_DISTRIBUTIONS`): what they converge to differs from the
    /// reference by about this much.
    pub limit_rmse: Option<f64>,
    /// The part of `limit_rmse` that noise does not explain: with
    /// independent samples the noise at N rays is the RMSE at the largest
    /// count n scaled by √(n/N), so bias ≈ √(limit² − noise²) (0 when the
    /// limit is all noise).
    pub bias_estimate: Option<f64>,
}

/// Distributions whose native shape is not the square of the jittered
/// reference: `random` fills a disk and `fast-random` a cube, so where an
/// effect uses the points as they are (reflection end points, film
/// positions) they blur with a different kernel and converge to a slightly
/// different image. (Lights and lenses map every distribution onto the same
/// surface, so there they share the limit.) Poisson shares the square, and a
/// reference-size Poisson set would be very slow to generate.
pub const LIMIT_DISTRIBUTIONS: [Distribution; 2] = [Distribution::Random, Distribution::FastRandom];

/// Seed of the limit renders.
const LIMIT_SEED: u32 = 2000;

/// The study of one effect.
#[derive(Clone, Debug, Serialize)]
pub struct Study {
    pub effect: String,
    pub unit: String,
    pub scene: String,
    /// Size of the crop in pixels.
    pub pixels: (u32, u32),
    /// Rays of each of the two jittered renders averaged into the reference.
    pub reference_rays: u32,
    /// RMSE of the reference itself, estimated from two references with
    /// different seeds (half the RMSE between them, as they are averaged).
    pub reference_rmse: f64,
    pub curves: Vec<Curve>,
    pub plot: Plot,
}

fn job(plan: &Plan, e: &Effect, n: u32, d: Distribution, seed: u32) -> Job {
    e.job(frame(plan.convergence), n, d, seed)
}

fn references(plan: &Plan, e: &Effect) -> [Job; 2] {
    let n = plan.conv_reference;
    [0, 1].map(|k| job(plan, e, n, Distribution::Jitter, REFERENCE_SEED + k))
}

fn limit(plan: &Plan, e: &Effect, d: Distribution) -> Job {
    job(plan, e, plan.conv_reference, d, LIMIT_SEED)
}

/// Every job of the study, for planning.
pub fn jobs(plan: &Plan) -> Vec<Job> {
    let mut out = Vec::new();
    for e in &EFFECTS {
        out.extend(references(plan, e));
        out.extend(LIMIT_DISTRIBUTIONS.map(|d| limit(plan, e, d)));
        for d in Distribution::THESIS {
            for &n in &plan.conv_counts {
                out.extend((1..=plan.conv_seeds).map(|s| job(plan, e, n, d, s)));
            }
        }
    }
    out
}

/// Runs the study for every effect and writes its plots into `dir/plots/`.
pub fn run(runner: &mut Runner, plan: &Plan, dir: &Path) -> Result<Vec<Study>, EvalError> {
    EFFECTS
        .iter()
        .map(|e| study(runner, plan, e, dir))
        .collect()
}

fn study(runner: &mut Runner, plan: &Plan, e: &Effect, dir: &Path) -> Result<Study, EvalError> {
    let [a, b] = references(plan, e);
    let (ra, rb) = (runner.run(&a)?, runner.run(&b)?);
    let reference = average(&ra.image, &rb.image);
    let reference_rmse = mse(&ra.image, &rb.image).sqrt() / 2.0;
    let curves = Distribution::THESIS
        .into_iter()
        .map(|d| curve(runner, plan, e, d, &reference))
        .collect::<Result<Vec<_>, _>>()?;
    let plot = write_plot(e, &curves, (reference_rmse, plan.conv_reference), dir)?;
    Ok(Study {
        effect: e.name.into(),
        unit: e.unit.into(),
        scene: e.scene.into(),
        pixels: (reference.width, reference.height),
        reference_rays: plan.conv_reference,
        reference_rmse,
        curves,
        plot,
    })
}

/// One distribution's errors over the counts, its slope and (for some) its limit.
fn curve(
    runner: &mut Runner,
    plan: &Plan,
    e: &Effect,
    d: Distribution,
    reference: &Image,
) -> Result<Curve, EvalError> {
    let mut points = Vec::new();
    for &n in &plan.conv_counts {
        let (mut m, mut rel) = (0.0, 0.0);
        for s in 1..=plan.conv_seeds {
            let r = runner.run(&job(plan, e, n, d, s))?;
            m += mse(&r.image, reference);
            rel += rel_mse(&r.image, reference);
        }
        let k = f64::from(plan.conv_seeds.max(1));
        points.push((n, (m / k).sqrt(), rel / k));
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|p| (f64::from(p.0), p.1)).collect();
    let limit_rmse = match LIMIT_DISTRIBUTIONS.contains(&d) {
        true => Some(mse(&runner.run(&limit(plan, e, d))?.image, reference).sqrt()),
        false => None,
    };
    let bias_estimate = limit_rmse.and_then(|l| {
        let (n, e, _) = points.last()?;
        let noise = e * (f64::from(*n) / f64::from(plan.conv_reference)).sqrt();
        Some((l * l - noise * noise).max(0.0).sqrt())
    });
    Ok(Curve {
        distribution: d.name().into(),
        points,
        slope: fit::power_law(&logs).map_or(f64::NAN, |f| f.slope),
        limit_rmse,
        bias_estimate,
    })
}

/// The pixel-wise mean of two images of one size.
pub fn average(a: &Image, b: &Image) -> Image {
    let mut out = a.clone();
    for (o, p) in out.pixels.iter_mut().zip(&b.pixels) {
        *o = (*o + *p) * 0.5;
    }
    out
}

/// Mean squared error over pixels and channels.
pub fn mse(a: &Image, b: &Image) -> f64 {
    let n = (a.pixels.len().min(b.pixels.len()) * 3).max(1) as f64;
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(x, r)| x.to_array().into_iter().zip(r.to_array()))
        .map(|(x, r)| (f64::from(x) - f64::from(r)).powi(2))
        .sum();
    sum / n
}

/// Mean of `(x − r)² / (r² + ε)` over pixels and channels, `r` the reference.
pub fn rel_mse(x: &Image, reference: &Image) -> f64 {
    let n = (x.pixels.len().min(reference.pixels.len()) * 3).max(1) as f64;
    let sum: f64 = x
        .pixels
        .iter()
        .zip(&reference.pixels)
        .flat_map(|(x, r)| x.to_array().into_iter().zip(r.to_array()))
        .map(|(x, r)| {
            let (x, r) = (f64::from(x), f64::from(r));
            (x - r).powi(2) / (r * r + REL_EPSILON)
        })
        .sum();
    sum / n
}

/// `reference` is the reference's own RMSE and its rays per unit.
fn write_plot(
    e: &Effect,
    curves: &[Curve],
    (reference_rmse, reference_rays): (f64, u32),
    dir: &Path,
) -> Result<Plot, EvalError> {
    let mut chart = Chart::new(
        &format!("Convergence: {}", e.name),
        e.unit,
        "RMSE against the reference",
        Scale::Log,
        Scale::Log,
    );
    chart.legend = Legend::UpperRight;
    for (i, c) in curves.iter().enumerate() {
        let points = c.points.iter().map(|p| (f64::from(p.0), p.1)).collect();
        chart.series.push(Series::styled(
            i,
            format!("{} ({:.2})", c.distribution, c.slope),
            points,
        ));
    }
    if let Some(first) = curves
        .iter()
        .find(|c| c.distribution == "random")
        .and_then(|c| c.points.first())
    {
        let (n0, e0) = (f64::from(first.0), first.1);
        let last = curves
            .iter()
            .flat_map(|c| c.points.last())
            .map(|p| f64::from(p.0))
            .fold(n0, f64::max);
        let points = [n0, last]
            .iter()
            .map(|&n| (n, e0 * (n / n0).powf(-0.5)))
            .collect();
        chart.series.push(Series::dashed(
            "slope -0.5",
            points,
            RGBColor(150, 150, 150),
        ));
    }
    if reference_rmse > 0.0 {
        let span: Vec<f64> = curves
            .iter()
            .flat_map(|c| c.points.iter().map(|p| f64::from(p.0)))
            .collect();
        let lo = span.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = span.iter().copied().fold(0.0, f64::max);
        let mut noise = Series::dashed(
            "reference noise",
            vec![(lo, reference_rmse), (hi, reference_rmse)],
            RGBColor(90, 90, 90),
        );
        noise.line = Line::Solid;
        chart.series.push(noise);
    }
    let id = format!("convergence-{}", e.name.replace(' ', "-"));
    let file = format!("plots/{id}.svg");
    chart.write(&dir.join(&file))?;
    Ok(Plot {
        id,
        title: chart.title.clone(),
        caption: format!(
            "RMSE of the {} crop against the reference (two {}-ray jittered renders), per distribution, on log–log \
             axes; the legend gives each fitted slope. The grey dashed line has slope −0.5 (independent \
             samples); the solid grey line is the reference's own error.",
            e.name, reference_rays
        ),
        file,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_are_zero_for_equal_images_and_scale_as_squares() {
        let mut a = Image::new(2, 2);
        let b = Image::new(2, 2);
        assert_eq!(mse(&a, &b), 0.0);
        a.pixels[0] = penumbra::math::Rgb::splat(1.0);
        // One pixel of four, three channels of twelve values, each off by 1.
        assert!((mse(&a, &b) - 0.25).abs() < 1e-12);
        assert!((rel_mse(&a, &b) - 0.25 / REL_EPSILON).abs() < 1e-9);
        assert!((rel_mse(&b, &a) - 0.25 / (1.0 + REL_EPSILON)).abs() < 1e-9);
    }

    #[test]
    fn the_study_covers_every_distribution_count_and_seed() {
        let plan = Plan::new(true);
        let n = jobs(&plan).len();
        let per_effect = 2 + 2 + 6 * plan.conv_counts.len() * plan.conv_seeds as usize;
        assert_eq!(n, 4 * per_effect);
        let keys: std::collections::HashSet<String> = jobs(&plan).iter().map(Job::key).collect();
        assert_eq!(keys.len(), n, "no two jobs render the same thing");
    }
}
