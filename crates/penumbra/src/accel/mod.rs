//! TEMPORARY linear-scan stand-in with the BVH's API.
use crate::math::{Aabb, Ray};
pub struct Bvh {
    n: usize,
    bounds: Aabb,
}
impl Bvh {
    pub fn build(b: &[Aabb]) -> Bvh {
        Bvh {
            n: b.len(),
            bounds: b.iter().fold(Aabb::EMPTY, |a, x| a.union(*x)),
        }
    }
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
    pub fn closest_hit(
        &self,
        _ray: &Ray,
        _tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        let mut best = None;
        let mut tmax = tmax;
        for i in 0..self.n {
            if let Some(t) = hit(i as u32, tmax) {
                tmax = t;
                best = Some((i as u32, t));
            }
        }
        best
    }
    pub fn any_hit(
        &self,
        _ray: &Ray,
        _tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32, f32) -> bool,
    ) -> bool {
        (0..self.n).any(|i| hit(i as u32, tmax))
    }
}
