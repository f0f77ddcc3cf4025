//! A discrete distribution over a list of non-negative weights, sampled by
//! inverting its cumulative sum: which triangle of a mesh light a sample
//! lands on (weights: areas); the same table serves any choice among
//! weighted items.
//!
//! Built once (a table of `n + 1` partial sums), sampled in `O(log n)` by a
//! binary search; the uniform number is reused for the position within the
//! chosen interval, so a stratified set of numbers stays stratified within
//! each item (pbrt-v4's `PiecewiseConstant1D`, Mitsuba 3's `DiscreteDistribution`).

/// A distribution over `0..n` proportional to the weights it was built from.
#[derive(Clone, Debug, PartialEq)]
pub struct Discrete {
    /// `cdf[i]` is the sum of the first `i` weights over the total; `cdf[n] = 1`.
    cdf: Vec<f32>,
    total: f64,
}

impl Discrete {
    /// The distribution of `weights` (each finite and ≥ 0); `None` if they
    /// are empty, some weight is negative or not finite, or all are 0.
    pub fn new(weights: impl IntoIterator<Item = f32>) -> Option<Discrete> {
        let mut sums = vec![0.0f64];
        for w in weights {
            if !(w.is_finite() && w >= 0.0) {
                return None;
            }
            sums.push(sums[sums.len() - 1] + f64::from(w));
        }
        let total = *sums.last()?;
        if total <= 0.0 || !total.is_finite() {
            return None;
        }
        let cdf = sums.iter().map(|&s| (s / total) as f32).collect();
        Some(Discrete { cdf, total })
    }

    /// The number of items.
    pub fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// Never true: a distribution has at least one item.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The sum of the weights.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The probability of item `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// The item for the uniform number `u` in [0, 1), its probability, and
    /// `u` remapped to [0, 1) within the item's interval. Items of zero
    /// weight are never chosen.
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        // The last index whose partial sum is at most `u`, skipping empty items.
        let n = self.len();
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(n - 1);
        // Rounding may leave `u` at an empty item's start: move to the next
        // non-empty one (or back to the last non-empty one).
        let i = (i..n)
            .find(|&k| self.pmf(k) > 0.0)
            .or_else(|| (0..i).rev().find(|&k| self.pmf(k) > 0.0))
            .unwrap_or(i);
        let p = self.pmf(i);
        let rest = ((u - self.cdf[i]) / p).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        (i, p, rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Pearson's χ² of sampled counts against the weights, 7 items with an
    /// empty one: below the 0.999 quantile for 5 degrees of freedom (20.5).
    /// A distribution with one weight off by 5% fails the same test.
    #[test]
    fn samples_follow_the_weights() {
        let weights = [1.0, 3.0, 0.0, 0.5, 2.0, 7.0, 1.5];
        let chi2 = |w: &[f32], draw: &Discrete| {
            let mut rng = Rng::new(7);
            let n = 200_000;
            let mut counts = [0u32; 7];
            for _ in 0..n {
                let (i, p, rest) = draw.sample(rng.next_f32());
                assert!((0.0..1.0).contains(&rest) && p > 0.0);
                counts[i] += 1;
            }
            let total: f32 = w.iter().sum();
            counts
                .iter()
                .zip(w)
                .filter(|(_, &w)| w > 0.0)
                .map(|(&c, &w)| {
                    let e = n as f32 * w / total;
                    (c as f32 - e).powi(2) / e
                })
                .sum::<f32>()
        };
        let d = Discrete::new(weights).unwrap();
        assert!((d.pmf(5) - 7.0 / 15.0).abs() < 1e-6 && d.pmf(2) == 0.0);
        assert!(chi2(&weights, &d) < 20.5);
        let mut off = weights;
        off[5] *= 1.05;
        assert!(chi2(&off, &d) > 20.5, "a 5% error is detected");
    }

    /// The remapped number is uniform within the chosen item: its mean over
    /// many draws is one half, and the whole range is reached.
    #[test]
    fn the_rest_is_uniform_within_the_item() {
        let d = Discrete::new([2.0, 1.0]).unwrap();
        let (mut sum, mut n) = (0.0f64, 0);
        for k in 0..10_000 {
            let u = (k as f32 + 0.5) / 10_000.0;
            let (i, _, rest) = d.sample(u);
            if i == 1 {
                sum += f64::from(rest);
                n += 1;
            }
        }
        assert!((sum / f64::from(n) - 0.5).abs() < 1e-3);
        assert_eq!(d.sample(0.0).0, 0);
        assert_eq!(d.sample(0.999_999).0, 1);
    }

    #[test]
    fn bad_weights_give_no_distribution() {
        assert!(Discrete::new([]).is_none());
        assert!(Discrete::new([0.0, 0.0]).is_none());
        assert!(Discrete::new([1.0, -1.0]).is_none());
        assert!(Discrete::new([1.0, f32::NAN]).is_none());
    }
}
