//! `penumbra reproduce --study distributions`: the integrand level
//! ([`integrand`](crate::integrand)), then the render level
//! ([`render_level`](crate::render_level)) and the stopping comparison
//! ([`stopping`](crate::stopping)) on one runner, written as one document.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::EvalError;
use crate::integrand::{self, DistributionStudy};
use crate::runner::Runner;
use crate::{render_level, stopping};

/// The sizes of the three levels.
#[derive(Clone, Debug, PartialEq)]
pub struct Levels {
    pub integrand: integrand::Config,
    pub render: render_level::Config,
    pub stopping: stopping::Config,
}

impl Levels {
    pub fn new(quick: bool) -> Levels {
        if quick {
            Levels {
                integrand: integrand::Config::quick(),
                render: render_level::Config::quick(),
                stopping: stopping::Config::quick(),
            }
        } else {
            Levels {
                integrand: integrand::Config::full(),
                render: render_level::Config::full(),
                stopping: stopping::Config::full(),
            }
        }
    }
}

/// Runs the three levels and writes `distributions.md`, `.html`, `.json`
/// and the plots into `out` (which must exist with `plots/`).
pub fn run(
    levels: &Levels,
    quick: bool,
    threads: Option<usize>,
    out: &Path,
    progress: &dyn Fn(&str, usize, usize),
) -> Result<DistributionStudy, EvalError> {
    let started = Instant::now();
    let (mut study, svgs) = integrand::study(&levels.integrand, quick, threads, out, progress)?;
    // The scenes are built in; no file is read.
    let mut runner = Runner::new(PathBuf::new(), threads, progress);
    study.render = Some(render_level::run(&mut runner, &levels.render, out)?);
    study.stopping = Some(stopping::run(&mut runner, &levels.stopping, out)?);
    runner.report("writing the report");
    study.elapsed_s = started.elapsed().as_secs_f64();
    integrand::write(&study, &svgs)?;
    Ok(study)
}
