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

use penumbra::sampling::{Distribution, Rng};
use penumbra_bench::{median, thread_time};
use serde_json::json;
use std::hint::black_box;
use std::process::ExitCode;

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

fn run() -> Result<serde_json::Value, String> {
    let (mut set, mut rounds, mut millis) = (256usize, 5usize, 200.0);
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let value = it.next().ok_or(format!("{a} needs a value"))?;
        let bad = |e: std::num::ParseIntError| format!("{a}: {e}");
        match a.as_str() {
            "--set" => set = value.parse().map_err(bad)?,
            "--rounds" => rounds = value.parse().map_err(bad)?,
            "--millis" => millis = f64::from(value.parse::<u32>().map_err(bad)?),
            _ => return Err(format!("unknown argument {a}")),
        }
    }
    if set == 0 || rounds == 0 {
        return Err("--set and --rounds must be at least 1".into());
    }
    let mut rows = serde_json::Map::new();
    let low = Distribution::ALL
        .into_iter()
        .skip(Distribution::THESIS.len());
    for d in low {
        let point: Vec<f64> = (0..rounds)
            .map(|_| per_set(d, set, millis) / set as f64)
            .collect();
        let one: Vec<f64> = (0..rounds).map(|_| per_set(d, 1, millis)).collect();
        rows.insert(
            d.name().into(),
            json!({"point_ns": median(point), "one_ns": median(one)}),
        );
    }
    Ok(json!({"set": set, "rounds": rounds, "distributions": rows}))
}

fn main() -> ExitCode {
    match run() {
        Ok(v) => {
            println!("{v}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("pointbench: {e}");
            ExitCode::from(2)
        }
    }
}
