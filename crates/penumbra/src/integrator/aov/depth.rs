//! `depth`: the distance along each camera ray to its first hit as the
//! image (0 where it meets nothing), Mitsuba 3's `depth` integrator. The
//! distance is measured from where the ray starts, the camera's near clip
//! plane, as Mitsuba's camera rays start there.

use crate::accel::{Hit, Hits};
use crate::integrator::clip::first_hits;
use crate::integrator::film::FilmTile;
use crate::integrator::interface::{BadSample, Integrator, PixelWorker, TileJob};
use crate::integrator::stats::RayStats;
use crate::integrator::whitted::{camera_samples_of, guard, CameraRays};
use crate::math::Rgb;
use crate::scene::Scene;

/// The depth integrator of a scene: its camera rays per pixel.
#[derive(Clone, Debug)]
pub struct Depth {
    pub spp: u32,
}

impl Depth {
    pub fn new(scene: &Scene) -> Depth {
        Depth {
            spp: scene.settings.spp,
        }
    }
}

impl Integrator for Depth {
    type Worker<'s> = DepthWorker<'s>;
    type TileState = ();

    fn worker<'s>(&'s self, scene: &'s Scene) -> DepthWorker<'s> {
        DepthWorker {
            scene,
            cam: CameraRays::default(),
            found: Hits::default(),
            hits: Vec::new(),
            stats: RayStats::default(),
        }
    }

    fn samples(&self) -> u32 {
        self.spp
    }

    fn passes(&self) -> u32 {
        1
    }

    fn whole_tiles(&self) -> bool {
        false
    }

    fn tile(&self) -> u32 {
        64
    }
}

/// A [`Depth`] worker: its buffers and ray counts.
pub struct DepthWorker<'s> {
    scene: &'s Scene,
    cam: CameraRays,
    /// The camera rays' first hits, compact, then as records.
    found: Hits,
    hits: Vec<Option<Hit>>,
    stats: RayStats,
}

impl PixelWorker for DepthWorker<'_> {
    type State = ();

    fn render(
        &mut self,
        tile: TileJob<'_>,
        _: &mut (),
        film: &mut FilmTile,
        bad: &mut Vec<BadSample>,
    ) -> bool {
        let (xs, samples) = (&tile.xs, &tile.samples);
        let m = samples.len();
        if m == 0 {
            return true;
        }
        let scene = self.scene;
        tile.rows(1, |ys| {
            for y in ys {
                self.cam.clear();
                let keep = samples.start as usize..samples.end as usize;
                camera_samples_of(scene, (xs.clone(), y), keep, &mut self.cam);
                first_hits(scene, &self.cam.rays, &mut self.found, &mut self.hits);
                self.stats.primary += self.cam.rays.len() as u64;
                let mut q = 0;
                for x in xs.clone() {
                    let k = film.index(x, y);
                    for i in samples.clone() {
                        let ray = &self.cam.rays[q];
                        let t = self.hits[q].as_ref().map_or(0.0, |h| {
                            let near = scene.camera.clip(ray).map_or(0.0, |(near, _)| near);
                            (h.t - near) * ray.dir.length()
                        });
                        let l = guard(Rgb::splat(t), x, y, i as usize, bad);
                        film.add(k, l, self.cam.weights[q], self.cam.offsets[q]);
                        q += 1;
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
