//! `penumbra reproduce`: the thesis's evaluation, regenerated.

use std::io::IsTerminal;
use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use penumbra::scene::default_bunny_path;
use penumbra_eval::{reproduce, ReproduceOptions};

use crate::error::{input, other, CliError};
use crate::ReproduceArgs;

pub fn run(a: &ReproduceArgs) -> Result<(), CliError> {
    let bunny = a.bunny.clone().or_else(default_bunny_path).ok_or_else(|| {
        input("the evaluation needs the Stanford bunny: pass --bunny PATH or set PENUMBRA_BUNNY to it")
    })?;
    let opts = ReproduceOptions {
        bunny,
        out: a.out.clone().unwrap_or_else(|| PathBuf::from("reproduce")),
        quick: a.quick,
        threads: a.threads.map(|t| t as usize),
    };
    let bar = if a.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{bar:30}] {pos}/{len} renders, {elapsed} elapsed, ~{eta} left: {msg}",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    };
    let progress = |stage: &str, done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(stage.to_string());
    };
    let report = reproduce(&opts, &progress).map_err(|e| {
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
            opts.out.join("report.md").display(),
            opts.out.join("report.html").display()
        );
        println!("{} renders in {:.1} s", report.renders, report.elapsed_s);
    }
    Ok(())
}
