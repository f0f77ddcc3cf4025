//! The phase functions' samplers against their densities: the χ² test of
//! the BSDFs (`bsdf/chi2.rs`), on the whole sphere.

use super::PhaseModel;
use crate::bsdf::chi2::{sidak, Chi2};
use crate::math::Vec3;

/// The views the tests draw from (directions back along the ray).
pub fn views() -> [Vec3; 3] {
    [
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.6, 0.2, 0.77).normalize(),
        Vec3::new(-0.3, -0.9, -0.3).normalize(),
    ]
}

/// Holds `m`'s sampler for the view `wo` to its density by χ² (at the
/// Šidák level of a family of 20 tests), its weights to `eval / pdf`, and
/// the density to a total of 1 over the sphere (by the χ² harness's
/// quadrature of the density over its cells); at the origin.
pub fn check_phase<M: PhaseModel>(m: &M, wo: Vec3) {
    check_phase_at(m, Vec3::ZERO, wo);
}

/// [`check_phase`] at the point `p`.
pub fn check_phase_at<M: PhaseModel>(m: &M, p: Vec3, wo: Vec3) {
    let chi2 = Chi2 {
        samples: 400_000,
        ..Chi2::default()
    };
    let sample = |u| {
        let s = m.sample(p, wo, u)?;
        let want = m.eval(p, wo, s.wi);
        assert!(
            (s.pdf - want).abs() <= 1e-3 * want && (s.weight - 1.0).abs() < 1e-6,
            "{s:?} against eval {want}"
        );
        Some(s.wi)
    };
    let pv = chi2
        .run(7, sample, |v| f64::from(m.eval(p, wo, v)))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(pv > sidak(20), "χ² p-value {pv} for the view {wo:?}");
    let total: f64 = chi2.expected(|v| f64::from(m.eval(p, wo, v))).iter().sum();
    let total = total / chi2.samples as f64;
    assert!(
        (total - 1.0).abs() < 2e-3,
        "the density integrates to {total}"
    );
}
