//! The numbers of the thesis's evaluation chapter (Tables 4.1–4.6),
//! transcribed so that every measured value can stand next to the original.
//! All are for the thesis's 800×600 frame and recursion depth 3.

/// A published ray count and how the thesis wrote it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Published {
    pub value: f64,
    pub text: &'static str,
}

const fn p(value: f64, text: &'static str) -> Published {
    Published { value, text }
}

/// Table 4.1: depth of field with 1, 4, 8 and 16 primary rays.
pub const TABLE_4_1: [Published; 4] = [
    p(1.0e6, "1·10⁶"),
    p(3.5e6, "3.5·10⁶"),
    p(7.3e6, "7.3·10⁶"),
    p(14.8e6, "14.8·10⁶"),
];

/// Tables 4.2, 4.3 and 4.5: rows "standard" and "4x supersampling", columns
/// the three ray budgets of the table.
pub struct TwoModes {
    pub budgets: [u32; 3],
    pub standard: [Published; 3],
    pub supersampled: [Published; 3],
}

/// Table 4.2: the Figure 4.4 scene (reflective floor, diffuse bunny).
pub const TABLE_4_2: TwoModes = TwoModes {
    budgets: [1, 4, 32],
    standard: [p(0.5e6, "0.5·10⁶"), p(4.0e6, "4·10⁶"), p(8.0e6, "8·10⁶")],
    supersampled: [p(1.0e6, "1·10⁶"), p(6.0e6, "6·10⁶"), p(32.0e6, "32·10⁶")],
};

/// Table 4.3: the same scene with a reflective bunny.
pub const TABLE_4_3: TwoModes = TwoModes {
    budgets: [1, 4, 32],
    standard: [p(1.0e6, "1·10⁶"), p(4.0e6, "4·10⁶"), p(118.0e6, "118·10⁶")],
    supersampled: [
        p(4.0e6, "4·10⁶"),
        p(15.0e6, "15·10⁶"),
        p(468.0e6, "468·10⁶"),
    ],
};

/// Table 4.5: penumbra with 1, 9 and 32 shadow rays.
pub const TABLE_4_5: TwoModes = TwoModes {
    budgets: [1, 9, 32],
    standard: [p(1.0e6, "1·10⁶"), p(3.5e6, "3.5·10⁶"), p(8.5e6, "8.5·10⁶")],
    supersampled: [p(4.0e6, "4·10⁶"), p(10.0e6, "10·10⁶"), p(35.0e6, "35·10⁶")],
};

/// One row of Tables 4.4 and 4.6: rays with and without the metric.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct MetricRow {
    pub with: Published,
    pub without: Published,
    /// Reduction in percent as printed.
    pub reduction: f64,
    /// Marked with an asterisk in the thesis: the count without the metric
    /// was computed, not rendered.
    pub theoretical: bool,
}

const fn m(with: Published, without: Published, reduction: f64, theoretical: bool) -> MetricRow {
    MetricRow {
        with,
        without,
        reduction,
        theoretical,
    }
}

/// Table 4.4 (reflection metric): "Figure 4.8 left 4r 4s 4x",
/// "Figure 4.8 right 4r 1s 1x", "Figure 4.8 right 32r 32s 4x".
pub const TABLE_4_4: [MetricRow; 3] = [
    m(
        p(3_356_763.0, "3'356'763"),
        p(3_446_789.0, "3'446'789"),
        2.5,
        false,
    ),
    m(p(10.0e6, "10·10⁶"), p(18.0e6, "18·10⁶"), 45.0, false),
    m(p(4.6e8, "4.6·10⁸"), p(2.0e12, "2·10¹²*"), 99.0, true),
];

/// Table 4.6 (shadow metric): "Figure 4.8 left 4r 4s 4x",
/// "Figure 4.8 right 1r 8s 4x", "Figure 4.8 right 1r 16s 4x".
pub const TABLE_4_6: [MetricRow; 3] = [
    m(
        p(3_360_307.0, "3'360'307"),
        p(3_446_789.0, "3'446'789"),
        2.5,
        false,
    ),
    m(p(7.0e6, "7·10⁶"), p(12.0e6, "12·10⁶"), 42.0, false),
    m(p(30.0e6, "30·10⁶"), p(90.0e6, "90·10⁶"), 66.0, false),
];

/// The thesis's estimate of the unaccelerated "32r 32s 4x" render (§4.3):
/// r³ reflection rays per sample, each with s shadow rays, for every sample.
pub fn unaccelerated_estimate(
    reflection: u32,
    shadow: u32,
    width: u32,
    height: u32,
    spp: u32,
) -> f64 {
    f64::from(reflection).powi(3)
        * f64::from(shadow)
        * f64::from(width)
        * f64::from(height)
        * f64::from(spp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thesis_arithmetic_holds() {
        // 32³ · 32 · 800 · 600 · 4 ≈ 2·10¹² (Table 4.4, last row).
        let e = unaccelerated_estimate(32, 32, 800, 600, 4);
        assert!((e / 2.0e12 - 1.0).abs() < 0.01, "{e}");
        // Table 4.4, first row: 720'854 + 715'909 + 1'920'000.
        assert_eq!(TABLE_4_4[0].with.value, 720_854.0 + 715_909.0 + 1_920_000.0);
        assert_eq!(TABLE_4_6[0].with.value, 810_880.0 + 629_427.0 + 1_920_000.0);
        for r in TABLE_4_4.iter().chain(&TABLE_4_6) {
            assert!(r.with.value < r.without.value);
        }
    }
}
