//! A pixel's camera rays, each sample added to the tile's film: one pixel
//! with its samples, or a span of pixels of one sample each.

use super::tracer::{Continued, Tracer};
use crate::camera::CameraSample;
use crate::integrator::film::FilmTile;
use crate::integrator::interface::{BadSample, TileJob};
use crate::integrator::metric::{Metric, RunningMean};
use crate::math::Rgb;
use crate::math::{Ray, Vec2, Vec3};
use crate::sampling::points::unit_disk;
use crate::sampling::{BranchKey, Dimension, Distribution, PixelSampler, Sampler};
use crate::scene::Scene;
use std::cell::RefCell;
use std::ops::Range;

/// Per-thread buffers of a pixel's film, lens and time sets and its camera
/// rays, so that rendering a pixel allocates nothing once the buffers have
/// grown.
#[derive(Default)]
pub(super) struct Scratch {
    pub(super) film: Vec<Vec3>,
    pub(super) lens: Vec<Vec3>,
    pub(super) times: Vec<f32>,
    pub(super) samples: Vec<CameraSample>,
    /// The pixel filter's weight of each camera sample.
    pub(super) weights: Vec<f32>,
    /// Each camera sample's film position, from its pixel's centre.
    pub(super) offsets: Vec<Vec2>,
    pub(super) rays: Vec<Ray>,
    pub(super) radiance: Vec<Rgb>,
    /// The branch of sample `i`'s path, `3 + i`, hashed once per thread.
    pub(super) paths: Vec<BranchKey>,
    /// The streams of the pixels traced together.
    pub(super) pixels: Vec<PixelSampler>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::default();
}

/// Runs `f` with this thread's buffers. A worker renders one pixel or span
/// at a time; should a caller nest them anyway, the inner one gets fresh
/// buffers.
pub(super) fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    SCRATCH.with(|scratch| match scratch.try_borrow_mut() {
        Ok(mut buf) => f(&mut buf),
        Err(_) => f(&mut Scratch::default()),
    })
}

/// Adds samples `tile.samples` of the pixels of `tile` to `film`, row by
/// row (see [`render_pixels`]); `false` if the tile's cancel flag became
/// true, which is checked before every row. `stopped` marks the pixels the
/// pixel `metric` stopped in earlier ranges (and is marked here).
pub(super) fn render_rows(
    scene: &Scene,
    tracer: &mut Tracer<'_>,
    tile: TileJob<'_>,
    metric: Option<&Metric>,
    mut stopped: Option<&mut Vec<bool>>,
    film: &mut FilmTile,
    bad: &mut Vec<BadSample>,
) -> bool {
    tile.rows(1, |ys| {
        let row = Row {
            xs: tile.xs.clone(),
            y: ys.start,
            samples: tile.samples.clone(),
        };
        render_pixels(
            scene,
            tracer,
            row,
            metric,
            stopped.as_deref_mut(),
            film,
            bad,
        );
    })
}

/// Samples `samples` of pixels `xs` of row `y`.
pub(super) struct Row {
    pub xs: Range<u32>,
    pub y: u32,
    pub samples: Range<u32>,
}

/// Adds samples `row.samples` of pixels `row.xs` of row `row.y` to `film`,
/// each the radiance of its camera ray (made as the private `camera_rays`
/// says: film, lens and time from decorrelated streams), in the order of
/// their index. Without the pixel metric the camera rays of a group of
/// pixels are traced together: a pixel's own when it has several, a span of
/// neighbouring pixels ([`span_width`]) when each has one. Their hits are
/// found together (a packet of nearly parallel rays) and their direct light
/// prepared together ([`Tracer::radiance`]). With the `metric`, a pixel's
/// rays are traced as [`Tracer::continue_mean`] says, so that none is
/// wasted when the pixel stops early; `stopped` marks the pixels it stopped.
/// A sample's value does not depend on its group (but for the rare tie
/// noted at [`World::intersect_all`](crate::accel::World::intersect_all)).
pub fn render_pixels(
    scene: &Scene,
    tracer: &mut Tracer<'_>,
    row: Row,
    metric: Option<&Metric>,
    mut stopped: Option<&mut Vec<bool>>,
    film: &mut FilmTile,
    bad: &mut Vec<BadSample>,
) {
    let Row { xs, y, samples } = row;
    if samples.is_empty() {
        return;
    }
    with_scratch(|buf| {
        let s = &scene.settings;
        let n = s.spp as usize;
        let range = samples.start as usize..samples.end as usize;
        if buf.paths.len() < n {
            let have = buf.paths.len();
            buf.paths.extend((have..n).map(PixelSampler::path_key));
        }
        let group = if n == 1 { span_width(s.width) } else { 1 };
        for x0 in xs.clone().step_by(group as usize) {
            let x1 = (x0 + group).min(xs.end);
            if let (Some(m), Some(stopped)) = (metric, stopped.as_deref_mut()) {
                let k = film.index(x0, y);
                if !stopped[k] {
                    stopped[k] =
                        metric_pixel(scene, tracer, (x0, y), m, range.clone(), film, bad, buf);
                }
                continue;
            }
            camera_rays((scene, tracer.ordered()), x0..x1, y, range.clone(), buf);
            let Scratch {
                rays,
                radiance,
                paths,
                pixels,
                weights,
                offsets,
                ..
            } = buf;
            // Ray `j` is sample `range.start + j % m` of pixel `j / m`, `m`
            // the samples per pixel of the range: with one sample the group
            // is a span of pixels, with several it is one pixel.
            let path = |j: usize| match n {
                1 => pixels[j].path_of(paths[0], 0),
                _ => pixels[0].path_of(paths[range.start + j], range.start + j),
            };
            radiance.clear();
            tracer.radiance(rays, 0, path, radiance);
            let m = range.len();
            for (x, ((samples, weights), offsets)) in (x0..x1).zip(
                radiance
                    .chunks_exact(m)
                    .zip(weights.chunks_exact(m))
                    .zip(offsets.chunks_exact(m)),
            ) {
                let k = film.index(x, y);
                for (j, ((&l, &w), &o)) in samples.iter().zip(weights).zip(offsets).enumerate() {
                    tracer.stats.primary += 1;
                    film.add(k, guard(l, x, y, range.start + j, bad), w, o);
                }
            }
        }
    })
}

/// The camera rays of samples `keep` of pixels `xs` of row `y`, pixel by
/// pixel and each pixel's in the order of their index, appended to `rays`,
/// with the stream of each ray's path appended to `paths`: the rays and
/// streams a Whitted render traces, for the integrators that follow paths
/// instead, and each ray's pixel-filter weight and film offset appended to
/// `film`.
pub(in crate::integrator) fn primary_rays(
    (scene, ordered): (&Scene, bool),
    (xs, y): (Range<u32>, u32),
    keep: Range<usize>,
    rays: &mut Vec<Ray>,
    paths: &mut Vec<crate::sampling::Rng>,
    (weights, offsets): (&mut Vec<f32>, &mut Vec<Vec2>),
) {
    with_scratch(|buf| {
        let n = scene.settings.spp as usize;
        if buf.paths.len() < n {
            let have = buf.paths.len();
            buf.paths.extend((have..n).map(PixelSampler::path_key));
        }
        camera_rays((scene, ordered), xs, y, keep.clone(), buf);
        rays.extend_from_slice(&buf.rays);
        weights.extend_from_slice(&buf.weights);
        offsets.extend_from_slice(&buf.offsets);
        for pixel in &buf.pixels {
            paths.extend(keep.clone().map(|i| pixel.path_of(buf.paths[i], i)));
        }
    })
}

/// The camera rays every integrator traces for samples `keep` of the
/// pixels `xs` of row `y`, pixel by pixel, appended to `out`: the camera
/// samples, their rays, pixel-filter weights and film offsets.
pub(in crate::integrator) fn camera_samples_of(
    scene: &Scene,
    (xs, y): (Range<u32>, u32),
    keep: Range<usize>,
    out: &mut CameraRays,
) {
    with_scratch(|buf| {
        camera_rays((scene, false), xs, y, keep, buf);
        out.samples.extend_from_slice(&buf.samples);
        out.rays.extend_from_slice(&buf.rays);
        out.weights.extend_from_slice(&buf.weights);
        out.offsets.extend_from_slice(&buf.offsets);
    })
}

/// Camera samples with their rays, filter weights and film offsets.
#[derive(Clone, Debug, Default)]
pub(in crate::integrator) struct CameraRays {
    pub samples: Vec<CameraSample>,
    pub rays: Vec<Ray>,
    pub weights: Vec<f32>,
    pub offsets: Vec<Vec2>,
}

impl CameraRays {
    pub fn clear(&mut self) {
        self.samples.clear();
        self.rays.clear();
        self.weights.clear();
        self.offsets.clear();
    }
}

/// Samples `range` of pixel `(x, y)` under the pixel metric, continuing
/// the running mean of its earlier samples (its film); true if the metric
/// stopped it.
#[allow(clippy::too_many_arguments)]
fn metric_pixel(
    scene: &Scene,
    tracer: &mut Tracer<'_>,
    (x, y): (u32, u32),
    m: &Metric,
    range: Range<usize>,
    film: &mut FilmTile,
    bad: &mut Vec<BadSample>,
    buf: &mut Scratch,
) -> bool {
    let n = scene.settings.spp as usize;
    let k = film.index(x, y);
    camera_rays((scene, tracer.ordered()), x..x + 1, y, range.clone(), buf);
    let Scratch {
        rays,
        paths,
        pixels,
        weights,
        offsets,
        ..
    } = buf;
    let path = |i: usize| pixels[0].path_of(paths[i], i);
    // The running mean is of the weighted samples `w·L` (whose mean tends
    // to the pixel's value, the weights' mean being 1), over the samples
    // added before: all of `..range.start`, the pixel not being stopped.
    let set = Continued {
        n,
        rays: range.clone(),
        mean: RunningMean::resume(film.sum[k], range.start as u32),
    };
    let value = |i: usize, l: Rgb| {
        let l = guard(l, x, y, i, bad);
        let w = weights[i - range.start];
        film.add(k, l, w, offsets[i - range.start]);
        l * w
    };
    let ray = |i: usize| rays[i - range.start];
    let (_, end, stopped) = tracer.continue_mean(set, ray, 0, path, Some(m), None, value);
    tracer.stats.primary += (end - range.start) as u64;
    if stopped {
        tracer.stats.saved.primary += (n - end) as u64;
    }
    stopped
}

/// How many pixels of a row are traced together in a frame of one camera
/// ray per pixel (a span): about 2% of the image's width, from 2 to 16.
/// Wider spans hold less coherent rays than a lone ray is worth: on the
/// bunny's Whitted frame (instruction counts) 16 is best at 800 pixels
/// across (8 and 32 cost 5% more) and 4 at 200 (16 costs 3% more than
/// tracing pixel by pixel).
fn span_width(width: u32) -> u32 {
    (width / 50).clamp(2, 16)
}

/// `l`, or black if it is not finite (reported as sample `i` of pixel (x, y)).
pub(in crate::integrator) fn guard(
    l: Rgb,
    x: u32,
    y: u32,
    i: usize,
    bad: &mut Vec<BadSample>,
) -> Rgb {
    if l.is_finite() {
        return l;
    }
    bad.push(BadSample {
        x,
        y,
        sample: i as u32,
    });
    Rgb::ZERO
}

/// The streams of pixel (x, y).
pub(super) fn pixel_stream(scene: &Scene, x: u32, y: u32) -> PixelSampler {
    let s = &scene.settings;
    Sampler::new(s.seed, s.width, s.spp).pixel(x, y)
}

/// The camera rays of samples `keep` of pixels `xs` of row `y`, pixel by
/// pixel, into `buf.rays`: one batch from the camera. The pixels' streams
/// are left in `buf.pixels`.
fn camera_rays(
    (scene, ordered): (&Scene, bool),
    xs: Range<u32>,
    y: u32,
    keep: Range<usize>,
    buf: &mut Scratch,
) {
    buf.pixels.clear();
    buf.pixels
        .extend(xs.clone().map(|x| pixel_stream(scene, x, y)));
    buf.samples.clear();
    buf.weights.clear();
    buf.offsets.clear();
    let n = scene.settings.spp as usize;
    // Without the pixel metric every camera ray is traced and the pixel is
    // their mean, so the order of the film points does not matter; the
    // lens and time sets are still shuffled, which keeps their pairing with
    // the film points random. `ordered`: the pixel metric is on.
    for (k, x) in xs.enumerate() {
        let pixel = buf.pixels[k];
        camera_samples(scene, (x, y), pixel, (n, ordered), keep.clone(), buf);
    }
    buf.rays.clear();
    scene.camera.generate(&buf.samples, &mut buf.rays);
}

/// Appends samples `keep` of the `n` camera samples of pixel (x, y) (drawn
/// from the streams of `pixel`, the film set in trace order if `ordered`)
/// to `buf.samples`, and their pixel-filter weights to `buf.weights`. Film positions, lens points and times come from three
/// decorrelated streams, each set in its own shuffled trace order, so
/// pairing them by index mixes them randomly.
pub(super) fn camera_samples(
    scene: &Scene,
    (x, y): (u32, u32),
    pixel: PixelSampler,
    (n, ordered): (usize, bool),
    keep: Range<usize>,
    buf: &mut Scratch,
) {
    let s = &scene.settings;
    let cam = &scene.camera;
    let Scratch {
        film,
        lens,
        times,
        samples,
        weights,
        offsets,
        ..
    } = buf;
    // The index in the set of the first film point made: a pass of an
    // unordered set makes only its own points where the distribution can.
    let mut first = 0;
    if n == 1 && s.pixel == Distribution::Grid {
        // The one grid point is the pixel centre (what `generate` returns,
        // pinned by a test below), without the set machinery: this is every
        // pixel of a Whitted render.
        film.clear();
        film.push(Vec3::ZERO);
    } else if !ordered
        && keep.len() < n
        && pixel.points_part(
            Dimension::Film,
            (s.pixel, &s.points),
            (n, 0.5),
            keep.clone(),
            film,
        )
    {
        first = keep.start;
    } else {
        pixel.points(Dimension::Film, (s.pixel, &s.points), n, 0.5, ordered, film);
    }
    lens.clear();
    if cam.has_lens() {
        pixel.points(Dimension::Lens, (s.lens, &s.points), n, 1.0, true, lens);
    }
    // Times matter only if something moves: each set has its own stream,
    // so skipping this one changes no other random number.
    times.clear();
    if cam.shutter_open() && (cam.moves() || !scene.world.is_static()) {
        pixel.values(Dimension::Time, (s.time, &s.points), n, times);
    }
    // All camera samples first, so that their hits can be found together
    // (making a ray costs far less than tracing it, so the few a pixel
    // metric may leave untraced are no loss).
    // The film points, warped by the pixel filter (the box leaves them),
    // and their weights (1 but for a filter with negative lobes).
    let f = &s.filter;
    let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
    let pinhole = lens.is_empty() && times.is_empty();
    // A pinhole camera and nothing moving: every sample is a film point at
    // the shutter's opening time.
    let opening = cam.time(0.0);
    for i in keep {
        // A splatting film takes the points as they are, uniform in the
        // pixel, and weighs them where it splats them.
        let p = film[i - first];
        let (offset, w) = if s.splat {
            ([p.x, p.y], 1.0)
        } else {
            f.sample(p.x, p.y)
        };
        weights.push(w);
        offsets.push(Vec2::from(offset));
        let film = centre + Vec2::from(offset);
        samples.push(if pinhole {
            CameraSample {
                film,
                lens: Vec2::ZERO,
                time: opening,
            }
        } else {
            CameraSample {
                film,
                lens: lens
                    .get(i)
                    .map_or(Vec2::ZERO, |p: &Vec3| unit_disk(*p, s.lens)),
                time: cam.time(times.get(i).copied().unwrap_or(0.0)),
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use crate::scene::{LoadOptions, Overrides, SceneSource};

    /// Film positions follow the pixel filter: within the pixel for the
    /// box, spread over the filter's radius (beyond the pixel) for the
    /// others, centred on the pixel's centre; each sample has its weight,
    /// 1 but for the filters with negative lobes, whose weights take both
    /// signs.
    #[test]
    fn film_positions_follow_the_filter() {
        use crate::sampling::Filter;
        for f in Filter::ALL {
            let mut src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
            Overrides {
                spp: Some(64),
                filter: Some(f),
                ..Default::default()
            }
            .apply(&mut src);
            let scene = src.build().expect("showcase builds");
            let mut buf = Scratch::default();
            camera_rays((&scene, false), 5..6, 7, 0..64, &mut buf);
            let (r, c) = (
                crate::sampling::PixelFilter::of(f).radius(),
                Vec2::new(5.5, 7.5),
            );
            let offsets: Vec<Vec2> = buf.samples.iter().map(|s| s.film - c).collect();
            assert!(
                offsets.iter().all(|o| o.abs().max_element() <= r + 1e-5),
                "{f:?}"
            );
            let outside = offsets
                .iter()
                .filter(|o| o.abs().max_element() > 0.5)
                .count();
            assert_eq!(
                outside == 0,
                f == Filter::Box,
                "{f:?}: {outside} outside the pixel"
            );
            let mean = offsets.iter().sum::<Vec2>() / offsets.len() as f32;
            assert!(mean.length() < 0.15 * r, "{f:?}: mean offset {mean:?}");
            assert_eq!(buf.weights.len(), buf.samples.len());
            let signed = matches!(f, Filter::Mitchell | Filter::CatmullRom | Filter::Lanczos);
            let negative = buf.weights.iter().filter(|w| **w < 0.0).count();
            assert_eq!(negative > 0, signed, "{f:?}: {:?}", buf.weights);
            if !signed {
                assert!(buf.weights.iter().all(|w| *w == 1.0), "{f:?}");
            }
        }
    }

    /// The shortcut for one grid ray per pixel gives what the distribution gives.
    #[test]
    fn one_grid_point_is_the_pixel_centre() {
        let mut out = Vec::new();
        for key in 0..100 {
            Distribution::Grid.generate(1, 0.5, &mut Rng::new(key), &mut out);
            assert_eq!(out, [Vec3::ZERO]);
        }
    }

    /// A pixel is the mean of its camera rays' radiance, ray `i` traced with
    /// the stream `pixel.derive(3 + i)` (the sampler's table of streams):
    /// recomputed here one ray at a time, for two sample counts in a row on
    /// one thread, so that the hashed branches kept between pixels are
    /// checked as they grow; the samples added in two ranges give it too.
    #[test]
    fn pixel_streams_are_the_documented_ones() {
        use crate::integrator::whitted::Whitted;
        for spp in [4u32, 16] {
            let mut src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
            Overrides {
                spp: Some(spp),
                ..Default::default()
            }
            .apply(&mut src);
            let scene = src.build().expect("showcase builds");
            let whitted = Whitted::of(&scene);
            let (mut tracer, mut bad) = (Tracer::new(&scene, &whitted), Vec::new());
            for (x, y) in [(3, 5), (40, 30), (17, 60)] {
                let mut film = FilmTile::new(x..x + 1, y..y + 1);
                for samples in [0..spp / 4, spp / 4..spp] {
                    let row = Row {
                        xs: x..x + 1,
                        y,
                        samples,
                    };
                    render_pixels(&scene, &mut tracer, row, None, None, &mut film, &mut bad);
                }
                let got = film.value(0);
                let mut buf = Scratch::default();
                camera_rays((&scene, false), x..x + 1, y, 0..spp as usize, &mut buf);
                let pixel = pixel_stream(&scene, x, y);
                let (mut mean, mut l) = (RunningMean::default(), Vec::new());
                for (i, ray) in buf.rays.iter().enumerate() {
                    tracer.radiance(std::slice::from_ref(ray), 0, |_| pixel.path(i), &mut l);
                    mean.push(l[i], None, spp);
                }
                let want = mean.mean();
                let bits = |c: Rgb| c.to_array().map(f32::to_bits);
                assert_eq!(bits(got), bits(want), "pixel ({x}, {y}) at {spp} spp");
            }
            assert!(bad.is_empty());
        }
    }

    /// Pearson correlation of two samples.
    fn correlation(a: &[f32], b: &[f32]) -> f32 {
        let n = a.len() as f32;
        let (ma, mb) = (a.iter().sum::<f32>() / n, b.iter().sum::<f32>() / n);
        let cov: f32 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
        let var = |v: &[f32], m: f32| v.iter().map(|x| (x - m) * (x - m)).sum::<f32>();
        cov / (var(a, ma) * var(b, mb)).sqrt()
    }

    /// Without the pixel metric a square film set comes in row order, but
    /// the lens set is still shuffled: a sample's film and lens positions
    /// are uncorrelated. Had the lens set come in row order too, they would
    /// correlate strongly (checked below on the same pixels).
    #[test]
    fn film_and_lens_points_pair_at_random() {
        let mut src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
        Overrides {
            spp: Some(16),
            distribution: Some(Distribution::Jitter),
            ..Default::default()
        }
        .apply(&mut src);
        let scene = src.build().expect("showcase builds");
        assert!(scene.camera.has_lens());
        let (mut buf, mut row_order) = (Scratch::default(), Vec::new());
        let (mut film, mut lens, mut lens_in_rows) = (Vec::new(), Vec::new(), Vec::new());
        for p in 0..400 {
            let (x, y) = (p % 20, p / 20);
            camera_rays((&scene, false), x..x + 1, y, 0..16, &mut buf);
            let mut expected = Vec::new();
            let mut rng = pixel_stream(&scene, x, y).stream(Dimension::Film);
            Distribution::Jitter.generate_unordered(16, 0.5, &mut rng, &mut expected);
            assert_eq!(buf.film, expected, "film points in row order");
            film.extend(buf.film.iter().map(|v| v.x));
            lens.extend(buf.lens.iter().map(|v| v.x));
            let mut rng = pixel_stream(&scene, x, y).stream(Dimension::Lens);
            Distribution::Jitter.generate_unordered(16, 1.0, &mut rng, &mut row_order);
            lens_in_rows.extend(row_order.iter().map(|v| v.x));
        }
        // 6400 pairs: an independent pairing gives |r| < 0.05 but for one
        // time in 10^4.
        let r = correlation(&film, &lens);
        assert!(r.abs() < 0.05, "film and lens correlate: r = {r}");
        let r_rows = correlation(&film, &lens_in_rows);
        assert!(
            r_rows > 0.5,
            "row order in both should correlate: r = {r_rows}"
        );
    }
}
