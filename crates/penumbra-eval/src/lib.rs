//! # penumbra-eval
//!
//! Reproduces the evaluation chapter of the thesis *Stochastic Ray Tracing*
//! with Penumbra: Tables 4.1–4.6 measured next to the published numbers,
//! Figures 4.1–4.10 rendered side by side, plots of how ray counts grow and
//! what the acceleration metrics save, and — beyond the thesis — a measured
//! comparison of how fast the six ray distributions converge.
//!
//! One entry point, [`reproduce`], writes `report.md`, `report.html` and
//! `report.json` with `figures/` and `plots/` into a directory.
//!
//! ```no_run
//! use penumbra_eval::{reproduce, ReproduceOptions};
//!
//! let opts = ReproduceOptions {
//!     bunny: "bunny.ply".into(),
//!     out: "reproduce".into(),
//!     quick: true,
//!     threads: None,
//!     study: None,
//! };
//! let report = reproduce(&opts, &|stage, done, total| eprintln!("[{done}/{total}] {stage}"))?;
//! println!("{}", report.markdown_path().display());
//! # Ok::<(), penumbra_eval::EvalError>(())
//! ```
//!
//! With `study: Some(StudyName::Distributions)` it runs instead the study of
//! every ray distribution at three levels: on integrals with known values
//! ([`integrand`]), in renders of six effects against a converged reference
//! ([`render_level`]), and under the stopping rules of adaptive sampling
//! compared at equal RMSE ([`stopping`]). It needs no bunny (its scenes are
//! built in) and writes `distributions.md`, `distributions.html`,
//! `distributions.json` and `plots/{distributions,render,stopping}-*.svg`.
//!
//! Every plot, figure and picture is an SVG drawn by `plotters` (or, for
//! figures, panels embedded as PNG data under SVG text labels): no font file
//! is read. [`samples`] draws the pictures of `penumbra samples`.

mod chart;
mod compose;
mod convergence;
mod distributions;
mod doc;
mod document;
mod error;
mod figures;
mod fit;
mod format;
mod growth;
pub mod integrand;
mod job;
mod loglog;
mod measure;
mod output;
mod plan;
pub mod render_level;
mod report;
mod runner;
pub mod samples;
mod sections;
pub mod stopping;
mod tables;
mod thesis;

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Instant;

pub use convergence::{Curve, Study};
pub use error::EvalError;
pub use figures::Figure;
pub use growth::{Plot, SweepPoint};
pub use integrand::DistributionStudy;
pub use measure::Measurement;
pub use report::Report;
pub use tables::{CountRow, CountTable, MetricRow, MetricTable, Tables};

use job::Job;
use penumbra::scene::{Overrides, WorldCache};
use plan::Plan;
use runner::Runner;

/// What to run and where to write it.
#[derive(Clone, Debug)]
pub struct ReproduceOptions {
    /// The Stanford bunny (`bunny.ply`).
    pub bunny: PathBuf,
    /// Output directory; created if missing, files in it are replaced.
    pub out: PathBuf,
    /// Small frames and reduced exponential budgets (about a minute).
    pub quick: bool,
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    /// Run only this study instead of the thesis's evaluation (the bunny is
    /// then not needed).
    pub study: Option<StudyName>,
}

/// A study that runs on its own, without the thesis's evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyName {
    /// Every ray distribution on integrals with known values
    /// ([`integrand`]), in renders ([`render_level`]) and under the
    /// stopping rules ([`stopping`]).
    Distributions,
}

impl StudyName {
    pub const ALL: [StudyName; 1] = [StudyName::Distributions];

    /// The name given to `--study`.
    pub fn name(self) -> &'static str {
        match self {
            StudyName::Distributions => "distributions",
        }
    }
}

impl fmt::Display for StudyName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for StudyName {
    type Err = EvalError;

    /// The exact name; an unknown one is invalid input whose message lists
    /// the valid names.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        StudyName::ALL
            .into_iter()
            .find(|n| n.name() == s)
            .ok_or_else(|| EvalError::UnknownStudy {
                name: s.to_string(),
                valid: StudyName::ALL.map(StudyName::name).join(", "),
            })
    }
}

/// What a run wrote: the thesis's report, or a study run on its own.
#[derive(Clone, Debug)]
pub enum Reproduction {
    Thesis(Box<Report>),
    Distributions(Box<DistributionStudy>),
}

impl Reproduction {
    /// The Markdown report.
    pub fn markdown_path(&self) -> PathBuf {
        match self {
            Reproduction::Thesis(r) => r.markdown_path(),
            Reproduction::Distributions(s) => s.markdown_path(),
        }
    }

    /// The HTML report.
    pub fn html_path(&self) -> PathBuf {
        match self {
            Reproduction::Thesis(r) => r.html_path(),
            Reproduction::Distributions(s) => s.html_path(),
        }
    }

    /// Wall-clock time of the run.
    pub fn elapsed_s(&self) -> f64 {
        match self {
            Reproduction::Thesis(r) => r.elapsed_s,
            Reproduction::Distributions(s) => s.elapsed_s,
        }
    }

    /// The thesis's report, if that is what ran.
    pub fn thesis(self) -> Option<Report> {
        match self {
            Reproduction::Thesis(r) => Some(*r),
            Reproduction::Distributions(_) => None,
        }
    }

    /// The distribution study, if that is what ran.
    pub fn distributions(self) -> Option<DistributionStudy> {
        match self {
            Reproduction::Distributions(s) => Some(*s),
            Reproduction::Thesis(_) => None,
        }
    }
}

/// Runs the whole evaluation and writes the report, or only the study
/// `opts.study` names.
///
/// `progress(stage, done, total)` is called before and after every render
/// (`done` and `total` count distinct renders; for a study, its steps) and
/// while writing; it is called on the calling thread only.
pub fn reproduce(
    opts: &ReproduceOptions,
    progress: &dyn Fn(&str, usize, usize),
) -> Result<Reproduction, EvalError> {
    match opts.study {
        None => thesis(opts, progress).map(|r| Reproduction::Thesis(Box::new(r))),
        Some(StudyName::Distributions) => {
            prepare_out(&opts.out, &["plots"])?;
            let levels = distributions::Levels::new(opts.quick);
            distributions::run(&levels, opts.quick, opts.threads, &opts.out, progress)
                .map(|s| Reproduction::Distributions(Box::new(s)))
        }
    }
}

fn thesis(
    opts: &ReproduceOptions,
    progress: &dyn Fn(&str, usize, usize),
) -> Result<Report, EvalError> {
    let started = Instant::now();
    check_bunny(&opts.bunny)?;
    prepare_out(&opts.out, &["figures", "plots"])?;
    let plan = Plan::new(opts.quick);
    let mut runner = Runner::new(opts.bunny.clone(), opts.threads, progress);
    runner.plan(&tables::jobs(&plan));
    runner.plan(&figures::jobs(&plan));
    runner.plan(&growth::sweep_jobs(&plan));
    runner.plan(&convergence::jobs(&plan));
    let tables = tables::run(&mut runner, &plan)?;
    let sweep = growth::run_sweep(&mut runner, &plan)?;
    let figures = figures::run(&mut runner, &plan, &opts.out)?;
    let convergence = convergence::run(&mut runner, &plan, &opts.out)?;
    runner.report("writing the report");
    let plots = growth::plots(&tables, &sweep, &opts.out)?;
    let report = Report {
        quick: opts.quick,
        threads: opts.threads.unwrap_or_else(default_threads),
        elapsed_s: started.elapsed().as_secs_f64(),
        renders: runner.total(),
        tables,
        figures,
        plots,
        sweep,
        convergence,
        deviations: plan.deviations(),
        warnings: runner.warnings().to_vec(),
        out: opts.out.clone(),
    };
    document::write(&report)?;
    runner.report("done");
    Ok(report)
}

fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The bunny must exist and load: checked before any work, so that a wrong
/// path is reported as the user's input, not as a failed render.
fn check_bunny(path: &Path) -> Result<(), EvalError> {
    let err = |reason: String| EvalError::Bunny {
        path: path.to_path_buf(),
        reason,
    };
    if !path.is_file() {
        return Err(err("no such file".into()));
    }
    let probe = Job::new(
        "loading the bunny",
        "bunny",
        Overrides {
            width: Some(8),
            height: Some(6),
            ..Default::default()
        },
    );
    let mut worlds = WorldCache::new(1);
    probe
        .build(path, &mut worlds)
        .map(|_| ())
        .map_err(|e| match e {
            EvalError::Scene { source, .. } => err(source.message),
            other => other,
        })
}

/// Creates the output directory and its subdirectories `subs` and proves it
/// is writable by creating and removing a file.
fn prepare_out(out: &Path, subs: &[&str]) -> Result<(), EvalError> {
    let err = |reason: String| EvalError::OutDir {
        path: out.to_path_buf(),
        reason,
    };
    for sub in subs {
        std::fs::create_dir_all(out.join(sub)).map_err(|e| err(e.to_string()))?;
    }
    let probe = out.join(".penumbra-eval-probe");
    std::fs::write(&probe, b"").map_err(|e| err(e.to_string()))?;
    std::fs::remove_file(&probe).map_err(|e| err(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_bunny_is_invalid_input() {
        let dir = tempfile::tempdir().map_err(|e| e.to_string());
        let Ok(dir) = dir else { return };
        let opts = ReproduceOptions {
            bunny: dir.path().join("no-bunny.ply"),
            out: dir.path().join("out"),
            quick: true,
            threads: Some(1),
            study: None,
        };
        let e = reproduce(&opts, &|_, _, _| {}).err();
        assert!(matches!(e, Some(EvalError::Bunny { .. })), "{e:?}");
        assert!(e.is_some_and(|e| e.is_invalid_input()));
    }

    #[test]
    fn a_bunny_that_is_not_a_mesh_is_invalid_input() {
        let Ok(dir) = tempfile::tempdir() else { return };
        let bad = dir.path().join("bunny.ply");
        assert!(std::fs::write(&bad, b"not a ply file").is_ok());
        let e = check_bunny(&bad).err();
        assert!(e.as_ref().is_some_and(EvalError::is_invalid_input), "{e:?}");
    }

    #[test]
    fn an_unwritable_output_is_invalid_input() {
        let Ok(dir) = tempfile::tempdir() else { return };
        let file = dir.path().join("a-file");
        assert!(std::fs::write(&file, b"x").is_ok());
        let e = prepare_out(&file.join("out"), &["plots"]).err();
        assert!(matches!(e, Some(EvalError::OutDir { .. })), "{e:?}");
        assert!(prepare_out(&dir.path().join("fresh"), &["plots"]).is_ok());
        assert!(!dir.path().join("fresh/.penumbra-eval-probe").exists());
    }

    #[test]
    fn study_names_parse_and_unknown_ones_list_the_valid() {
        for n in StudyName::ALL {
            assert_eq!(n.name().parse::<StudyName>().ok(), Some(n));
        }
        let e = "distribution".parse::<StudyName>().err();
        let message = e.as_ref().map(ToString::to_string).unwrap_or_default();
        assert!(
            message.contains("'distribution'") && message.contains("distributions"),
            "{message}"
        );
        assert!(e.is_some_and(|e| e.is_invalid_input()));
    }

    /// A study needs no bunny: a missing one is not even looked at.
    #[test]
    fn the_distribution_study_runs_without_the_bunny() {
        let Ok(dir) = tempfile::tempdir() else { return };
        let opts = ReproduceOptions {
            bunny: dir.path().join("no-bunny.ply"),
            out: dir.path().join("out"),
            quick: true,
            threads: Some(2),
            study: Some(StudyName::Distributions),
        };
        let r = reproduce(&opts, &|_, _, _| {});
        let study = match r.map(Reproduction::distributions) {
            Ok(Some(s)) => s,
            other => panic!("{other:?}"),
        };
        assert!(dir.path().join("out/distributions.html").is_file());
        assert!(!dir.path().join("out/figures").exists());
        for f in study.files() {
            assert!(dir.path().join("out").join(&f).is_file(), "missing {f}");
        }
        let html = std::fs::read_to_string(study.html_path()).unwrap_or_default();
        let plots = integrand::Integrand::ALL.len()
            + 2 * render_level::EFFECTS.len()
            + stopping::SCENES.len();
        assert_eq!(html.matches("<svg").count(), plots);

        // The render level: every effect has a curve of every distribution
        // with a fit, and independent samples converge at −0.5, inside their
        // interval.
        let render = study
            .render
            .as_ref()
            .unwrap_or_else(|| panic!("no render level"));
        assert_eq!(render.effects.len(), render_level::EFFECTS.len());
        for e in &render.effects {
            assert_eq!(e.curves.len(), penumbra::sampling::Distribution::ALL.len());
            for c in &e.curves {
                assert!(c.fit.is_some(), "{} on {}: no fit", c.distribution, e.name);
                assert!(c.points.iter().all(|p| p.seconds > 0.0 && p.rays > 0.0));
            }
            let random = render.curve(&e.name, "random").and_then(|c| c.fit);
            let f = random.unwrap_or_else(|| panic!("{}: no random fit", e.name));
            println!(
                "random on {}: {:.3} [{:.3}, {:.3}]",
                e.name, f.slope, f.low, f.high
            );
            assert!(f.low <= -0.5 && -0.5 <= f.high, "{}: {f:?}", e.name);
            assert!((f.slope + 0.5).abs() < 0.15, "{}: {f:?}", e.name);
        }

        // The stopping comparison: every scene, every rule's sweep, and the
        // calibrated rule's pixels checked.
        let stop = study
            .stopping
            .as_ref()
            .unwrap_or_else(|| panic!("no stopping"));
        assert_eq!(stop.scenes.len(), stopping::SCENES.len());
        for sc in &stop.scenes {
            assert_eq!(sc.variants.len(), stopping::Variant::ALL.len());
            assert!(sc.variants.iter().all(|v| !v.runs.is_empty()));
            assert!(sc.variants.iter().flat_map(|v| &v.runs).all(|r| r.rays > 0));
            let c = sc.coverage;
            let pixels = (stop.frame.0 * stop.frame.1) as usize;
            assert_eq!(c.total, pixels * sc.variants[0].runs.len(), "{}", sc.name);
            assert_eq!(c.pixels, c.total, "every calibrated pixel has an interval");
        }
        let c = stop.summary.coverage;
        println!(
            "coverage {:.3}, false stops {:.4}",
            c.rate(),
            c.false_stop_rate()
        );
        assert!(c.rate() > 0.5 && c.stopped > 0);
    }
}
