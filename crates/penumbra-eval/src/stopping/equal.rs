//! Rays at equal RMSE: each rule's sweep is a few (rays, RMSE) points; the
//! rays a rule needs for a target RMSE are interpolated linearly in
//! (ln rays, ln RMSE) between the two sweep points that bracket it, and
//! rules are compared at common targets spaced evenly in ln RMSE.

/// The rays at which `sweep` ((rays, RMSE) points, any order) first comes
/// down to `target`: interpolated on log–log axes between the last point
/// above it and the next, in order of rays. `None` when no two points
/// bracket it (the target lies outside the sweep: no extrapolation).
pub fn rays_at(sweep: &[(f64, f64)], target: f64) -> Option<f64> {
    let mut points: Vec<(f64, f64)> = sweep
        .iter()
        .copied()
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    if target.is_nan() || target <= 0.0 {
        return None;
    }
    points.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        if a.1 < target || target < b.1 {
            return None;
        }
        if a.1 == b.1 {
            return Some(a.0);
        }
        let t = (target.ln() - a.1.ln()) / (b.1.ln() - a.1.ln());
        Some((a.0.ln() + t * (b.0.ln() - a.0.ln())).exp())
    })
}

/// The smallest and largest RMSE of a sweep.
pub fn range(sweep: &[(f64, f64)]) -> Option<(f64, f64)> {
    let rmse = sweep
        .iter()
        .map(|p| p.1)
        .filter(|v| *v > 0.0 && v.is_finite());
    let lo = rmse.clone().fold(f64::INFINITY, f64::min);
    let hi = rmse.fold(0.0, f64::max);
    (lo < hi).then_some((lo, hi))
}

/// `count` targets spaced evenly in ln RMSE over `[lo, hi]`, drawn in by
/// a thousandth of the interval at both ends (so that every sweep reaching
/// an end brackets it); none if the interval is empty.
pub fn targets(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if lo.is_nan() || hi.is_nan() || lo <= 0.0 || hi <= lo || count == 0 {
        return Vec::new();
    }
    let (a, b) = (lo.ln(), hi.ln());
    let pad = (b - a) / 1000.0;
    let (a, b) = (a + pad, b - pad);
    if count == 1 {
        return vec![((a + b) / 2.0).exp()];
    }
    (0..count)
        .map(|k| (a + (b - a) * k as f64 / (count - 1) as f64).exp())
        .collect()
}

/// The median of finite values; `None` without any.
pub fn median(values: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On an exact power law RMSE = c · rays^s the interpolation is exact
    /// between any two points; a rule with half the constant needs
    /// 2^(1/|s|) times fewer rays for the same RMSE.
    #[test]
    fn interpolation_is_exact_on_a_power_law() {
        let law = |c: f64, s: f64| -> Vec<(f64, f64)> {
            [1e3, 4e3, 1.6e4, 6.4e4, 2.56e5]
                .iter()
                .rev()
                .map(|&n| (n, c * f64::powf(n, s)))
                .collect()
        };
        let a = law(1.0, -0.5);
        for target in [0.03, 0.01, 0.0025] {
            let n = rays_at(&a, target).unwrap_or(f64::NAN);
            assert!((n - target.powi(-2)).abs() / n < 1e-9, "{target}: {n}");
        }
        let b = law(0.5, -0.75);
        let t = 0.5 * 1e4f64.powf(-0.75);
        let nb = rays_at(&b, t).unwrap_or(f64::NAN);
        assert!((nb / 1e4 - 1.0).abs() < 1e-9, "{nb}");
        let c = law(0.5, -0.5);
        let ratio = rays_at(&c, 0.01).unwrap_or(f64::NAN) / rays_at(&a, 0.01).unwrap_or(f64::NAN);
        assert!((ratio - 0.25).abs() < 1e-9, "{ratio}");
        // Outside the sweep: nothing.
        assert!(rays_at(&a, 1.0).is_none() && rays_at(&a, 1e-4).is_none());
    }

    /// A curve that rises again: the first crossing counts.
    #[test]
    fn the_first_crossing_counts() {
        let sweep = [(100.0, 0.1), (200.0, 0.04), (400.0, 0.06), (800.0, 0.02)];
        let n = rays_at(&sweep, 0.05).unwrap_or(f64::NAN);
        assert!(n > 100.0 && n < 200.0, "{n}");
        assert!(rays_at(&[(1.0, 0.1)], 0.1).is_none());
    }

    #[test]
    fn targets_ranges_and_medians() {
        let t = targets(0.001, 0.1, 3);
        assert_eq!(t.len(), 3);
        assert!(t[0] > 0.001 && t[2] < 0.1 && (t[1] - 0.01).abs() < 1e-12);
        assert!(targets(0.1, 0.01, 3).is_empty());
        assert_eq!(
            range(&[(1.0, 0.3), (2.0, 0.1), (3.0, 0.2)]),
            Some((0.1, 0.3))
        );
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(&[f64::NAN]), None);
    }
}
