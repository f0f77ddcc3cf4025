//! `ptracer`: a particle tracer, as Mitsuba 3's `ptracer` (an adjoint
//! integrator): paths leave the emitters, and every vertex they make is
//! connected to the camera and splatted where the camera sees it.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `max_depth` | integer ≥ −1 | `-1` | the longest path, in vertices counted from the camera as `path` counts them: 0 renders black, 1 only the emitters seen directly, 2 direct light, −1 no bound |
//! | `rr_depth` | integer ≥ 1 | `5` | the depth from which Russian roulette may end a light path |
//! | `hide_emitters` | bool | `false` | emitters seen directly are black; what they light is not |
//! | `samples_per_pass` | integer ≥ 1 | all | light paths per pixel of the frame in each pass (Mitsuba's) |
//! | `passes` | integer ≥ 1 | `1` | passes (Penumbra's) |
//!
//! # The estimator
//!
//! A render of `spp` samples traces `spp` light paths per pixel of the
//! frame, `spp · width · height` in all, as Mitsuba launches them. Each
//! path chooses one emitter uniformly, draws a ray leaving it
//! ([`Emitter::sample_ray`](crate::emitter::Emitter::sample_ray): from a
//! surface, a point or a disk facing the scene from infinity) and follows
//! it by BSDF sampling. At each surface it meets, the camera is asked how
//! it sees the point ([`Camera::see`](crate::camera::Camera::see):
//! film position and importance `W cos θ / r²`), a shadow ray tests the
//! connection, and the particle's power times the BSDF toward the camera
//! (times the cosine there), the importance and `1 / spp` is splatted at
//! that film position through the film's filter, normalised over its
//! footprint (Mitsuba's normalised `ImageBlock`). A pixel's value is the sum
//! of what reached it: with the box filter, the radiance it sees.
//!
//! Emitters seen directly are connected separately, as Mitsuba does: a
//! second emitter is chosen, a point of its surface drawn
//! ([`Emitter::sample_position`](crate::emitter::Emitter::sample_position))
//! and connected to the camera with its emitted radiance; an emitter at
//! infinity is drawn in a direction from the eye. Delta emitters are never
//! seen.
//!
//! The BSDFs are Penumbra's (radiance transport). At a connection the BSDF
//! is evaluated with the light arriving from the previous vertex and leaving
//! toward the camera, which is the measurement itself. A sampled direction
//! is drawn by the BSDF as if the previous vertex were the viewer; where it
//! refracts, the radiance scaling `1 / η²` the sample carries is undone
//! (times `η²`, the sample's relative index), which is pbrt-v4's
//! `TransportMode::Importance` and Mitsuba's adjoint BSDF. Shading normals
//! take Veach's correction `|cos θ_i^s cos θ_o^g| / |cos θ_o^s cos θ_i^g|`
//! (the importance side's shading cosine swapped for its geometric one),
//! and a direction on opposite sides of the two normals ends the path (no
//! light leaks), as in Mitsuba. From `rr_depth` on, a path survives with
//! probability `min(max(throughput) · η², 0.95)` and is divided by it.
//! A connection is blocked by any surface a camera ray would meet, and a
//! light path meets every surface, those that cast no shadow
//! (`casts_shadows = false`, a `[[lights]]` light's by default) included:
//! such a surface, which `path`'s shadow rays cross, blocks light paths.
//! Cameras: the pinhole and thin lens (an aperture point drawn uniformly
//! per connection) perspective cameras and the orthographic one; a pinhole
//! sees emitters at infinity directly, the others do not (the measure of
//! the directions they see from one point is zero).
//!
//! # Units of work and the film
//!
//! Light paths are numbered as camera samples are: light path `(p, i)`,
//! for pixel `p` and sample `i`, draws its numbers from the stream of
//! primary sample `i` of pixel `p` (see the
//! [stream table](crate::integrator#random-streams)), so the render driver
//! hands a tile job the light paths of its pixels and range of samples,
//! and how the work is cut changes no value. Its splats land anywhere on
//! the frame: the driver gives each job a light image of the region
//! rendered ([`Integrator::splats_anywhere`]), in the fixed-point sums of
//! [`splat`](crate::integrator::splat), which merge in any order into the
//! same integers, and adds them up at the end. An image is therefore the
//! same bit for bit on any number of threads, in any number of passes and
//! with any tile size. A region (a crop window, a `render_region` call, a
//! Dask tile) traces every light path of the frame and keeps its own
//! pixels, which are the frame's bits: a region costs the whole frame's
//! light paths, and a frame cut into `k` Dask tiles costs `k` frames.

mod config;
pub mod plugin;

pub use config::{PtracerSettings, PLUGINS};
pub use plugin::PtracerPlugin;

use super::film::FilmTile;
use super::interface::{BadSample, Integrator, PixelWorker, TileJob};
use super::shading::ShadingPoint;
use super::splat::SplatFilm;
use super::stats::RayStats;
use super::streams;
use crate::bsdf::BsdfFlags;
use crate::camera::Seen;
use crate::math::{reach, Ray, Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_disk_concentric;
use crate::sampling::{Rng, Sampler, SetPoint};
use crate::scene::Scene;

/// Where a connection to the camera ends, as a fraction of the way: short
/// of the lens.
const SHADOW_END: f32 = 1.0 - 1e-4;

/// The most a path survives Russian roulette with.
const RR_MAX: f32 = 0.95;

/// The particle tracer, with its settings, ready to render a scene.
#[derive(Clone, Debug)]
pub struct Ptracer {
    pub settings: PtracerSettings,
    /// Light paths per pixel of the frame.
    pub spp: u32,
    /// The scene's bounding sphere (centre, radius), which rays from
    /// emitters at infinity enter through.
    pub sphere: (Vec3, f32),
}

impl Ptracer {
    /// The integrator of `settings` for `scene`.
    pub fn new(scene: &Scene, settings: PtracerSettings) -> Ptracer {
        let b = scene.world.bounds();
        let radius = 0.5 * (b.max - b.min).length();
        let sphere = if radius.is_finite() && radius > 0.0 {
            (0.5 * (b.min + b.max), radius)
        } else {
            (Vec3::ZERO, 1.0)
        };
        Ptracer {
            settings,
            spp: scene.settings.spp,
            sphere,
        }
    }
}

impl Integrator for Ptracer {
    type Worker<'s> = PtracerWorker<'s>;
    type TileState = ();

    fn worker<'s>(&'s self, scene: &'s Scene) -> PtracerWorker<'s> {
        PtracerWorker {
            scene,
            tracer: self,
            stats: RayStats::default(),
        }
    }

    fn samples(&self) -> u32 {
        self.spp
    }

    fn passes(&self) -> u32 {
        self.settings.passes_of(self.spp)
    }

    fn whole_tiles(&self) -> bool {
        false
    }

    /// 64 pixels: a job of 4,096 light paths per sample, few enough jobs
    /// that merging their light images costs little.
    fn tile(&self) -> u32 {
        64
    }

    fn splats_anywhere(&self) -> bool {
        true
    }
}

/// A [`Ptracer`] worker: its ray counts.
pub struct PtracerWorker<'s> {
    scene: &'s Scene,
    tracer: &'s Ptracer,
    stats: RayStats,
}

/// What one light path adds to the light image, and where a bad value is
/// reported.
struct Splats<'a> {
    film: &'a mut SplatFilm,
    bad: &'a mut Vec<BadSample>,
    /// The light path: its pixel and sample.
    id: (u32, u32, u32),
    /// `1 / spp`.
    scale: f32,
}

impl Splats<'_> {
    /// Splats `v` (times `1 / spp`) at film position `at`, or reports it
    /// if it is not finite.
    fn put(&mut self, at: Vec2, v: Rgb) {
        let v = v * self.scale;
        if !v.is_finite() {
            let (x, y, sample) = self.id;
            self.bad.push(BadSample { x, y, sample });
            return;
        }
        if v.max_element() > 0.0 || v.min_element() < 0.0 {
            self.film.put_light(at, v);
        }
    }
}

impl PixelWorker for PtracerWorker<'_> {
    type State = ();

    fn render(
        &mut self,
        tile: TileJob<'_>,
        _: &mut (),
        film: &mut FilmTile,
        bad: &mut Vec<BadSample>,
    ) -> bool {
        // The driver hands a particle tracer a light image of the region
        // (see `Integrator::splats_anywhere`); without one nothing lands.
        let Some(light) = film.splat.as_mut() else {
            return true;
        };
        let s = &self.scene.settings;
        let sampler = Sampler::new(s.seed, s.width, s.spp);
        let scale = 1.0 / self.tracer.spp.max(1) as f32;
        let (xs, samples) = (tile.xs.clone(), tile.samples.clone());
        tile.rows(1, |ys| {
            for y in ys {
                for x in xs.clone() {
                    let pixel = sampler.pixel(x, y);
                    for i in samples.clone() {
                        let mut out = Splats {
                            film: &mut *light,
                            bad: &mut *bad,
                            id: (x, y, i),
                            scale,
                        };
                        self.path(pixel.path(i as usize), &mut out);
                    }
                }
            }
        })
    }

    fn stats(&self) -> &RayStats {
        &self.stats
    }

    fn clear_counts(&mut self) {
        self.stats = RayStats::default();
    }
}

impl PtracerWorker<'_> {
    /// Traces the light path of stream `path`.
    fn path(&mut self, path: Rng, out: &mut Splats<'_>) {
        let scene = self.scene;
        let n = scene.emitters.len();
        if n == 0 {
            return;
        }
        let set = self.tracer.settings;
        let cam = &scene.camera;
        // The emission's numbers: time, emitter, position, direction.
        let mut u = path.derive(streams::bounce(0));
        let t = u.next_f32();
        let time = cam.time(if cam.shutter_open() { t } else { 0.0 });
        if set.max_depth != Some(0) && !set.hide_emitters {
            self.seen_emitter(path.derive(streams::SEEN_EMITTER), time, out);
        }
        let (k, pick) = choose(u.next_f32(), n);
        let (u_pos, u_dir) = (point(&mut u), point(&mut u));
        let emitter = &scene.emitters[k];
        let Some(ray) = emitter.sample_ray(u_pos, u_dir, time, self.tracer.sphere) else {
            return;
        };
        let mut beta = ray.weight * pick;
        if beta.max_element() <= 0.0 || beta.max_element().is_nan() {
            return;
        }
        let origin = match ray.normal {
            Some(nl) => {
                let at = ShadingPoint {
                    p: ray.origin,
                    ng: nl,
                    reach: reach(ray.origin, ray.origin),
                    time,
                };
                at.origin(ray.dir)
            }
            None => ray.origin,
        };
        let mut r = Ray::new(origin, ray.dir, time);
        let max_depth = set.max_depth.unwrap_or(u32::MAX);
        let mut depth = 1u32;
        let mut eta2 = 1.0f32;
        self.stats.primary += 1;
        while depth < max_depth {
            let Some(hit) = scene.world.intersect(&r, 0.0, f32::INFINITY) else {
                return;
            };
            let mut u = path.derive(streams::bounce(depth));
            let lens = square_to_disk_concentric(point(&mut u));
            let bsdf = &scene.bsdfs[hit.material as usize];
            // Toward the light the particle came from.
            let wl = -r.dir.normalize();
            let at = ShadingPoint::new(&r, hit.p, hit.ng);
            let (ng, ns) = (hit.ng, hit.n);
            if let Some(seen) = cam.see(hit.p, time, lens) {
                let to = seen.at - hit.p;
                let wc = to.normalize_or_zero();
                let (li_s, li_g) = (wl.dot(ns), wl.dot(ng));
                let (lc_s, lc_g) = (wc.dot(ns), wc.dot(ng));
                if li_s * li_g > 0.0 && lc_s * lc_g > 0.0 {
                    let correction = ((li_s * lc_g) / (lc_s * li_g)).abs();
                    let f = bsdf.eval(&hit, wc, wl);
                    let v = beta * f * (lc_s.abs() * correction * seen.weight);
                    if v.max_element() > 0.0 {
                        self.connect(&at, wc, &seen, v, out);
                    }
                }
            }
            // The next direction, drawn as if the light's side were the
            // viewer's.
            let mut sp = SetPoint::uniform(point(&mut u));
            let roulette = u.next_f32();
            let third = u.next_f32();
            if bsdf.wants_third() {
                sp = sp.with_third(third);
            }
            let Some(s) = bsdf.sample(&hit, wl, None, sp) else {
                return;
            };
            if !s.flags.is_delta() && (s.pdf <= 0.0 || s.pdf.is_nan()) {
                return;
            }
            let wn = s.wi;
            let (li_s, li_g) = (wl.dot(ns), wl.dot(ng));
            let (ln_s, ln_g) = (wn.dot(ns), wn.dot(ng));
            if !(li_s * li_g > 0.0 && ln_s * ln_g > 0.0) {
                return;
            }
            let correction = ((li_s * ln_g) / (ln_s * li_g)).abs();
            // The adjoint: the radiance scaling of a refraction undone.
            beta *= s.weight * (s.eta * s.eta * correction);
            eta2 *= s.eta * s.eta;
            if beta.max_element() <= 0.0 || beta.max_element().is_nan() {
                return;
            }
            if s.flags.contains(BsdfFlags::TRANSMISSION) {
                self.stats.refraction += 1;
            } else {
                self.stats.reflection += 1;
            }
            depth += 1;
            if depth > set.rr_depth {
                let q = (beta.max_element() * eta2).min(RR_MAX);
                if roulette >= q || q.is_nan() {
                    return;
                }
                beta /= q;
            }
            r = at.spawn_ray(wn);
        }
    }

    /// Splats `v` where the camera sees the shading point `at` if nothing
    /// lies between (`wc` the unit direction toward the camera).
    fn connect(&mut self, at: &ShadingPoint, wc: Vec3, seen: &Seen, v: Rgb, out: &mut Splats<'_>) {
        let origin = at.origin(wc);
        let shadow = at.spawn_ray_to(origin, seen.at);
        self.stats.shadow += 1;
        // Every surface a camera ray would meet blocks it, shadow-casting or
        // not.
        if self
            .scene
            .world
            .intersect(&shadow, 0.0, SHADOW_END)
            .is_none()
        {
            out.put(seen.film, v);
        }
    }

    /// The emitters seen directly (Mitsuba's `sample_visible_emitters`):
    /// one chosen uniformly with the numbers of `stream`; a point of its
    /// surface connected to the camera with its radiance toward it, or for
    /// an emitter at infinity a direction from a pinhole's eye.
    fn seen_emitter(&mut self, mut stream: Rng, time: f32, out: &mut Splats<'_>) {
        let scene = self.scene;
        let cam = &scene.camera;
        let (k, pick) = choose(stream.next_f32(), scene.emitters.len());
        let u = point(&mut stream);
        let lens = square_to_disk_concentric(point(&mut stream));
        let emitter = &scene.emitters[k];
        if emitter.is_delta() {
            return;
        }
        if emitter.is_infinite() {
            let Some((to, l, pdf)) = emitter.sample_direction(u) else {
                return;
            };
            let Some((film, w)) = cam.see_direction(to, time) else {
                return;
            };
            if pdf <= 0.0 || pdf.is_nan() {
                return;
            }
            let ray = Ray::new(cam.eye(time), to, time);
            let range = cam.clip(&ray).unwrap_or((0.0, f32::INFINITY));
            self.stats.shadow += 1;
            if scene.world.intersect(&ray, range.0, range.1).is_none() {
                out.put(film, l * (pick * w / pdf));
            }
            return;
        }
        let Some(sp) = emitter.sample_position(u, time) else {
            return;
        };
        let Some(seen) = cam.see(sp.p, time, lens) else {
            return;
        };
        let wc = (seen.at - sp.p).normalize_or_zero();
        // The radiance leaving toward the camera (a camera ray's `-wc`).
        let le = emitter.eval(sp.n, sp.uv, -wc);
        let cos = sp.n.dot(wc).abs();
        let v = le * (pick * sp.inv_pdf * cos * seen.weight);
        if v.max_element() <= 0.0 || v.max_element().is_nan() {
            return;
        }
        let at = ShadingPoint {
            p: sp.p,
            ng: sp.n,
            reach: reach(sp.p, seen.at),
            time,
        };
        self.connect(&at, wc, &seen, v, out);
    }
}

/// The emitter the number `u` chooses among `n` uniformly, and the inverse
/// of its probability.
fn choose(u: f32, n: usize) -> (usize, f32) {
    let k = ((u * n as f32) as usize).min(n - 1);
    (k, n as f32)
}

/// The next two numbers of `u` as a point of the unit square.
fn point(u: &mut Rng) -> Vec2 {
    let x = u.next_f32();
    Vec2::new(x, u.next_f32())
}
