//! Pinhole and thin-lens cameras with a shutter.
//!
//! The camera takes its random numbers as a [`CameraSample`] and owns no
//! generator. Depth of field follows thesis §2.3.5: the pinhole ray of a pixel
//! sample meets the focal plane at one point, and every lens ray of that
//! sample starts on the aperture and passes through that point.

use crate::math::{Ray, Vec2, Vec3};

/// Where on the film, the lens and the shutter one primary ray is taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// Continuous pixel coordinates: x to the right, y down, (0, 0) the image's top-left corner.
    pub film: Vec2,
    /// A point of the unit disk, scaled by the aperture radius.
    pub lens: Vec2,
    /// Frame time in [0, 1] (objects move from `transform` at 0 to `transform_end` at 1).
    pub time: f32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub position: [Vec3; 2],
    pub look_at: [Vec3; 2],
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub fov: f32,
    pub aperture: f32,
    pub focal_distance: f32,
    pub shutter: [f32; 2],
    pub width: u32,
    pub height: u32,
}

impl Camera {
    /// The frame time of a shutter fraction in [0, 1).
    pub fn time(&self, fraction: f32) -> f32 {
        self.shutter[0] + (self.shutter[1] - self.shutter[0]) * fraction
    }

    pub fn generate_ray(&self, s: &CameraSample) -> Ray {
        let moving = self.position[0] != self.position[1] || self.look_at[0] != self.look_at[1];
        let (eye, target) = if moving {
            let t = s.time.clamp(0.0, 1.0);
            (
                self.position[0].lerp(self.position[1], t),
                self.look_at[0].lerp(self.look_at[1], t),
            )
        } else {
            (self.position[0], self.look_at[0])
        };
        let forward = (target - eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let tan = (0.5 * self.fov).tan();
        let aspect = self.width as f32 / self.height as f32;
        let ndc_x = 2.0 * s.film.x / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * s.film.y / self.height as f32;
        let dir = (forward + (ndc_x * tan * aspect) * right + (ndc_y * tan) * up).normalize();
        if self.aperture <= 0.0 {
            return Ray::new(eye, dir, s.time);
        }
        // The focal plane is perpendicular to the view axis at focal_distance.
        let focus = eye + dir * (self.focal_distance / dir.dot(forward));
        let origin = eye + self.aperture * (s.lens.x * right + s.lens.y * up);
        Ray::new(origin, (focus - origin).normalize(), s.time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(aperture: f32) -> Camera {
        Camera {
            position: [Vec3::new(0.0, 0.0, 5.0); 2],
            look_at: [Vec3::ZERO; 2],
            up: Vec3::Y,
            fov: 60f32.to_radians(),
            aperture,
            focal_distance: 5.0,
            shutter: [0.0, 1.0],
            width: 200,
            height: 100,
        }
    }

    #[test]
    fn centre_pixel_looks_at_target() {
        let r = cam(0.0).generate_ray(&CameraSample {
            film: Vec2::new(100.0, 50.0),
            lens: Vec2::ZERO,
            time: 0.0,
        });
        assert!((r.dir - -Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn lens_rays_meet_on_focal_plane() {
        let c = cam(0.5);
        let film = Vec2::new(30.0, 80.0);
        let pin = cam(0.0).generate_ray(&CameraSample {
            film,
            lens: Vec2::ZERO,
            time: 0.0,
        });
        let focus = pin.at(5.0 / pin.dir.dot(-Vec3::Z));
        for lens in [
            Vec2::new(1.0, 0.0),
            Vec2::new(-0.3, 0.7),
            Vec2::new(0.0, -1.0),
        ] {
            let r = c.generate_ray(&CameraSample {
                film,
                lens,
                time: 0.0,
            });
            let t = (r.origin.z - focus.z) / -r.dir.z;
            assert!((r.at(t) - focus).length() < 1e-4);
        }
    }
}
