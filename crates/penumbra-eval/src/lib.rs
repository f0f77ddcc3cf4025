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
//! };
//! let report = reproduce(&opts, &|stage, done, total| eprintln!("[{done}/{total}] {stage}"))?;
//! println!("{}", report.markdown_path().display());
//! # Ok::<(), penumbra_eval::EvalError>(())
//! ```

mod compose;
mod convergence;
mod doc;
mod document;
mod error;
mod figures;
mod format;
mod growth;
mod job;
mod measure;
mod output;
mod plan;
mod plot;
mod report;
mod runner;
mod sections;
mod tables;
mod thesis;

use std::path::{Path, PathBuf};
use std::time::Instant;

pub use convergence::{Curve, Study};
pub use error::EvalError;
pub use figures::Figure;
pub use growth::{Plot, SweepPoint};
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
}

/// Runs the whole evaluation and writes the report.
///
/// `progress(stage, done, total)` is called before and after every render
/// (`done` and `total` count distinct renders) and while writing; it is
/// called on the calling thread only.
pub fn reproduce(
    opts: &ReproduceOptions,
    progress: &dyn Fn(&str, usize, usize),
) -> Result<Report, EvalError> {
    let started = Instant::now();
    check_bunny(&opts.bunny)?;
    prepare_out(&opts.out)?;
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

/// Creates the output directory and its subdirectories and proves it is
/// writable by creating and removing a file.
fn prepare_out(out: &Path) -> Result<(), EvalError> {
    let err = |reason: String| EvalError::OutDir {
        path: out.to_path_buf(),
        reason,
    };
    for sub in ["figures", "plots"] {
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
        let e = prepare_out(&file.join("out")).err();
        assert!(matches!(e, Some(EvalError::OutDir { .. })), "{e:?}");
        assert!(prepare_out(&dir.path().join("fresh")).is_ok());
        assert!(!dir.path().join("fresh/.penumbra-eval-probe").exists());
    }
}
