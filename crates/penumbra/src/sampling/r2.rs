//! `r2`: Roberts' R2 sequence, the rank-1 Kronecker sequence of the plastic
//! number, with a random toroidal shift per set (M. Roberts, "The
//! Unreasonable Effectiveness of Quasirandom Sequences", 2018).
//!
//! # The sequence
//!
//! Point `i` is `frac(s + i · alpha)` per axis, with `alpha = (1/g, 1/g^2)`
//! and `g ≈ 1.3247179572` the plastic number, the real root of
//! `x^3 = x + 1`, which Roberts proposes as the 2D analogue of the golden
//! ratio. The arithmetic is done
//! exactly on the torus in 64-bit fixed point (`alpha` to 2^-64), so the
//! sequence does not drift with the index.
//!
//! # Randomisation
//!
//! Each set draws its shift `s` uniformly in `[0, 1)^2` (Cranley–Patterson
//! rotation): every point is then uniform over the square, and the set's
//! structure (its gaps, its lattice-like spread) is that of the unshifted
//! sequence moved on the torus.
//!
//! # Guarantees
//!
//! We know of no proven bound with a constant for this sequence (for an
//! algebraic `alpha` such as this one, Schmidt's subspace theorem gives
//! only `D*_N = O(N^(ε - 1))` for every `ε > 0`); what we promise is
//! measured: for the six shifts the tests try and every `N` from 1 to 64
//! (and a spread of `N` up to 256), the star
//! discrepancy of the first `N` points is below [`discrepancy_bound`]
//! `= 2 (1 + ln N) / N` (the largest measured ratio to it is 0.67, over six
//! shifts). A set of `N` is the first `N` points, in the trace order of
//! [`Distribution`](super::Distribution) (a permutation whose power-of-two
//! prefixes are runs of consecutive points).

use super::sobol::unit;
use super::Rng;
use crate::math::Vec2;

/// `1/g` and `1/g^2` for the plastic number `g`, in 64-bit fixed point.
const ALPHA: [u64; 2] = [0xc13f_a9a9_02a6_328f, 0x91e1_0da5_c79e_7b1d];
/// `1/phi` (golden ratio), for the one-dimensional set.
const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c16;

/// One randomised `r2` set: its shift.
#[derive(Clone, Copy, Debug)]
pub struct R2 {
    shift: [u64; 2],
}

impl R2 {
    /// A set drawn from its stream (two draws).
    pub fn new(rng: &mut Rng) -> R2 {
        let x = rng.next_u64();
        R2 {
            shift: [x, rng.next_u64()],
        }
    }

    /// Point `i` in `[0, 1)^2`.
    #[inline]
    pub fn point(&self, i: u32) -> Vec2 {
        let at = |axis: usize| {
            let t = self.shift[axis].wrapping_add(u64::from(i).wrapping_mul(ALPHA[axis]));
            unit((t >> 32) as u32)
        };
        Vec2::new(at(0), at(1))
    }

    /// Value `i` of the one-dimensional set: the golden-ratio sequence
    /// shifted by the set's first shift.
    #[inline]
    pub fn value(&self, i: u32) -> f32 {
        let t = self.shift[0].wrapping_add(u64::from(i).wrapping_mul(GOLDEN));
        unit((t >> 32) as u32)
    }
}

/// The measured bound on the star discrepancy of `n` shifted `r2` points
/// (see the module docs).
pub fn discrepancy_bound(n: usize) -> f64 {
    let n = n as f64;
    2.0 * (1.0 + n.ln()) / n
}

#[cfg(test)]
mod tests {
    use super::super::checks;
    use super::*;

    #[test]
    fn the_sequence_is_roberts() {
        let s = R2 { shift: [0, 0] };
        let g = 1.324_717_957_244_746_f64;
        for i in [1u32, 2, 3, 10, 1000, 1 << 20] {
            let p = s.point(i);
            let x = (f64::from(i) / g).fract();
            let y = (f64::from(i) / (g * g)).fract();
            assert!((f64::from(p.x) - x).abs() < 1e-6, "{i}");
            assert!((f64::from(p.y) - y).abs() < 1e-6, "{i}");
        }
    }

    #[test]
    fn star_discrepancy_is_within_the_stated_bound() {
        let counts = (1..=64).chain((70..=256).step_by(13)).chain([128, 256]);
        let mut worst: f64 = 0.0;
        for n in counts {
            for seed in 0..6 {
                let s = R2::new(&mut Rng::new(seed));
                let points: Vec<Vec2> = (0..n as u32).map(|i| s.point(i)).collect();
                let d = checks::star_discrepancy(&points);
                assert!(d < discrepancy_bound(n), "n={n} seed={seed}: D* = {d}");
                worst = worst.max(d / discrepancy_bound(n));
            }
        }
        println!("r2: largest D* / bound = {worst:.3}");
        // The check can fail: a poor Kronecker constant (1/2, 1/3) exceeds it.
        let poor: Vec<Vec2> = (0..64)
            .map(|i| Vec2::new((i as f32 * 0.5).fract(), (i as f32 / 3.0).fract()))
            .collect();
        assert!(checks::star_discrepancy(&poor) > discrepancy_bound(64));
    }

    #[test]
    fn points_are_uniform_in_expectation() {
        checks::uniform_in_expectation("r2", |seed, count, out| {
            let s = R2::new(&mut Rng::new(seed));
            out.extend((0..count).map(|i| s.point(i)));
        });
    }
}
