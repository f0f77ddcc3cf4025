//! Checks of the guarantees the low-discrepancy distributions promise,
//! shared by their tests: nets, strata, uniformity and star discrepancy.

use crate::math::Vec2;

/// Seeds every net and strata check runs over.
pub const SEEDS: u64 = 20;
/// The largest prefix checked: `2^MAX_M` points.
pub const MAX_M: u32 = 10;

/// The shape `(j, k)` of the first elementary interval family (`2^j` columns
/// by `2^k` rows, `j + k = m`) in which the first `n = 2^m` points of
/// `point` do not have exactly one point per interval; `None` for a net.
pub fn first_non_net(n: u32, point: impl Fn(u32) -> [u32; 2]) -> Option<(u32, u32)> {
    assert!(n.is_power_of_two());
    let m = n.trailing_zeros();
    let points: Vec<[u32; 2]> = (0..n).map(point).collect();
    let mut hits = vec![0u32; n as usize];
    for j in 0..=m {
        let k = m - j;
        hits.fill(0);
        for &[x, y] in &points {
            let column = u64::from(x) >> (32 - j);
            let row = u64::from(y) >> (32 - k);
            hits[(column << k | row) as usize] += 1;
        }
        if hits.iter().any(|&h| h != 1) {
            return Some((j, k));
        }
    }
    None
}

/// Every power-of-two prefix up to `2^MAX_M` of the sets of seeds
/// `0..SEEDS` is a (0,m,2)-net in base 2: every elementary interval of every
/// shape holds exactly one point.
pub fn prefixes_are_nets<F: Fn(u32) -> [u32; 2]>(name: &str, set: impl Fn(u64) -> F) {
    for seed in 0..SEEDS {
        let point = set(seed);
        for m in 0..=MAX_M {
            let bad = first_non_net(1 << m, &point);
            assert_eq!(
                bad, None,
                "{name} seed {seed}: 2^{m} points, intervals (j, k)"
            );
        }
    }
}

/// The same for points in `[0, 1)^2`, read back to fixed point (exact for
/// points with 24-bit coordinates, which is all the distributions give).
pub fn fixed(p: Vec2) -> [u32; 2] {
    let f = |t: f32| (f64::from(t) * 4_294_967_296.0) as u32;
    [f(p.x), f(p.y)]
}

/// A power-of-two count `N` of points in `[0, 1)^2` is stratified in 1D
/// and 2D: each of the `N` columns and the `N` rows of width `1/N` holds one
/// point, and so does each cell of the `sqrt(N) x sqrt(N)` grid when `N` is
/// a square (else of the `sqrt(2N) x sqrt(N/2)` grids both ways).
pub fn stratified(points: &[Vec2]) -> Result<(), String> {
    let n = points.len();
    assert!(n.is_power_of_two());
    let m = n.trailing_zeros();
    let (a, b) = (1usize << m.div_ceil(2), 1usize << (m / 2));
    let grids = [(n, 1), (1, n), (a, b), (b, a)];
    for (columns, rows) in grids {
        let mut hits = vec![0u32; n];
        for p in points {
            let c = ((f64::from(p.x) * columns as f64) as usize).min(columns - 1);
            let r = ((f64::from(p.y) * rows as f64) as usize).min(rows - 1);
            hits[r * columns + c] += 1;
        }
        if hits.iter().any(|&h| h != 1) {
            return Err(format!(
                "{n} points: not one per cell of {columns} x {rows}"
            ));
        }
    }
    Ok(())
}

/// 99.9% quantile of the chi-square distribution with 63 degrees of freedom.
const CHI2_999_DF63: f64 = 103.44;

/// Randomised sets are uniform in expectation: over 6400 seeds, the first,
/// a middle and the last point of sets of several sizes fall into the 8 x 8
/// cells of the square as uniform points would (a chi-square test at the
/// 0.1% level; the seeds are fixed, so the test cannot flake). A set
/// without randomisation puts point 0 in the same cell every time.
pub fn uniform_in_expectation(name: &str, set: impl Fn(u64, u32, &mut Vec<Vec2>)) {
    if let Err(e) = chi2_uniform(set) {
        panic!("{name}: {e}");
    }
}

/// The test of [`uniform_in_expectation`], with the failure as a message.
pub fn chi2_uniform(set: impl Fn(u64, u32, &mut Vec<Vec2>)) -> Result<(), String> {
    let sets = 6400u64;
    let mut points = Vec::new();
    for count in [1u32, 5, 16, 64] {
        for index in [0, count / 2, count - 1] {
            let mut hits = [0u64; 64];
            for seed in 0..sets {
                points.clear();
                set(seed, count, &mut points);
                assert_eq!(points.len(), count as usize);
                let p = points[index as usize];
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
                let cell = |t: f32| ((t * 8.0) as usize).min(7);
                hits[cell(p.y) * 8 + cell(p.x)] += 1;
            }
            let expected = sets as f64 / 64.0;
            let chi2: f64 = hits
                .iter()
                .map(|&h| (h as f64 - expected).powi(2) / expected)
                .sum();
            if chi2 >= CHI2_999_DF63 {
                return Err(format!("point {index} of {count}: chi2 = {chi2:.1}"));
            }
        }
    }
    Ok(())
}

#[test]
fn the_uniformity_test_can_fail() {
    // Unscrambled Sobol' points: the same set every time.
    let fixed_set = |_: u64, count: u32, out: &mut Vec<Vec2>| {
        out.extend((0..count).map(|i| {
            let x = super::sobol::first_dimension(i);
            let y = super::sobol::second_dimension(i);
            Vec2::new(super::sobol::unit(x), super::sobol::unit(y))
        }))
    };
    assert!(chi2_uniform(fixed_set).is_err());
    // Points uniform over the lower half only.
    let half = |seed: u64, count: u32, out: &mut Vec<Vec2>| {
        let mut rng = super::Rng::new(seed);
        out.extend((0..count).map(|_| Vec2::new(rng.next_f32(), 0.5 * rng.next_f32())))
    };
    assert!(chi2_uniform(half).is_err());
}

/// The exact star discrepancy of `points` in `[0, 1)^2`: the largest
/// difference between the fraction of points in a box `[0, a) x [0, b)` (or
/// the closed box) and its area. The supremum is reached at a box whose
/// corner coordinates are point coordinates or 1, so trying those
/// `O(N^2)` boxes (open and closed) is exact.
pub fn star_discrepancy(points: &[Vec2]) -> f64 {
    let n = points.len();
    if n == 0 {
        return 1.0;
    }
    let mut xs: Vec<f64> = points.iter().map(|p| f64::from(p.x)).collect();
    let mut ys: Vec<f64> = points.iter().map(|p| f64::from(p.y)).collect();
    xs.push(1.0);
    ys.push(1.0);
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    ys.sort_by(f64::total_cmp);
    ys.dedup();
    let mut by_x: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (f64::from(p.x), f64::from(p.y)))
        .collect();
    by_x.sort_by(|a, b| a.0.total_cmp(&b.0));
    let nf = n as f64;
    let mut worst = 0.0f64;
    // y values of the points with x < a (open) and x <= a (closed), sorted.
    let (mut open, mut closed): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let (mut next_open, mut next_closed) = (0, 0);
    let insert = |v: &mut Vec<f64>, y: f64| {
        let at = v.partition_point(|&w| w < y);
        v.insert(at, y);
    };
    for &a in &xs {
        while next_open < n && by_x[next_open].0 < a {
            insert(&mut open, by_x[next_open].1);
            next_open += 1;
        }
        while next_closed < n && by_x[next_closed].0 <= a {
            insert(&mut closed, by_x[next_closed].1);
            next_closed += 1;
        }
        for &b in &ys {
            let inside_open = open.partition_point(|&y| y < b) as f64;
            let inside_closed = closed.partition_point(|&y| y <= b) as f64;
            let area = a * b;
            worst = worst
                .max(area - inside_open / nf)
                .max(inside_closed / nf - area);
        }
    }
    worst
}

#[test]
fn star_discrepancy_of_known_sets() {
    // One point at the centre: the box [0, 1) x [0, 0.5] holds it, area 1/2;
    // the open box just below it ([0, 1) x [0, 0.5)) misses it, area 1/2;
    // the closed box [0, 0.5]^2 holds it with area 1/4: D* = 3/4.
    let d = star_discrepancy(&[Vec2::splat(0.5)]);
    assert!((d - 0.75).abs() < 1e-12, "{d}");
    // The centred 4 x 4 grid: the closed box [0, 7/8]^2 holds all 16
    // points with area 49/64, so D* = 15/64.
    let grid: Vec<Vec2> = (0..16)
        .map(|k| Vec2::new((k % 4) as f32 * 0.25 + 0.125, (k / 4) as f32 * 0.25 + 0.125))
        .collect();
    let d = star_discrepancy(&grid);
    assert!((d - 15.0 / 64.0).abs() < 1e-9, "{d}");
    // All points in a corner: D* is nearly 1.
    let corner = vec![Vec2::splat(0.001); 8];
    assert!(star_discrepancy(&corner) > 0.99);
}
