//! Ray distributions: where the extra rays of stochastic ray tracing go.
//!
//! A stochastic ray tracer replaces one ray (the *original ray* of classic
//! ray tracing: the perfect reflection, the ray to the centre of a light, the
//! ray through the centre of a pixel) by a set of rays whose end points (or,
//! for depth of field, origins) are spread around the original one. The
//! spreading is done in the plane normal to the original ray: a
//! [`Frame`](crate::math::Frame) turns the 2D points returned here into a
//! translation vector `x * u + y * v` that is added to the end point. The
//! exception is [`Distribution::FastRandom`], which returns 3D offsets meant to
//! be added directly, without a frame.
//!
//! Every distribution is a pure function of `(count, radius, random stream)`:
//! the same [`Rng`] key gives the same points, whatever thread asks. There
//! are the six of the thesis ([`Distribution::THESIS`]) and six
//! low-discrepancy sets ([below](#the-low-discrepancy-sets)).
//!
//! # The six distributions
//!
//! Sets of 16 points each, in the square `[-r, r]^2` (`o` is a point, `8`
//! two; fast-random seen from above, its x and y; `penumbra samples
//! --distribution all --format svg` draws the same as a picture):
//!
//! ```text
//!       grid             jitter         semi-jitter
//! +--------------+  +--------------+  +--------------+
//! |              |  |   o        o |  | o     o     o|
//! | o   o  o   o |  |  o    o      |  |    o         |
//! |              |  |         o   o|  | o     o    o |
//! | o   o  o   o |  |  o   o       |  |    o         |
//! |              |  | o      o     |  | o         o  |
//! | o   o  o   o |  |    o     o   |  |     o  o     |
//! |              |  |    o     o   |  |         o  o |
//! | o   o  o   o |  |  o    o      |  | o   o        |
//! +--------------+  +--------------+  +--------------+
//!     poisson            random         fast-random
//! +--------------+  +--------------+  +--------------+
//! |o     o       |  |     o    o   |  |  o        o  |
//! |          o o |  |       o   8  |  |            o |
//! | o     o      |  |  o  o   o    |  | o  o   o     |
//! | o         o  |  |              |  | o  o   o     |
//! |     o  o     |  |o  oo         |  |o       o     |
//! |  o         o |  |o o      oo  o|  |      o    o  |
//! |o   o o       |  |              |  | o           o|
//! |         o    |  |              |  |            o |
//! +--------------+  +--------------+  +--------------+
//! ```
//!
//! * **`grid`** ([`grid`]) — the centres of an `s x s` grid of equal cells over the
//!   square (`s = sqrt(count)`). Deterministic up to the trace order: every
//!   set is the same pattern, which is why it can show Moiré patterns and
//!   banded penumbras. Guarantee: the points are exactly the cell centres,
//!   `r * ((2i + 1) / s - 1)` per axis.
//! * **`jitter`** ([`jitter`]) — one point uniformly distributed over the whole of each grid
//!   cell (stratified sampling). Guarantee: exactly one point per cell, and the
//!   union of all cells is covered uniformly.
//! * **`semi-jitter`** ([`semi_jitter`]) — one point per cell, uniform in the centred square of
//!   half the cell's side. A compromise between `grid` (regular) and `jitter`
//!   (noisy): no two points come closer than half a cell side. Guarantee:
//!   exactly one point per cell, inside its centred half-size sub-square.
//! * **`poisson`** ([`poisson`]) — a Poisson-disk set: random points no two of which are
//!   closer than [`poisson_min_distance`]`(count, r) = r * sqrt(2 / count)`,
//!   covering the whole square without clumps or regular structure; each
//!   point is uniform over the square. See
//!   [Poisson-disk points](poisson#poisson-disk-points).
//! * **`random`** ([`random`]) — independent points uniform *per area* over the disk of
//!   radius `r` (polar coordinates with radius `r * sqrt(u)`). No guarantee of
//!   spread: a set may clump in one part of the disk. Points lie within `r` up
//!   to a relative rounding error of about `1e-7`.
//! * **`fast-random`** ([`fast_random`]) — independent points uniform in the cube `[-r, r]^3`,
//!   to be added to a ray's end point in world axes, without building a frame.
//!   Cheaper, but the resulting *directions* are not uniform: the cube is
//!   aligned with the world axes, not with the ray, so the spread depends on
//!   the ray's direction, and seen along a ray its cross-section is a square
//!   or a hexagon rather than a disk (more rays toward its corners). Only this
//!   distribution returns a non-zero `z`; see [`Distribution::is_3d`].
//!
//! # The low-discrepancy sets
//!
//! Six more distributions come from quasi-Monte Carlo rather than from the
//! thesis. Each is a deterministic sequence in `[0, 1)^2` randomised per set
//! from the set's stream (one to three 64-bit draws; `zsobol` from the
//! stream's place in the frame instead), so like the six it is a
//! pure function of the stream, hence of (seed, pixel, set, dimension); its
//! first `count` points are scaled to `[-r, r]^2` and returned in the set's
//! trace order (see [Trace order](#trace-order)), a permutation that keeps
//! every power-of-two prefix a block of the sequence, already spread over the
//! whole square (the property the shuffle gives the grid family). Each has its own module with its construction, its guarantees
//! and the tests that check them:
//!
//! * **`sobol`** ([`sobol`](super::sobol)) — the first two dimensions of
//!   Sobol's sequence, Owen-scrambled by hashing (Burley 2020). Guarantee:
//!   for every set, every prefix of `2^m` points is a (0,m,2)-net in base 2:
//!   each elementary interval `2^-j x 2^-k`, `j + k = m`, holds exactly one
//!   point (so one point per cell of the `2^k x 2^k` grid for `4^k` points, and
//!   one per row and per column of `N` strata for `N = 2^m`).
//! * **`zsobol`** ([`zsobol`](super::zsobol)) — Ahmed and Wonka's (2020)
//!   Morton-ordered Sobol', pbrt-v4's default: the sets of all pixels are
//!   blocks of one Owen-scrambled Sobol' sequence, scrambled per dimension
//!   rather than per set, with the pixels in Morton order (digits randomly
//!   permuted). Same guarantee as `sobol` for each set; besides, the sets of
//!   the 4 pixels of a Morton quad together form a net, so neighbouring
//!   pixels fill each other's gaps and the error of few samples is spread as
//!   blue noise over the screen.
//! * **`pmj02`** ([`pmj02`](super::pmj02)) — a progressive multi-jittered
//!   (0,2) sequence (Christensen et al. 2018), built, after Helmer et al.'s
//!   (2021) view of pmj02 as randomised (0,2)-sequences, from the Sobol'
//!   (0,2)-sequence with a randomly scrambled order and Owen-scrambled
//!   points. Same guarantee as `sobol` (power-of-two sets are the same
//!   scrambled nets); the order of the points differs, which matters for
//!   other counts and for sets stopped early.
//! * **`pmj02bn`** ([`pmj02bn`](super::pmj02bn)) — pmj02 with blue noise
//!   (Christensen et al.'s best-candidate variant): one of a pool of four
//!   linearly scrambled Sobol' (0,2)-sequences, built at first use (20 to
//!   45 ms) with scrambles chosen so that their points keep apart, then
//!   digitally shifted (`xor` of a random 32-bit word per axis) and
//!   possibly transposed per set. Same guarantee as `sobol`; besides,
//!   measured, the mean distance to the nearest neighbour is 10 to 25%
//!   larger than `pmj02`'s from 16 to 1024 points.
//! * **`halton`** ([`halton`](super::halton)) — the Halton sequence in bases
//!   2 and 3 with a random permutation of the digits at each position.
//!   Guarantee: every prefix of `N` points has star discrepancy below
//!   `(2 + (0.7213 ln N + 1.5)(0.9102 ln N + 2)) / N`, Niederreiter's
//!   Halton bound ([`halton::discrepancy_bound`](super::halton::discrepancy_bound)).
//! * **`r2`** ([`r2`](super::r2)) — Roberts' R2 sequence (the Kronecker
//!   sequence of the plastic number) with a random toroidal shift. Promise,
//!   measured rather than proven (six shifts, every `N` up to 64 and a
//!   spread of `N` up to 256): the first `N` points have star discrepancy
//!   below `2 (1 + ln N) / N`
//!   ([`r2::discrepancy_bound`](super::r2::discrepancy_bound)).
//!
//! Every point of each of these six is uniform over the square in expectation
//! (tested by a chi-square test over thousands of sets). Non-power-of-two
//! counts are fine: a set is a prefix of its sequence, so it keeps its
//! spread, but only powers of two give `sobol`, `zsobol`, `pmj02` and
//! `pmj02bn` their full nets. Their shutter times
//! ([`Distribution::generate_1d`]) are the sequence's first coordinate
//! (`halton`'s base-2 one; for `r2` the golden-ratio sequence, shifted),
//! whose every `2^m` prefix for `sobol`, `zsobol`, `pmj02`, `pmj02bn` and
//! `halton` has one value in each stratum of width `2^-m`.
//!
//! *Cost.* Measured on a shared test machine (criterion, `cargo bench -p
//! penumbra-bench --bench distributions`, group `point`, sets of 256): 15 ns
//! a point for `sobol`, `zsobol` and `halton`, 13.5 for `pmj02`, 7 for
//! `pmj02bn` (eight table lookups) and 6 for `r2`; about 7 ns of each but
//! `pmj02`'s is the trace order's scramble of the index (`pmj02`'s own
//! order is such a scramble). A whole set of one point, with the derivation of
//! its stream as a render makes it (about 7 ns), takes 17, 79, 26, 30 and
//! 10 ns: a `zsobol` set hashes once per base-4 digit of its index (about
//! 12 for a pixel of an 800x600 frame with 16 samples); for `pmj02bn`, 22
//! ns (on a busier day, when `pmj02`'s took 37), plus 20 to 45 ms once per
//! process for the first set, which builds the pool.
//!
//! # The user's points
//!
//! **`custom`** draws every set from a [`PointTable`] of point sets the user
//! gives (a file, or in Python an array or a function): a set of the right
//! size chosen from the stream, shifted by a random offset modulo the unit
//! square; see [`custom`](super::custom). It is not in
//! [`Distribution::ALL`] (it needs a table), but it is in
//! [`Distribution::SELECTABLE`]. Its methods with a table are the `_in`
//! ones ([`generate_in`](Distribution::generate_in) …); without a table
//! (as [`generate`](Distribution::generate) draws), `custom` gives
//! independent uniform points.
//!
//! # A count of one
//!
//! With one point, `grid` gives exactly the centre `(0, 0)`: the original ray,
//! so a count of 1 reproduces classic (Whitted) ray tracing. `jitter` gives one
//! point uniform over the square, `semi-jitter` one point uniform in
//! `[-r/2, r/2]^2`, `poisson` one random point of the square, `random` one
//! point uniform in the disk and `fast-random` one point uniform in the cube.
//! The low-discrepancy sets give their first point, uniform over the square.
//! A count of zero gives no points.
//!
//! # Non-square counts
//!
//! `grid`, `jitter` and `semi-jitter` need a square count to have one point
//! per cell ([`Distribution::needs_square_count`]). For another count `N` we
//! round up to the next square `s^2 >= N`, generate all `s^2` cells, shuffle
//! them into trace order and keep the first `N`. The kept cells are a uniformly
//! random subset, so no part of the square is systematically left out, but
//! some cells of each set stay empty. [`Distribution::non_square_warning`]
//! gives a message for the user (the caller warns once).
//!
//! # Trace order
//!
//! [`Distribution::generate`] returns the points of the thesis's six already
//! shuffled (with [`shuffle`], on the same stream), and `custom`'s too. A set
//! of rays is traced in that order,
//! never row by row: when tracing stops early because the result has
//! converged (the acceleration metrics of the thesis, §3.4), row-major order
//! would always have sampled the first rows and never the last ones, biasing
//! every early-terminated pixel toward one side of the square.
//!
//! The other low-discrepancy sets are not shuffled but permuted so that
//! their progressive structure survives (`pmj02`'s own order, an Owen
//! scramble of the index, does this already): point `i` of a set of `N`
//! (`2^(m-1) < N ≤ 2^m`) is the sequence's point `π(i)`, where `π` is a
//! nested uniform (Owen) scramble of the index read as an `m`-digit binary
//! fraction, seeded per set, with indices at `N` or beyond scrambled again
//! until they fall below it. The set is still its sequence's first `N`
//! points; the first `2^j` in trace order are an aligned block of `2^j`
//! consecutive points of the sequence (for `sobol`, `zsobol` and `pmj02bn`
//! a `(0, j, 2)`-net, for `halton` and `r2` a run of consecutive
//! points). The permutation matters where sets are paired by index: a camera
//! sample takes point `i` of its film, lens and time sets. Two sets of one
//! sequence in sequence order would pair point `i` with point `i` under two
//! randomisations, which are dependent (the first digit of a `sobol` point's
//! first coordinate is the index's last bit, up to the scramble; an `r2` lens
//! point is the film point plus a constant), so a pixel would converge to
//! another image. pbrt-v4 permutes each dimension's sample index for the same
//! reason.
//!
//! # Shutter times
//!
//! [`Distribution::generate_1d`] is the one-dimensional analogue on `[0, 1)`,
//! used for the shutter time of motion blur: stratified for grid, jitter and
//! semi-jitter, hard-core for poisson, independent for the random ones, and
//! the first coordinate of the low-discrepancy sets' sequences (see
//! [above](#the-low-discrepancy-sets)).
//!
//! # Differences from the thesis listings
//!
//! The text of "Stochastic Ray Tracing" (§2.4, §3.2) and its pseudo code
//! disagree; we follow the text's stated intent. Each distribution's file
//! says where and how: [`jitter`] and [`semi_jitter`] (the listings'
//! offsets are half the text's), [`random`] (the listing's radius crowds
//! the centre), [`grid`] (the listing's loop runs once too often) and
//! [`poisson`] (dart throwing with a count, or Bridson's algorithm without
//! one); [`fast_random`] follows Listing 3.6 exactly, including its bias.
//!
//! # Degenerate input
//!
//! Counts and radii come from users. A count of 0 gives no points; memory is
//! proportional to the count, so the caller should cap it. Rejecting a
//! negative, infinite or NaN radius is the caller's job, but nothing here
//! panics or loops on one: every distribution only scales unit-square points
//! by the radius (Bridson's algorithm runs on the unit square, independent of
//! the radius), so a zero radius puts every point at the origin, a negative
//!
//! # One file per distribution
//!
//! Each distribution is a type implementing [`DistributionModel`]: its
//! names, its kind of points, and how it fills a set, gives the one point
//! of a set of one, and draws shutter times. The thesis's six and their
//! algorithms have a file each in this folder ([`grid`], [`jitter`],
//! [`semi_jitter`], [`poisson`], [`random`], [`fast_random`]); the
//! low-discrepancy sets implement it beside their sequences
//! ([`sobol`](super::sobol), [`zsobol`](super::zsobol),
//! [`pmj02`](super::pmj02), [`pmj02bn`](super::pmj02bn),
//! [`halton`](super::halton), [`r2`](super::r2)) and `custom` beside its
//! table ([`custom`](super::custom)). The closed enum [`Distribution`] and
//! its dispatch are made by the `distributions!` list at the end of this
//! file, one line per distribution: adding one is a file and a line.

pub mod cells;
pub mod custom;
pub mod fast_random;
pub mod grid;
mod halton;
pub mod jitter;
mod pmj02;
mod pmj02bn;
pub mod poisson;
mod r2;
pub mod random;
pub mod semi_jitter;
mod sobol;
#[cfg(test)]
mod testing;
mod zsobol;

pub(super) mod model;

use std::fmt;
use std::str::FromStr;

use crate::math::{Vec2, Vec3};

use super::custom::PointTable;
use super::{Place, Rng};

pub use model::{shuffle, square_side, DistributionModel, Domain};
pub use poisson::{poisson_min_distance, poisson_min_distance_1d};

impl Distribution {
    /// True only for fast-random, whose points are 3D offsets added in world
    /// axes; all others are 2D (z = 0) and meant for a frame around the ray.
    #[inline]
    pub fn is_3d(self) -> bool {
        self.domain() == Domain::Cube
    }

    /// A message for the user when `count` is not a perfect square for a
    /// distribution that needs one (see [Non-square counts](self#non-square-counts));
    /// `None` when the count is fine. The caller should warn once, not per set.
    pub fn non_square_warning(self, count: usize) -> Option<String> {
        let s = square_side(count);
        if !self.needs_square_count() || s.checked_mul(s) == Some(count) {
            return None;
        }
        let cells = s.saturating_mul(s);
        let lower = (s - 1) * (s - 1);
        Some(format!(
            "the {name} distribution needs a square ray count; {count} is not a square, \
             so each set traces a random {count} of the {cells} cells of a {s}x{s} grid \
             (use {lower} or {cells} for exactly one ray per cell)",
            name = self.name(),
        ))
    }

    /// Fills `out` (cleared first) with exactly `count` points, already in
    /// trace order (shuffled). 2D distributions return `z = 0`. Points lie in
    /// `[-r, r]^2`, the disk of radius `r` (random) or the cube `[-r, r]^3`
    /// (fast-random); see the [module docs](self).
    pub fn generate(self, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        self.generate_in(&PointTable::NONE, count, radius, rng, out);
    }

    /// The one point of a set of one, as [`generate`](Self::generate) and
    /// [`generate_unordered`](Self::generate_unordered) give it for `count =
    /// 1` (the same bits and the same draws), without a buffer: a camera ray
    /// with one shadow ray makes hundreds of thousands of such sets.
    pub fn one(self, radius: f32, rng: &mut Rng) -> Vec3 {
        self.one_in(&PointTable::NONE, radius, rng)
    }

    /// The points [`generate`](Self::generate) gives, for a set whose trace
    /// order cannot matter (a shadow set without the metric, whose rays are
    /// summed): a square count of the grid family skips the final shuffle,
    /// since it keeps every cell anyway. Other distributions and counts are
    /// generated as by `generate`, whose shuffle chooses the cells kept.
    pub fn generate_unordered(self, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        self.generate_unordered_in(&PointTable::NONE, count, radius, rng, out);
    }

    /// Fills `out` (cleared first) with exactly `count` values in `[0, 1)`,
    /// shuffled into trace order, for the shutter time. With `n = count`:
    /// grid gives `(i + 0.5) / n`; jitter `(i + u) / n`; semi-jitter
    /// `(i + 0.25 + 0.5 u) / n`; poisson a uniformly random set with gaps of
    /// at least [`poisson_min_distance_1d`]; random and fast-random
    /// independent uniform values (time has no direction to bias). The
    /// low-discrepancy sets give their sequence's first coordinate in the
    /// set's trace order (for `r2` the shifted golden-ratio sequence);
    /// `custom` the first coordinates of its points, shuffled.
    pub fn generate_1d(self, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        self.generate_1d_in(&PointTable::NONE, count, rng, out);
    }
}

impl fmt::Display for Distribution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing an unknown distribution name; its message lists the
/// valid names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownDistribution(pub String);

impl fmt::Display for UnknownDistribution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = Distribution::SELECTABLE.iter().map(|d| d.name()).collect();
        write!(
            f,
            "unknown ray distribution '{}' (expected one of: {})",
            self.0,
            names.join(", ")
        )
    }
}

impl std::error::Error for UnknownDistribution {}

impl FromStr for Distribution {
    type Err = UnknownDistribution;

    /// Same as [`Distribution::from_name`], with an error message.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Distribution::from_name(s).ok_or_else(|| UnknownDistribution(s.to_string()))
    }
}

/// Makes [`Distribution`], the enum of the distributions listed (each
/// `Variant => Model`, the model implementing [`DistributionModel`]), its
/// lists and names, and its dispatch.
macro_rules! distributions {
    ($($variant:ident => $model:ty,)*) => {
        /// How the points of a ray set are placed; see the [module docs](self).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize)]
        #[serde(rename_all = "kebab-case")]
        pub enum Distribution {
            $($variant,)*
        }

        /// Every distribution listed, in the list's order.
        const LISTED: [Distribution; [$(Distribution::$variant,)*].len()] =
            [$(Distribution::$variant,)*];

        /// The listed distributions for which `keep` holds, in the list's
        /// order; `N` of them.
        const fn listed_where<const N: usize>(keep: [bool; LISTED.len()]) -> [Distribution; N] {
            let mut out = [LISTED[0]; N];
            let (mut i, mut n) = (0, 0);
            while i < LISTED.len() {
                if keep[i] {
                    out[n] = LISTED[i];
                    n += 1;
                }
                i += 1;
            }
            assert!(n == N);
            out
        }

        /// How many of `keep` hold.
        const fn count(keep: [bool; LISTED.len()]) -> usize {
            let (mut i, mut n) = (0, 0);
            while i < keep.len() {
                n += keep[i] as usize;
                i += 1;
            }
            n
        }

        const NEEDS_NO_TABLE: [bool; LISTED.len()] =
            [$(!<$model as DistributionModel>::NEEDS_TABLE,)*];
        const OF_THE_THESIS: [bool; LISTED.len()] =
            [$(<$model as DistributionModel>::THESIS,)*];
        const SEQUENCE: [bool; LISTED.len()] =
            [$(<$model as DistributionModel>::SEQUENCE,)*];

        impl Distribution {
            /// Every distribution: the thesis's six, then the low-discrepancy
            /// sets (not `custom`, which needs a table).
            pub const ALL: [Distribution; count(NEEDS_NO_TABLE)] = listed_where(NEEDS_NO_TABLE);

            /// Every name a user may select: [`ALL`](Self::ALL), then `custom`.
            pub const SELECTABLE: [Distribution; LISTED.len()] = LISTED;

            /// The thesis's six, in the order of its Figure 2.18 plus
            /// fast-random: the first six of [`ALL`](Self::ALL).
            pub const THESIS: [Distribution; count(OF_THE_THESIS)] = listed_where(OF_THE_THESIS);

            /// The sequences a path sampler may draw from (`sobol`,
            /// `zsobol`, `pmj02`, `pmj02bn`, `halton`, `r2`).
            pub const SEQUENCES: [Distribution; count(SEQUENCE)] = listed_where(SEQUENCE);

            /// The kebab-case name users write (the serde name too).
            pub const fn name(self) -> &'static str {
                match self {
                    $(Distribution::$variant => <$model as DistributionModel>::NAME,)*
                }
            }

            /// Parses a user-written name: the names, case-insensitively,
            /// with `_` accepted for `-`, and each distribution's aliases
            /// (`semijitter`, `fastrandom`, `poisson-disk`, `owen-sobol`,
            /// `z-sobol`, `pmj`).
            pub fn from_name(s: &str) -> Option<Self> {
                let key = s.trim().to_ascii_lowercase().replace('_', "-");
                let key = key.as_str();
                $(if key == <$model as DistributionModel>::NAME
                    || <$model as DistributionModel>::ALIASES.contains(&key)
                {
                    return Some(Distribution::$variant);
                })*
                None
            }

            /// Where its points lie (see [`Domain`]).
            #[inline]
            pub const fn domain(self) -> Domain {
                match self {
                    $(Distribution::$variant => <$model as DistributionModel>::DOMAIN,)*
                }
            }

            /// True for the user's points (`custom`), which need a table
            /// ([`PointTable`]); without one they are independent uniform
            /// points.
            pub const fn needs_table(self) -> bool {
                match self {
                    $(Distribution::$variant => <$model as DistributionModel>::NEEDS_TABLE,)*
                }
            }

            /// True for the distributions with one point per grid cell
            /// (grid, jitter, semi-jitter), which only fill their pattern for
            /// square counts.
            pub fn needs_square_count(self) -> bool {
                match self {
                    $(Distribution::$variant => <$model as DistributionModel>::NEEDS_SQUARE_COUNT,)*
                }
            }

            /// [`generate`](Self::generate), with `custom`'s points from `table`.
            pub fn generate_in(
                self,
                table: &PointTable,
                count: usize,
                radius: f32,
                rng: &mut Rng,
                out: &mut Vec<Vec3>,
            ) {
                out.clear();
                if count == 0 {
                    return;
                }
                match self {
                    $(Distribution::$variant => {
                        <$model as DistributionModel>::generate(table, count, radius, rng, out)
                    })*
                }
            }

            /// [`one`](Self::one), with `custom`'s points from `table`.
            pub fn one_in(self, table: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
                match self {
                    $(Distribution::$variant => <$model as DistributionModel>::one(table, radius, rng),)*
                }
            }

            /// [`generate_unordered`](Self::generate_unordered), with
            /// `custom`'s points from `table`.
            pub fn generate_unordered_in(
                self,
                table: &PointTable,
                count: usize,
                radius: f32,
                rng: &mut Rng,
                out: &mut Vec<Vec3>,
            ) {
                out.clear();
                match self {
                    $(Distribution::$variant => {
                        <$model as DistributionModel>::generate_unordered(table, count, radius, rng, out)
                    })*
                }
            }

            /// Points `part` of [`generate_unordered_in`](Self::generate_unordered_in)'s
            /// set, made alone where the distribution can (see
            /// [`DistributionModel::generate_unordered_part`]); `false`
            /// where it cannot.
            pub fn generate_unordered_part_in(
                self,
                table: &PointTable,
                (count, radius): (usize, f32),
                rng: &mut Rng,
                part: std::ops::Range<usize>,
                out: &mut Vec<Vec3>,
            ) -> bool {
                out.clear();
                match self {
                    $(Distribution::$variant => {
                        <$model as DistributionModel>::generate_unordered_part(table, count, radius, rng, part, out)
                    })*
                }
            }

            /// [`generate_1d`](Self::generate_1d), with `custom`'s points
            /// from `table` (their first coordinates, shuffled).
            pub fn generate_1d_in(
                self,
                table: &PointTable,
                count: usize,
                rng: &mut Rng,
                out: &mut Vec<f32>,
            ) {
                out.clear();
                if count == 0 {
                    return;
                }
                match self {
                    $(Distribution::$variant => {
                        <$model as DistributionModel>::generate_1d(table, count, rng, out)
                    })*
                }
            }

            /// As a path sampler: the value of the dimension whose stream
            /// is at `place` (see [`DistributionModel::bounce_value`]).
            #[inline]
            pub(in crate::sampling) fn bounce_value(self, place: Place) -> f32 {
                match self {
                    $(Distribution::$variant => <$model as DistributionModel>::bounce_value(place),)*
                }
            }

            /// As a path sampler: the point of the dimension pair whose
            /// stream is at `place`.
            #[inline]
            pub(in crate::sampling) fn bounce_point(self, place: Place) -> Vec2 {
                match self {
                    $(Distribution::$variant => <$model as DistributionModel>::bounce_point(place),)*
                }
            }
        }
    };
}

distributions! {
    Grid => grid::Grid,
    Jitter => jitter::Jitter,
    SemiJitter => semi_jitter::SemiJitter,
    Poisson => poisson::Poisson,
    Random => random::Random,
    FastRandom => fast_random::FastRandom,
    Sobol => sobol::Sobol,
    Zsobol => zsobol::ZSobol,
    Pmj02 => pmj02::Pmj02,
    Pmj02bn => pmj02bn::Pmj02bn,
    Halton => halton::Halton,
    R2 => r2::R2,
    Custom => custom::Custom,
}

#[cfg(test)]
mod tests {
    use super::testing::{chi2, gen, CHI2_999_DF6};
    use super::*;

    #[test]
    fn counts_are_exact() {
        for d in Distribution::ALL {
            for count in 0..=100 {
                for seed in 0..3 {
                    assert_eq!(gen(d, count, 1.0, seed).len(), count, "{d} {count}");
                }
            }
        }
    }

    fn in_domain(d: Distribution, p: Vec3, r: f32) -> bool {
        match d.domain() {
            Domain::Disk => p.z == 0.0 && p.length() <= r * (1.0 + 1e-6),
            Domain::Cube => p.abs().max_element() <= r,
            Domain::Square => p.z == 0.0 && p.x.abs() <= r && p.y.abs() <= r,
        }
    }

    #[test]
    fn points_stay_in_their_domain() {
        let counts = [1, 2, 3, 4, 5, 7, 9, 10, 16, 17, 25, 33, 64, 100, 256];
        for d in Distribution::ALL {
            for count in counts {
                for r in [1e-3, 0.5, 1.0, 7.5, 1000.0] {
                    for seed in 0..20 {
                        for p in gen(d, count, r, seed) {
                            assert!(in_domain(d, p, r), "{d} n={count} r={r}: {p:?}");
                        }
                    }
                }
            }
        }
    }

    /// The unordered variant gives exactly the points `generate` gives (as a
    /// set), for every distribution and square and non-square counts.
    #[test]
    fn unordered_sets_hold_the_same_points() {
        let key = |p: &Vec3| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
        for d in Distribution::ALL {
            for count in [1, 2, 4, 9, 10, 16, 64] {
                let (mut a, mut b) = (Vec::new(), Vec::new());
                d.generate(count, 0.7, &mut Rng::new(9), &mut a);
                d.generate_unordered(count, 0.7, &mut Rng::new(9), &mut b);
                let (mut a, mut b): (Vec<_>, Vec<_>) =
                    (a.iter().map(key).collect(), b.iter().map(key).collect());
                a.sort_unstable();
                b.sort_unstable();
                assert_eq!(a, b, "{d} with {count} points");
            }
        }
    }

    /// `one` is what a set of one gives, bit for bit, and leaves the stream
    /// where a set of one leaves it.
    #[test]
    fn one_point_is_a_set_of_one() {
        let mut out = Vec::new();
        for key in 0..300 {
            for d in Distribution::ALL {
                for radius in [1.0, 0.5, 0.0] {
                    let (mut a, mut b, mut c) = (Rng::new(key), Rng::new(key), Rng::new(key));
                    let p = d.one(radius, &mut a);
                    d.generate(1, radius, &mut b, &mut out);
                    assert_eq!(out.len(), 1);
                    assert_eq!(
                        p.to_array().map(f32::to_bits),
                        out[0].to_array().map(f32::to_bits)
                    );
                    d.generate_unordered(1, radius, &mut c, &mut out);
                    assert_eq!(
                        p.to_array().map(f32::to_bits),
                        out[0].to_array().map(f32::to_bits)
                    );
                    assert!(a == b && b == c, "{d:?} leaves the stream elsewhere");
                }
            }
        }
    }

    #[test]
    fn shuffle_is_uniform() {
        let mut rng = Rng::new(5);
        let mut position = [0u64; 7];
        for _ in 0..70_000 {
            let mut items = [0, 1, 2, 3, 4, 5, 6];
            shuffle(&mut items, &mut rng);
            position[items.iter().position(|&x| x == 0).unwrap_or(7)] += 1;
        }
        let c = chi2(&position);
        assert!(c < CHI2_999_DF6, "chi2 = {c}");
        shuffle::<u8>(&mut [], &mut rng);
    }

    #[test]
    fn shutter_times_have_range_count_and_strata() {
        for d in Distribution::ALL {
            for count in 0..=64 {
                let mut out = vec![7.0; 2];
                d.generate_1d(count, &mut Rng::new(count as u64), &mut out);
                assert_eq!(out.len(), count);
                assert!(out.iter().all(|t| (0.0..1.0).contains(t)), "{d} {count}");
                if d.needs_square_count() {
                    check_strata(d, &out);
                }
            }
        }
    }

    /// One value per stratum `[i/n, (i+1)/n)`, at the stated offset.
    fn check_strata(d: Distribution, times: &[f32]) {
        let n = times.len();
        let mut sorted = times.to_vec();
        sorted.sort_by(f32::total_cmp);
        for (i, &t) in sorted.iter().enumerate() {
            let offset = t * n as f32 - i as f32;
            let ok = match d {
                Distribution::Grid => (offset - 0.5).abs() < 1e-4,
                Distribution::SemiJitter => (0.25 - 1e-4..=0.75 + 1e-4).contains(&offset),
                _ => (-1e-4..=1.0 + 1e-4).contains(&offset),
            };
            assert!(ok, "{d} n={n}: value {i} has offset {offset}");
        }
    }

    /// Every power-of-two prefix of the shutter times of `sobol`, `pmj02`,
    /// `pmj02bn` and `halton` has one value per stratum of its width.
    #[test]
    fn low_discrepancy_shutter_times_are_stratified() {
        let mut out = Vec::new();
        for d in [
            Distribution::Sobol,
            Distribution::Pmj02,
            Distribution::Pmj02bn,
            Distribution::Halton,
        ] {
            for seed in 0..20 {
                d.generate_1d(1024, &mut Rng::new(seed), &mut out);
                for m in 0..=10 {
                    let n = 1usize << m;
                    let mut strata: Vec<usize> =
                        out[..n].iter().map(|&t| (t * n as f32) as usize).collect();
                    strata.sort_unstable();
                    assert_eq!(strata, (0..n).collect::<Vec<_>>(), "{d} seed {seed}");
                }
            }
        }
    }

    /// Sets drawn from independent streams are independent when paired by
    /// index, as a camera sample pairs its film, lens and time points: the
    /// mean over a pair of sets of a function of both points converges as
    /// the sets grow. Two copies of one sequence in sequence order would
    /// not (an `r2` lens point is its film point plus a constant, a
    /// `sobol` one shares its first digit), and the error would stay.
    #[test]
    fn sets_paired_by_index_are_independent() {
        // Whether two coordinates lie within 1/4 of each other on the
        // circle: 1/2 for independent uniform ones.
        let near = |a: f32, b: f32| {
            let d = (a - b).rem_euclid(1.0);
            f64::from(u8::from(d.min(1.0 - d) < 0.25))
        };
        let unit = |v: f32| 0.5 * (v + 1.0);
        let (mut film, mut lens, mut times) = (Vec::new(), Vec::new(), Vec::new());
        for d in Distribution::ALL {
            // The spread of the mean over pairs of sets (not its error: the
            // disk of `random` moves the mean away from 1/2).
            let mut spread = |count: usize| {
                let pairs = 400;
                let mut means = [Vec::new(), Vec::new()];
                for p in 0..pairs {
                    d.generate(count, 1.0, &mut Rng::new(3 * p), &mut film);
                    d.generate(count, 1.0, &mut Rng::new(3 * p + 1), &mut lens);
                    d.generate_1d(count, &mut Rng::new(3 * p + 2), &mut times);
                    let n = count as f64;
                    let xy: f64 = (film.iter().zip(&lens))
                        .map(|(f, l)| near(unit(f.x), unit(l.x)) + near(unit(f.y), unit(l.y)))
                        .sum::<f64>()
                        / (2.0 * n);
                    let xt: f64 = film
                        .iter()
                        .zip(&times)
                        .map(|(f, &t)| near(unit(f.x), t))
                        .sum::<f64>()
                        / n;
                    means[0].push(xy);
                    means[1].push(xt);
                }
                means.map(|m| {
                    let mean = m.iter().sum::<f64>() / m.len() as f64;
                    (m.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / m.len() as f64).sqrt()
                })
            };
            let (small, large) = (spread(16), spread(256));
            for k in 0..2 {
                // Independent pairs: 1/4 of the spread at 16 times the
                // points; sequence order keeps it (0.99 for `sobol`'s
                // times). Measured: 0.23 to 0.34, but `r2`'s lens 0.44
                // (its steps 4α to 16α are within 0.08 of an integer, so
                // the scramble's flips of those digits barely move a
                // point).
                let ratio = large[k] / small[k];
                assert!(ratio < 0.6, "{d} ({}): {ratio}", ["lens", "time"][k]);
            }
        }
    }

    #[test]
    fn same_key_gives_same_points() {
        for d in Distribution::ALL {
            let root = Rng::new(42);
            let (mut a, mut b, mut c) = (Vec::new(), Vec::new(), Vec::new());
            d.generate(25, 1.0, &mut root.derive(3), &mut a);
            d.generate(25, 1.0, &mut root.derive(3), &mut b);
            d.generate(25, 1.0, &mut root.derive(4), &mut c);
            assert_eq!(a, b, "{d}");
            assert_ne!(a, c, "{d}: different keys gave the same set");
            let (mut s, mut t) = (Vec::new(), Vec::new());
            d.generate_1d(9, &mut root.derive(3), &mut s);
            d.generate_1d(9, &mut root.derive(3), &mut t);
            assert_eq!(s, t, "{d}");
        }
    }

    #[test]
    fn degenerate_radii_neither_panic_nor_hang() {
        for d in Distribution::ALL {
            for r in [0.0, -1.0, f32::NAN, f32::INFINITY, f32::MIN_POSITIVE] {
                assert_eq!(gen(d, 17, r, 1).len(), 17);
            }
            assert!(gen(d, 9, 0.0, 1).iter().all(|p| *p == Vec3::ZERO), "{d}");
            let mirrored = gen(d, 9, -1.0, 1);
            assert!(mirrored.iter().all(|p| p.abs().max_element() <= 1.0), "{d}");
        }
    }

    #[test]
    fn names_round_trip_and_aliases_parse() {
        for d in Distribution::ALL {
            assert_eq!(Distribution::from_name(d.name()), Some(d));
            assert_eq!(d.name().parse::<Distribution>(), Ok(d));
            assert_eq!(d.to_string(), d.name());
            assert_eq!(d.is_3d(), d == Distribution::FastRandom);
        }
        let aliases = [
            ("semijitter", Distribution::SemiJitter),
            ("fastrandom", Distribution::FastRandom),
            ("poisson-disk", Distribution::Poisson),
            (" Semi_Jitter ", Distribution::SemiJitter),
        ];
        for (name, d) in aliases {
            assert_eq!(Distribution::from_name(name), Some(d), "{name}");
        }
        assert_eq!(Distribution::from_name("gird"), None);
        let more = [
            ("owen-sobol", Distribution::Sobol),
            ("z-sobol", Distribution::Zsobol),
            ("pmj", Distribution::Pmj02),
            ("CUSTOM", Distribution::Custom),
        ];
        for (name, d) in more {
            assert_eq!(Distribution::from_name(name), Some(d), "{name}");
        }
        let err = "gird".parse::<Distribution>().err().map(|e| e.to_string());
        assert!(err.is_some_and(|e| e.contains("gird") && e.contains("semi-jitter")));
    }

    #[test]
    fn non_square_counts_warn_for_cell_distributions_only() {
        assert_eq!(Distribution::Grid.non_square_warning(16), None);
        assert_eq!(Distribution::Grid.non_square_warning(1), None);
        assert_eq!(Distribution::Poisson.non_square_warning(10), None);
        let w = Distribution::Jitter
            .non_square_warning(10)
            .unwrap_or_default();
        assert!(
            w.contains("10") && w.contains("16") && w.contains("4x4") && w.contains(" 9 "),
            "{w}"
        );
        assert!(Distribution::SemiJitter
            .non_square_warning(usize::MAX)
            .is_some());
    }

    #[test]
    fn square_side_is_the_ceiling_of_the_root() {
        let cases = [
            (0, 0),
            (1, 1),
            (2, 2),
            (4, 2),
            (5, 3),
            (9, 3),
            (10, 4),
            (1024, 32),
        ];
        for (count, s) in cases {
            assert_eq!(square_side(count), s, "{count}");
        }
        assert_eq!(square_side(usize::MAX), 1 << (usize::BITS / 2));
    }

    /// The serde names are the names users write, and the lists are the
    /// list's: `custom` selectable only, the thesis's six first.
    #[test]
    fn serde_names_and_lists() {
        for d in Distribution::SELECTABLE {
            let json = serde_json::to_string(&d).unwrap_or_default();
            assert_eq!(json, format!("\"{}\"", d.name()));
        }
        assert_eq!(Distribution::ALL.len(), 12);
        assert!(!Distribution::ALL.contains(&Distribution::Custom));
        assert_eq!(Distribution::SELECTABLE[..12], Distribution::ALL);
        assert_eq!(Distribution::THESIS[..], Distribution::ALL[..6]);
    }
}
