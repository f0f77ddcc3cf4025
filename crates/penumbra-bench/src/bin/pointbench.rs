//! Times drawing the points of each low-discrepancy distribution and prints,
//! as JSON, the median over rounds of the cost of one point (sets of
//! `--set` points, 256 by default, so that a set's own randomisation is
//! spread over many points) and of a whole set of one point, in ns on the
//! calling thread's CPU clock. Each set's stream is one a render makes: a
//! pixel of an 800×600 frame, a sample of 16, a kind of set.
//!
//! ```text
//! pointbench [--set N] [--rounds N] [--millis MS]
//! ```

use clap::Parser;
use penumbra::sampling::{Distribution, Rng};
use penumbra_bench::{median, thread_time};
use serde_json::json;
use std::hint::black_box;

/// The stream of set `key`, as a render derives it.
fn stream(root: &Rng, key: u64) -> Rng {
    let (x, y) = ((key % 800) as u32, (key / 800 % 600) as u32);
    root.at_pixel(key, (x, y)).child(3, 16).derive(1)
}

/// CPU ns per set of `count` points of `d`, over about `millis` ms.
fn per_set(d: Distribution, count: usize, millis: f64) -> f64 {
    let root = Rng::new(7);
    let mut out = Vec::with_capacity(count);
    let (mut sets, mut key) = (0u64, 0u64);
    let start = thread_time();
    loop {
        for _ in 0..64 {
            key += 1;
            d.generate(count, 1.0, &mut stream(&root, key), &mut out);
            black_box(&out);
        }
        sets += 64;
        let spent = thread_time() - start;
        if spent * 1e3 >= millis {
            return spent * 1e9 / sets as f64;
        }
    }
}

/// Times a point of each low-discrepancy distribution and a set of one;
/// prints JSON (medians over rounds, CPU ns on the calling thread).
#[derive(Parser)]
#[command(name = "pointbench")]
struct Args {
    /// Points per set when timing one point.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..))]
    set: u32,
    /// Rounds whose median is reported.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    rounds: u32,
    /// CPU time each measurement runs for, in milliseconds.
    #[arg(long, default_value_t = 200)]
    millis: u32,
}

fn run(args: &Args) -> serde_json::Value {
    let (set, rounds, millis) = (args.set as usize, args.rounds, f64::from(args.millis));
    let mut rows = serde_json::Map::new();
    let low = Distribution::ALL
        .into_iter()
        .skip(Distribution::THESIS.len());
    for d in low {
        // Once-per-process work (`pmj02bn` builds its pool) is not timed.
        d.generate(1, 1.0, &mut Rng::new(0), &mut Vec::new());
        let point: Vec<f64> = (0..rounds)
            .map(|_| per_set(d, set, millis) / set as f64)
            .collect();
        let one: Vec<f64> = (0..rounds).map(|_| per_set(d, 1, millis)).collect();
        rows.insert(
            d.name().into(),
            json!({"point_ns": median(point), "one_ns": median(one)}),
        );
    }
    json!({"set": set, "rounds": rounds, "distributions": rows})
}

fn main() {
    let args = Args::parse();
    println!("{}", run(&args));
}
