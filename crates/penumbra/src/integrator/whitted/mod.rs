//! The thesis's integrator: Whitted recursion in which every event traces a
//! set of rays from its own distribution (see the [module above](super)).
//!
//! A pixel's camera rays are made together and, without the pixel metric,
//! their hits found together (a packet) and their direct light prepared
//! together, light by light; a frame of one camera ray per pixel does the
//! same for spans of neighbouring pixels of a row.

mod pixel;
mod tracer;

use std::ops::Range;

pub use tracer::Tracer;

use super::interface::{BadSample, Integrator, PixelWorker};
use super::stats::RayStats;
use crate::math::Rgb;
use crate::scene::Scene;

/// The thesis's distributed Whitted integrator.
#[derive(Clone, Copy, Debug, Default)]
pub struct Whitted;

impl Integrator for Whitted {
    type Worker<'s> = WhittedWorker<'s>;

    fn worker<'s>(&'s self, scene: &'s Scene) -> WhittedWorker<'s> {
        WhittedWorker {
            scene,
            tracer: Tracer::new(scene),
        }
    }
}

/// A [`Whitted`] worker: a tracer with its buffers and ray counts.
pub struct WhittedWorker<'s> {
    scene: &'s Scene,
    tracer: Tracer<'s>,
}

impl PixelWorker for WhittedWorker<'_> {
    fn row(&mut self, y: u32, xs: Range<u32>, out: &mut Vec<Rgb>, bad: &mut Vec<BadSample>) {
        let scene = self.scene;
        if scene.settings.spp == 1 {
            let span = span_width(scene.settings.width);
            for x0 in xs.clone().step_by(span as usize) {
                let span = x0..(x0 + span).min(xs.end);
                pixel::render_span(scene, &mut self.tracer, span, y, bad, out);
            }
            return;
        }
        for x in xs {
            out.push(pixel::render_pixel(scene, &mut self.tracer, x, y, bad));
        }
    }

    fn stats(&self) -> &RayStats {
        &self.tracer.stats
    }
}

/// How many pixels of a row are rendered together in a frame of one
/// camera ray per pixel (a span): about 2% of the image's width, from 2 to
/// 16. Wider spans hold less coherent rays than a lone ray is worth: on the
/// bunny's Whitted frame (instruction counts) 16 is best at 800 pixels
/// across (8 and 32 cost 5% more) and 4 at 200 (16 costs 3% more than
/// tracing pixel by pixel).
fn span_width(width: u32) -> u32 {
    (width / 50).clamp(2, 16)
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
        let (xs, ys) = (3..3 + span_width(scene.settings.width) * 2 + 5, 5..12);
        let mut worker = Whitted.worker(&scene);
        let (mut pixels, mut bad) = (Vec::new(), Vec::new());
        for y in ys.clone() {
            worker.row(y, xs.clone(), &mut pixels, &mut bad);
        }
        let mut tracer = Tracer::new(&scene);
        let mut lit = 0;
        let coords = ys.flat_map(|y| xs.clone().map(move |x| (x, y)));
        for (k, (x, y)) in coords.enumerate() {
            let alone = pixel::render_pixel(&scene, &mut tracer, x, y, &mut bad);
            let bits = |c: Rgb| c.to_array().map(f32::to_bits);
            assert_eq!(bits(pixels[k]), bits(alone), "pixel ({x}, {y})");
            lit += usize::from(alone != Rgb::ZERO);
        }
        assert_eq!(*worker.stats(), tracer.stats);
        assert!(lit > 100, "{lit} pixels not black");
    }
}
