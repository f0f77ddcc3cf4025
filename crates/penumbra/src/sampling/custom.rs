//! `custom`: point sets the user brings, from a file (see the scene
//! format's `points` key) or, in Python, from an array or a function.
//!
//! A [`PointTable`] holds one or more *sets* of points in the unit square
//! `[0, 1)^2`; sets may differ in size. A ray set of `N` points is made
//! from the table as follows:
//!
//! 1. **Which sets.** The sets of exactly `N` points if the table has
//!    some; else the smallest sets larger than `N`, of which the first `N`
//!    points are used (a progressive set, such as a prefix of a
//!    low-discrepancy sequence, keeps its spread); else, when every set is
//!    smaller than `N`, the largest ones, several of them one after
//!    another until there are `N` points.
//! 2. **A random set** of those, chosen uniformly from the ray set's stream.
//! 3. **A random toroidal shift** (Cranley–Patterson rotation): one offset
//!    uniform in `[0, 1)^2` is added to every point of the set, modulo 1.
//!    Each set used for a ray set gets its own offset.
//!
//! The shift is what keeps the estimate unbiased: whatever the table holds,
//! every point of a shifted set is uniform over the square, while the
//! distances between the points of a set (measured on the torus, where the
//! square's opposite edges meet) are kept, so a well-spread set stays well
//! spread. It also keeps neighbouring pixels from repeating one pattern,
//! which would alias. A table of a single set is fine for that reason.
//!
//! Shutter times (one dimension) are the first coordinates of the same
//! points.
//!
//! [`PointTable::NONE`] holds no set: a ray set drawn from it is `N`
//! independent uniform points (as if the table were the one point
//! `(0.5, 0.5)`). It is what the distribution falls back on where no
//! table is given, such as `Distribution::generate`; the front ends refuse
//! a render or a `samples` command that selects `custom` without points.

use std::collections::HashMap;
use std::fmt;

use super::Rng;
use crate::math::Vec2;

/// Most points a table holds in all: 4 M points (32 MiB as `f32`).
pub const MAX_POINTS: usize = 1 << 22;

/// The user's point sets; see the [module docs](self).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointTable {
    /// The sets grouped by size, smallest first.
    groups: Vec<Group>,
}

/// The sets of one size, one after another.
#[derive(Clone, Debug, PartialEq)]
struct Group {
    size: usize,
    points: Vec<Vec2>,
}

impl Group {
    fn sets(&self) -> usize {
        self.points.len() / self.size
    }
}

/// What is wrong with a point table: the set and point it is about, when
/// it is about one, and what.
#[derive(Clone, Debug, PartialEq)]
pub struct PointsError {
    /// The set (from 0) and, within it, the point (from 0).
    pub at: Option<(usize, Option<usize>)>,
    pub message: String,
}

impl PointsError {
    pub fn new(message: impl Into<String>) -> PointsError {
        PointsError {
            at: None,
            message: message.into(),
        }
    }

    fn at(set: usize, point: Option<usize>, message: impl Into<String>) -> PointsError {
        PointsError {
            at: Some((set, point)),
            message: message.into(),
        }
    }
}

impl fmt::Display for PointsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.at {
            Some((set, Some(point))) => write!(f, "set {set}, point {point}: ")?,
            Some((set, None)) => write!(f, "set {set}: ")?,
            None => {}
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for PointsError {}

impl PointTable {
    /// The table with no set: independent uniform points.
    pub const NONE: PointTable = PointTable { groups: Vec::new() };

    /// A table of `sets`, each a list of `[x, y]` points, after checking
    /// that there is at least one set, that no set is empty, that every
    /// coordinate is a number in `[0, 1)` and that there are at most
    /// [`MAX_POINTS`] points in all. A number that rounds to 1 as `f32`
    /// is kept just below 1.
    pub fn new<S>(sets: impl IntoIterator<Item = S>) -> Result<PointTable, PointsError>
    where
        S: AsRef<[[f64; 2]]>,
    {
        let mut groups: Vec<Group> = Vec::new();
        // Group of each size: a hostile table may hold thousands of sizes.
        let mut by_size: HashMap<usize, usize> = HashMap::new();
        let mut total = 0usize;
        for (s, set) in sets.into_iter().enumerate() {
            let set = set.as_ref();
            if set.is_empty() {
                return Err(PointsError::at(s, None, "a set needs at least one point"));
            }
            total = total.saturating_add(set.len());
            if total > MAX_POINTS {
                return Err(PointsError::new(format!(
                    "more than {MAX_POINTS} points in all; a table of that size is never needed"
                )));
            }
            let i = *by_size.entry(set.len()).or_insert_with(|| {
                groups.push(Group {
                    size: set.len(),
                    points: Vec::new(),
                });
                groups.len() - 1
            });
            let group = &mut groups[i];
            for (i, p) in set.iter().enumerate() {
                let (x, y) = (coordinate(p[0]), coordinate(p[1]));
                match (x, y) {
                    (Some(x), Some(y)) => group.points.push(Vec2::new(x, y)),
                    _ => {
                        let message = format!(
                            "({}, {}) is not in the unit square: coordinates must be numbers in [0, 1)",
                            p[0], p[1]
                        );
                        return Err(PointsError::at(s, Some(i), message));
                    }
                }
            }
        }
        if groups.is_empty() {
            return Err(PointsError::new(
                "no point sets: give at least one set of points",
            ));
        }
        groups.sort_by_key(|g| g.size);
        Ok(PointTable { groups })
    }

    /// Whether the table holds no set ([`NONE`](Self::NONE)).
    pub fn is_none(&self) -> bool {
        self.groups.is_empty()
    }

    /// The sizes of its sets, smallest first, with how many sets have each.
    pub fn sizes(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.groups.iter().map(|g| (g.size, g.sets()))
    }

    /// The points of a ray set of `count`, in `[0, 1)^2`, given to `emit`
    /// in the set's own order; see the [module docs](self).
    pub fn fill(&self, count: usize, rng: &mut Rng, mut emit: impl FnMut(Vec2)) {
        let Some(group) = self.group(count) else {
            (0..count).for_each(|_| emit(Vec2::new(rng.next_f32(), rng.next_f32())));
            return;
        };
        let mut left = count;
        while left > 0 {
            let set = rng.below(group.sets() as u32) as usize;
            let shift = Vec2::new(rng.next_f32(), rng.next_f32());
            let take = left.min(group.size);
            let points = &group.points[set * group.size..][..take];
            for &p in points {
                emit(Vec2::new(wrap(p.x + shift.x), wrap(p.y + shift.y)));
            }
            left -= take;
        }
    }

    /// The sets a ray set of `count` draws from: those of exactly `count`
    /// points, else the smallest larger ones, else the largest.
    fn group(&self, count: usize) -> Option<&Group> {
        let larger = self.groups.iter().find(|g| g.size >= count);
        larger.or(self.groups.last())
    }
}

/// `x` as an `f32` in `[0, 1)`, if it is a number in `[0, 1)`.
fn coordinate(x: f64) -> Option<f32> {
    if !(0.0..1.0).contains(&x) {
        return None;
    }
    Some((x as f32).min(ONE_BELOW))
}

/// The largest `f32` below 1.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// `x` modulo 1 for `x` in `[0, 2)`.
#[inline]
fn wrap(x: f32) -> f32 {
    let x = if x >= 1.0 { x - 1.0 } else { x };
    x.min(ONE_BELOW)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> Vec<[f64; 2]> {
        let s = (n as f64).sqrt() as usize;
        let c = |i: usize| (i as f64 + 0.5) / s as f64;
        (0..n).map(|k| [c(k % s), c(k / s)]).collect()
    }

    fn torus_gap(a: Vec2, b: Vec2) -> f32 {
        let d = |u: f32, v: f32| {
            let d = (u - v).abs();
            d.min(1.0 - d)
        };
        d(a.x, b.x).hypot(d(a.y, b.y))
    }

    #[test]
    fn sets_keep_their_shape_under_the_shift() {
        let table = PointTable::new([grid(16)]).unwrap();
        let mut rng = Rng::new(3);
        for _ in 0..100 {
            let mut out = Vec::new();
            table.fill(16, &mut rng, |p| out.push(p));
            assert_eq!(out.len(), 16);
            // A shifted grid: every point keeps its torus distance to the first.
            for (p, q) in out.iter().zip(grid(16)) {
                let q0 = grid(16)[0];
                let want = torus_gap(
                    Vec2::new(q[0] as f32, q[1] as f32),
                    Vec2::new(q0[0] as f32, q0[1] as f32),
                );
                assert!((torus_gap(*p, out[0]) - want).abs() < 1e-5);
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            }
        }
    }

    #[test]
    fn counts_pick_the_documented_sets() {
        let table = PointTable::new([grid(4), grid(16), grid(64), grid(16)]).unwrap();
        assert_eq!(
            table.sizes().collect::<Vec<_>>(),
            [(4, 1), (16, 2), (64, 1)]
        );
        assert_eq!(table.group(16).unwrap().size, 16);
        assert_eq!(table.group(5).unwrap().size, 16);
        assert_eq!(table.group(1).unwrap().size, 4);
        assert_eq!(table.group(65).unwrap().size, 64);
        let mut rng = Rng::new(9);
        for count in [0, 1, 3, 16, 17, 64, 65, 200] {
            let mut out = vec![Vec2::ZERO];
            table.fill(count, &mut rng, |p| out.push(p));
            assert_eq!(out.len(), count + 1, "count {count}");
        }
    }

    /// Both sets of a size are chosen, about equally often.
    #[test]
    fn sets_are_chosen_at_random() {
        let a = vec![[0.0, 0.0], [0.5, 0.0]];
        let b = vec![[0.0, 0.0], [0.0, 0.5]];
        let table = PointTable::new([a, b]).unwrap();
        let mut rng = Rng::new(1);
        let mut first = 0;
        for _ in 0..2000 {
            let mut out = Vec::new();
            table.fill(2, &mut rng, |p| out.push(p));
            let dx = (out[1].x - out[0].x).abs();
            first += usize::from((dx - 0.5).abs() < 1e-5);
        }
        assert!((900..1100).contains(&first), "{first}");
    }

    /// Every point is uniform over the square in expectation (χ² over an
    /// 8×8 grid of bins, 99.9% critical value for 63 degrees of freedom).
    #[test]
    fn points_are_uniform() {
        let table = PointTable::new([grid(4)]).unwrap();
        let mut rng = Rng::new(5);
        let mut bins = [0u32; 64];
        let sets = 4000;
        for _ in 0..sets {
            let mut out = Vec::new();
            table.fill(4, &mut rng, |p| out.push(p));
            let p = out[0];
            bins[(p.y * 8.0) as usize * 8 + (p.x * 8.0) as usize] += 1;
        }
        let e = sets as f64 / 64.0;
        let chi2: f64 = bins.iter().map(|&o| (o as f64 - e).powi(2) / e).sum();
        assert!(chi2 < 103.4, "chi2 {chi2}");
    }

    #[test]
    fn bad_tables_are_refused_with_their_place() {
        let no_sets: [Vec<[f64; 2]>; 0] = [];
        assert!(PointTable::new(no_sets)
            .unwrap_err()
            .message
            .contains("no point sets"));
        let e = PointTable::new([vec![[0.5, 0.5]], vec![]]).unwrap_err();
        assert_eq!(e.to_string(), "set 1: a set needs at least one point");
        for bad in [1.0, -0.1, f64::NAN, f64::INFINITY] {
            let e = PointTable::new([vec![[0.5, 0.5], [0.2, bad]]]).unwrap_err();
            assert_eq!(e.at, Some((0, Some(1))), "{bad}");
            assert!(e.message.contains("[0, 1)"));
        }
        let huge = vec![[0.5, 0.5]; MAX_POINTS / 2 + 1];
        let e = PointTable::new([huge.clone(), huge]).unwrap_err();
        assert!(e.message.contains("points in all"));
    }

    #[test]
    fn near_one_stays_below_one() {
        let table = PointTable::new([vec![[1.0 - 1e-12, 0.0]]]).unwrap();
        assert!(table.groups[0].points[0].x < 1.0);
    }

    #[test]
    fn no_table_gives_uniform_points() {
        let mut out = Vec::new();
        PointTable::NONE.fill(8, &mut Rng::new(2), |p| out.push(p));
        assert_eq!(out.len(), 8);
        assert!(out.windows(2).all(|w| w[0] != w[1]));
    }
}
