//! The integrands of the study: functions on the unit square with exact
//! integrals computed in closed form, never by sampling. Shapes are placed
//! off-centre, with radii and vertices that are no simple fractions and edges
//! that are not parallel to the axes, so that no grid of points lines up with
//! them.

use serde::Serialize;
use statrs::function::erf::erf;

use super::polygon::{self, P2};

/// What kind of function an integrand is; the theoretical convergence rates
/// depend on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Class {
    /// Infinitely differentiable over the square.
    Smooth,
    /// An indicator function: a jump across a curve or polyline.
    Edge,
}

impl Class {
    pub fn name(self) -> &'static str {
        match self {
            Class::Smooth => "smooth",
            Class::Edge => "edge",
        }
    }
}

/// One integrand of the study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrand {
    Disk,
    Triangle,
    Gaussian,
    SoftShadow,
}

/// Centre and radius of the disk.
const DISK_CENTRE: P2 = [0.5123, 0.4771];
const DISK_RADIUS: f64 = 0.3141;

/// The triangle's vertices (counter-clockwise); no edge is parallel to an
/// axis.
const TRIANGLE: [P2; 3] = [[0.1234, 0.2113], [0.8672, 0.3391], [0.4119, 0.9087]];

/// Centre and standard deviation of the Gaussian bump.
const GAUSSIAN_CENTRE: P2 = [0.4713, 0.5287];
const GAUSSIAN_SIGMA: f64 = 0.1673;

/// The soft-shadow scene: a point on the floor (`z = 0`), a square light of
/// side 1 centred above the origin at height `LIGHT_HEIGHT`, parametrised by
/// the unit square as `(u - 1/2, v - 1/2, LIGHT_HEIGHT)`, and between them a
/// rectangle parallel to the floor at `OCCLUDER_HEIGHT`, turned by
/// `OCCLUDER_ANGLE` radians.
const FLOOR_POINT: P2 = [0.2, -0.1];
const LIGHT_HEIGHT: f64 = 2.0;
const OCCLUDER_HEIGHT: f64 = 1.0;
const OCCLUDER_CENTRE: P2 = [0.325, 0.125];
const OCCLUDER_HALF: P2 = [0.275, 0.15];
const OCCLUDER_ANGLE: f64 = 0.52;

impl Integrand {
    pub const ALL: [Integrand; 4] = [
        Integrand::Disk,
        Integrand::Triangle,
        Integrand::Gaussian,
        Integrand::SoftShadow,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Integrand::Disk => "disk",
            Integrand::Triangle => "triangle",
            Integrand::Gaussian => "gaussian",
            Integrand::SoftShadow => "soft shadow",
        }
    }

    /// The name in file names: `soft-shadow`.
    pub fn slug(self) -> String {
        self.name().replace(' ', "-")
    }

    pub fn class(self) -> Class {
        match self {
            Integrand::Gaussian => Class::Smooth,
            Integrand::Disk | Integrand::Triangle | Integrand::SoftShadow => Class::Edge,
        }
    }

    /// What the function is, for the report.
    pub fn description(self) -> String {
        match self {
            Integrand::Disk => format!(
                "the indicator of the disk of radius {DISK_RADIUS} centred at ({}, {}); exact value π r²",
                DISK_CENTRE[0], DISK_CENTRE[1]
            ),
            Integrand::Triangle => format!(
                "the indicator of the triangle ({}, {}), ({}, {}), ({}, {}); exact value its shoelace area",
                TRIANGLE[0][0], TRIANGLE[0][1], TRIANGLE[1][0], TRIANGLE[1][1], TRIANGLE[2][0], TRIANGLE[2][1]
            ),
            Integrand::Gaussian => format!(
                "exp(−|p − c|² / 2σ²) with c = ({}, {}) and σ = {GAUSSIAN_SIGMA}; exact value a product of two differences of erf",
                GAUSSIAN_CENTRE[0], GAUSSIAN_CENTRE[1]
            ),
            Integrand::SoftShadow => format!(
                "the visibility of a unit square light at height {LIGHT_HEIGHT} from the floor point ({}, {}, 0), past a {}×{} rectangle at height {OCCLUDER_HEIGHT} turned by {OCCLUDER_ANGLE} rad, whose shadow on the light has a corner and slanted edges inside it; a sample is the light point (u − ½, v − ½, {LIGHT_HEIGHT}) and is 1 when the segment to it misses the rectangle; exact value 1 minus the area of the rectangle's central projection onto the light, clipped to the light (Sutherland–Hodgman)",
                FLOOR_POINT[0], FLOOR_POINT[1], 2.0 * OCCLUDER_HALF[0], 2.0 * OCCLUDER_HALF[1]
            ),
        }
    }

    /// The function at `p` in the unit square.
    #[inline]
    pub fn eval(self, p: P2) -> f64 {
        match self {
            Integrand::Disk => {
                let (dx, dy) = (p[0] - DISK_CENTRE[0], p[1] - DISK_CENTRE[1]);
                f64::from(u8::from(dx * dx + dy * dy <= DISK_RADIUS * DISK_RADIUS))
            }
            Integrand::Triangle => f64::from(u8::from(polygon::contains(&TRIANGLE, p))),
            Integrand::Gaussian => {
                let (dx, dy) = (p[0] - GAUSSIAN_CENTRE[0], p[1] - GAUSSIAN_CENTRE[1]);
                (-(dx * dx + dy * dy) / (2.0 * GAUSSIAN_SIGMA * GAUSSIAN_SIGMA)).exp()
            }
            Integrand::SoftShadow => {
                let light = [p[0] - 0.5, p[1] - 0.5];
                // Where the segment from the floor point to the light point
                // crosses the occluder's plane.
                let t = OCCLUDER_HEIGHT / LIGHT_HEIGHT;
                let hit = [
                    FLOOR_POINT[0] + t * (light[0] - FLOOR_POINT[0]),
                    FLOOR_POINT[1] + t * (light[1] - FLOOR_POINT[1]),
                ];
                f64::from(u8::from(!polygon::contains(&occluder(), hit)))
            }
        }
    }

    /// The integral over the unit square, in closed form.
    pub fn exact(self) -> f64 {
        match self {
            Integrand::Disk => std::f64::consts::PI * DISK_RADIUS * DISK_RADIUS,
            Integrand::Triangle => polygon::area(&TRIANGLE),
            Integrand::Gaussian => {
                // ∫_0^1 exp(−(x − c)² / 2σ²) dx = σ √(π/2) (erf((1 − c)/σ√2) + erf(c/σ√2)).
                let s = GAUSSIAN_SIGMA * std::f64::consts::SQRT_2;
                let axis = |c: f64| {
                    GAUSSIAN_SIGMA
                        * (std::f64::consts::PI / 2.0).sqrt()
                        * (erf((1.0 - c) / s) + erf(c / s))
                };
                axis(GAUSSIAN_CENTRE[0]) * axis(GAUSSIAN_CENTRE[1])
            }
            Integrand::SoftShadow => {
                let light = [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
                1.0 - polygon::area(&polygon::clip(&shadow(), &light))
            }
        }
    }
}

/// The occluder's corners in its plane (world x and y).
fn occluder() -> [P2; 4] {
    let (sin, cos) = OCCLUDER_ANGLE.sin_cos();
    [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]].map(|[a, b]| {
        let (x, y) = (a * OCCLUDER_HALF[0], b * OCCLUDER_HALF[1]);
        [
            OCCLUDER_CENTRE[0] + cos * x - sin * y,
            OCCLUDER_CENTRE[1] + sin * x + cos * y,
        ]
    })
}

/// The occluder projected from the floor point onto the light's plane.
fn shadow() -> [P2; 4] {
    let k = LIGHT_HEIGHT / OCCLUDER_HEIGHT;
    occluder().map(|q| {
        [
            FLOOR_POINT[0] + k * (q[0] - FLOOR_POINT[0]),
            FLOOR_POINT[1] + k * (q[1] - FLOOR_POINT[1]),
        ]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Midpoint rule on a `k x k` grid.
    fn brute_force(f: Integrand, k: usize) -> f64 {
        let h = 1.0 / k as f64;
        let mut sum = 0.0;
        for i in 0..k {
            for j in 0..k {
                sum += f.eval([(i as f64 + 0.5) * h, (j as f64 + 0.5) * h]);
            }
        }
        sum * h * h
    }

    #[test]
    fn exact_values_match_a_fine_grid() {
        for f in Integrand::ALL {
            let (exact, grid) = (f.exact(), brute_force(f, 2000));
            // Edges: the cells cut by a boundary of length < 4 number about
            // 4 * 2000 and each errs by less than a cell: 1e-3 is loose.
            // The Gaussian's midpoint error is O(h²).
            let tolerance = match f.class() {
                Class::Edge => 1e-3,
                Class::Smooth => 1e-8,
            };
            println!("{}: exact {exact:.9}, grid {grid:.9}", f.name());
            assert!(
                (exact - grid).abs() < tolerance,
                "{}: {exact} vs {grid}",
                f.name()
            );
        }
    }

    #[test]
    fn exact_values_are_the_stated_shapes() {
        let pi_r2 = std::f64::consts::PI * 0.3141 * 0.3141;
        assert!((Integrand::Disk.exact() - pi_r2).abs() < 1e-15);
        // Triangle by the cross product, computed by hand from the vertices.
        let (a, b, c) = (TRIANGLE[0], TRIANGLE[1], TRIANGLE[2]);
        let cross = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        assert!((Integrand::Triangle.exact() - cross / 2.0).abs() < 1e-15);
        // The Gaussian over the square is below the whole plane's 2πσ².
        let plane = 2.0 * std::f64::consts::PI * GAUSSIAN_SIGMA * GAUSSIAN_SIGMA;
        let g = Integrand::Gaussian.exact();
        assert!(g < plane && g > 0.9 * plane, "{g} vs {plane}");
    }

    #[test]
    fn shapes_lie_inside_the_square() {
        assert!(DISK_CENTRE
            .iter()
            .all(|&c| c - DISK_RADIUS > 0.0 && c + DISK_RADIUS < 1.0));
        assert!(TRIANGLE.iter().flatten().all(|&c| c > 0.0 && c < 1.0));
        for i in 0..3 {
            let (p, q) = (TRIANGLE[i], TRIANGLE[(i + 1) % 3]);
            assert!(p[0] != q[0] && p[1] != q[1], "edge {i} is axis-parallel");
        }
    }

    /// The shadow covers part of the light, not all, with at least one
    /// corner strictly inside it and no edge parallel to the light's.
    #[test]
    fn the_occluder_casts_a_partial_shadow_with_a_corner() {
        let visible = Integrand::SoftShadow.exact();
        assert!(visible > 0.2 && visible < 0.8, "{visible}");
        let s = shadow();
        let inside = |p: &P2| p.iter().all(|c| c.abs() < 0.5);
        assert!(s.iter().any(inside), "{s:?}");
        assert!(!s.iter().all(inside), "{s:?}");
        for i in 0..4 {
            let (p, q) = (s[i], s[(i + 1) % 4]);
            assert!((p[0] - q[0]).abs() > 0.1 && (p[1] - q[1]).abs() > 0.1);
        }
        // The light point behind the occluder's centre is in shadow, two
        // far corners of the light are lit.
        assert_eq!(Integrand::SoftShadow.eval([0.95, 0.85]), 0.0);
        assert_eq!(Integrand::SoftShadow.eval([0.0, 1.0]), 1.0);
        assert_eq!(Integrand::SoftShadow.eval([0.0, 0.0]), 1.0);
    }

    #[test]
    fn classes_and_names() {
        assert_eq!(Integrand::Gaussian.class(), Class::Smooth);
        assert_eq!(Integrand::SoftShadow.slug(), "soft-shadow");
        assert!(
            Integrand::ALL
                .iter()
                .filter(|f| f.class() == Class::Edge)
                .count()
                == 3
        );
    }
}
