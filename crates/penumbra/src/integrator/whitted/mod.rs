//! The thesis's integrator: Whitted recursion in which every event traces a
//! set of rays from its own distribution (see the [module above](super)).
//!
//! Rays are traced in batches ([`Tracer::radiance`]): a pixel's camera rays
//! (a span of neighbouring pixels of a row in a frame of one camera ray per
//! pixel), then each hit's reflection and refraction sets, a level deeper.
//! A batch's hits are found together (a packet where its rays are nearly
//! parallel) and its direct light prepared together, light by light.

mod adaptive;
mod pixel;
mod tracer;

use std::ops::Range;

pub use tracer::Tracer;

use super::interface::{by_rows, BadSample, Integrator, PixelWorker, TileJob};
use super::stats::RayStats;
use super::stopping::{PixelSamples, Stopper};
use crate::math::Rgb;
use crate::scene::Scene;

/// The thesis's distributed Whitted integrator.
#[derive(Clone, Copy, Debug, Default)]
pub struct Whitted;

impl Integrator for Whitted {
    type Worker<'s> = WhittedWorker<'s>;

    fn worker<'s>(&'s self, scene: &'s Scene) -> WhittedWorker<'s> {
        let s = &scene.settings;
        let image = s.width as usize * s.height as usize;
        WhittedWorker {
            scene,
            tracer: Tracer::new(scene),
            stopper: s.stopping.map(|rule| Stopper::new(rule, s.spp, image)),
            samples: Vec::new(),
        }
    }
}

/// A [`Whitted`] worker: a tracer with its buffers and ray counts.
pub struct WhittedWorker<'s> {
    scene: &'s Scene,
    tracer: Tracer<'s>,
    /// The adaptive sampling rule, if on.
    stopper: Option<Stopper>,
    /// How the pixels of the tiles rendered adaptively ended.
    samples: Vec<PixelSamples>,
}

impl PixelWorker for WhittedWorker<'_> {
    fn row(&mut self, y: u32, xs: Range<u32>, out: &mut Vec<Rgb>, bad: &mut Vec<BadSample>) {
        pixel::render_pixels(self.scene, &mut self.tracer, xs, y, bad, out);
    }

    fn tile(&mut self, tile: TileJob<'_>, out: &mut Vec<Rgb>, bad: &mut Vec<BadSample>) -> bool {
        let Some(stopper) = &self.stopper else {
            return by_rows(self, tile, out, bad);
        };
        let samples = &mut self.samples;
        adaptive::render_tile(
            self.scene,
            &mut self.tracer,
            stopper,
            tile,
            bad,
            out,
            samples,
        )
    }

    fn take_samples(&mut self) -> Vec<PixelSamples> {
        std::mem::take(&mut self.samples)
    }

    fn stats(&self) -> &RayStats {
        &self.tracer.stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{LoadOptions, SceneSource};

    /// A frame of one camera ray per pixel is rendered in spans of a row;
    /// every pixel is what rendering it alone gives (the showcase at one
    /// sample: lens, motion, mirror, glass and an area light), and the rays
    /// are counted alike.
    #[test]
    fn spans_give_what_single_pixels_give() {
        let mut src = SceneSource::open("showcase", &LoadOptions::default()).expect("built-in");
        src.desc.render.spp = 1;
        let scene = src.build().expect("showcase builds");
        assert_eq!(scene.settings.spp, 1);
        let (xs, ys) = (3..3 + 16 * 2 + 5, 5..12);
        let mut worker = Whitted.worker(&scene);
        let (mut pixels, mut bad) = (Vec::new(), Vec::new());
        for y in ys.clone() {
            worker.row(y, xs.clone(), &mut pixels, &mut bad);
        }
        let mut tracer = Tracer::new(&scene);
        let mut lit = 0;
        let coords = ys.flat_map(|y| xs.clone().map(move |x| (x, y)));
        for (k, (x, y)) in coords.enumerate() {
            let mut one = Vec::new();
            pixel::render_pixels(&scene, &mut tracer, x..x + 1, y, &mut bad, &mut one);
            let alone = one[0];
            let bits = |c: Rgb| c.to_array().map(f32::to_bits);
            assert_eq!(bits(pixels[k]), bits(alone), "pixel ({x}, {y})");
            lit += usize::from(alone != Rgb::ZERO);
        }
        assert_eq!(*worker.stats(), tracer.stats);
        assert!(lit > 100, "{lit} pixels not black");
    }
}
