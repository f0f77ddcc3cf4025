//! `penumbra reproduce`: the thesis's evaluation, regenerated, or one study
//! on its own (`--study NAME`).

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::scene::default_bunny_path;
use penumbra_eval::{reproduce, ReproduceOptions, Reproduction, StudyName};

use crate::error::{input, other, CliError};

/// Options of `penumbra reproduce`.
#[derive(Args)]
pub struct ReproduceArgs {
    /// The Stanford bunny PLY (else $PENUMBRA_BUNNY).
    #[arg(long, value_name = "PATH")]
    pub bunny: Option<PathBuf>,
    /// Output directory for the report, images and plots (default: reproduce).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// The same pipeline at a small resolution with reduced budgets (about a minute or two).
    #[arg(long)]
    pub quick: bool,
    /// Run only this study instead of the thesis's evaluation: `distributions`
    /// (every ray distribution on integrals with known values, in renders,
    /// and the stopping rules at equal RMSE; needs no bunny).
    #[arg(long, value_name = "NAME")]
    pub study: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// No progress bar and no summary.
    #[arg(short, long)]
    pub quiet: bool,
}

pub fn run(a: &ReproduceArgs) -> Result<(), CliError> {
    let study = a
        .study
        .as_deref()
        .map(str::parse::<StudyName>)
        .transpose()
        .map_err(input)?;
    let bunny = a.bunny.clone().or_else(default_bunny_path);
    let bunny = match (bunny, study) {
        (Some(b), _) => b,
        // A study on its own does not load the bunny.
        (None, Some(_)) => PathBuf::new(),
        (None, None) => {
            return Err(input(
                "the evaluation needs the Stanford bunny: pass --bunny PATH or set PENUMBRA_BUNNY to it",
            ))
        }
    };
    let opts = ReproduceOptions {
        bunny,
        out: a.out.clone().unwrap_or_else(|| PathBuf::from("reproduce")),
        quick: a.quick,
        threads: a.threads.map(|t| t as usize),
        study,
    };
    let unit = if study.is_some() { "steps" } else { "renders" };
    let bar = if a.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(&format!(
            "{{spinner}} [{{bar:30}}] {{pos}}/{{len}} {unit}, {{elapsed}} elapsed, ~{{eta}} left: {{msg}}"
        )) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    };
    let progress = |stage: &str, done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(stage.to_string());
    };
    let outcome = reproduce(&opts, &progress).map_err(|e| {
        if e.is_invalid_input() {
            input(&e)
        } else {
            other(&e)
        }
    })?;
    bar.finish_and_clear();
    if !a.quiet {
        println!(
            "wrote {} and {}",
            outcome.markdown_path().display(),
            outcome.html_path().display()
        );
        match &outcome {
            Reproduction::Thesis(r) => println!("{} renders in {:.1} s", r.renders, r.elapsed_s),
            Reproduction::Distributions(s) => println!(
                "study of {} distributions in {:.1} s",
                s.integrands.first().map_or(0, |i| i.curves.len()),
                s.elapsed_s
            ),
        }
    }
    Ok(())
}
