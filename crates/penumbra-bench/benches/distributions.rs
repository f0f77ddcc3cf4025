//! Generating a set of points with each of the six distributions, at the
//! set sizes the renderer uses (1 ray per effect up to 64 shadow rays).
//!
//! `cargo bench -p penumbra-bench --bench distributions`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use penumbra::sampling::{Distribution, Rng};
use std::hint::black_box;

fn distributions(c: &mut Criterion) {
    let mut g = c.benchmark_group("generate");
    for count in [1usize, 16, 64] {
        g.throughput(Throughput::Elements(count as u64));
        for d in Distribution::ALL {
            g.bench_with_input(BenchmarkId::new(d.name(), count), &count, |b, &n| {
                let mut out = Vec::with_capacity(n);
                let mut key = 0u64;
                b.iter(|| {
                    key += 1;
                    let mut rng = Rng::new(key);
                    d.generate(n, 1.0, &mut rng, &mut out);
                    black_box(out.len())
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, distributions);
criterion_main!(benches);
