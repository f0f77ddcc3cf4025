//! The shading point every integrator spawns its rays from.

use crate::math::{offset_origin, reach, Ray, Vec3};

/// A point rays leave from: a hit, the geometric normal they are offset
/// along, how far (in proportion to [`reach`]), and the time every ray of
/// the path inherits. `whitted` keeps the normal on the viewer's side, the
/// path tracers the surface's own; the offset goes to the side of the
/// direction a ray leaves in, so either gives the same rays.
#[derive(Clone, Copy, Debug)]
pub struct ShadingPoint {
    pub p: Vec3,
    /// The geometric normal rays are offset along.
    pub ng: Vec3,
    /// The magnitude that rays leaving `p` are offset in proportion to
    /// ([`reach`]).
    pub reach: f32,
    /// The path's time: every secondary ray inherits its primary ray's time.
    pub time: f32,
}

impl ShadingPoint {
    /// The point `p` with normal `ng`, reached along `ray`.
    #[inline]
    pub fn new(ray: &Ray, p: Vec3, ng: Vec3) -> ShadingPoint {
        ShadingPoint {
            p,
            ng,
            reach: reach(p, ray.origin),
            time: ray.time,
        }
    }

    /// Where rays leaving toward `toward`'s side of the surface start.
    #[inline]
    pub fn origin(&self, toward: Vec3) -> Vec3 {
        offset_origin(self.p, self.reach, self.ng, toward)
    }

    /// The ray leaving in direction `w`.
    #[inline]
    pub fn spawn_ray(&self, w: Vec3) -> Ray {
        Ray::new(self.origin(w), w, self.time)
    }

    /// The ray from `origin` (one of [`origin`](Self::origin)) to `target`,
    /// as long as the segment: a shadow ray.
    #[inline]
    pub fn spawn_ray_to(&self, origin: Vec3, target: Vec3) -> Ray {
        Ray::new(origin, target - origin, self.time)
    }
}
