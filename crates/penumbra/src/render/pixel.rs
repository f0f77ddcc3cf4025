use super::BadSample;
use crate::camera::CameraSample;
use crate::integrator::{RunningMean, Tracer};
use crate::material::Rgb;
use crate::math::{Vec2, Vec3};
use crate::sampling::points::unit_disk;
use crate::sampling::Rng;
use crate::scene::Scene;

/// The value of pixel (x, y): the average of its primary rays. Film positions,
/// lens points and times come from three decorrelated streams, each set in its
/// own shuffled trace order, so pairing them by index mixes them randomly.
pub fn render_pixel(
    scene: &Scene,
    tracer: &mut Tracer<'_>,
    x: u32,
    y: u32,
    bad: &mut Vec<BadSample>,
) -> Rgb {
    let s = &scene.settings;
    let cam = &scene.camera;
    let n = s.spp as usize;
    let pixel = Rng::new(s.seed).derive(u64::from(y) * u64::from(s.width) + u64::from(x));
    let mut film = Vec::with_capacity(n);
    s.pixel.generate(n, 0.5, &mut pixel.derive(0), &mut film);
    let mut lens = Vec::new();
    if cam.aperture > 0.0 {
        s.lens.generate(n, 1.0, &mut pixel.derive(1), &mut lens);
    }
    let mut times = Vec::new();
    if cam.shutter[0] < cam.shutter[1] {
        s.time.generate_1d(n, &mut pixel.derive(2), &mut times);
    }
    let metric = s.metric.filter(|m| m.pixels);
    let mut mean = RunningMean::default();
    for (i, f) in film.iter().enumerate() {
        let sample = CameraSample {
            film: Vec2::new(x as f32 + 0.5 + f.x, y as f32 + 0.5 + f.y),
            lens: lens
                .get(i)
                .map_or(Vec2::ZERO, |p: &Vec3| unit_disk(*p, s.lens)),
            time: cam.time(times.get(i).copied().unwrap_or(0.0)),
        };
        let ray = cam.generate_ray(&sample);
        tracer.stats.primary += 1;
        let mut l = tracer.radiance(&ray, 0, pixel.derive(3 + i as u64));
        if !l.is_finite() {
            bad.push(BadSample {
                x,
                y,
                sample: i as u32,
            });
            l = Rgb::ZERO;
        }
        if mean.push(l, metric.as_ref(), n as u32) {
            tracer.stats.saved.primary += (n - i - 1) as u64;
            break;
        }
    }
    mean.mean()
}
