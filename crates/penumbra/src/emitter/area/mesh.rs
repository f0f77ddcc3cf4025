//! A triangle mesh as an area light: one-sided triangles emitting along
//! their geometric normals, sampled uniformly by area through a table of
//! the triangles' areas built once.

use crate::emitter::sample::{area_pdf, area_sample, LightSample};
use crate::math::{Aabb, Rgb, Vec2, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::warp::square_to_triangle;
use crate::sampling::{Discrete, Distribution};

/// The triangles of an emitting mesh in world space and the table that
/// picks one in proportion to its area.
#[derive(Clone, Debug)]
pub struct MeshLight {
    triangles: Vec<[Vec3; 3]>,
    /// Unit geometric normals, `(p1 − p0) × (p2 − p0)`.
    normals: Vec<Vec3>,
    table: Discrete,
    area: f32,
}

impl MeshLight {
    /// The light of these triangles; `None` if their area is zero (or not finite).
    pub fn new(triangles: Vec<[Vec3; 3]>) -> Option<MeshLight> {
        let cross = |t: &[Vec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]);
        let table = Discrete::new(triangles.iter().map(|t| 0.5 * cross(t).length()))?;
        let area = table.total() as f32;
        let normals = triangles
            .iter()
            .map(|t| cross(t).normalize_or_zero())
            .collect();
        Some(MeshLight {
            triangles,
            normals,
            table,
            area,
        })
    }

    pub fn area(&self) -> f32 {
        self.area
    }

    /// The box around the triangles.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.triangles.iter().flatten().copied())
    }

    /// A cone holding every triangle's normal: its axis (the area-weighted
    /// mean normal) and the cosine of its half-angle (the smallest cosine
    /// between the axis and a normal); the whole sphere (−1) when the
    /// normals cancel out.
    pub fn normal_cone(&self) -> (Vec3, f32) {
        let sum: Vec3 = (0..self.triangles.len())
            .map(|i| self.table.pmf(i) * self.normals[i])
            .sum();
        if sum.length() < 1e-3 {
            return (Vec3::Z, -1.0);
        }
        let axis = sum.normalize();
        let cos = self
            .normals
            .iter()
            .filter(|n| **n != Vec3::ZERO)
            .map(|n| n.dot(axis))
            .fold(1.0f32, f32::min);
        // A little wider than the smallest cosine, against rounding.
        (axis, if cos > -0.999 { cos - 1e-4 } else { -1.0 })
    }

    /// The area-weighted centroid.
    pub fn centroid(&self) -> Vec3 {
        let sum: Vec3 = (0..self.triangles.len())
            .map(|i| {
                let t = &self.triangles[i];
                self.table.pmf(i) * (t[0] + t[1] + t[2]) / 3.0
            })
            .sum();
        sum
    }

    /// A point uniform in area for the distribution point `point`, seen
    /// from `p`.
    #[inline]
    pub fn sample(&self, power: Rgb, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        let u = unit_square(point, d);
        let (i, _, rest) = self.table.sample(u.x);
        let (b0, b1) = square_to_triangle(Vec2::new(rest, u.y));
        let [a, b, c] = self.triangles[i];
        let target = b0 * a + b1 * b + (1.0 - b0 - b1) * c;
        area_sample(power, p, target, self.normals[i], self.area, false)
    }

    /// The solid-angle density of [`sample`](Self::sample) at a point seen
    /// at `cos_l` and squared distance `r2`.
    pub fn pdf(&self, cos_l: f32, r2: f32) -> f32 {
        area_pdf(cos_l, r2, self.area)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Samples are uniform in area: over a mesh of a large and a small
    /// triangle (areas 8 and 0.5), the share landing on each is its share
    /// of the area (binomial, 5 sigma), and within the large triangle the
    /// points' mean is its centroid.
    #[test]
    fn samples_are_uniform_in_area() {
        let big = [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 4.0),
        ];
        let small = [
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::new(6.0, 0.0, 0.0),
            Vec3::new(5.0, 0.0, 1.0),
        ];
        // Normals down (−y), seen from below.
        let light = MeshLight::new(vec![big, small]).unwrap();
        assert!((light.area() - 8.5).abs() < 1e-5);
        let p = Vec3::new(2.0, -3.0, 1.0);
        let mut rng = Rng::new(13);
        let (n, mut on_small, mut sum) = (40_000, 0, Vec3::ZERO);
        for _ in 0..n {
            let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
            let s = light
                .sample(Rgb::ONE, p, point, Distribution::Jitter)
                .unwrap();
            if s.target.x > 4.5 {
                on_small += 1;
            } else {
                sum += s.target;
            }
            // The weight is L / pdf in solid angle.
            let to = s.target - p;
            // The triangles face down (−y), toward `p`.
            let cos_l = (-Vec3::Y).dot(-to) / to.length();
            let pdf = light.pdf(cos_l, to.length_squared());
            assert!(
                (s.weight.r - 1.0 / pdf).abs() < 1e-3 / pdf,
                "{:?}",
                s.weight
            );
        }
        let share = 0.5 / 8.5;
        let sigma = (n as f32 * share * (1.0 - share)).sqrt();
        assert!(
            (on_small as f32 - n as f32 * share).abs() < 5.0 * sigma,
            "{on_small}"
        );
        let mean = sum / (n - on_small) as f32;
        assert!(
            (mean - Vec3::new(4.0 / 3.0, 0.0, 4.0 / 3.0)).length() < 0.03,
            "{mean:?}"
        );
        assert!(MeshLight::new(vec![[Vec3::ZERO; 3]]).is_none(), "no area");
    }
}
