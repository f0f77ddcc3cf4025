//! The camera's clip planes, applied where the integrators first intersect
//! camera rays: a hit before the near plane is replaced by the first one
//! past it, and a hit beyond the far plane is dropped (the ray then misses,
//! and sees what a miss sees: the environment), as Mitsuba's camera rays,
//! which start on the near plane and end on the far one, find.

use crate::accel::{Hit, Hits};
use crate::math::Ray;
use crate::scene::Scene;

/// Clips the hits `hits` of camera rays `rays` (in order) to the camera's
/// planes. A camera without clip planes leaves them untouched, and so does
/// one whose planes a ray's hit lies between.
pub(in crate::integrator) fn clip_camera_hits(scene: &Scene, rays: &[Ray], hits: &mut Hits) {
    let camera = &scene.camera;
    if !camera.clips() {
        return;
    }
    for (i, ray) in rays.iter().enumerate() {
        let Some((near, far)) = camera.clip(ray) else {
            continue;
        };
        match hits.get(i) {
            Some(h) if h.t <= near => hits.set(i, scene.world.closest(ray, near, far)),
            Some(h) if h.t >= far => hits.set(i, None),
            _ => {}
        }
    }
}

/// The first hits of camera rays `rays`, clipped to the camera's planes,
/// into `hits` (`found` holds them in the compact form): what every
/// integrator's camera rays meet.
pub(in crate::integrator) fn first_hits(
    scene: &Scene,
    rays: &[Ray],
    found: &mut Hits,
    hits: &mut Vec<Option<Hit>>,
) {
    found.clear();
    for r in rays {
        found.push(scene.world.closest(r, 0.0, f32::INFINITY));
    }
    clip_camera_hits(scene, rays, found);
    scene.world.surfaces(rays, found, hits);
}
