//! Convex polygon clipping (Sutherland–Hodgman) and the shoelace area: the
//! exact reference of the soft-shadow integrand is the area of a light
//! square minus the part a projected occluder covers.

/// A point of the plane.
pub type P2 = [f64; 2];

/// Signed area by the shoelace formula: positive for counter-clockwise
/// vertices.
pub fn signed_area(poly: &[P2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

/// Area of a simple polygon, whatever its orientation.
pub fn area(poly: &[P2]) -> f64 {
    signed_area(poly).abs()
}

/// Twice the signed area of the triangle `(a, b, p)`: positive when `p` is
/// left of the directed edge `a → b`.
fn side(a: P2, b: P2, p: P2) -> f64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// The counter-clockwise version of `poly`.
fn ccw(poly: &[P2]) -> Vec<P2> {
    let mut v = poly.to_vec();
    if signed_area(&v) < 0.0 {
        v.reverse();
    }
    v
}

/// True when `p` lies inside the convex polygon `poly` (either orientation)
/// or on its boundary. Allocates nothing: it is the inner loop of an
/// integrand.
pub fn contains(poly: &[P2], p: P2) -> bool {
    let n = poly.len();
    let orientation = signed_area(poly).signum();
    n >= 3 && (0..n).all(|i| orientation * side(poly[i], poly[(i + 1) % n], p) >= 0.0)
}

/// The part of `subject` (any simple polygon) inside the convex polygon
/// `clip` (either orientation), by Sutherland–Hodgman: the subject is cut by
/// the half-plane of each clip edge in turn. Empty when they do not overlap.
pub fn clip(subject: &[P2], clip: &[P2]) -> Vec<P2> {
    let clip = ccw(clip);
    let mut out = subject.to_vec();
    for i in 0..clip.len() {
        let (a, b) = (clip[i], clip[(i + 1) % clip.len()]);
        let input = std::mem::take(&mut out);
        for j in 0..input.len() {
            let (p, q) = (input[j], input[(j + 1) % input.len()]);
            let (sp, sq) = (side(a, b, p), side(a, b, q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: [P2; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn shoelace_areas_of_simple_shapes() {
        assert!(close(signed_area(&UNIT), 1.0));
        let cw: Vec<P2> = UNIT.iter().rev().copied().collect();
        assert!(close(signed_area(&cw), -1.0) && close(area(&cw), 1.0));
        assert!(close(area(&[[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]]), 6.0));
        assert!(close(area(&[]), 0.0));
    }

    #[test]
    fn overlapping_squares() {
        let shifted = [[0.5, 0.25], [1.5, 0.25], [1.5, 1.25], [0.5, 1.25]];
        // Overlap [0.5, 1] x [0.25, 1]: 0.5 * 0.75.
        assert!(close(area(&clip(&UNIT, &shifted)), 0.375));
        assert!(close(area(&clip(&shifted, &UNIT)), 0.375));
    }

    #[test]
    fn diamonds_in_the_unit_square() {
        // |x - 1/2| + |y - 1/2| <= d.
        let diamond = |d: f64| {
            [
                [0.5 - d, 0.5],
                [0.5, 0.5 - d],
                [0.5 + d, 0.5],
                [0.5, 0.5 + d],
            ]
        };
        // Inscribed: the whole diamond, 2 d^2.
        assert!(close(area(&clip(&diamond(0.5), &UNIT)), 0.5));
        // d = 0.7: the square minus four corner triangles with legs 0.3.
        assert!(close(area(&clip(&diamond(0.7), &UNIT)), 1.0 - 4.0 * 0.045));
        assert!(close(area(&clip(&UNIT, &diamond(0.7))), 0.82));
        // Large enough to hold the square.
        assert!(close(area(&clip(&UNIT, &diamond(1.0))), 1.0));
    }

    #[test]
    fn triangle_cut_by_a_square() {
        // The triangle (0,0) (2,0) (0,2) inside the unit square is the whole
        // square (x + y <= 2 holds everywhere in it).
        let t = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
        assert!(close(area(&clip(&t, &UNIT)), 1.0));
        // (0,0) (1.5,0) (0,1.5): the square minus the corner x + y > 1.5,
        // a triangle with legs 0.5.
        let t = [[0.0, 0.0], [1.5, 0.0], [0.0, 1.5]];
        assert!(close(area(&clip(&t, &UNIT)), 1.0 - 0.125));
    }

    #[test]
    fn disjoint_and_contained() {
        let far = [[2.0, 2.0], [3.0, 2.0], [3.0, 3.0]];
        assert!(clip(&far, &UNIT).is_empty());
        let inner = [[0.2, 0.2], [0.4, 0.2], [0.3, 0.5]];
        assert!(close(area(&clip(&inner, &UNIT)), area(&inner)));
    }

    #[test]
    fn containment_is_inclusive_and_orientation_free() {
        let cw: Vec<P2> = UNIT.iter().rev().copied().collect();
        for poly in [&UNIT[..], &cw[..]] {
            assert!(contains(poly, [0.5, 0.5]));
            assert!(contains(poly, [1.0, 0.5]));
            assert!(!contains(poly, [1.0001, 0.5]));
            assert!(!contains(poly, [-0.1, -0.1]));
        }
    }
}
