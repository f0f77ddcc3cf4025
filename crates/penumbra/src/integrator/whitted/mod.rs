//! The thesis's integrator: Whitted recursion in which every event traces a
//! set of rays from its own distribution (see the [module above](super)).
//!
//! Rays are traced in batches ([`Tracer::radiance`]): a pixel's camera rays
//! (a span of neighbouring pixels of a row in a frame of one camera ray per
//! pixel), then each hit's reflection and refraction sets, a level deeper.
//! A batch's hits are found together (a packet where its rays are nearly
//! parallel) and its direct light prepared together, light by light.

mod adaptive;
mod config;
mod pixel;
mod state;
mod tracer;

pub use config::{Whitted, WhittedPlugin, WhittedSettings};
pub(super) use pixel::{camera_samples_of, guard, primary_rays, CameraRays};
pub use state::TileState;
pub use tracer::Tracer;

use super::film::FilmTile;
use super::interface::{BadSample, Integrator, PixelWorker, TileJob};
use super::stats::RayStats;
use super::stopping::{PixelSamples, Stopper};
use crate::scene::Scene;

impl Integrator for Whitted {
    type Worker<'s> = WhittedWorker<'s>;
    type TileState = TileState;

    fn worker<'s>(&'s self, scene: &'s Scene) -> WhittedWorker<'s> {
        WhittedWorker {
            scene,
            config: self,
            tracer: Tracer::new(scene, self),
            stopper: self
                .stopping
                .map(|rule| Stopper::new(rule, self.spp, self.image)),
        }
    }

    fn samples(&self) -> u32 {
        self.spp
    }

    fn passes(&self) -> u32 {
        self.passes
    }

    fn whole_tiles(&self) -> bool {
        self.stopping.is_some()
    }

    /// 32 pixels: an adaptive sampling rule judges a pixel by the others
    /// of its tile.
    fn tile(&self) -> u32 {
        32
    }

    fn state_fits(&self, state: &TileState, (w, h): (u32, u32)) -> bool {
        let n = w as usize * h as usize;
        match (state, self.stopping) {
            (TileState::Plain, _) => true,
            (TileState::Stopped(stopped), None) => stopped.len() == n,
            (TileState::Adaptive(s), Some(rule)) => {
                let stopper = Stopper::new(rule, self.spp, self.image);
                let povray = rule.rule == crate::scene::StopRule::Povray;
                s.fits(self.spp)
                    && s.block
                        .fits(w as usize, h as usize, stopper.replicas() as usize, povray)
            }
            _ => false,
        }
    }
}

/// A [`Whitted`] worker: a tracer with its buffers and ray counts.
pub struct WhittedWorker<'s> {
    scene: &'s Scene,
    config: &'s Whitted,
    tracer: Tracer<'s>,
    /// The adaptive sampling rule, if on.
    stopper: Option<Stopper>,
}

impl PixelWorker for WhittedWorker<'_> {
    type State = TileState;

    fn render(
        &mut self,
        tile: TileJob<'_>,
        state: &mut TileState,
        film: &mut FilmTile,
        bad: &mut Vec<BadSample>,
    ) -> bool {
        if let Some(stopper) = &self.stopper {
            return adaptive::render_tile(
                self.scene,
                &mut self.tracer,
                stopper,
                tile,
                state,
                film,
                bad,
            );
        }
        let metric = self
            .config
            .metric
            .filter(|m| m.pixels && self.config.spp > 1);
        if metric.is_some() && matches!(state, TileState::Plain) {
            *state = TileState::Stopped(vec![false; film.sum.len()]);
        }
        let stopped = match state {
            TileState::Stopped(s) => Some(s),
            _ => None,
        };
        pixel::render_rows(
            self.scene,
            &mut self.tracer,
            tile,
            metric.as_ref(),
            stopped,
            film,
            bad,
        )
    }

    fn pixel_samples(&self, state: &TileState) -> Vec<PixelSamples> {
        match (state, &self.stopper) {
            (TileState::Adaptive(s), Some(stopper)) => stopper.samples(&s.block),
            _ => Vec::new(),
        }
    }

    fn stats(&self) -> &RayStats {
        &self.tracer.stats
    }

    fn clear_counts(&mut self) {
        self.tracer.stats = RayStats::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;
    use crate::scene::{LoadOptions, Overrides, SceneSource};

    /// A frame of one camera ray per pixel is rendered in spans of a row;
    /// every pixel is what rendering it alone gives (the showcase at one
    /// sample: lens, motion, mirror, glass and an area light), and the rays
    /// are counted alike.
    #[test]
    fn spans_give_what_single_pixels_give() {
        let mut src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
        Overrides {
            spp: Some(1),
            ..Default::default()
        }
        .apply(&mut src);
        let scene = src.build().expect("showcase builds");
        let whitted = Whitted::of(&scene);
        assert_eq!(whitted.spp, 1);
        let (xs, ys) = (3..3 + 16 * 2 + 5, 5..12);
        let mut worker = whitted.worker(&scene);
        let mut film = FilmTile::new(xs.clone(), ys.clone());
        let mut bad = Vec::new();
        let never = || false;
        let job = TileJob {
            xs: xs.clone(),
            ys: ys.clone(),
            samples: 0..1,
            cancelled: &never,
        };
        assert!(worker.render(job, &mut TileState::default(), &mut film, &mut bad));
        let mut alone = whitted.worker(&scene);
        let mut lit = 0;
        for y in ys.clone() {
            for x in xs.clone() {
                let mut one = FilmTile::new(x..x + 1, y..y + 1);
                let job = TileJob {
                    xs: x..x + 1,
                    ys: y..y + 1,
                    samples: 0..1,
                    cancelled: &never,
                };
                assert!(alone.render(job, &mut TileState::default(), &mut one, &mut bad));
                let bits = |c: Rgb| c.to_array().map(f32::to_bits);
                let k = film.index(x, y);
                assert_eq!(bits(film.value(k)), bits(one.value(0)), "pixel ({x}, {y})");
                lit += usize::from(one.value(0) != Rgb::ZERO);
            }
        }
        assert_eq!(*worker.stats(), *alone.stats());
        assert!(lit > 100, "{lit} pixels not black");
    }
}
