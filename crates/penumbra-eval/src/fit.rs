//! A convergence rate as a fitted power law: least squares of ln RMSE on
//! ln N, with a 95% confidence interval of the slope from Student's t on the
//! regression's residuals.

use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

use crate::format::signed;

/// A fitted power law `RMSE ≈ exp(intercept) · N^slope`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Fit {
    pub slope: f64,
    pub intercept: f64,
    /// The 95% confidence interval of the slope: `slope ± t · SE`, with `t`
    /// the 97.5% quantile of Student's t with `points − 2` degrees of
    /// freedom and `SE = sqrt(SSR / (points − 2) / Sxx)`. It covers the
    /// scatter of the points about the line, whatever its cause: the RMSE's
    /// own sampling noise, and a curve that is not a straight line (log
    /// factors, a deterministic set's erratic error). Equal to the slope
    /// with only two points.
    pub low: f64,
    pub high: f64,
    /// Points the fit used.
    pub points: usize,
}

/// Fits `y = a · x^slope` to the points with finite positive `x` and `y`;
/// `None` with fewer than two such points or a single `x`.
pub fn power_law(points: &[(f64, f64)]) -> Option<Fit> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let mx = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let half = if logs.len() > 2 {
        let df = n - 2.0;
        let ssr: f64 = logs
            .iter()
            .map(|p| (p.1 - intercept - slope * p.0).powi(2))
            .sum();
        let se = (ssr / df / sxx).sqrt();
        t_975(df) * se
    } else {
        0.0
    };
    Some(Fit {
        slope,
        intercept,
        low: slope - half,
        high: slope + half,
        points: logs.len(),
    })
}

/// A table cell: `slope [low, high]`, or `–` without a fit.
pub fn cell(fit: Option<Fit>) -> String {
    fit.map_or("–".into(), |f| {
        format!(
            "{} [{}, {}]",
            signed(f.slope),
            signed(f.low),
            signed(f.high)
        )
    })
}

/// The 97.5% quantile of Student's t with `df > 0` degrees of freedom.
fn t_975(df: f64) -> f64 {
    StudentsT::new(0.0, 1.0, df).map_or(f64::NAN, |t| t.inverse_cdf(0.975))
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra::sampling::Rng;

    /// A standard normal value (Box–Muller).
    fn normal(rng: &mut Rng) -> f64 {
        let u = 1.0 - f64::from(rng.next_f32());
        let v = f64::from(rng.next_f32());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }

    fn counts() -> Vec<f64> {
        (2..=12).map(|k| f64::from(1u32 << k)).collect()
    }

    #[test]
    fn an_exact_power_law_gives_its_exponent() {
        let pts: Vec<(f64, f64)> = counts().iter().map(|&n| (n, 3.0 * n.powf(-0.75))).collect();
        let f = power_law(&pts).unwrap_or_else(|| panic!("no fit"));
        assert!((f.slope + 0.75).abs() < 1e-12, "{f:?}");
        assert!((f.intercept - 3f64.ln()).abs() < 1e-9);
        assert!(f.high - f.low < 1e-9 && f.low <= f.slope && f.slope <= f.high);
        assert_eq!(f.points, 11);
    }

    #[test]
    fn noisy_data_is_fitted_within_its_interval() {
        let mut rng = Rng::new(17);
        let pts: Vec<(f64, f64)> = counts()
            .iter()
            .map(|&n| (n, 0.4 * n.powf(-1.5) * (0.05 * normal(&mut rng)).exp()))
            .collect();
        let f = power_law(&pts).unwrap_or_else(|| panic!("no fit"));
        println!("{f:?}");
        assert!(f.low < -1.5 && -1.5 < f.high, "{f:?}");
        assert!(f.high - f.low < 0.1 && f.high - f.low > 0.0, "{f:?}");
    }

    /// Over many synthetic curves with Gaussian scatter in ln y, the 95%
    /// interval holds the true exponent about 95% of the time.
    #[test]
    fn the_interval_covers_the_exponent_95_percent_of_the_time() {
        let mut rng = Rng::new(3);
        let trials = 2000;
        let mut covered = 0;
        for _ in 0..trials {
            let pts: Vec<(f64, f64)> = counts()
                .iter()
                .map(|&n| (n, n.powf(-0.5) * (0.2 * normal(&mut rng)).exp()))
                .collect();
            if let Some(f) = power_law(&pts) {
                covered += usize::from(f.low <= -0.5 && -0.5 <= f.high);
            }
        }
        let rate = covered as f64 / trials as f64;
        println!("coverage {rate}");
        // Binomial standard error ≈ 0.005; an interval of ±1.645 SE (a
        // 90% one) would cover about 0.90.
        assert!((0.93..=0.97).contains(&rate), "{rate}");
    }

    #[test]
    fn degenerate_input_has_no_fit() {
        assert!(power_law(&[]).is_none());
        assert!(power_law(&[(4.0, 1.0)]).is_none());
        assert!(power_law(&[(4.0, 1.0), (4.0, 2.0)]).is_none());
        assert!(power_law(&[(4.0, 1.0), (8.0, 0.0), (16.0, f64::NAN)]).is_none());
        let two = power_law(&[(4.0, 1.0), (16.0, 0.5)]).unwrap_or_else(|| panic!("no fit"));
        assert!((two.slope + 0.5).abs() < 1e-12 && two.low == two.high);
    }
}
