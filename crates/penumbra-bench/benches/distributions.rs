//! Generating a set of points with each distribution, at the set sizes the
//! renderer uses (1 ray per effect up to 64 shadow rays), and the cost of
//! one point of each low-discrepancy set (group `point`: sets of 256, whose
//! per-set randomisation is spread over many points; the target is at most
//! 20 ns a point).
//!
//! `cargo bench -p penumbra-bench --bench distributions`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use penumbra::sampling::{Distribution, Rng};
use std::hint::black_box;

/// The sets from quasi-Monte Carlo, beyond the thesis's six.
const LOW_DISCREPANCY: [Distribution; 6] = [
    Distribution::Sobol,
    Distribution::Zsobol,
    Distribution::Pmj02,
    Distribution::Pmj02bn,
    Distribution::Halton,
    Distribution::R2,
];

fn bench_set(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    d: Distribution,
    count: usize,
) {
    g.throughput(Throughput::Elements(count as u64));
    g.bench_with_input(BenchmarkId::new(d.name(), count), &count, |b, &n| {
        let mut out = Vec::with_capacity(n);
        let mut key = 0u64;
        let root = Rng::new(7);
        b.iter(|| {
            key += 1;
            // A set's stream in a render: a pixel of an 800×600 frame, a
            // sample of 16, a kind of set.
            let (x, y) = ((key % 800) as u32, (key / 800 % 600) as u32);
            let mut rng = root.at_pixel(key, (x, y)).child(3, 16).derive(1);
            d.generate(n, 1.0, &mut rng, &mut out);
            black_box(out.len())
        })
    });
}

fn distributions(c: &mut Criterion) {
    let mut g = c.benchmark_group("generate");
    for count in [1usize, 16, 64] {
        for d in Distribution::ALL {
            bench_set(&mut g, d, count);
        }
    }
    g.finish();
    let mut g = c.benchmark_group("point");
    for d in LOW_DISCREPANCY {
        bench_set(&mut g, d, 256);
    }
    g.finish();
}

criterion_group!(benches, distributions);
criterion_main!(benches);
