//! Runs the evaluation without the CLI:
//! `cargo run --release -p penumbra-eval --example reproduce -- [--quick] [--bunny PATH] [--out DIR] [--threads N] [--study NAME]`.

use std::path::PathBuf;
use std::process::ExitCode;

use penumbra_eval::{reproduce, ReproduceOptions};

fn main() -> ExitCode {
    let mut opts = ReproduceOptions {
        bunny: penumbra::scene::default_bunny_path().unwrap_or_else(|| "bunny.ply".into()),
        out: PathBuf::from("reproduce"),
        quick: false,
        threads: None,
        study: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--quick" {
            opts.quick = true;
            continue;
        }
        match (a.as_str(), args.next()) {
            ("--bunny", Some(v)) => opts.bunny = v.into(),
            ("--out", Some(v)) => opts.out = v.into(),
            ("--study", Some(v)) => match v.parse() {
                Ok(s) => opts.study = Some(s),
                Err(e) => {
                    eprintln!("{e}");
                    return ExitCode::from(2);
                }
            },
            ("--threads", Some(v)) => match v.parse() {
                Ok(n) => opts.threads = Some(n),
                Err(_) => {
                    eprintln!("--threads: not a number: {v}");
                    return ExitCode::from(2);
                }
            },
            _ => {
                eprintln!("usage: reproduce [--quick] [--bunny PATH] [--out DIR] [--threads N] [--study NAME]");
                return ExitCode::from(2);
            }
        }
    }
    let started = std::time::Instant::now();
    let progress = |stage: &str, done: usize, total: usize| {
        eprintln!(
            "[{:>6.1} s] {done}/{total} {stage}",
            started.elapsed().as_secs_f64()
        );
    };
    match reproduce(&opts, &progress) {
        Ok(r) => {
            println!(
                "wrote {} in {:.1} s",
                r.markdown_path().display(),
                r.elapsed_s()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(if e.is_invalid_input() { 2 } else { 1 })
        }
    }
}
