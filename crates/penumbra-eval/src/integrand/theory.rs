//! The convergence rates theory predicts, in one table: the slope of
//! log RMSE against log N for each distribution and class of integrand.
//! A distribution missing from the table (one added to
//! `Distribution::ALL` later) gets no target, not an error.

use penumbra::sampling::Distribution;

use super::functions::Class;

/// One row of the table.
#[derive(Clone, Copy, Debug)]
pub struct Rate {
    /// Distribution names (`Distribution::name`); names not (yet) in
    /// `Distribution::ALL` are harmless.
    pub distributions: &'static [&'static str],
    /// Target slope for indicator functions with a piecewise smooth boundary.
    pub edge: Option<f64>,
    /// Target slope for smooth functions.
    pub smooth: Option<f64>,
    /// Why, with the source.
    pub basis: &'static str,
}

/// The table. Slopes are of the RMSE (half the variance's exponent).
pub const RATES: &[Rate] = &[
    Rate {
        distributions: &["random", "fast-random"],
        edge: Some(-0.5),
        smooth: Some(-0.5),
        basis: "independent uniform points: variance σ²/N for any square-integrable function \
                (the central limit theorem); `random`'s disk points are mapped back to the square \
                by the inverse polar map, `fast-random` is read by its x and y",
    },
    Rate {
        distributions: &["jitter", "semi-jitter"],
        edge: Some(-0.75),
        smooth: Some(-1.0),
        basis: "one point per cell of an s×s grid: in 2D the variance is O(N^−2) for smooth \
                functions and O(N^−3/2) for a jump along a curve, whose O(√N) cut cells each \
                contribute O(N^−2) (Mitchell 1996, “Consequences of stratified sampling in \
                graphics”; Pharr, Jakob & Humphreys, PBRT 4th ed., §8.5). `semi-jitter` keeps a \
                bias of the same order (its points avoid the outer ring of each cell)",
    },
    Rate {
        distributions: &["sobol", "zsobol", "pmj02"],
        edge: Some(-0.75),
        smooth: Some(-1.5),
        basis: "Owen-scrambled (0,m,2)-nets: variance O(N^−3 (log N)^(s−1)) for smooth \
                functions (Owen 1997, “Scrambled net variance for integrals of smooth \
                functions”, Ann. Statist. 25); for jumps the elementary intervals stratify like \
                jitter, O(N^−3/2), as measured on these kinds of integrands by Christensen, \
                Kensler & Kilpatrick 2018 (“Progressive multi-jittered sample sequences”)",
    },
    Rate {
        distributions: &["pmj02bn"],
        edge: Some(-0.75),
        smooth: Some(-1.0),
        basis: "(0,m,2)-nets randomised by a digital shift only (an xor per axis, which keeps \
                their blue noise), not by a nested scramble: the variance is the sum of the \
                squared Walsh coefficients of the function over the dual of the net, which is \
                fixed, so smoothness guarantees only O(N^−2) up to log factors, not Owen's \
                extra N^−1 (that needs independent flips at every digit); a given smooth \
                function may do better, erratically, as its coefficients fall on the dual or \
                not. For jumps the elementary intervals stratify like jitter, O(N^−3/2)",
    },
    Rate {
        distributions: &["halton", "r2"],
        edge: Some(-0.75),
        smooth: Some(-1.0),
        basis: "low-discrepancy sequences randomised by digit permutations (`halton`) or a \
                shift (`r2`): the Koksma–Hlawka inequality with star discrepancy \
                O(N^−1 log² N) bounds smooth integrands by N^−1 up to log factors \
                (Niederreiter 1992); for convex sets the discrepancy of well-spread point sets \
                is of order N^−3/4 (Beck & Chen 1987, “Irregularities of distribution”)",
    },
    Rate {
        distributions: &["grid"],
        edge: None,
        smooth: None,
        basis: "deterministic: every set is the same pattern (only its order changes), so the \
                RMSE over seeds is the absolute error of one set, a bias; its slope is reported \
                without a target",
    },
    Rate {
        distributions: &["poisson"],
        edge: None,
        smooth: None,
        basis: "Poisson-disk sets have no closed-form rate; the slope is reported without a \
                target (hard-core point processes are not hyperuniform, so their variance is \
                expected to approach O(N^−1) with a smaller constant than independent points: \
                Pilleboue et al. 2015, “Variance analysis for Monte Carlo integration”)",
    },
];

/// The row of `d`, if the table has one.
pub fn row(d: Distribution) -> Option<&'static Rate> {
    RATES.iter().find(|r| r.distributions.contains(&d.name()))
}

/// The target slope for `d` on integrands of `class`, if theory gives one.
pub fn target(d: Distribution, class: Class) -> Option<f64> {
    let r = row(d)?;
    match class {
        Class::Edge => r.edge,
        Class::Smooth => r.smooth,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_name_is_in_two_rows() {
        let mut names: Vec<&str> = RATES
            .iter()
            .flat_map(|r| r.distributions.iter().copied())
            .collect();
        let n = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), n, "a name is in two rows");
    }

    #[test]
    fn targets_by_class() {
        assert_eq!(target(Distribution::Random, Class::Smooth), Some(-0.5));
        assert_eq!(target(Distribution::Jitter, Class::Edge), Some(-0.75));
        assert_eq!(target(Distribution::Sobol, Class::Smooth), Some(-1.5));
        assert_eq!(target(Distribution::R2, Class::Smooth), Some(-1.0));
        assert_eq!(target(Distribution::Pmj02bn, Class::Smooth), Some(-1.0));
        assert_eq!(target(Distribution::Grid, Class::Edge), None);
        assert_eq!(target(Distribution::Poisson, Class::Smooth), None);
    }
}
