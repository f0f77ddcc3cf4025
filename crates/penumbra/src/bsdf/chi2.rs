//! A χ² goodness-of-fit test of a direction sampler against its density,
//! after Mitsuba 3's `chi2` test: directions drawn from uniform points
//! (a fixed seed) are counted on a grid of (θ, φ) cells of the sphere;
//! each cell's expected count is the density integrated over the cell (a
//! midpoint rule on sub-cells) times the number of points drawn; cells
//! expecting fewer than [`MIN_EXPECTED`] are pooled; a sample where the
//! density is 0 fails outright; the statistic Σ (O − E)² / E is
//! referred to χ² with one degree of freedom fewer than the cells, and the
//! test returns its p-value. Points that give no direction count nowhere,
//! so a density that integrates to less than 1 must be matched by as many
//! failed draws.
//!
//! A family of tests is held to a significance of 1% as a whole: each test
//! to the Šidák level `1 − 0.99^(1/n)` ([`sidak`]).

use statrs::distribution::{ChiSquared, ContinuousCDF};

use std::collections::HashMap;
use std::sync::Arc;

use super::Bsdf;
use super::{BsdfModel, Defaults};
use crate::description::{from_toml, Invalid, Kind, Props};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_uniform_sphere;
use crate::sampling::{Distribution, EffectSpec, Rng, SetPoint};

pub(crate) use super::thesis::tests::interaction;

/// Cells expecting fewer samples are pooled into one.
pub const MIN_EXPECTED: f64 = 5.0;

/// The significance of a family of tests.
pub const SIGNIFICANCE: f64 = 0.01;

/// The per-test level of a family of `n` tests (Šidák).
pub fn sidak(n: usize) -> f64 {
    1.0 - (1.0 - SIGNIFICANCE).powf(1.0 / n.max(1) as f64)
}

/// The grid and the sample count of a test.
#[derive(Clone, Copy, Debug)]
pub struct Chi2 {
    /// Cells in θ ∈ [0, π] (uniform in θ).
    pub theta: usize,
    /// Cells in φ ∈ [0, 2π).
    pub phi: usize,
    /// Sub-cells per cell side for the integral of the density.
    pub sub: usize,
    /// Points drawn.
    pub samples: usize,
}

impl Default for Chi2 {
    fn default() -> Chi2 {
        Chi2 {
            theta: 90,
            phi: 180,
            sub: 8,
            samples: 1_000_000,
        }
    }
}

impl Chi2 {
    fn cell(&self, v: Vec3) -> Option<usize> {
        let v = v.as_dvec3();
        let len = v.length();
        if !(len > 0.5 && len < 1.5) {
            return None;
        }
        let theta = (v.z / len).clamp(-1.0, 1.0).acos();
        let phi = v.y.atan2(v.x).rem_euclid(std::f64::consts::TAU);
        let i = ((theta / std::f64::consts::PI * self.theta as f64) as usize).min(self.theta - 1);
        let j = ((phi / std::f64::consts::TAU * self.phi as f64) as usize).min(self.phi - 1);
        Some(i * self.phi + j)
    }

    /// The counts of `samples` directions of `sample` (local unit vectors;
    /// `None` for a point that gives none) from the stream `seed`.
    /// An error if a direction is not a unit vector or has density 0
    /// (`pdf`).
    pub fn histogram(
        &self,
        seed: u64,
        mut sample: impl FnMut(Vec2) -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f64,
    ) -> Result<Vec<f64>, String> {
        let mut counts = vec![0.0; self.theta * self.phi];
        let mut rng = Rng::new(0x5eed_c412 ^ seed);
        for _ in 0..self.samples {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let Some(v) = sample(u) else { continue };
            let cell = self
                .cell(v)
                .ok_or_else(|| format!("not a unit direction: {v:?}"))?;
            let density = pdf(v);
            if density.is_nan() || density <= 0.0 {
                return Err(format!("a sample where the density is 0: {v:?} of {u:?}"));
            }
            counts[cell] += 1.0;
        }
        Ok(counts)
    }

    /// The expected counts: `samples` times the density `pdf` integrated
    /// over each cell.
    pub fn expected(&self, pdf: impl Fn(Vec3) -> f64) -> Vec<f64> {
        let (dt, dp) = (
            std::f64::consts::PI / self.theta as f64,
            std::f64::consts::TAU / self.phi as f64,
        );
        let sp = dp / self.sub as f64;
        let mut out = vec![0.0; self.theta * self.phi];
        for i in 0..self.theta {
            // Eight times finer by the poles, where a sharp lobe (a
            // refraction at normal incidence) may fit in one cell.
            let sub = if i < 3 || i + 3 >= self.theta {
                8 * self.sub
            } else {
                self.sub
            };
            let st = dt / sub as f64;
            for a in 0..sub {
                let theta = i as f64 * dt + (a as f64 + 0.5) * st;
                let (s, c) = theta.sin_cos();
                for j in 0..self.phi {
                    let mut sum = 0.0;
                    for b in 0..self.sub {
                        let phi = j as f64 * dp + (b as f64 + 0.5) * sp;
                        let v = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                        sum += pdf(v);
                    }
                    out[i * self.phi + j] += sum * s * st * sp;
                }
            }
        }
        for e in &mut out {
            *e *= self.samples as f64;
        }
        out
    }

    /// The p-value of the counts of `sample` against the density `pdf`
    /// (see the [module docs](self)); an error if a direction falls where
    /// the density is 0 or no cell expects enough.
    pub fn run(
        &self,
        seed: u64,
        sample: impl FnMut(Vec2) -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f64,
    ) -> Result<f64, String> {
        let observed = self.histogram(seed, sample, &pdf)?;
        let expected = self.expected(pdf);
        p_value(&observed, &expected)
    }
}

/// The χ² p-value of `observed` counts against `expected` ones, cells
/// expecting fewer than [`MIN_EXPECTED`] pooled.
pub fn p_value(observed: &[f64], expected: &[f64]) -> Result<f64, String> {
    let mut cells: Vec<(f64, f64)> = expected
        .iter()
        .copied()
        .zip(observed.iter().copied())
        .collect();
    cells.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut pool_e, mut pool_o, mut stat, mut dof) = (0.0, 0.0, 0.0, 0usize);
    for &(e, o) in &cells {
        if e < MIN_EXPECTED {
            pool_e += e;
            pool_o += o;
        } else {
            stat += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pool_e > 0.0 {
        if pool_e >= MIN_EXPECTED {
            stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
            dof += 1;
        } else if pool_o > 2.0 * MIN_EXPECTED {
            return Err(format!(
                "{pool_o} samples in cells expecting {pool_e} in all"
            ));
        }
    }
    if dof < 2 {
        return Err(format!("too few cells ({dof})"));
    }
    let chi = ChiSquared::new((dof - 1) as f64).map_err(|e| e.to_string())?;
    Ok(chi.sf(stat))
}

/// Four views of the shading frame's local space: along the normal, two
/// oblique from outside (one grazing) and one from inside.
pub fn views() -> [Vec3; 4] {
    [
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.6, 0.2, 0.77).normalize(),
        Vec3::new(-0.3, 0.9, 0.15).normalize(),
        Vec3::new(0.5, -0.1, -0.8).normalize(),
    ]
}

/// The model `M` of the parameters `text` (TOML keys of a material).
pub fn build<M: BsdfModel>(text: &str) -> Result<M, Invalid> {
    build_in(text, &HashMap::new())
}

/// [`build`] among the named `materials` (which a model may hold).
pub fn build_in<M: BsdfModel>(
    text: &str,
    materials: &HashMap<String, Arc<Bsdf>>,
) -> Result<M, Invalid> {
    with_defaults(text, materials, |p, d| M::build(p, d))
}

/// `build` called with the parameters of the material of `text` (TOML
/// keys of a material) and the defaults of a test: one ray per set, no
/// textures, the named `materials`.
pub fn with_defaults<T>(
    text: &str,
    materials: &HashMap<String, Arc<Bsdf>>,
    build: impl FnOnce(&Props, &Defaults) -> T,
) -> T {
    let root = from_toml(
        &format!("[materials.m]\n{text}\n"),
        std::path::Path::new("t.toml"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let node = root.child(Kind::Bsdf).expect("a material");
    let set = EffectSpec {
        rays: 1,
        distribution: Distribution::Jitter,
    };
    let textures = crate::texture::Textures::default();
    let d = Defaults {
        reflection: set,
        refraction: set,
        textures: &textures,
        materials,
    };
    build(&Props::new(node), &d)
}

/// The χ² p-value of `m`'s directions sampled (no lobe asked for) for the
/// view `wo` at the surface `si`, against its `pdf`.
pub fn model_p_value<M: BsdfModel>(
    m: &M,
    si: &SurfaceInteraction,
    wo: Vec3,
    seed: u64,
) -> Result<f64, String> {
    Chi2::default().run(
        seed,
        |u| m.sample(si, wo, None, SetPoint::uniform(u)).map(|s| s.wi),
        |v| f64::from(m.pdf(si, wo, v)),
    )
}

/// Asserts that the sampler of every model follows its density from every
/// view at the surface `si`: one χ² test per (model, view), at the
/// family's significance (Šidák). `p_value` is [`model_p_value`] or
/// [`smooth_p_value`]; a model's text names it in a failure.
pub fn assert_samplers_pass<M: BsdfModel, T: std::fmt::Display>(
    models: Vec<(T, M)>,
    views: &[Vec3],
    si: &SurfaceInteraction,
    p_value: fn(&M, &SurfaceInteraction, Vec3, u64) -> Result<f64, String>,
) {
    let level = sidak(models.len() * views.len());
    let cases = models
        .iter()
        .flat_map(|(text, m)| views.iter().map(move |&wo| (text, m, wo)));
    for (k, (text, m, wo)) in cases.enumerate() {
        let p = p_value(m, si, wo, k as u64).unwrap_or_else(|e| panic!("{text} {wo:?}: {e}"));
        assert!(p > level, "{text} {wo:?}: p = {p:e}");
    }
}

/// [`model_p_value`] of a model with delta lobes too: their samples count
/// as draws that give no direction (the density of the smooth lobes
/// integrates to their probability).
pub fn smooth_p_value<M: BsdfModel>(
    m: &M,
    si: &SurfaceInteraction,
    wo: Vec3,
    seed: u64,
) -> Result<f64, String> {
    Chi2::default().run(
        seed,
        |u| {
            m.sample(si, wo, None, SetPoint::uniform(u))
                .filter(|s| !s.flags.is_delta())
                .map(|s| s.wi)
        },
        |v| f64::from(m.pdf(si, wo, v)),
    )
}

/// The albedo of `m` seen from `wo` by sampling: the mean weight of `n`
/// samples (no lobe asked for; a point giving none counts 0), delta lobes
/// included, and its standard error (of the largest channel).
pub fn sampled_albedo<M: BsdfModel>(
    m: &M,
    si: &SurfaceInteraction,
    wo: Vec3,
    n: usize,
) -> (Rgb, f32) {
    albedo_of(|u| m.sample(si, wo, None, u), n)
}

/// [`sampled_albedo`] of a sampler (a held [`Bsdf`]'s, say).
pub fn albedo_of(sample: impl Fn(SetPoint) -> Option<super::BsdfSample>, n: usize) -> (Rgb, f32) {
    let mut rng = Rng::new(93);
    let (mut sum, mut sq) = ([0.0f64; 3], 0.0f64);
    for _ in 0..n {
        let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
        if let Some(s) = sample(u) {
            for (a, w) in sum.iter_mut().zip([s.weight.r, s.weight.g, s.weight.b]) {
                *a += f64::from(w);
            }
            sq += f64::from(s.weight.max_element()).powi(2);
        }
    }
    let mean = sum.map(|a| a / n as f64);
    let top = mean[0].max(mean[1]).max(mean[2]);
    let var = (sq / n as f64 - top * top).max(0.0);
    (
        Rgb::new(mean[0] as f32, mean[1] as f32, mean[2] as f32),
        (var / n as f64).sqrt() as f32,
    )
}

/// For `n` samples of `m` (no lobe asked for) seen from `wo`: each
/// weight of a smooth lobe is `eval · |cos| / pdf` and each pdf the one
/// `pdf` gives (both to a relative 1e-3; delta samples are not checked);
/// returns the largest weight channel seen.
pub fn check_weights<M: BsdfModel>(m: &M, si: &SurfaceInteraction, wo: Vec3, n: usize) -> f32 {
    let mut rng = Rng::new(77);
    let mut most = 0.0f32;
    for _ in 0..n {
        let u = SetPoint::uniform(Vec2::new(rng.next_f32(), rng.next_f32()));
        let Some(s) = m.sample(si, wo, None, u) else {
            continue;
        };
        most = most.max(s.weight.max_element());
        if s.flags.is_delta() {
            continue;
        }
        let pdf = m.pdf(si, wo, s.wi);
        assert!(
            (s.pdf - pdf).abs() <= 1e-3 * pdf.max(1e-3),
            "pdf {} vs {pdf} at {:?}",
            s.pdf,
            s.wi
        );
        let want = m.eval(si, wo, s.wi) * (s.wi.dot(si.n).abs() / s.pdf);
        let err = (s.weight - want).abs().max_element();
        assert!(
            err <= 1e-3 * want.max_element().max(1e-2),
            "weight {:?} vs eval·cos/pdf {want:?} at {:?}",
            s.weight,
            s.wi
        );
    }
    most
}

/// The albedo of `m` seen from `wo`, ∫ eval · |cos| dω over the sphere by
/// Monte Carlo (`n` uniform directions, stratified), and its standard error.
pub fn albedo<M: BsdfModel>(m: &M, si: &SurfaceInteraction, wo: Vec3, n: usize) -> (Rgb, f32) {
    let side = (n as f64).sqrt() as usize;
    let mut rng = Rng::new(91);
    let (mut sum, mut sq) = ([0.0f64; 3], 0.0f64);
    let frame = si.shading_frame();
    for i in 0..side {
        for j in 0..side {
            let u = Vec2::new(
                (i as f32 + rng.next_f32()) / side as f32,
                (j as f32 + rng.next_f32()) / side as f32,
            );
            let wi = frame.to_world(square_to_uniform_sphere(u));
            let f = m.eval(si, wo, wi) * (wi.dot(si.n).abs() * 4.0 * std::f32::consts::PI);
            for (a, w) in sum.iter_mut().zip([f.r, f.g, f.b]) {
                *a += f64::from(w);
            }
            sq += f64::from(f.max_element()).powi(2);
        }
    }
    let k = (side * side) as f64;
    let mean = Rgb::new(
        (sum[0] / k) as f32,
        (sum[1] / k) as f32,
        (sum[2] / k) as f32,
    );
    let var = (sq / k - f64::from(mean.max_element()).powi(2)).max(0.0);
    (mean, (var / k).sqrt() as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};

    fn cosine(v: Vec3) -> f64 {
        f64::from(square_to_cosine_hemisphere_pdf(v))
    }

    /// The harness passes a correct sampler and fails one whose density is
    /// 5% off in half its domain, and one whose sampler is bent by 5%: it
    /// catches an error of 5%.
    #[test]
    fn passes_a_right_sampler_and_catches_five_percent() {
        let c = Chi2::default();
        let level = sidak(1);
        let good = c
            .run(1, |u| Some(square_to_cosine_hemisphere(u)), cosine)
            .unwrap();
        assert!(good > level, "correct sampler: p = {good}");
        // The density 5% high where y > 0 (and the sampler unchanged).
        let scaled = |v: Vec3| cosine(v) * if v.y > 0.0 { 1.05 } else { 1.0 };
        let p = c
            .run(1, |u| Some(square_to_cosine_hemisphere(u)), scaled)
            .unwrap();
        assert!(p < 1e-9, "5% density error: p = {p:e}");
        // The sampler bent: 5% of the radial coordinate's mass moved.
        let bent = |u: Vec2| Some(square_to_cosine_hemisphere(Vec2::new(u.x.powf(1.05), u.y)));
        let p = c.run(1, bent, cosine).unwrap();
        assert!(p < 1e-9, "5% sampler error: p = {p:e}");
        // A sample where the density is 0 fails outright.
        let below = |u: Vec2| Some(-square_to_cosine_hemisphere(u));
        assert!(c.run(1, below, cosine).is_err());
        assert!(sidak(100) < 1.01e-4 && sidak(100) > 1e-4);
    }
}
