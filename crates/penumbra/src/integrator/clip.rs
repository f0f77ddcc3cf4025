//! The camera's clip planes, applied where the integrators first intersect
//! camera rays: a hit before the near plane is replaced by the first one
//! past it, and a hit beyond the far plane is dropped (the ray then misses,
//! and sees what a miss sees: the environment), as Mitsuba's camera rays,
//! which start on the near plane and end on the far one, find.

use crate::accel::Hit;
use crate::math::Ray;
use crate::scene::Scene;

/// Clips the hits `hits` of camera rays `rays` (in order) to the camera's
/// planes. A camera without clip planes leaves them untouched, and so does
/// one whose planes a ray's hit lies between.
pub(in crate::integrator) fn clip_camera_hits(
    scene: &Scene,
    rays: &[Ray],
    hits: &mut [Option<Hit>],
) {
    let camera = &scene.camera;
    if !camera.clips() {
        return;
    }
    for (ray, hit) in rays.iter().zip(hits.iter_mut()) {
        let Some((near, far)) = camera.clip(ray) else {
            continue;
        };
        match hit {
            Some(h) if h.t <= near => *hit = scene.world.intersect(ray, near, far),
            Some(h) if h.t >= far => *hit = None,
            _ => {}
        }
    }
}

/// The first hits of camera rays `rays`, clipped to the camera's planes,
/// into `hits`: what every integrator's camera rays meet.
pub(in crate::integrator) fn first_hits(scene: &Scene, rays: &[Ray], hits: &mut Vec<Option<Hit>>) {
    hits.clear();
    hits.extend(
        rays.iter()
            .map(|r| scene.world.intersect(r, 0.0, f32::INFINITY)),
    );
    clip_camera_hits(scene, rays, hits);
}
