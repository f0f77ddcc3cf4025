//! Pinhole, thin-lens and orthographic cameras with a shutter.
//!
//! The camera takes its random numbers as a [`CameraSample`] and owns no
//! generator. Depth of field follows thesis §2.3.5: the pinhole ray of a pixel
//! sample meets the focal plane at one point, and every lens ray of that
//! sample starts on the aperture and passes through that point.
//!
//! Clip planes are planes perpendicular to the view axis, at `near_clip`
//! and `far_clip` from the eye: a camera ray sees only what lies between
//! them ([`Camera::clip`], which the integrators apply where they first
//! intersect camera rays). A ray's origin stays at the eye (or on the lens),
//! so that a camera without clip planes makes the same rays as before.

use crate::math::{Ray, Vec2, Vec3};
use glam::Vec4;

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

/// How the camera maps the film onto rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Projection {
    /// Rays from the eye (or the lens) through the film, spread by the
    /// field of view.
    #[default]
    Perspective,
    /// Parallel rays along the view axis, from the points of a rectangle
    /// centred on the eye and perpendicular to the axis.
    Orthographic,
}

/// What a scene says about its camera (validated by the scene builder).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraSpec {
    pub projection: Projection,
    pub position: [Vec3; 2],
    pub look_at: [Vec3; 2],
    pub up: Vec3,
    /// Vertical field of view, radians (perspective).
    pub fov: f32,
    /// Width and height of the rectangle the rays start from, scene units
    /// (orthographic).
    pub view_size: Vec2,
    /// Distances from the eye, along the view axis, of the planes between
    /// which the camera sees: 0 and infinity see everything.
    pub near_clip: f32,
    pub far_clip: f32,
    /// Shift of the image's centre, in film widths (x, to the right) and
    /// heights (y, down): the ray of film point `p` is the one the unshifted
    /// camera makes at `p + principal_point · (width, height)`.
    pub principal_point: Vec2,
    pub aperture: f32,
    pub focal_distance: f32,
    pub shutter: [f32; 2],
    /// The film's size in pixels.
    pub width: u32,
    pub height: u32,
    /// The pixels sampled beyond the film on each side: the camera's
    /// film point `p` is the film's `p − (border, border)`.
    pub border: u32,
}

/// The camera's orthonormal view basis at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
struct View {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
}

/// A camera ready to generate rays. Everything that does not depend on the
/// sample (the view basis of a still camera, the film-to-direction scale) is
/// computed once here: per ray it would cost a fifth of a 16-sample render.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    spec: CameraSpec,
    /// The view of a still camera; `None` when the camera moves during the
    /// shutter interval, whose view depends on the ray's time.
    still: Option<View>,
    /// NDC to view-plane offsets: `(tan(fov/2) · aspect, tan(fov/2))` for
    /// a perspective camera, half the view's size for an orthographic one.
    scale: Vec2,
    /// The principal point's shift in pixels.
    shift: Vec2,
}

impl Camera {
    pub fn new(spec: CameraSpec) -> Camera {
        let tan = (0.5 * spec.fov).tan();
        let aspect = spec.width as f32 / spec.height as f32;
        let moving = spec.position[0] != spec.position[1] || spec.look_at[0] != spec.look_at[1];
        let still = (!moving).then(|| View::new(spec.position[0], spec.look_at[0], spec.up));
        let scale = match spec.projection {
            Projection::Perspective => Vec2::new(tan * aspect, tan),
            Projection::Orthographic => 0.5 * spec.view_size,
        };
        let shift = spec.principal_point * Vec2::new(spec.width as f32, spec.height as f32)
            - Vec2::splat(spec.border as f32);
        Camera {
            spec,
            still,
            scale,
            shift,
        }
    }

    /// True if the camera has clip planes (see [`clip`](Self::clip)).
    pub fn clips(&self) -> bool {
        self.spec.near_clip > 0.0 || self.spec.far_clip < f32::INFINITY
    }

    /// The interval of distances along camera ray `ray` (of unit
    /// direction, made by this camera) within which it may hit: those
    /// between the clip planes. `None` when the camera does not clip.
    pub fn clip(&self, ray: &Ray) -> Option<(f32, f32)> {
        let c = &self.spec;
        if !self.clips() {
            return None;
        }
        if c.projection == Projection::Orthographic {
            return Some((c.near_clip, c.far_clip));
        }
        let forward = match self.still {
            Some(view) => view.forward,
            None => self.view(ray.time).forward,
        };
        // The planes' distance along the ray: the axial distance over the
        // cosine of the ray with the axis.
        let inv = 1.0 / ray.dir.dot(forward);
        Some((c.near_clip * inv, c.far_clip * inv))
    }

    /// The view at frame time `time`.
    fn view(&self, time: f32) -> View {
        let c = &self.spec;
        let t = time.clamp(0.0, 1.0);
        let eye = c.position[0].lerp(c.position[1], t);
        View::new(eye, c.look_at[0].lerp(c.look_at[1], t), c.up)
    }

    pub fn spec(&self) -> &CameraSpec {
        &self.spec
    }

    /// True if the camera moves during the shutter interval.
    pub fn moves(&self) -> bool {
        self.still.is_none()
    }

    /// True if the camera has a lens (depth of field) rather than a pinhole.
    pub fn has_lens(&self) -> bool {
        self.spec.aperture > 0.0
    }

    /// The frame time of a shutter fraction in [0, 1).
    pub fn time(&self, fraction: f32) -> f32 {
        let [open, close] = self.spec.shutter;
        open + (close - open) * fraction
    }

    /// True if the shutter stays open for a while (motion blur is possible).
    pub fn shutter_open(&self) -> bool {
        self.spec.shutter[0] < self.spec.shutter[1]
    }

    /// The camera rays of `samples`, appended to `out` in order: the only
    /// way rays are made. A still pinhole camera makes them four at a time
    /// (`rays4`), each lane the ray the portable form (`ray`) makes, bit
    /// for bit; a lens or a moving camera uses the portable form.
    pub fn generate(&self, samples: &[CameraSample], out: &mut Vec<Ray>) {
        let wide = self.still.is_some()
            && self.spec.aperture <= 0.0
            && self.spec.projection == Projection::Perspective;
        let split = if wide { samples.len() / 4 * 4 } else { 0 };
        for four in samples[..split].chunks_exact(4) {
            let film = std::array::from_fn(|k| four[k].film);
            let time = std::array::from_fn(|k| four[k].time);
            out.extend(self.rays4(film, time).expect("a still pinhole camera"));
        }
        out.extend(samples[split..].iter().map(|s| self.ray(s)));
    }

    /// The portable form: one ray, for any camera.
    fn ray(&self, s: &CameraSample) -> Ray {
        let c = &self.spec;
        let view = self.still.unwrap_or_else(|| self.view(s.time));
        let ndc_x = 2.0 * (s.film.x + self.shift.x) / c.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * (s.film.y + self.shift.y) / c.height as f32;
        if c.projection == Projection::Orthographic {
            let origin =
                view.eye + (ndc_x * self.scale.x) * view.right + (ndc_y * self.scale.y) * view.up;
            return Ray::new(origin, view.forward, s.time);
        }
        let dir =
            (view.forward + (ndc_x * self.scale.x) * view.right + (ndc_y * self.scale.y) * view.up)
                .normalize();
        if c.aperture <= 0.0 {
            return Ray::new(view.eye, dir, s.time);
        }
        // The focal plane is perpendicular to the view axis at focal_distance.
        let focus = view.eye + dir * (c.focal_distance / dir.dot(view.forward));
        let origin = view.eye + c.aperture * (s.lens.x * view.right + s.lens.y * view.up);
        Ray::new(origin, (focus - origin).normalize(), s.time)
    }
}

/// A point seen by the camera, for light tracing (Mitsuba's
/// `sample_direction` of a sensor): where on the film it is seen, the
/// point of the camera it is seen from, and the importance carried to it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seen {
    /// The film position, in pixels (continuous, `[0, width] × [0, height]`).
    pub film: Vec2,
    /// The camera's point the connection ends at (the eye, a point of the
    /// lens, or of an orthographic camera's view plane).
    pub at: Vec3,
    /// The importance `W · cos θ_camera / r²` of the connection (for an
    /// orthographic camera, `1 / view area`): a particle's power times the
    /// scattering toward the camera, times this, is what it adds to the
    /// film, normalised so that a pixel's value is the radiance its camera
    /// rays see.
    pub weight: f32,
}

impl Camera {
    /// The area of the image at distance 1 from a perspective camera's eye
    /// (of the view plane for an orthographic camera).
    fn image_area(&self) -> f32 {
        4.0 * self.scale.x * self.scale.y
    }

    /// The film position of the point at `(x, y, z)` from the eye along the
    /// view's right, up and forward axes; `None` off the film.
    fn film_of(&self, x: f32, y: f32, z: f32) -> Option<Vec2> {
        let c = &self.spec;
        let (ndc_x, ndc_y) = match c.projection {
            Projection::Perspective => (x / (z * self.scale.x), y / (z * self.scale.y)),
            Projection::Orthographic => (x / self.scale.x, y / self.scale.y),
        };
        let (w, h) = (c.width as f32, c.height as f32);
        let film = Vec2::new(
            0.5 * (ndc_x + 1.0) * w - self.shift.x,
            0.5 * (1.0 - ndc_y) * h - self.shift.y,
        );
        let inside = (0.0..=w).contains(&film.x) && (0.0..=h).contains(&film.y);
        inside.then_some(film)
    }

    /// How the camera sees the point `p` at `time` (Mitsuba's
    /// `sample_direction`): a pinhole from its eye; a thin lens from the
    /// point of its aperture the point `lens` of the unit disk gives (drawn
    /// uniformly, which cancels the aperture's density); an orthographic
    /// camera along its axis. `None` where the point is behind the camera,
    /// outside its clip planes or off the film.
    pub fn see(&self, p: Vec3, time: f32, lens: Vec2) -> Option<Seen> {
        let c = &self.spec;
        let view = self.still.unwrap_or_else(|| self.view(time));
        let d = p - view.eye;
        let z = d.dot(view.forward);
        if (z <= 0.0 || z.is_nan()) || z < c.near_clip || z > c.far_clip {
            return None;
        }
        if c.projection == Projection::Orthographic {
            let (x, y) = (d.dot(view.right), d.dot(view.up));
            let film = self.film_of(x, y, z)?;
            return Some(Seen {
                film,
                at: view.eye + x * view.right + y * view.up,
                weight: 1.0 / self.image_area(),
            });
        }
        let (at, seen) = if c.aperture > 0.0 {
            // The lens ray through `p` meets the focal plane where the
            // pinhole ray of its film position does.
            let at = view.eye + c.aperture * (lens.x * view.right + lens.y * view.up);
            let focus = at + (p - at) * (c.focal_distance / z);
            (at, focus - view.eye)
        } else {
            (view.eye, d)
        };
        let film = self.film_of(
            seen.dot(view.right),
            seen.dot(view.up),
            seen.dot(view.forward),
        )?;
        let to = p - at;
        let r2 = to.length_squared();
        let cos = to.dot(view.forward) / r2.sqrt();
        if cos <= 0.0 || cos.is_nan() {
            return None;
        }
        Some(Seen {
            film,
            at,
            weight: 1.0 / (self.image_area() * cos * cos * cos * r2),
        })
    }

    /// The film position and importance per solid angle (`W · cos θ`) of
    /// the direction `dir` leaving a pinhole camera's eye at `time`; `None`
    /// for other cameras (which see no direction from a single point) and
    /// off the film.
    pub fn see_direction(&self, dir: Vec3, time: f32) -> Option<(Vec2, f32)> {
        let c = &self.spec;
        if c.projection != Projection::Perspective || c.aperture > 0.0 {
            return None;
        }
        let view = self.still.unwrap_or_else(|| self.view(time));
        let z = dir.dot(view.forward);
        if z <= 0.0 || z.is_nan() {
            return None;
        }
        let film = self.film_of(dir.dot(view.right), dir.dot(view.up), z)?;
        let cos = z / dir.length();
        Some((film, 1.0 / (self.image_area() * cos * cos * cos)))
    }

    /// The eye at `time`.
    pub fn eye(&self, time: f32) -> Vec3 {
        self.still.unwrap_or_else(|| self.view(time)).eye
    }
}

impl Camera {
    /// The four-wide form of [`ray`](Self::ray) for a still perspective
    /// pinhole camera (film positions and times; no lens), lane by lane the
    /// same rays: the same operations in the same order, none fused. `None`
    /// for a lens, a moving or an orthographic camera.
    fn rays4(&self, film: [Vec2; 4], time: [f32; 4]) -> Option<[Ray; 4]> {
        let view = self.still?;
        let c = &self.spec;
        if c.aperture > 0.0 || c.projection != Projection::Perspective {
            return None;
        }
        let (two, one) = (Vec4::splat(2.0), Vec4::ONE);
        let (fx, fy) = (
            film.map(|f| f.x + self.shift.x),
            film.map(|f| f.y + self.shift.y),
        );
        let ndc_x = two * Vec4::from_array(fx) / Vec4::splat(c.width as f32) - one;
        let ndc_y = one - two * Vec4::from_array(fy) / Vec4::splat(c.height as f32);
        let (a, b) = (ndc_x * self.scale.x, ndc_y * self.scale.y);
        let d: [Vec4; 3] = std::array::from_fn(|k| {
            (Vec4::splat(view.forward[k]) + a * view.right[k]) + b * view.up[k]
        });
        // `Vec3::normalize`: times 1 / sqrt(x·x + y·y + z·z).
        let inv = one / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let d = d.map(|c| (c * inv).to_array());
        Some(std::array::from_fn(|i| {
            Ray::new(view.eye, Vec3::new(d[0][i], d[1][i], d[2][i]), time[i])
        }))
    }
}

impl View {
    fn new(eye: Vec3, target: Vec3, up: Vec3) -> View {
        let forward = (target - eye).normalize();
        let right = forward.cross(up).normalize();
        View {
            eye,
            forward,
            right,
            up: right.cross(forward),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(aperture: f32) -> Camera {
        Camera::new(CameraSpec {
            projection: Projection::Perspective,
            position: [Vec3::new(0.0, 0.0, 5.0); 2],
            look_at: [Vec3::ZERO; 2],
            up: Vec3::Y,
            fov: 60f32.to_radians(),
            view_size: Vec2::new(2.0, 1.0),
            near_clip: 0.0,
            far_clip: f32::INFINITY,
            principal_point: Vec2::ZERO,
            aperture,
            focal_distance: 5.0,
            shutter: [0.0, 1.0],
            width: 200,
            height: 100,
            border: 0,
        })
    }

    /// Four rays at once are, lane by lane, the rays made one by one, for
    /// film positions over and past the image and an oblique view; a lens
    /// or a moving camera has no four-wide path.
    #[test]
    fn four_rays_match_one_by_one() {
        use crate::sampling::Rng;
        let mut spec = cam(0.0).spec.clone();
        spec.position = [Vec3::new(1.3, 2.1, 4.7); 2];
        spec.look_at = [Vec3::new(-0.2, 0.4, 0.1); 2];
        spec.width = 801;
        let c = Camera::new(spec);
        let mut r = Rng::new(3);
        for _ in 0..5000 {
            let film = [(); 4].map(|_| Vec2::new(r.range(-5.0, 810.0), r.range(-5.0, 110.0)));
            let time = [(); 4].map(|_| r.next_f32());
            let four = c.rays4(film, time).expect("a still pinhole camera");
            for i in 0..4 {
                let lens = Vec2::ZERO;
                let one = c.ray(&CameraSample {
                    film: film[i],
                    lens,
                    time: time[i],
                });
                let bits = |r: &Ray| {
                    (
                        r.origin.to_array(),
                        r.dir.to_array().map(f32::to_bits),
                        r.time,
                    )
                };
                assert_eq!(bits(&four[i]), bits(&one), "{:?}", film[i]);
            }
        }
        assert!(cam(0.5).rays4([Vec2::ZERO; 4], [0.0; 4]).is_none());
        let mut moving = cam(0.0).spec.clone();
        moving.position[1] = Vec3::ONE;
        assert!(Camera::new(moving)
            .rays4([Vec2::ZERO; 4], [0.0; 4])
            .is_none());
    }

    /// A batch is the portable rays in order, whatever its length and
    /// camera (the four-wide path covers the multiples of four).
    #[test]
    fn batches_are_the_portable_rays_in_order() {
        use crate::sampling::Rng;
        let mut r = Rng::new(8);
        let mut moving = cam(0.0).spec.clone();
        moving.position[1] = Vec3::ONE;
        for c in [cam(0.0), cam(0.5), Camera::new(moving)] {
            for n in [0, 1, 3, 4, 7, 16] {
                let samples: Vec<CameraSample> = (0..n)
                    .map(|_| CameraSample {
                        film: Vec2::new(r.range(0.0, 200.0), r.range(0.0, 100.0)),
                        lens: Vec2::new(r.range(-0.7, 0.7), r.range(-0.7, 0.7)),
                        time: r.next_f32(),
                    })
                    .collect();
                let mut out = vec![Ray::new(Vec3::ZERO, Vec3::X, 0.0)];
                c.generate(&samples, &mut out);
                assert_eq!(out.len(), n + 1, "appends");
                for (s, got) in samples.iter().zip(&out[1..]) {
                    let want = c.ray(s);
                    assert_eq!(want.dir.to_array(), got.dir.to_array());
                    assert_eq!(want.origin.to_array(), got.origin.to_array());
                }
            }
        }
    }

    /// A point a camera ray of film position `f` meets is seen at `f`, from
    /// the ray's origin, by the pinhole, the thin lens (from the ray's lens
    /// point) and the orthographic camera; and a perspective camera's
    /// importance is `1 / (A cos³θ r²)`, `A` the image's area at distance 1
    /// (Mitsuba's normalisation: uniform film points have the solid-angle
    /// density `1 / (A cos³θ)`).
    #[test]
    fn points_are_seen_where_their_rays_leave() {
        use crate::sampling::Rng;
        let mut r = Rng::new(5);
        let mut ortho = cam(0.0).spec.clone();
        ortho.projection = Projection::Orthographic;
        for c in [cam(0.0), cam(0.5), Camera::new(ortho)] {
            for _ in 0..500 {
                let s = CameraSample {
                    film: Vec2::new(r.range(0.0, 200.0), r.range(0.0, 100.0)),
                    lens: if c.has_lens() {
                        Vec2::new(r.range(-0.6, 0.6), r.range(-0.6, 0.6))
                    } else {
                        Vec2::ZERO
                    },
                    time: 0.0,
                };
                let ray = c.ray(&s);
                let p = ray.at(r.range(0.5, 9.0));
                let seen = c.see(p, 0.0, s.lens).expect("seen");
                let off = (seen.film - s.film).abs().max_element();
                assert!(off < 2e-3, "{:?} {:?}", seen.film, s.film);
                assert!((seen.at - ray.origin).length() < 1e-4);
                if c.spec.projection == Projection::Perspective {
                    let to = p - seen.at;
                    let cos = to.normalize().dot(-Vec3::Z);
                    let w = seen.weight * to.length_squared() * cos.powi(3) * c.image_area();
                    assert!((w - 1.0).abs() < 1e-4, "{w}");
                }
            }
        }
        // Behind the camera, and off the film.
        let c = cam(0.0);
        assert!(c.see(Vec3::new(0.0, 0.0, 6.0), 0.0, Vec2::ZERO).is_none());
        assert!(c.see(Vec3::new(0.0, 4.0, 0.0), 0.0, Vec2::ZERO).is_none());
    }

    #[test]
    fn centre_pixel_looks_at_target() {
        let r = cam(0.0).ray(&CameraSample {
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
        let pin = cam(0.0).ray(&CameraSample {
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
            let r = c.ray(&CameraSample {
                film,
                lens,
                time: 0.0,
            });
            let t = (r.origin.z - focus.z) / -r.dir.z;
            assert!((r.at(t) - focus).length() < 1e-4);
        }
    }

    fn at(film: Vec2) -> CameraSample {
        CameraSample {
            film,
            lens: Vec2::ZERO,
            time: 0.0,
        }
    }

    /// An orthographic camera's rays are all along the view axis and start
    /// on the rectangle of its view size centred on the eye, covering it:
    /// the film's corners go to the rectangle's corners.
    #[test]
    fn orthographic_rays_are_parallel_and_cover_the_view() {
        let mut spec = cam(0.0).spec.clone();
        spec.projection = Projection::Orthographic;
        spec.position = [Vec3::new(1.0, 2.0, 3.0); 2];
        spec.look_at = [Vec3::new(1.0, 2.0, -7.0); 2];
        spec.view_size = Vec2::new(6.0, 1.5);
        let c = Camera::new(spec);
        let corner = |x: f32, y: f32| c.ray(&at(Vec2::new(x, y))).origin;
        let near = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
        assert!(near(corner(0.0, 0.0), Vec3::new(-2.0, 2.75, 3.0)));
        assert!(near(corner(200.0, 0.0), Vec3::new(4.0, 2.75, 3.0)));
        assert!(near(corner(0.0, 100.0), Vec3::new(-2.0, 1.25, 3.0)));
        assert!(near(corner(200.0, 100.0), Vec3::new(4.0, 1.25, 3.0)));
        assert!(near(corner(100.0, 50.0), Vec3::new(1.0, 2.0, 3.0)));
        let mut samples = Vec::new();
        let mut r = crate::sampling::Rng::new(4);
        for _ in 0..100 {
            let film = Vec2::new(r.range(0.0, 200.0), r.range(0.0, 100.0));
            samples.push(at(film));
        }
        let mut rays = Vec::new();
        c.generate(&samples, &mut rays);
        for (s, ray) in samples.iter().zip(&rays) {
            assert_eq!(ray.dir, -Vec3::Z);
            // Linear in the film position.
            let want = Vec3::new(
                -2.0 + 6.0 * s.film.x / 200.0,
                2.75 - 1.5 * s.film.y / 100.0,
                3.0,
            );
            assert!(near(ray.origin, want), "{:?} {want:?}", ray.origin);
        }
    }

    /// The clip interval of a perspective ray is the planes' distances
    /// along it (the axial distance over its cosine with the axis); an
    /// orthographic ray's is the axial one; a camera without planes has
    /// none.
    #[test]
    fn clip_planes_are_perpendicular_to_the_axis() {
        assert_eq!(cam(0.0).clip(&Ray::new(Vec3::ZERO, -Vec3::Z, 0.0)), None);
        let mut spec = cam(0.0).spec.clone();
        (spec.near_clip, spec.far_clip) = (2.0, 4.0);
        let c = Camera::new(spec.clone());
        for film in [Vec2::new(0.0, 0.0), Vec2::new(150.0, 20.0)] {
            let ray = c.ray(&at(film));
            let (near, far) = c.clip(&ray).expect("clip planes");
            assert!((ray.at(near).z - 3.0).abs() < 1e-5, "{:?}", ray.at(near));
            assert!((ray.at(far).z - 1.0).abs() < 1e-5, "{:?}", ray.at(far));
        }
        spec.projection = Projection::Orthographic;
        let c = Camera::new(spec);
        let ray = c.ray(&at(Vec2::new(13.0, 71.0)));
        assert_eq!(c.clip(&ray), Some((2.0, 4.0)));
    }

    /// A principal point offset of (a, b) makes at film point p the ray
    /// the centred camera makes at p + (a·width, b·height), for every
    /// form of the camera.
    #[test]
    fn principal_point_shifts_the_film() {
        let mut spec = cam(0.0).spec.clone();
        spec.principal_point = Vec2::new(0.25, -0.125);
        let shifted = Camera::new(spec.clone());
        let centred = cam(0.0);
        let (film, moved) = (Vec2::new(20.0, 40.0), Vec2::new(70.0, 27.5));
        let a = shifted.ray(&at(film));
        let b = centred.ray(&at(moved));
        assert!((a.dir - b.dir).length() < 1e-6, "{:?} {:?}", a.dir, b.dir);
        let mut four = Vec::new();
        shifted.generate(&[at(film); 4], &mut four);
        assert!(four.iter().all(|r| (r.dir - b.dir).length() < 1e-6));
        spec.projection = Projection::Orthographic;
        let shifted = Camera::new(spec.clone());
        spec.principal_point = Vec2::ZERO;
        let centred = Camera::new(spec);
        let a = shifted.ray(&at(film));
        let b = centred.ray(&at(moved));
        assert!((a.origin - b.origin).length() < 1e-6);
    }
}
