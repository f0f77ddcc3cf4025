//! The distributions on known integrals: for every distribution of
//! `Distribution::ALL` and every integrand of [`Integrand::ALL`], the RMSE
//! of the N-point estimate of the integral over the unit square, over many
//! independent sets, for N = 4, 8, …; the slope of log RMSE against log N
//! fitted with a 95% interval and set against the slope theory predicts.
//!
//! A set of `N` points comes from `Distribution::generate(N, 1, Rng)` on
//! `[-1, 1]^2` and is mapped to `[0, 1]^2` by `p ↦ (p + 1) / 2`, except
//! `random`, whose points are uniform in the unit disk: they are mapped back
//! through the inverse of the polar map the library uses (`u = x² + y²`,
//! `v = atan2(y, x) / 2π mod 1`), which turns them into independent uniform
//! points of the square, the same i.i.d. points statistically; and
//! `fast-random`, whose x and y are uniform on the square (its z is dropped).
//! The estimate is the mean of the integrand over the set (the square has
//! area 1); each set has its own stream `Rng::new(seed).derive(N).derive(k)`
//! for set `k`, so a run is reproducible bit for bit on any number of
//! threads.
//!
//! `grid`, `jitter` and `semi-jitter` fill their pattern only for square
//! counts; at other counts they keep a random subset of the next square's
//! cells, another estimator. Their slopes are therefore fitted on the square
//! counts only (4, 16, 64, …); the other counts are measured and drawn but
//! not fitted.

mod functions;
mod plot;
mod polygon;
mod results;
mod section;
mod theory;

use std::path::Path;
use std::time::Instant;

use penumbra::math::Vec3;
use penumbra::sampling::{Distribution, Domain, Rng};
use rayon::prelude::*;

use crate::error::EvalError;
use crate::fit;

pub use crate::fit::Fit;
pub use functions::{Class, Integrand};
pub use results::{
    Curve, DistributionStudy, IntegrandResult, Point, TheoryRow, TAIL_FROM, TOLERANCE,
};

use polygon::P2;

/// Root seed of every set.
const SEED: u64 = 0x1a7e_6a2d;

/// Which counts and how many sets per count.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// Independent sets per (distribution, count).
    pub seeds: u32,
    /// Points per set, increasing.
    pub counts: Vec<usize>,
}

impl Config {
    /// 1024 sets at every power of two from 4 to 4096.
    pub fn full() -> Config {
        Config {
            seeds: 1024,
            counts: powers_of_two(4, 4096),
        }
    }

    /// 64 sets at every power of two from 4 to 1024.
    pub fn quick() -> Config {
        Config {
            seeds: 64,
            counts: powers_of_two(4, 1024),
        }
    }
}

fn powers_of_two(from: usize, to: usize) -> Vec<usize> {
    std::iter::successors(Some(from), |n| n.checked_mul(2))
        .take_while(|&n| n <= to)
        .collect()
}

/// Runs the study with `config` on `threads` workers (`None`: every core)
/// and writes `distributions.md`, `distributions.html`, `distributions.json`
/// and one SVG plot per integrand under `plots/` into `out`, which must
/// exist with its `plots/` subdirectory. `progress(stage, done, total)`
/// counts distributions.
pub fn run(
    config: &Config,
    quick: bool,
    threads: Option<usize>,
    out: &Path,
    progress: &dyn Fn(&str, usize, usize),
) -> Result<DistributionStudy, EvalError> {
    let (study, svgs) = study(config, quick, threads, out, progress)?;
    write(&study, &svgs)?;
    Ok(study)
}

/// The study as [`run`] makes it, and its plots' SVG texts (in the order
/// of the integrands), without writing the documents: the render and
/// stopping levels may be added to it first.
pub fn study(
    config: &Config,
    quick: bool,
    threads: Option<usize>,
    out: &Path,
    progress: &dyn Fn(&str, usize, usize),
) -> Result<(DistributionStudy, Vec<String>), EvalError> {
    let started = Instant::now();
    let pool = threads.and_then(|t| rayon::ThreadPoolBuilder::new().num_threads(t).build().ok());
    let errors = measure(config, pool.as_ref(), progress);
    let integrands = Integrand::ALL
        .iter()
        .enumerate()
        .map(|(i, &f)| result(f, config, &errors, i))
        .collect();
    let mut study = DistributionStudy {
        quick,
        seeds: config.seeds,
        counts: config.counts.clone(),
        threads: pool
            .as_ref()
            .map_or_else(rayon::current_num_threads, |p| p.current_num_threads()),
        elapsed_s: 0.0,
        integrand_s: 0.0,
        tolerance: TOLERANCE,
        theory: theory::RATES
            .iter()
            .map(|r| TheoryRow {
                distributions: r.distributions.iter().map(|s| s.to_string()).collect(),
                edge: r.edge,
                smooth: r.smooth,
                basis: r.basis.to_string(),
            })
            .collect(),
        integrands,
        render: None,
        stopping: None,
        out: out.to_path_buf(),
    };
    progress(
        "writing the integrand plots",
        Distribution::ALL.len(),
        Distribution::ALL.len(),
    );
    let svgs = study
        .integrands
        .iter()
        .map(|i| plot::write(i, &out.join(&i.plot)))
        .collect::<Result<Vec<String>, EvalError>>()?;
    study.integrand_s = started.elapsed().as_secs_f64();
    study.elapsed_s = study.integrand_s;
    Ok((study, svgs))
}

/// Writes the study's three documents; `svgs` are the integrand plots'.
pub fn write(study: &DistributionStudy, svgs: &[String]) -> Result<(), EvalError> {
    section::write(study, svgs)
}

/// Errors (estimate − exact) per distribution of `Distribution::ALL`, per
/// count, per set, per integrand of `Integrand::ALL`.
type Errors = Vec<Vec<Vec<[f64; Integrand::ALL.len()]>>>;

fn measure(
    config: &Config,
    pool: Option<&rayon::ThreadPool>,
    progress: &dyn Fn(&str, usize, usize),
) -> Errors {
    let total = Distribution::ALL.len();
    let tasks: Vec<(usize, u32)> = config
        .counts
        .iter()
        .flat_map(|&n| (0..config.seeds).map(move |k| (n, k)))
        .collect();
    let mut all = Vec::with_capacity(total);
    for (i, &d) in Distribution::ALL.iter().enumerate() {
        progress(&format!("measuring {d}"), i, total);
        let run = || errors_of(d, &tasks);
        let errors = match pool {
            Some(p) => p.install(run),
            None => run(),
        };
        let seeds = (config.seeds as usize).max(1);
        all.push(errors.chunks(seeds).map(<[_]>::to_vec).collect());
    }
    all
}

/// The errors of `d`'s sets `(count, set)`, in the order of `tasks`
/// whatever the number of threads.
fn errors_of(d: Distribution, tasks: &[(usize, u32)]) -> Vec<[f64; Integrand::ALL.len()]> {
    let exact = Integrand::ALL.map(Integrand::exact);
    tasks
        .par_iter()
        .map_init(
            || (Vec::new(), Vec::new()),
            |(scratch, points), &(n, k)| {
                let mut rng = Rng::new(SEED).derive(n as u64).derive(u64::from(k));
                unit_points(d, n, &mut rng, scratch, points);
                let mut e = [0.0; Integrand::ALL.len()];
                for (j, f) in Integrand::ALL.iter().enumerate() {
                    let sum: f64 = points.iter().map(|&p| f.eval(p)).sum();
                    e[j] = sum / n as f64 - exact[j];
                }
                e
            },
        )
        .collect()
}

/// The `count` points of one set of `d` in the unit square; see the module
/// docs for `random` and `fast-random`.
pub fn unit_points(
    d: Distribution,
    count: usize,
    rng: &mut Rng,
    scratch: &mut Vec<Vec3>,
    out: &mut Vec<P2>,
) {
    d.generate(count, 1.0, rng, scratch);
    out.clear();
    out.extend(scratch.iter().map(|p| {
        let (x, y) = (f64::from(p.x), f64::from(p.y));
        if d.domain() == Domain::Disk {
            let u = (x * x + y * y).min(1.0);
            let v = (y.atan2(x) / std::f64::consts::TAU).rem_euclid(1.0);
            [u, v.min(1.0)]
        } else {
            [(x + 1.0) / 2.0, (y + 1.0) / 2.0]
        }
    }));
}

/// Whether the slope of `d` is fitted at `n` (see the module docs).
fn fitted(d: Distribution, n: usize) -> bool {
    if !d.needs_square_count() {
        return true;
    }
    let s = (n as f64).sqrt().round() as usize;
    s * s == n
}

fn result(f: Integrand, config: &Config, errors: &Errors, j: usize) -> IntegrandResult {
    let curves = Distribution::ALL
        .iter()
        .zip(errors)
        .map(|(&d, per_count)| {
            let points: Vec<Point> = config
                .counts
                .iter()
                .zip(per_count)
                .map(|(&n, sets)| {
                    let m = sets.len().max(1) as f64;
                    let mse = sets.iter().map(|e| e[j] * e[j]).sum::<f64>() / m;
                    Point {
                        n,
                        rmse: mse.sqrt(),
                        mean_error: sets.iter().map(|e| e[j]).sum::<f64>() / m,
                        fitted: fitted(d, n),
                    }
                })
                .collect();
            let xy: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.fitted)
                .map(|p| (p.n as f64, p.rmse))
                .collect();
            let fit = fit::power_law(&xy);
            let tail: Vec<(f64, f64)> = xy
                .iter()
                .copied()
                .filter(|p| p.0 >= TAIL_FROM as f64)
                .collect();
            let tail_fit = fit::power_law(&tail);
            let theory = theory::target(d, f.class());
            let within = fit
                .zip(theory)
                .map(|(fit, t)| (fit.slope - t).abs() <= TOLERANCE);
            Curve {
                distribution: d.name().to_string(),
                points,
                fit,
                tail_fit,
                theory,
                within,
            }
        })
        .collect();
    IntegrandResult {
        name: f.name().to_string(),
        class: f.class(),
        description: f.description(),
        exact: f.exact(),
        plot: format!("plots/distributions-{}.svg", f.slug()),
        curves,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configurations() {
        let full = Config::full();
        assert_eq!(full.counts.first(), Some(&4));
        assert_eq!(full.counts.last(), Some(&4096));
        assert_eq!(full.counts.len(), 11);
        assert!(full.seeds >= 128);
        assert_eq!(Config::quick().counts.last(), Some(&1024));
    }

    #[test]
    fn square_counts_only_for_the_grid_family() {
        assert!(fitted(Distribution::Jitter, 16) && !fitted(Distribution::Jitter, 32));
        assert!(fitted(Distribution::Grid, 4096) && !fitted(Distribution::Grid, 8));
        assert!(fitted(Distribution::Sobol, 32) && fitted(Distribution::Random, 8));
    }

    /// Every distribution's points land in the unit square; the mapped
    /// `random` and `fast-random` points are uniform over it (a chi-square
    /// test over its 8 x 8 cells, 63 degrees of freedom).
    #[test]
    fn unit_points_are_in_the_square_and_random_ones_uniform() {
        let (mut scratch, mut points) = (Vec::new(), Vec::new());
        for d in Distribution::ALL {
            let mut cells = [0u64; 64];
            for seed in 0..1000 {
                unit_points(d, 64, &mut Rng::new(seed), &mut scratch, &mut points);
                assert_eq!(points.len(), 64);
                for p in &points {
                    assert!(p.iter().all(|c| (0.0..=1.0).contains(c)), "{d}: {p:?}");
                    let cell = |c: f64| ((c * 8.0) as usize).min(7);
                    cells[cell(p[0]) + 8 * cell(p[1])] += 1;
                }
            }
            if d.domain() != Domain::Square {
                let expected = 1000.0;
                let chi2: f64 = cells
                    .iter()
                    .map(|&c| (c as f64 - expected).powi(2) / expected)
                    .sum();
                // The 99.9% quantile of chi-square with 63 degrees of freedom.
                assert!(chi2 < 103.4, "{d}: chi2 = {chi2}");
            }
        }
    }

    /// A small study end to end: its files, every distribution on every
    /// integrand, and the two rates no implementation detail can excuse:
    /// independent points at −0.5, Owen-scrambled Sobol' on a smooth
    /// function far steeper than −1.
    #[test]
    fn a_small_study_writes_its_files_and_finds_the_known_rates() {
        let Ok(dir) = tempfile::tempdir() else { return };
        let out = dir.path();
        assert!(std::fs::create_dir_all(out.join("plots")).is_ok());
        let config = Config {
            seeds: 64,
            counts: powers_of_two(4, 1024),
        };
        let study = run(&config, true, Some(2), out, &|_, done, total| {
            assert!(done <= total);
        });
        let study = match study {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        };
        for f in study.files() {
            assert!(out.join(&f).is_file(), "missing {f}");
        }
        let json = std::fs::read_to_string(study.json_path()).unwrap_or_default();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap_or_default();
        let integrands = v["integrands"].as_array().map_or(0, Vec::len);
        assert_eq!(integrands, Integrand::ALL.len());
        for i in v["integrands"].as_array().into_iter().flatten() {
            let curves = i["curves"].as_array().map_or(0, Vec::len);
            assert_eq!(curves, Distribution::ALL.len(), "{}", i["name"]);
        }
        assert!(v["integrands"][0]["curves"][0]["points"][0]["rmse"].is_f64());
        let html = std::fs::read_to_string(study.html_path()).unwrap_or_default();
        let md = std::fs::read_to_string(study.markdown_path()).unwrap_or_default();
        assert_eq!(html.matches("<svg").count(), Integrand::ALL.len());
        assert!(
            md.contains("](plots/distributions-soft-shadow.svg)"),
            "{md}"
        );
        let svg = std::fs::read_to_string(out.join("plots/distributions-gaussian.svg"))
            .unwrap_or_default();
        assert!(svg.contains("<text") && svg.contains("sobol"), "no labels");

        let slope = |f: &str, d: &str| {
            study
                .curve(f, d)
                .and_then(|c| c.fit)
                .map_or(f64::NAN, |fit| fit.slope)
        };
        for f in Integrand::ALL {
            let s = slope(f.name(), "random");
            println!("random on {}: {s:.3}", f.name());
            assert!((s + 0.5).abs() < 0.1, "random on {}: {s}", f.name());
        }
        let s = slope("gaussian", "sobol");
        println!("sobol on gaussian: {s:.3}");
        assert!(s < -1.25, "sobol on the gaussian: {s}");
        let c = study.curve("gaussian", "sobol");
        assert_eq!(c.and_then(|c| c.theory), Some(-1.5));
        assert!(c.is_some_and(|c| c.within.is_some()));
        assert!(study
            .curve("disk", "grid")
            .is_some_and(|c| c.theory.is_none() && c.within.is_none()));
    }
}
