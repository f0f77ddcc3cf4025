//! The calibrated rule on one set of shadow, reflection or refraction rays.
//!
//! With the calibrated rule on, a set of `n` rays below a camera ray is
//! judged as a pixel is ([`calibrated`]): its points are `R` independent
//! sets of the effect's distribution (`replicas`), each from a stream of
//! its own, interleaved so that ray `i` is point `i / R` of replica
//! `i mod R`. The set is traced in passes, the first of
//! [`FIRST_PER_REPLICA`]` · R` rays, then doubling; after each pass the
//! interval of its mean is computed from the replicas' means, and the set
//! stops when the half-width is at most `T` times its mean's largest
//! channel (or the floor). A set lit or shadowed throughout, or a glossy
//! lobe over a flat colour, stops at the first judgement; a set across a
//! shadow's edge goes on. Sets of at most `FIRST_PER_REPLICA · R` rays are
//! traced whole, as one set.
//!
//! The set's value is the mean of the rays it traced, which at a pass's end
//! is the mean of the replicas' means (they hold equal counts), so every
//! replica stays an unbiased estimate of the set's integral.

use super::calibrated;
use super::{StopRule, Stopping};
use crate::math::{Rgb, Vec3};
use crate::sampling::{Distribution, PointTable, Rng};

/// Rays each replica of a set takes before its first judgement.
pub const FIRST_PER_REPLICA: u32 = 2;

/// The calibrated rule as sets use it.
#[derive(Clone, Copy, Debug)]
pub struct SetRule {
    threshold: f32,
    /// The value below which `threshold` is absolute.
    floor: f32,
    /// Student's quantile of the rule's confidence.
    t: f32,
    replicas: u32,
}

impl SetRule {
    /// The rule for sets of a render with these settings: on with the
    /// calibrated rule, off otherwise.
    pub fn new(stopping: Option<Stopping>) -> Option<SetRule> {
        let s = stopping.filter(|s| s.rule == StopRule::Calibrated)?;
        Some(SetRule {
            threshold: s.threshold,
            floor: s.floor,
            t: calibrated::quantile(s.replicas, s.confidence),
            replicas: s.replicas,
        })
    }

    /// The rule, if a set of `n` rays is long enough for it.
    pub fn for_set(rule: Option<SetRule>, n: usize) -> Option<SetRule> {
        rule.filter(|r| n > r.first())
    }

    fn first(&self) -> usize {
        (FIRST_PER_REPLICA * self.replicas) as usize
    }

    /// The end of the pass that starts after `done` rays of a set of `n`.
    pub fn pass_end(&self, done: usize, n: usize) -> usize {
        let end = if done == 0 { self.first() } else { 2 * done };
        end.min(n)
    }

    /// The `n` points of a set (in `[-1, 1]^2`, as
    /// [`Distribution::generate_in`] gives them) as the rule's replicas,
    /// interleaved: point `i` is point `i / R` of replica `i mod R`, whose
    /// set of `⌈(n − r) / R⌉` points comes from `rng.child(r, R)` in trace
    /// order. `scratch` holds one replica at a time.
    pub fn points(
        &self,
        (d, table): (Distribution, &PointTable),
        n: usize,
        rng: &Rng,
        scratch: &mut Vec<Vec3>,
        out: &mut Vec<Vec3>,
    ) {
        let r_count = self.replicas as usize;
        out.clear();
        out.resize(n, Vec3::ZERO);
        for r in 0..r_count.min(n) {
            let count = (n - r).div_ceil(r_count);
            d.generate_in(table, count, 1.0, &mut rng.child(r, r_count), scratch);
            for (j, &p) in scratch.iter().enumerate() {
                out[j * r_count + r] = p;
            }
        }
    }
}

/// The replicas' sums of a set being traced.
#[derive(Clone, Debug, Default)]
pub struct SetTally {
    sums: Vec<(Rgb, u32)>,
    lo: Rgb,
    hi: Rgb,
}

impl SetTally {
    /// Empty, for a set split into `rule`'s replicas.
    pub fn reset(&mut self, rule: &SetRule) {
        self.sums.clear();
        self.sums.resize(rule.replicas as usize, (Rgb::ZERO, 0));
        self.lo = Rgb::splat(f32::INFINITY);
        self.hi = Rgb::splat(f32::NEG_INFINITY);
    }

    /// Adds ray `i`'s value.
    pub fn push(&mut self, i: usize, l: Rgb) {
        let r = i % self.sums.len();
        self.sums[r].0 += l;
        self.sums[r].1 += 1;
        self.lo = self.lo.min(l);
        self.hi = self.hi.max(l);
    }

    /// Whether the set may stop: its interval is narrow enough.
    pub fn converged(&self, rule: &SetRule) -> bool {
        calibrated::converged(
            (rule.threshold, rule.floor),
            rule.t,
            &self.sums,
            self.hi - self.lo,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rule(replicas: u32) -> SetRule {
        SetRule::new(Some(Stopping {
            rule: StopRule::Calibrated,
            threshold: 0.05,
            confidence: 0.9,
            replicas,
            floor: 1.0,
            min_spp: 0,
        }))
        .expect("calibrated")
    }

    #[test]
    fn only_the_calibrated_rule_stops_sets() {
        let s = Stopping {
            rule: StopRule::Cycles,
            threshold: 0.05,
            confidence: 0.9,
            replicas: 8,
            floor: 1.0,
            min_spp: 0,
        };
        assert!(SetRule::new(Some(s)).is_none());
        assert!(SetRule::new(None).is_none());
        assert!(SetRule::for_set(Some(rule(4)), 8).is_none());
        assert!(SetRule::for_set(Some(rule(4)), 9).is_some());
    }

    #[test]
    fn passes_double_up_to_the_set() {
        let r = rule(4);
        let mut ends = vec![r.pass_end(0, 100)];
        while *ends.last().unwrap() < 100 {
            ends.push(r.pass_end(*ends.last().unwrap(), 100));
        }
        assert_eq!(ends, [8, 16, 32, 64, 100]);
    }

    /// The interleaved points are the replicas' own sets: for `sobol` and
    /// 4 replicas of 16, each replica's points are a net of 16.
    #[test]
    fn replicas_are_whole_sets() {
        let r = rule(4);
        let (mut scratch, mut out) = (Vec::new(), Vec::new());
        let table = PointTable::NONE;
        r.points(
            (Distribution::Sobol, &table),
            64,
            &Rng::new(5),
            &mut scratch,
            &mut out,
        );
        assert_eq!(out.len(), 64);
        for k in 0..4 {
            let mut cells: Vec<usize> = (k..64)
                .step_by(4)
                .map(|i| {
                    let p = 0.5 * (out[i].truncate() + 1.0);
                    (p.x * 16.0) as usize
                })
                .collect();
            cells.sort_unstable();
            assert_eq!(cells, (0..16).collect::<Vec<_>>(), "replica {k}");
        }
        // Independent replicas: not four copies of one set.
        assert_ne!(out[0], out[1]);
    }

    #[test]
    fn a_flat_set_stops_and_an_edge_does_not() {
        let r = rule(4);
        let mut t = SetTally::default();
        t.reset(&r);
        (0..8).for_each(|i| t.push(i, Rgb::splat(0.5)));
        assert!(t.converged(&r));
        t.reset(&r);
        (0..8).for_each(|i| t.push(i, Rgb::splat(if i % 3 == 0 { 1.0 } else { 0.0 })));
        assert!(!t.converged(&r));
    }
}
