//! Shaft culling (Haines and Wallace, "Shaft Culling for Efficient Ray-Traced
//! Radiosity", 1991): the convex hull of two boxes, tested against BVH boxes
//! so that a whole set of segments between them is culled at once.
//!
//! A shadow set of the distributed tracer is up to hundreds of segments from
//! one shading point to points of one light. Every one of them lies in the
//! hull of the box of their origins and the box of their targets, so a BVH
//! leaf whose box misses that hull can hold no occluder of any of them. The
//! tracer gathers the leaves inside the shaft once per set
//! ([`TriangleBvh::gather`](super::TriangleBvh::gather)) and tests each ray
//! against those leaves only; for a point of the ground in full light the
//! list is empty and the set costs no traversal at all.
//!
//! # The hull
//! The hull of two axis-aligned boxes is bounded by faces of their union box
//! and by planes parallel to one axis, each through an edge of either box
//! (a face spanned by two non-parallel box edges is perpendicular to the
//! third axis, hence a face of the union box). Projected along an axis, the
//! planes of the second kind are the edges of the 2D convex hull of the two
//! projected rectangles; so the shaft is the union box cut by the slanted
//! edges of three 2D hulls. Both boxes are first grown by a small margin
//! relative to the coordinates' size, so that rounding in the plane tests
//! can only keep a box, never cull one that touches the hull.

use crate::math::{Aabb, Vec3};
use glam::Vec4;

/// A plane parallel to one axis: inside is `na · x[a] + nb · x[b] <= d` for
/// the other two axes `a` and `b` (given to [`Plane::new`]). `ia` and `ib`
/// say which of a box's six bounds (`lo[0..3]`, then `hi[0..3]`) is its
/// corner farthest inside the plane along `a` and `b`, so that the box test
/// needs no choice per plane.
#[derive(Clone, Copy, Debug, Default)]
struct Plane {
    ia: u8,
    ib: u8,
    na: f32,
    nb: f32,
    d: f32,
}

impl Plane {
    fn new(a: usize, b: usize, na: f32, nb: f32, d: f32) -> Plane {
        // The corner farthest inside: the low side where the normal is positive.
        let side = |axis: usize, n: f32| (axis + if n > 0.0 { 0 } else { 3 }) as u8;
        Plane {
            ia: side(a, na),
            ib: side(b, nb),
            na,
            nb,
            d,
        }
    }
}

/// At most this many slanted planes: three projections, whose hull of two
/// rectangles has at most four slanted edges each.
const MAX_PLANES: usize = 12;

/// The convex hull of two boxes; see the module docs.
#[derive(Clone, Copy, Debug)]
pub struct Shaft {
    bounds: Aabb,
    planes: [Plane; MAX_PLANES],
    len: usize,
}

/// Relative size of the margin the boxes are grown by.
const MARGIN: f32 = 1e-5;

/// +1 for a box's high side along an axis, -1 for its low side.
fn sign(high: bool) -> f32 {
    if high {
        1.0
    } else {
        -1.0
    }
}

impl Shaft {
    /// The hull of boxes `a` and `b` (grown by a small margin); `None` if
    /// either is empty or not finite.
    #[inline(always)]
    pub fn new(a: Aabb, b: Aabb) -> Option<Shaft> {
        let finite = |b: &Aabb| b.min.is_finite() && b.max.is_finite() && b.min.cmple(b.max).all();
        if !(finite(&a) && finite(&b)) {
            return None;
        }
        let u = a.union(b);
        let size = u.min.abs().max(u.max.abs()).max_element() + (u.max - u.min).max_element();
        let m = Vec3::splat(MARGIN * size.max(1e-6));
        let (a, b) = (
            Aabb::new(a.min - m, a.max + m),
            Aabb::new(b.min - m, b.max + m),
        );
        let mut shaft = Shaft {
            bounds: a.union(b),
            planes: [Plane::default(); MAX_PLANES],
            len: 0,
        };
        let bounds = |r: &Aabb| [r.min.to_array(), r.max.to_array()];
        let (a, b) = (bounds(&a), bounds(&b));
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            shaft.add_hull_edges(&a, &b, i, j);
        }
        Some(shaft)
    }

    /// Adds the slanted edges of the 2D hull of both boxes (`[min, max]`)
    /// projected on axes (i, j): at a corner direction (a side of each axis)
    /// where one box reaches farther along axis i and the other farther
    /// along axis j, the hull has an edge from the one box's corner to the
    /// other's (Haines and Wallace's plane construction). Its line has both
    /// boxes on one side.
    fn add_hull_edges(&mut self, a: &[[f32; 3]; 2], b: &[[f32; 3]; 2], i: usize, j: usize) {
        for (hi_i, hi_j) in [(true, true), (true, false), (false, true), (false, false)] {
            let (si, sj) = (sign(hi_i), sign(hi_j));
            let corner = |r: &[[f32; 3]; 2]| (r[usize::from(hi_i)][i], r[usize::from(hi_j)][j]);
            let (p, q) = (corner(a), corner(b));
            // Signed reach beyond the other box along each axis.
            let (dx, dy) = (si * (q.0 - p.0), sj * (q.1 - p.1));
            if !((dx > 0.0 && dy < 0.0) || (dx < 0.0 && dy > 0.0)) || self.len == MAX_PLANES {
                // One box reaches farther on both axes (or as far): its
                // corner is a hull vertex, and the edges there are axis-aligned.
                continue;
            }
            // The normal points away from both boxes: toward the corner direction.
            let len = (dx * dx + dy * dy).sqrt();
            let (na, nb) = (si * dy.abs() / len, sj * dx.abs() / len);
            // Both corners lie on the line in exact arithmetic; the farther
            // one keeps rounding from pulling it inward.
            let d = (na * p.0 + nb * p.1).max(na * q.0 + nb * q.1);
            self.planes[self.len] = Plane::new(i, j, na, nb, d);
            self.len += 1;
        }
    }

    /// Whether `b` may overlap the shaft (false only if it surely does not).
    pub fn overlaps(&self, b: &Aabb) -> bool {
        let lo = b.min.to_array().map(Vec4::splat);
        let hi = b.max.to_array().map(Vec4::splat);
        self.overlaps4(&lo, &hi) & 1 != 0
    }

    /// Four boxes at once, one per lane (`lo[axis]`, `hi[axis]`): a bit mask
    /// of those that may overlap the shaft. Empty boxes (min > max) never do.
    #[inline(always)]
    pub fn overlaps4(&self, lo: &[Vec4; 3], hi: &[Vec4; 3]) -> u32 {
        let mut inside = lo[0].cmple(hi[0]) & lo[1].cmple(hi[1]) & lo[2].cmple(hi[2]);
        for axis in 0..3 {
            inside &= lo[axis].cmple(Vec4::splat(self.bounds.max[axis]));
            inside &= hi[axis].cmpge(Vec4::splat(self.bounds.min[axis]));
        }
        let bounds = [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]];
        for p in &self.planes[..self.len] {
            // The box's corner farthest inside the plane.
            let near = Vec4::splat(p.na) * bounds[usize::from(p.ia)]
                + Vec4::splat(p.nb) * bounds[usize::from(p.ib)];
            inside &= near.cmple(Vec4::splat(p.d));
        }
        inside.bitmask()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    fn rand_box(r: &mut Rng, size: f32) -> Aabb {
        let c = Vec3::new(r.next_f32(), r.next_f32(), r.next_f32()) * 10.0 - 5.0;
        let e = Vec3::new(r.next_f32(), r.next_f32(), r.next_f32()) * size;
        // Some boxes are flat or points, like a rectangle light or one origin.
        let e = e * Vec3::new(
            f32::from(r.next_f32() > 0.3),
            f32::from(r.next_f32() > 0.3),
            1.0,
        );
        Aabb::new(c - e, c + e)
    }

    fn point_in(r: &mut Rng, b: &Aabb) -> Vec3 {
        b.min + (b.max - b.min) * Vec3::new(r.next_f32(), r.next_f32(), r.next_f32())
    }

    /// Every small box around a point of a segment between the two boxes
    /// overlaps the shaft.
    #[test]
    fn segments_between_the_boxes_are_inside() {
        let mut r = Rng::new(11);
        for _ in 0..2000 {
            let (a, b) = (rand_box(&mut r, 2.0), rand_box(&mut r, 3.0));
            let shaft = Shaft::new(a, b).expect("finite boxes");
            for _ in 0..20 {
                let (p, q) = (point_in(&mut r, &a), point_in(&mut r, &b));
                let x = p.lerp(q, r.next_f32());
                assert!(shaft.overlaps(&Aabb::new(x, x)), "{a:?} {b:?} {x}");
            }
        }
    }

    /// Boxes far from both boxes and the segments between them are culled,
    /// and every corner of the union box that is not in the hull is outside
    /// a plane.
    #[test]
    fn culls_what_lies_outside() {
        // A point below the centre of a flat square: a pyramid.
        let a = Aabb::new(Vec3::ZERO, Vec3::ZERO);
        let b = Aabb::new(Vec3::new(-1.0, 4.0, -1.0), Vec3::new(1.0, 4.0, 1.0));
        let shaft = Shaft::new(a, b).expect("finite boxes");
        let at = |x: f32, y: f32, z: f32| {
            let p = Vec3::new(x, y, z);
            shaft.overlaps(&Aabb::new(p - 0.01, p + 0.01))
        };
        assert!(at(0.0, 2.0, 0.0));
        assert!(at(0.45, 2.0, 0.45));
        assert!(
            !at(0.8, 2.0, 0.0),
            "outside the pyramid, inside the union box"
        );
        assert!(!at(0.0, 1.0, -0.9));
        assert!(!at(0.0, 5.0, 0.0), "beyond the light");
        assert!(!at(3.0, 2.0, 0.0));
        // Empty boxes never overlap.
        assert!(!shaft.overlaps(&Aabb::EMPTY));
    }

    #[test]
    fn rejects_non_finite_and_empty_boxes() {
        let p = Aabb::new(Vec3::ZERO, Vec3::ONE);
        assert!(Shaft::new(Aabb::EMPTY, p).is_none());
        assert!(Shaft::new(p, Aabb::new(Vec3::ZERO, Vec3::splat(f32::NAN))).is_none());
        assert!(Shaft::new(p, Aabb::new(Vec3::ZERO, Vec3::splat(f32::INFINITY))).is_none());
    }

    /// A cross of two flat boxes: the hull is an octagon in projection, so
    /// the four corner regions between the arms are culled.
    #[test]
    fn cross_of_two_boxes_is_an_octagon() {
        let a = Aabb::new(Vec3::new(-1.0, -5.0, 0.0), Vec3::new(1.0, 5.0, 0.0));
        let b = Aabb::new(Vec3::new(-5.0, -1.0, 0.0), Vec3::new(5.0, 1.0, 0.0));
        let shaft = Shaft::new(a, b).expect("finite boxes");
        assert_eq!(shaft.len, 4);
        let at =
            |x: f32, y: f32| shaft.overlaps(&Aabb::new(Vec3::new(x, y, 0.0), Vec3::new(x, y, 0.0)));
        for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
            assert!(at(2.9 * sx, 2.9 * sy), "on the bridge's inner side");
            assert!(!at(3.1 * sx, 3.1 * sy), "beyond the bridge");
        }
    }
}
