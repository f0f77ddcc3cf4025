//! Watertight ray–triangle intersection.
//!
//! This is the algorithm of "Watertight Ray/Triangle Intersection" (JCGT 2013).
//! The ray is made the +z axis of a sheared frame (translate to the origin,
//! permute axes so that the dominant direction component is z, shear x and y
//! by `-d.x/d.z`, `-d.y/d.z`). Each vertex is transformed on its own, so a
//! vertex shared by neighbouring triangles gets bit-identical sheared
//! coordinates, and the 2D edge functions of a shared edge are computed from the
//! same numbers in every triangle that contains it. A ray can therefore not slip
//! between two triangles of a closed mesh through an edge or a vertex, which the
//! common edge-vector/determinant test (computing barycentrics per triangle with
//! their own rounding) does not guarantee. When an edge function rounds to exactly zero it
//! is recomputed in `f64`, so its sign is the true one and the tie-breaking is
//! consistent between the two triangles sharing the edge.
//!
//! There is no backface culling: a path tracer needs hits from both sides
//! (refraction, two-sided emitters), and culling is cheap to do in the caller.

use crate::math::{Ray, Vec3};

/// Precomputed per-ray data for the watertight test (shear constants, axis permutation).
///
/// Computing it once per ray, not per triangle, removes three divisions and the
/// dominant-axis search from the inner loop of the BVH traversal.
#[derive(Clone, Copy, Debug)]
pub struct RayShear {
    /// Axis permutation: `kz` is the dominant axis of the direction, `kx` and
    /// `ky` the other two, swapped when `d[kz] < 0` to keep the winding (and
    /// hence the sign convention of the edge functions) unchanged.
    pub(crate) kx: usize,
    pub(crate) ky: usize,
    pub(crate) kz: usize,
    /// Shear constants `d[kx]/d[kz]`, `d[ky]/d[kz]` and the scale `1/d[kz]`
    /// that makes the sheared z coordinate the ray parameter `t`.
    pub(crate) sx: f32,
    pub(crate) sy: f32,
    pub(crate) sz: f32,
}

impl RayShear {
    /// Shear constants for `ray`. A zero direction gives non-finite constants,
    /// for which [`intersect_triangle`] reports no hit.
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let d = ray.dir;
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let mut kx = if kz == 2 { 0 } else { kz + 1 };
        let mut ky = if kx == 2 { 0 } else { kx + 1 };
        let d = d.to_array();
        let dz = d[kz];
        if dz < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        RayShear {
            kx,
            ky,
            kz,
            sx: d[kx] / dz,
            sy: d[ky] / dz,
            sz: 1.0 / dz,
        }
    }

    /// Vertex `p` in the sheared ray frame, before scaling z: (x, y, z).
    /// The arrays are padded to four entries and indices masked with `& 3`,
    /// which lets the compiler drop the bounds checks (the permutation entries
    /// are always below 3, so the padding is never read).
    #[inline(always)]
    fn transform(&self, p: Vec3, origin: Vec3) -> (f32, f32, f32) {
        let a = p - origin;
        let a = [a.x, a.y, a.z, 0.0];
        let z = a[self.kz & 3];
        (
            a[self.kx & 3] - self.sx * z,
            a[self.ky & 3] - self.sy * z,
            z,
        )
    }
}

/// Returns (t, b1, b2) with barycentrics b0 = 1-b1-b2 for p0, b1 for p1, b2 for p2, when tmin < t < tmax.
///
/// Degenerate (zero-area) triangles, rays in the plane of the triangle and a zero
/// ray direction give `None`; the result is never NaN or infinite.
#[inline(always)]
pub fn intersect_triangle(
    ray: &Ray,
    shear: &RayShear,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32, f32)> {
    let (ax, ay, az) = shear.transform(p0, ray.origin);
    let (bx, by, bz) = shear.transform(p1, ray.origin);
    let (cx, cy, cz) = shear.transform(p2, ray.origin);

    // Scaled barycentrics: 2D edge functions of the edges opposite p0, p1, p2.
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;

    // An edge function that rounded to exactly zero decides between the two
    // triangles sharing the edge; recompute it in double precision (products of
    // two f32 are exact in f64) so the sign is right and consistent.
    if u == 0.0 || v == 0.0 || w == 0.0 {
        (u, v, w) = edge_functions_f64([ax, ay, bx, by, cx, cy]);
    }

    // Mixed signs: the ray passes outside one of the edges. Points on an edge
    // (a zero) are accepted, so both neighbours may report the edge; never neither.
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    // Zero determinant: zero-area triangle or a ray in its plane. A NaN
    // determinant (zero or non-finite direction) fails the range test below.
    if det == 0.0 {
        return None;
    }
    let t_scaled = shear.sz * (u * az + v * bz + w * cz);
    let t = t_scaled / det;
    if !(t > tmin && t < tmax) {
        return None;
    }
    let b1 = v / det;
    let b2 = w / det;
    if !(t.is_finite() && b1.is_finite() && b2.is_finite()) {
        return None;
    }
    Some((t, b1, b2))
}

/// The three edge functions in double precision, out of line: it is rare, and
/// keeping it out of the hot path lets the common case inline into the BVH
/// traversal loop.
#[cold]
#[inline(never)]
pub(crate) fn edge_functions_f64([ax, ay, bx, by, cx, cy]: [f32; 6]) -> (f32, f32, f32) {
    let (ax, ay, bx, by, cx, cy) = (
        f64::from(ax),
        f64::from(ay),
        f64::from(bx),
        f64::from(by),
        f64::from(cx),
        f64::from(cy),
    );
    (
        (cx * by - cy * bx) as f32,
        (ax * cy - ay * cx) as f32,
        (bx * ay - by * ax) as f32,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The common edge-vector/determinant test, in f64: an independent oracle.
    fn determinant_test(ray: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<(f64, f64, f64)> {
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let (p0, p1, p2) = (p0.as_dvec3(), p1.as_dvec3(), p2.as_dvec3());
        let e1 = p1 - p0;
        let e2 = p2 - p0;
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-300 {
            return None;
        }
        let inv = 1.0 / det;
        let s = o - p0;
        let b1 = s.dot(pv) * inv;
        let q = s.cross(e1);
        let b2 = d.dot(q) * inv;
        if b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0 {
            return None;
        }
        Some((e2.dot(q) * inv, b1, b2))
    }

    fn hit(ray: &Ray, p: [Vec3; 3], tmin: f32, tmax: f32) -> Option<(f32, f32, f32)> {
        intersect_triangle(ray, &RayShear::new(ray), p[0], p[1], p[2], tmin, tmax)
    }

    fn rand_vec(r: &mut Rng, s: f32) -> Vec3 {
        Vec3::new(r.range(-s, s), r.range(-s, s), r.range(-s, s))
    }

    #[test]
    fn ray_through_centroid_has_equal_barycentrics() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
        ];
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let ray = Ray::new(c + Vec3::new(0.0, 0.0, 2.0), -Vec3::Z, 0.0);
        let (t, b1, b2) = hit(&ray, p, 0.0, f32::INFINITY).expect("centroid ray must hit");
        assert!((t - 2.0).abs() < 1e-6, "t = {t}");
        assert!((b1 - 1.0 / 3.0).abs() < 1e-6 && (b2 - 1.0 / 3.0).abs() < 1e-6);
        // The barycentrics reconstruct the hit point.
        let q = (1.0 - b1 - b2) * p[0] + b1 * p[1] + b2 * p[2];
        assert!((q - ray.at(t)).length() < 1e-5);
        // Vertex hits give the matching unit barycentric.
        let r1 = Ray::new(
            p[1] + Vec3::new(-0.5, 0.25, 1.0),
            Vec3::new(0.5, -0.25, -1.0),
            0.0,
        );
        let (t, b1, b2) = hit(&r1, p, 0.0, f32::INFINITY).expect("vertex ray must hit");
        assert!((t - 1.0).abs() < 1e-6 && (b1 - 1.0).abs() < 1e-6 && b2.abs() < 1e-6);
    }

    #[test]
    fn range_is_open_and_respected() {
        let p = [
            Vec3::new(-1.0, -1.0, 5.0),
            Vec3::new(1.0, -1.0, 5.0),
            Vec3::new(0.0, 1.0, 5.0),
        ];
        let ray = Ray::new(Vec3::ZERO, Vec3::Z, 0.0);
        assert!(hit(&ray, p, 0.0, 10.0).is_some());
        assert!(hit(&ray, p, 0.0, 5.0).is_none(), "t == tmax is excluded");
        assert!(hit(&ray, p, 0.0, 4.9).is_none());
        assert!(hit(&ray, p, 5.0, 10.0).is_none(), "t == tmin is excluded");
        assert!(hit(&ray, p, 5.1, 10.0).is_none());
        // Behind the origin.
        let back = Ray::new(Vec3::ZERO, -Vec3::Z, 0.0);
        assert!(hit(&back, p, 0.0, f32::INFINITY).is_none());
        assert!(hit(&back, p, f32::NEG_INFINITY, f32::INFINITY).is_some());
        // The direction need not be unit length: t scales inversely.
        let long = Ray::new(Vec3::ZERO, 2.0 * Vec3::Z, 0.0);
        let (t, _, _) = hit(&long, p, 0.0, f32::INFINITY).expect("hit");
        assert_eq!(t, 2.5);
    }

    #[test]
    fn backfaces_are_hit() {
        let p = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let front = Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, 0.0);
        let back = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 0.0);
        let a = hit(&front, p, 0.0, f32::INFINITY).expect("front");
        let b = hit(&back, p, 0.0, f32::INFINITY).expect("back");
        assert_eq!(a, b);
        // Both windings of the same triangle.
        let q = [p[0], p[2], p[1]];
        let c = hit(&front, q, 0.0, f32::INFINITY).expect("flipped winding");
        assert_eq!(c.0, a.0);
        assert_eq!((c.1, c.2), (a.2, a.1));
    }

    #[test]
    fn degenerate_triangles_never_hit_and_never_nan() {
        let mut r = Rng::new(11);
        for i in 0..20_000 {
            let a = rand_vec(&mut r, 2.0);
            let b = rand_vec(&mut r, 2.0);
            let tri = match i % 4 {
                0 => [a, a, a],
                1 => [a, b, a + 0.5 * (b - a)],
                2 => [a, b, b],
                _ => [a, a + 2.0 * (b - a), b],
            };
            let o = rand_vec(&mut r, 4.0);
            // Aim at a point of the degenerate triangle, and at random.
            let dir = if i % 2 == 0 {
                tri[(i / 2) % 3] - o
            } else {
                rand_vec(&mut r, 1.0)
            };
            let ray = Ray::new(o, dir, 0.0);
            let got = hit(&ray, tri, f32::NEG_INFINITY, f32::INFINITY);
            // Collinear points in f32 may not be exactly collinear after
            // rounding: then the triangle has a tiny true area, and a hit must
            // at least be finite and consistent.
            if let Some((t, b1, b2)) = got {
                assert!(t.is_finite() && b1.is_finite() && b2.is_finite());
                assert!(i % 4 == 1 || i % 4 == 3, "exactly degenerate {tri:?} hit");
            }
        }
        // Exactly degenerate ones, by construction in exact arithmetic.
        let ray = Ray::new(Vec3::new(0.5, 0.5, 1.0), -Vec3::Z, 0.0);
        let line = [
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
        ];
        assert!(hit(&ray, line, f32::NEG_INFINITY, f32::INFINITY).is_none());
        let point = [Vec3::new(0.5, 0.5, 0.0); 3];
        assert!(hit(&ray, point, f32::NEG_INFINITY, f32::INFINITY).is_none());
        // A zero direction is not a ray.
        let zero = Ray::new(Vec3::ZERO, Vec3::ZERO, 0.0);
        let tri = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        assert!(hit(&zero, tri, f32::NEG_INFINITY, f32::INFINITY).is_none());
        // A ray in the plane of the triangle.
        let inplane = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X, 0.0);
        assert!(hit(&inplane, tri, f32::NEG_INFINITY, f32::INFINITY).is_none());
    }

    #[test]
    fn agrees_with_determinant_test_away_from_edges() {
        let mut r = Rng::new(5);
        let (mut hits, mut checked) = (0, 0);
        for _ in 0..200_000 {
            let tri = [
                rand_vec(&mut r, 1.0),
                rand_vec(&mut r, 1.0),
                rand_vec(&mut r, 1.0),
            ];
            let o = rand_vec(&mut r, 3.0);
            let ray = Ray::new(o, rand_vec(&mut r, 1.0), 0.0);
            let Some((t, b1, b2)) = determinant_test(&ray, tri[0], tri[1], tri[2]) else {
                // A miss by a clear margin must be a miss.
                continue;
            };
            let b0 = 1.0 - b1 - b2;
            let margin = b0.min(b1).min(b2);
            let got = hit(&ray, tri, f32::NEG_INFINITY, f32::INFINITY);
            if margin > 1e-3 {
                checked += 1;
                let (gt, g1, g2) = got.expect("clear hit missed");
                hits += 1;
                let scale = 1.0 + t.abs();
                assert!((f64::from(gt) - t).abs() < 1e-3 * scale, "t {gt} vs {t}");
                assert!((f64::from(g1) - b1).abs() < 1e-3 && (f64::from(g2) - b2).abs() < 1e-3);
            }
        }
        assert!(checked > 1000 && hits == checked);
        // And clear misses agree too.
        let mut r = Rng::new(6);
        for _ in 0..200_000 {
            let tri = [
                rand_vec(&mut r, 1.0),
                rand_vec(&mut r, 1.0),
                rand_vec(&mut r, 1.0),
            ];
            let ray = Ray::new(rand_vec(&mut r, 3.0), rand_vec(&mut r, 1.0), 0.0);
            let mt = determinant_test(&ray, tri[0], tri[1], tri[2]);
            let near_edge = {
                // Barycentrics of the plane crossing, hit or not.
                let e1 = (tri[1] - tri[0]).as_dvec3();
                let e2 = (tri[2] - tri[0]).as_dvec3();
                let d = ray.dir.as_dvec3();
                let pv = d.cross(e2);
                let det = e1.dot(pv);
                let s = (ray.origin - tri[0]).as_dvec3();
                let b1 = s.dot(pv) / det;
                let b2 = d.dot(s.cross(e1)) / det;
                let m = (1.0 - b1 - b2).abs().min(b1.abs()).min(b2.abs());
                det.abs() < 1e-6 || m < 1e-3
            };
            if mt.is_none() && !near_edge {
                assert!(hit(&ray, tri, f32::NEG_INFINITY, f32::INFINITY).is_none());
            }
        }
    }

    #[test]
    fn shared_edges_of_a_fan_are_watertight() {
        // A fan of triangles around a centre vertex; rays aimed exactly at the
        // centre and at points on the spokes must hit at least one triangle.
        let mut r = Rng::new(9);
        let mut tested = 0;
        let centre = Vec3::new(0.3, -0.2, 0.1);
        let n = 7;
        let rim: Vec<Vec3> = (0..n)
            .map(|k| {
                let a = k as f32 / n as f32 * std::f32::consts::TAU;
                centre + Vec3::new(a.cos(), a.sin(), 0.2 * (3.0 * a).sin())
            })
            .collect();
        for _ in 0..20_000 {
            let o = centre + Vec3::new(r.range(-2.0, 2.0), r.range(-2.0, 2.0), r.range(0.5, 3.0));
            let k = r.below(n as u32) as usize;
            let target = match r.below(3) {
                0 => centre,
                1 => centre + r.next_f32() * (rim[k] - centre),
                _ => rim[k] + r.next_f32() * (rim[(k + 1) % n] - rim[k]),
            };
            let ray = Ray::new(o, target - o, 0.0);
            // A ray grazing a fold of the fan (one triangle seen from the front,
            // its neighbour from the back) touches the surface only tangentially
            // and may legitimately miss; keep rays that cross every triangle's
            // plane clearly from the same side.
            let dir = ray.dir.normalize();
            let crosses = (0..n).all(|j| {
                let nrm = (rim[j] - centre)
                    .cross(rim[(j + 1) % n] - centre)
                    .normalize();
                nrm.dot(dir) < -0.05
            });
            if !crosses {
                continue;
            }
            tested += 1;
            let shear = RayShear::new(&ray);
            let any = (0..n).any(|j| {
                intersect_triangle(&ray, &shear, centre, rim[j], rim[(j + 1) % n], 0.0, 2.0)
                    .is_some()
            });
            // Points on the outer rim edges are on the boundary of the fan and
            // may legitimately round to either side: only test interior ones.
            if target != centre && (target - centre).length() > 0.9 {
                continue;
            }
            assert!(any, "ray {ray:?} slipped through the fan at {target:?}");
        }
        assert!(tested > 5000, "only {tested} rays tested");
    }
}
